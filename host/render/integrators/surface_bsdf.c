/* The BSDF of a surface record (matte, plastic, metal and lobe lists) as pbrt-v3 evaluates,
 * weighs and samples it. */
#include "surface_bsdf.h"
#include <math.h>
#include "lambertian.h"
#include "microfacet.h"
#include "vec3.h"
#include "float_minmax.h"

#define ONE_MINUS_EPSILON 0x1.fffffep-1f

/* pbrt-v3 OrenNayar::f / R * pi: A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta), in the
 * shading frame (1 for a Lambertian surface). */
static float oren_nayar_factor(const clr_surface *s, const float wo[3], const float wi[3]) {
  if (s->on_b == 0.0f) return s->on_a;
  float ss[3], ts[3];
  clr_shading_frame(s, ss, ts);
  float o[3] = {rs_dot(wo, ss), rs_dot(wo, ts), rs_dot(wo, s->ns)};
  float i[3] = {rs_dot(wi, ss), rs_dot(wi, ts), rs_dot(wi, s->ns)};
  float sin_o = sqrtf(rs_fmaxf(0.0f, 1.0f - o[2] * o[2])),
        sin_i = sqrtf(rs_fmaxf(0.0f, 1.0f - i[2] * i[2]));
  float max_cos = 0.0f;
  if (sin_i > 1e-4f && sin_o > 1e-4f) {
    float cpi = rs_fminf(1.0f, rs_fmaxf(-1.0f, i[0] / sin_i)),
          spi = rs_fminf(1.0f, rs_fmaxf(-1.0f, i[1] / sin_i));
    float cpo = rs_fminf(1.0f, rs_fmaxf(-1.0f, o[0] / sin_o)),
          spo = rs_fminf(1.0f, rs_fmaxf(-1.0f, o[1] / sin_o));
    max_cos = rs_fmaxf(0.0f, cpi * cpo + spi * spo);
  }
  float sin_alpha, tan_beta;
  if (fabsf(i[2]) > fabsf(o[2])) {
    sin_alpha = sin_o;
    tan_beta = sin_i / fabsf(i[2]);
  } else {
    sin_alpha = sin_i;
    tan_beta = sin_o / fabsf(o[2]);
  }
  return s->on_a + s->on_b * max_cos * sin_alpha * tan_beta;
}

/* Matte BSDF value / Kd times |cos| for world directions, pbrt BSDF::f reflect rule:
 * Lambertian, or Oren-Nayar when the material has "sigma". */
static float lambert_cos(const clr_surface *s, const float wo[3], const float wi[3]) {
  if (!clr_reflects(s, wo, wi)) return 0.0f;
  float f = fabsf(rs_dot(wi, s->ns)) * RS_INV_PI;
  return s->on_b == 0.0f && s->on_a == 1.0f ? f : f * oren_nayar_factor(s, wo, wi);
}

/* pbrt Lambertian Sample_f: direction wi and pdf; returns f*|cos| scale (without Kd). */
static float lambert_sample(const clr_surface *s, const float wo[3], const float u_in[2],
                            float wi[3], float *pdf) {
  clr_lambert_sample_dir(s, wo, u_in, wi, pdf);
  return lambert_cos(s, wo, wi);
}

static int is_black_c(const float c[3]) { return c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f; }

static void to_local(const float ss[3], const float ts[3], const float ns[3], const float w[3],
                     float l[3]) {
  l[0] = rs_dot(w, ss);
  l[1] = rs_dot(w, ts);
  l[2] = rs_dot(w, ns);
}

static int plastic_components(const clr_surface *s, int *diffuse, int *glossy) {
  *diffuse = !is_black_c(s->kd);
  *glossy = !is_black_c(s->ks);
  return *diffuse + *glossy;
}

/* pbrt-v3 metal: MicrofacetReflection(1, TrowbridgeReitz, FresnelConductor), f |cos| in
 * local coordinates. */
static int metal_eval_local(const clr_surface *s, const float lo[3], const float li[3],
                            float f[3]) {
  float cos_h, dg = clr_microfacet_dg(lo, li, s->alpha, &cos_h) * fabsf(li[2]);
  for (int k = 0; k < 3; ++k)
    f[k] = dg > 0.0f ? dg * clr_fr_conductor(cos_h, s->m_eta[k], s->m_k[k]) : 0.0f;
  return !is_black_c(f);
}

