/* pbrt-v3's BxDFs (reflection.cpp, microfacet.cpp) as lobes of one BSDF, in the local shading
 * frame, re-implemented from their definitions. */
#include <math.h>
#include <string.h>
#include "bsdf_lobes.h"
#include "local_frame.h"
#include "microfacet.h"
#include "vec3.h"
#include "float_minmax.h"

#define ONE_MINUS_EPS 0x1.fffffep-1f

/* ---------- trigonometry in the local frame ---------- */

static int same_hemisphere(const float a[3], const float b[3]) { return a[2] * b[2] > 0.0f; }
static void normalize3(float v[3]) { rs_normalize(v); }

/* ---------- Fresnel ---------- */

static void fresnel_eval(const clr_lobe *l, float cos_i, float F[3]) {
  for (int k = 0; k < 3; ++k) {
    if (l->fresnel == CLR_FRESNEL_DIELECTRIC)
      F[k] = clr_fr_dielectric(cos_i, 1.0f, l->eta);
    else if (l->fresnel == CLR_FRESNEL_CONDUCTOR)
      F[k] = clr_fr_conductor(fabsf(cos_i), l->cond_eta[k], l->cond_k[k]);
    else
      F[k] = 1.0f;
  }
}

static void reflect(const float wo[3], const float n[3], float wi[3]) {
  float d = 2.0f * rs_dot(wo, n);
  for (int k = 0; k < 3; ++k) wi[k] = -wo[k] + d * n[k];
}

/* pbrt-v3 Refract: wt for wi through a surface of normal n, eta = eta_i / eta_t. */
static int refract(const float wi[3], const float n[3], float eta, float wt[3]) {
  float cos_i = rs_dot(n, wi), sin2_i = rs_fmaxf(0.0f, 1.0f - cos_i * cos_i);
  float sin2_t = eta * eta * sin2_i;
  if (sin2_t >= 1.0f) return 0;
  float cos_t = sqrtf(1.0f - sin2_t);
  for (int k = 0; k < 3; ++k) wt[k] = -eta * wi[k] + (eta * cos_i - cos_t) * n[k];
  return 1;
}

/* ---------- lobes ---------- */

static int is_specular(const clr_lobe *l) {
  return l->type == CLR_LOBE_SPECULAR_R || l->type == CLR_LOBE_SPECULAR_T ||
         l->type == CLR_LOBE_FRESNEL_SPECULAR;
}
static int has_reflection(const clr_lobe *l) {
  return l->type != CLR_LOBE_LAMBERT_T && l->type != CLR_LOBE_MICROFACET_T &&
         l->type != CLR_LOBE_SPECULAR_T;
}
static int has_transmission(const clr_lobe *l) {
  return l->type == CLR_LOBE_LAMBERT_T || l->type == CLR_LOBE_MICROFACET_T ||
         l->type == CLR_LOBE_SPECULAR_T || l->type == CLR_LOBE_FRESNEL_SPECULAR;
}

static int matches(const clr_lobe *l, int mask) {
  switch (mask) {
    case CLR_BXDF_NON_SPECULAR:
      return !is_specular(l);
    case CLR_BXDF_SPECULAR_REFLECTION:
      return is_specular(l) && has_reflection(l);
    case CLR_BXDF_SPECULAR_TRANSMISSION:
      return is_specular(l) && has_transmission(l);
    default:
      return 1;
  }
}

clr_lobe *clr_bsdf_add(clr_bsdf *b, clr_lobe_type type) {
  if (b->n >= CLR_MAX_LOBES) return NULL;
  clr_lobe *l = &b->lobes[b->n++];
  memset(l, 0, sizeof *l);
  l->type = type;
  l->on_a = 1.0f;
  l->eta = 1.0f;
  l->scale[0] = l->scale[1] = l->scale[2] = 1.0f;
  return l;
}

int clr_bsdf_count(const clr_bsdf *b, int mask) {
  int n = 0;
  for (int i = 0; i < b->n; ++i) n += matches(&b->lobes[i], mask);
  return n;
}

/* pbrt-v3 OrenNayar::f / (R / pi). */
static float oren_nayar(const clr_lobe *l, const float wo[3], const float wi[3]) {
  if (l->on_b == 0.0f) return l->on_a;
  float si = sqrtf(sin2_theta(wi)), so = sqrtf(sin2_theta(wo)), max_cos = 0.0f;
  if (si > 1e-4f && so > 1e-4f) {
    float dcos = cos_phi(wi) * cos_phi(wo) + sin_phi(wi) * sin_phi(wo);
    max_cos = rs_fmaxf(0.0f, dcos);
  }
  float sin_alpha, tan_beta;
  if (fabsf(wi[2]) > fabsf(wo[2])) {
    sin_alpha = so;
    tan_beta = si / fabsf(wi[2]);
  } else {
    sin_alpha = si;
    tan_beta = so / fabsf(wo[2]);
  }
  return l->on_a + l->on_b * max_cos * sin_alpha * tan_beta;
}

static float pow5(float v) { return (v * v) * (v * v) * v; }

/* BxDF::f of one lobe (without its scale). */
static void lobe_f(const clr_lobe *l, const float wo[3], const float wi[3], float f[3]) {
  f[0] = f[1] = f[2] = 0.0f;
  switch (l->type) {
    case CLR_LOBE_LAMBERT_R: {
      float s = RS_INV_PI * oren_nayar(l, wo, wi);
      for (int k = 0; k < 3; ++k) f[k] = l->c[k] * s;
      return;
    }
    case CLR_LOBE_LAMBERT_T:
      for (int k = 0; k < 3; ++k) f[k] = l->c[k] * RS_INV_PI;
      return;
    case CLR_LOBE_MICROFACET_R: {
      float co = fabsf(wo[2]), ci = fabsf(wi[2]);
      float wh[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
      if (ci == 0.0f || co == 0.0f || (wh[0] == 0.0f && wh[1] == 0.0f && wh[2] == 0.0f)) return;
      normalize3(wh);
      float F[3], ff[3] = {wh[0], wh[1], wh[2]};
      if (ff[2] < 0.0f)
        for (int k = 0; k < 3; ++k) ff[k] = -ff[k]; /* Faceforward(wh, (0, 0, 1)) */
      fresnel_eval(l, rs_dot(wi, ff), F);
      float dg = clr_tr_d(wh, l->ax, l->ay) * clr_tr_g(wo, wi, l->ax, l->ay) / (4.0f * ci * co);
      for (int k = 0; k < 3; ++k) f[k] = l->c[k] * dg * F[k];
      return;
    }
    case CLR_LOBE_MICROFACET_T: {
      if (same_hemisphere(wo, wi)) return;
      float co = wo[2], ci = wi[2];
      if (ci == 0.0f || co == 0.0f) return;
      float eta = co > 0.0f ? l->eta : 1.0f / l->eta;
      float wh[3] = {wo[0] + wi[0] * eta, wo[1] + wi[1] * eta, wo[2] + wi[2] * eta};
      normalize3(wh);
      if (wh[2] < 0.0f)
        for (int k = 0; k < 3; ++k) wh[k] = -wh[k];
      float dwo = rs_dot(wo, wh), dwi = rs_dot(wi, wh);
      if (dwo * dwi > 0.0f) return;
      float F = clr_fr_dielectric(dwo, 1.0f, l->eta);
      float sd = dwo + eta * dwi, factor = 1.0f / eta; /* radiance transport */
      float v = fabsf(clr_tr_d(wh, l->ax, l->ay) * clr_tr_g(wo, wi, l->ax, l->ay) * eta * eta *
                      fabsf(dwi) * fabsf(dwo) * factor * factor / (ci * co * sd * sd));
      for (int k = 0; k < 3; ++k) f[k] = (1.0f - F) * l->c[k] * v;
      return;
    }
    case CLR_LOBE_FRESNEL_BLEND: {
      float a =
          (1.0f - pow5(1.0f - 0.5f * fabsf(wi[2]))) * (1.0f - pow5(1.0f - 0.5f * fabsf(wo[2])));
      float wh[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
      for (int k = 0; k < 3; ++k)
        f[k] = (28.0f / (23.0f * RS_PI)) * l->c[k] * (1.0f - l->c2[k]) * a;
      if (wh[0] == 0.0f && wh[1] == 0.0f && wh[2] == 0.0f) return;
      normalize3(wh);
      float dh = rs_dot(wi, wh);
      float spec =
          clr_tr_d(wh, l->ax, l->ay) / (4.0f * fabsf(dh) * rs_fmaxf(fabsf(wi[2]), fabsf(wo[2])));
      for (int k = 0; k < 3; ++k) f[k] += spec * (l->c2[k] + pow5(1.0f - dh) * (1.0f - l->c2[k]));
      return;
    }
    default:
      return; /* specular: a delta */
  }
}

static float lobe_pdf(const clr_lobe *l, const float wo[3], const float wi[3]) {
  switch (l->type) {
    case CLR_LOBE_LAMBERT_R:
      return same_hemisphere(wo, wi) ? fabsf(wi[2]) * RS_INV_PI : 0.0f;
    case CLR_LOBE_LAMBERT_T:
      return !same_hemisphere(wo, wi) ? fabsf(wi[2]) * RS_INV_PI : 0.0f;
    case CLR_LOBE_MICROFACET_R: {
      if (!same_hemisphere(wo, wi)) return 0.0f;
      float wh[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
      normalize3(wh);
      return clr_tr_pdf_wh(wo, wh, l->ax, l->ay) / (4.0f * rs_dot(wo, wh));
    }
    case CLR_LOBE_MICROFACET_T: {
      if (same_hemisphere(wo, wi)) return 0.0f;
      float eta = wo[2] > 0.0f ? l->eta : 1.0f / l->eta;
      float wh[3] = {wo[0] + wi[0] * eta, wo[1] + wi[1] * eta, wo[2] + wi[2] * eta};
      normalize3(wh);
      float dwo = rs_dot(wo, wh), dwi = rs_dot(wi, wh);
      if (dwo * dwi > 0.0f) return 0.0f;
      float sd = dwo + eta * dwi, dwh_dwi = fabsf(eta * eta * dwi / (sd * sd));
      return clr_tr_pdf_wh(wo, wh, l->ax, l->ay) * dwh_dwi;
    }
    case CLR_LOBE_FRESNEL_BLEND: {
      if (!same_hemisphere(wo, wi)) return 0.0f;
      float wh[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
      normalize3(wh);
      return 0.5f * (fabsf(wi[2]) * RS_INV_PI +
                     clr_tr_pdf_wh(wo, wh, l->ax, l->ay) / (4.0f * rs_dot(wo, wh)));
    }
    default:
      return 0.0f;
  }
}

static void cosine_hemisphere(const float u[2], float w[3]) {
  rs_concentric_disk(u[0], u[1], &w[0], &w[1]);
  w[2] = sqrtf(rs_fmaxf(0.0f, 1.0f - w[0] * w[0] - w[1] * w[1]));
}

/* BxDF::Sample_f of one lobe: wi, pdf and f (unscaled); 0 when no direction. */
static int lobe_sample(const clr_lobe *l, const float wo[3], const float u_in[2], float wi[3],
                       float *pdf, float f[3]) {
  float u[2] = {u_in[0], u_in[1]};
  *pdf = 0.0f;
  f[0] = f[1] = f[2] = 0.0f;
  switch (l->type) {
    case CLR_LOBE_LAMBERT_R:
    case CLR_LOBE_LAMBERT_T:
      cosine_hemisphere(u, wi);
      if ((l->type == CLR_LOBE_LAMBERT_R) == (wo[2] < 0.0f)) wi[2] = -wi[2];
      break;
    case CLR_LOBE_MICROFACET_R:
    case CLR_LOBE_MICROFACET_T: {
      if (wo[2] == 0.0f) return 0;
      float wh[3];
      clr_tr_sample_wh(wo, u, l->ax, l->ay, wh);
      if (rs_dot(wo, wh) < 0.0f) return 0;
      if (l->type == CLR_LOBE_MICROFACET_R) {
        reflect(wo, wh, wi);
        if (!same_hemisphere(wo, wi)) return 0;
      } else if (!refract(wo, wh, wo[2] > 0.0f ? 1.0f / l->eta : l->eta, wi)) {
        return 0;
      }
      break;
    }
    case CLR_LOBE_FRESNEL_BLEND:
      if (u[0] < 0.5f) {
        u[0] = rs_fminf(2.0f * u[0], ONE_MINUS_EPS);
        cosine_hemisphere(u, wi);
        if (wo[2] < 0.0f) wi[2] = -wi[2];
      } else {
        u[0] = rs_fminf(2.0f * (u[0] - 0.5f), ONE_MINUS_EPS);
        float wh[3];
        clr_tr_sample_wh(wo, u, l->ax, l->ay, wh);
        reflect(wo, wh, wi);
        if (!same_hemisphere(wo, wi)) return 0;
      }
      break;
    case CLR_LOBE_SPECULAR_R: {
      wi[0] = -wo[0];
      wi[1] = -wo[1];
      wi[2] = wo[2];
      float F[3], c = fabsf(wi[2]);
      if (c == 0.0f) return 0;
      fresnel_eval(l, wi[2], F);
      for (int k = 0; k < 3; ++k) f[k] = F[k] * l->c[k] / c;
      *pdf = 1.0f;
      return 1;
    }
    case CLR_LOBE_SPECULAR_T:
    case CLR_LOBE_FRESNEL_SPECULAR: {
      float cos_o = wo[2];
      float F = clr_fr_dielectric(cos_o, 1.0f, l->eta);
      int entering = cos_o > 0.0f;
      float eta_i = entering ? 1.0f : l->eta, eta_t = entering ? l->eta : 1.0f;
      if (l->type == CLR_LOBE_FRESNEL_SPECULAR && u[0] < F) {
        wi[0] = -wo[0];
        wi[1] = -wo[1];
        wi[2] = wo[2];
        if (wi[2] == 0.0f) return 0;
        *pdf = F;
        for (int k = 0; k < 3; ++k) f[k] = F * l->c[k] / fabsf(wi[2]);
        return 1;
      }
      float n[3] = {0.0f, 0.0f, entering ? 1.0f : -1.0f};
      if (!refract(wo, n, eta_i / eta_t, wi) || wi[2] == 0.0f) return 0;
      const float *T = l->type == CLR_LOBE_FRESNEL_SPECULAR ? l->c2 : l->c;
      float Ft = l->type == CLR_LOBE_FRESNEL_SPECULAR ? F : clr_fr_dielectric(wi[2], 1.0f, l->eta);
      float s = (1.0f - Ft) * (eta_i * eta_i) / (eta_t * eta_t) / fabsf(wi[2]);
      for (int k = 0; k < 3; ++k) f[k] = T[k] * s;
      *pdf = l->type == CLR_LOBE_FRESNEL_SPECULAR ? 1.0f - F : 1.0f;
      return 1;
    }
  }
  *pdf = lobe_pdf(l, wo, wi);
  lobe_f(l, wo, wi, f);
  return 1;
}

void clr_bsdf_f_local(const clr_bsdf *b, const float wo[3], const float wi[3], int refl,
                      float f[3]) {
  f[0] = f[1] = f[2] = 0.0f;
  if (wo[2] == 0.0f) return;
  for (int i = 0; i < b->n; ++i) {
    const clr_lobe *l = &b->lobes[i];
    if (is_specular(l)) continue;
    if (!((refl && has_reflection(l)) || (!refl && has_transmission(l)))) continue;
    float g[3];
    lobe_f(l, wo, wi, g);
    for (int k = 0; k < 3; ++k) f[k] += l->scale[k] * g[k];
  }
  float c = fabsf(wi[2]);
  for (int k = 0; k < 3; ++k) f[k] *= c;
}

float clr_bsdf_pdf_local(const clr_bsdf *b, const float wo[3], const float wi[3], int mask) {
  if (wo[2] == 0.0f) return 0.0f;
  int n = 0;
  float pdf = 0.0f;
  for (int i = 0; i < b->n; ++i)
    if (matches(&b->lobes[i], mask)) {
      ++n;
      pdf += lobe_pdf(&b->lobes[i], wo, wi);
    }
  return n ? pdf / (float)n : 0.0f;
}

int clr_bsdf_sample_local(const clr_bsdf *b, const float wo[3], const float u_in[2], int mask,
                          const float ng[3], float wi[3], float *pdf, float f[3], int *flags) {
  *pdf = 0.0f;
  *flags = 0;
  f[0] = f[1] = f[2] = 0.0f;
  int n = clr_bsdf_count(b, mask);
  if (!n || wo[2] == 0.0f) return 0;
  int comp = (int)rs_fminf(floorf(u_in[0] * (float)n), (float)(n - 1)), chosen = -1;
  for (int i = 0, c = comp; i < b->n; ++i)
    if (matches(&b->lobes[i], mask) && c-- == 0) {
      chosen = i;
      break;
    }
  const clr_lobe *l = &b->lobes[chosen];
  float u[2] = {rs_fminf(u_in[0] * (float)n - (float)comp, ONE_MINUS_EPS), u_in[1]}, g[3];
  if (!lobe_sample(l, wo, u, wi, pdf, g) || !(*pdf > 0.0f)) return 0;
  int refl = rs_dot(wi, ng) * rs_dot(wo, ng) > 0.0f;
  if (is_specular(l)) {
    *flags = CLR_BSDF_SPECULAR | (wi[2] * wo[2] < 0.0f ? CLR_BSDF_TRANSMISSION : 0);
    if (n > 1) *pdf /= (float)n;
    for (int k = 0; k < 3; ++k) f[k] = l->scale[k] * g[k] * fabsf(wi[2]);
  } else {
    *flags = wi[2] * wo[2] < 0.0f ? CLR_BSDF_TRANSMISSION : 0;
    *pdf = clr_bsdf_pdf_local(b, wo, wi, mask);
    clr_bsdf_f_local(b, wo, wi, refl, f);
  }
  return *pdf > 0.0f && (f[0] != 0.0f || f[1] != 0.0f || f[2] != 0.0f);
}

/* ---------- world space ---------- */

void clr_bsdf_set_frame(clr_bsdf *b, const float dpdu[3], const float ns[3], const float ng[3]) {
  float d = rs_dot(dpdu, ns);
  for (int i = 0; i < 3; ++i) b->ss[i] = dpdu[i] - d * ns[i];
  if (!(rs_dot(b->ss, b->ss) > 1e-20f)) {
    if (fabsf(ns[0]) > fabsf(ns[1])) {
      b->ss[0] = -ns[2];
      b->ss[1] = 0;
      b->ss[2] = ns[0];
    } else {
      b->ss[0] = 0;
      b->ss[1] = ns[2];
      b->ss[2] = -ns[1];
    }
  }
  rs_normalize(b->ss);
  memcpy(b->ns, ns, sizeof b->ns);
  memcpy(b->ng, ng, sizeof b->ng);
  rs_cross(ns, b->ss, b->ts);
}

static void to_local(const clr_bsdf *b, const float w[3], float l[3]) {
  l[0] = rs_dot(w, b->ss);
  l[1] = rs_dot(w, b->ts);
  l[2] = rs_dot(w, b->ns);
}

int clr_bsdf_f(const clr_bsdf *b, const float wo[3], const float wi[3], float f[3]) {
  float lo[3], li[3];
  to_local(b, wo, lo);
  to_local(b, wi, li);
  clr_bsdf_f_local(b, lo, li, rs_dot(wi, b->ng) * rs_dot(wo, b->ng) > 0.0f, f);
  return f[0] != 0.0f || f[1] != 0.0f || f[2] != 0.0f;
}

float clr_bsdf_pdf(const clr_bsdf *b, const float wo[3], const float wi[3], int mask) {
  float lo[3], li[3];
  to_local(b, wo, lo);
  to_local(b, wi, li);
  return clr_bsdf_pdf_local(b, lo, li, mask);
}

int clr_bsdf_sample(const clr_bsdf *b, const float wo[3], const float u[2], int mask, float wi[3],
                    float *pdf, float f[3], int *flags) {
  float lo[3], li[3], ng[3];
  to_local(b, wo, lo);
  to_local(b, b->ng, ng);
  if (!clr_bsdf_sample_local(b, lo, u, mask, ng, li, pdf, f, flags)) return 0;
  for (int i = 0; i < 3; ++i) wi[i] = b->ss[i] * li[0] + b->ts[i] * li[1] + b->ns[i] * li[2];
  return 1;
}