/* f * |cos(wi, ns)| (colour) with BSDF::f's reflect rule; 1 when not black. */
int clr_surface_bsdf_eval(const clr_surface *s, const float wo[3], const float wi[3], float f[3]) {
  if (s->general) return clr_bsdf_f(&s->bsdf, wo, wi, f);
  if (s->metal) {
    f[0] = f[1] = f[2] = 0.0f;
    if (!(rs_dot(wi, s->ng) * rs_dot(wo, s->ng) > 0.0f)) return 0;
    float ss[3], ts[3], lo[3], li[3];
    clr_shading_frame(s, ss, ts);
    to_local(ss, ts, s->ns, wo, lo);
    to_local(ss, ts, s->ns, wi, li);
    if (lo[2] == 0.0f) return 0;
    return metal_eval_local(s, lo, li, f);
  }
  float fc = lambert_cos(s, wo, wi);
  if (!s->plastic) {
    for (int k = 0; k < 3; ++k) f[k] = s->kd[k] * fc;
    return fc > 0.0f && !is_black_c(f);
  }
  f[0] = f[1] = f[2] = 0.0f;
  if (!(rs_dot(wi, s->ng) * rs_dot(wo, s->ng) > 0.0f)) return 0;
  float ss[3], ts[3], n[3], lo[3], li[3];
  clr_shape_frame(s, ss, ts, n);
  to_local(ss, ts, n, wo, lo);
  to_local(ss, ts, n, wi, li);
  if (lo[2] == 0.0f) return 0;
  float g = clr_microfacet_f(lo, li, s->alpha) * fabsf(li[2]);
  for (int k = 0; k < 3; ++k) f[k] = s->kd[k] * fc + s->ks[k] * g;
  return !is_black_c(f);
}

float clr_surface_bsdf_pdf(const clr_surface *s, const float wo[3], const float wi[3]) {
  if (s->general) return clr_bsdf_pdf(&s->bsdf, wo, wi, CLR_BXDF_NON_SPECULAR);
  if (s->metal) {
    float ss[3], ts[3], lo[3], li[3];
    clr_shading_frame(s, ss, ts);
    to_local(ss, ts, s->ns, wo, lo);
    to_local(ss, ts, s->ns, wi, li);
    return lo[2] == 0.0f ? 0.0f : clr_microfacet_pdf(lo, li, s->alpha);
  }
  if (!s->plastic) return clr_lambert_pdf(s, wo, wi);
  int d, g, n = plastic_components(s, &d, &g);
  if (!n) return 0.0f;
  float ss[3], ts[3], nf[3], lo[3], li[3];
  clr_shape_frame(s, ss, ts, nf);
  to_local(ss, ts, nf, wo, lo);
  to_local(ss, ts, nf, wi, li);
  if (lo[2] == 0.0f) return 0.0f;
  float pdf =
      (d ? clr_lambert_pdf(s, wo, wi) : 0.0f) + (g ? clr_microfacet_pdf(lo, li, s->alpha) : 0.0f);
  return pdf / (float)n;
}

/* BSDF::Sample_f: wi, pdf and f * |cos| (colour); 1 when usable. */
int clr_surface_bsdf_sample(const clr_surface *s, const float wo[3], const float u_in[2],
                            float wi[3], float *pdf, float f[3]) {
  int flags;
  if (s->general)
    return clr_bsdf_sample(&s->bsdf, wo, u_in, CLR_BXDF_NON_SPECULAR, wi, pdf, f, &flags);
  if (s->metal) {
    float ss[3], ts[3], n[3], lo[3], li[3];
    *pdf = 0.0f;
    clr_shape_frame(s, ss, ts, n);
    to_local(ss, ts, n, wo, lo);
    if (!clr_microfacet_sample_wi(lo, u_in, s->alpha, li, pdf)) return 0;
    for (int i = 0; i < 3; ++i) wi[i] = ss[i] * li[0] + ts[i] * li[1] + n[i] * li[2];
    return clr_surface_bsdf_eval(s, wo, wi, f) && *pdf > 0.0f;
  }
  if (!s->plastic) {
    float fc = lambert_sample(s, wo, u_in, wi, pdf);
    for (int k = 0; k < 3; ++k) f[k] = s->kd[k] * fc;
    return fc > 0.0f && *pdf > 0.0f && !is_black_c(f);
  }
  int d, g, n = plastic_components(s, &d, &g);
  *pdf = 0.0f;
  if (!n) return 0;
  int comp = (int)rs_fminf(floorf(u_in[0] * (float)n), (float)(n - 1));
  float u[2] = {rs_fminf(u_in[0] * (float)n - (float)comp, ONE_MINUS_EPSILON), u_in[1]};
  int glossy = g && (comp == 1 || !d);
  float ss[3], ts[3], nf[3], lo[3];
  clr_shape_frame(s, ss, ts, nf);
  to_local(ss, ts, nf, wo, lo);
  if (lo[2] == 0.0f) return 0;
  if (glossy) {
    float li[3], p;
    if (!(clr_microfacet_sample(lo, u, s->alpha, li, &p) > 0.0f) || !(p > 0.0f)) return 0;
    for (int i = 0; i < 3; ++i) wi[i] = ss[i] * li[0] + ts[i] * li[1] + nf[i] * li[2];
  } else {
    float p;
    lambert_sample(s, wo, u, wi, &p);
    if (!(p > 0.0f)) return 0;
  }
  *pdf = clr_surface_bsdf_pdf(s, wo, wi);
  return clr_surface_bsdf_eval(s, wo, wi, f) && *pdf > 0.0f;
}
