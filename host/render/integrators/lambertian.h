/* The scalar Lambertian sampling steps the integrators share: pbrt-v3's concentric disk and
 * cosine hemisphere, the shading frame and pbrt-v3's BSDF frame. lambert_wave.c computes the
 * same float operations, in the same order, across a wave. */
#ifndef CLR_LAMBERTIAN_H
#define CLR_LAMBERTIAN_H

#include <math.h>
#include "render_scene.h"
#include "vec3.h"
#include "float_minmax.h"

#define CLR_ONE_MINUS_EPSILON 0x1.fffffep-1f

/* sin and cos of a in [-pi/4, pi/4]: Taylor polynomials, error below 2e-9 there (a float ulp). */
static inline void clr_sincos_quarter(float a, float *sn, float *cs) {
  float a2 = a * a;
  *sn = a * (1.0f + a2 * (-1.0f / 6.0f +
                          a2 * (1.0f / 120.0f + a2 * (-1.0f / 5040.0f + a2 * (1.0f / 362880.0f)))));
  *cs = 1.0f + a2 * (-0.5f + a2 * (1.0f / 24.0f +
                                   a2 * (-1.0f / 720.0f +
                                         a2 * (1.0f / 40320.0f + a2 * (-1.0f / 3628800.0f)))));
}

/* pbrt ConcentricSampleDisk; its angles stay within pi/4 of an axis, so the quarter-range
 * polynomials give cos and sin (pi/2 - a = a swapped). */
static inline void clr_concentric_disk(const float u[2], float *x, float *y) {
  float ox = 2.0f * u[0] - 1.0f, oy = 2.0f * u[1] - 1.0f;
  if (ox == 0.0f && oy == 0.0f) {
    *x = *y = 0.0f;
    return;
  }
  float sn, cs;
  if (fabsf(ox) > fabsf(oy)) {
    clr_sincos_quarter((RS_PI / 4.0f) * (oy / ox), &sn, &cs);
    *x = ox * cs;
    *y = ox * sn;
  } else {
    clr_sincos_quarter((RS_PI / 4.0f) * (ox / oy), &sn, &cs);
    *x = oy * sn;
    *y = oy * cs;
  }
}

static inline void clr_cosine_hemisphere(const float u[2], float w[3]) {
  clr_concentric_disk(u, &w[0], &w[1]);
  float z2 = 1.0f - w[0] * w[0] - w[1] * w[1];
  w[2] = sqrtf(z2 > 0.0f ? z2 : 0.0f);
}

/* Shading frame (ss, ts, ns) of a surface. */
static inline void clr_shading_frame(const clr_surface *s, float ss[3], float ts[3]) {
  float d = rs_dot(s->dpdu, s->ns);
  for (int i = 0; i < 3; ++i) ss[i] = s->dpdu[i] - d * s->ns[i];
  if (!(rs_dot(ss, ss) > 1e-20f)) {
    if (fabsf(s->ns[0]) > fabsf(s->ns[1])) {
      ss[0] = -s->ns[2];
      ss[1] = 0;
      ss[2] = s->ns[0];
    } else {
      ss[0] = 0;
      ss[1] = s->ns[2];
      ss[2] = -s->ns[1];
    }
  }
  rs_normalize(ss);
  rs_cross(s->ns, ss, ts);
}

/* pbrt-v3's BSDF frame: the shading normal oriented as the shape's (isect.shading.n), not
 * toward wo; plastic's FresnelDielectric(1.5, 1) depends on the side (cos < 0 swaps the etas). */
static inline void clr_shape_frame(const clr_surface *s, float ss[3], float ts[3], float n[3]) {
  clr_shading_frame(s, ss, ts);
  int flip = rs_dot(s->ns, s->n_geom) < 0.0f;
  for (int i = 0; i < 3; ++i) {
    n[i] = flip ? -s->ns[i] : s->ns[i];
    ts[i] = flip ? -ts[i] : ts[i];
  }
}

/* A plain Lambertian surface: matte without Oren-Nayar's sigma, nor plastic, metal, mirror,
 * glass or a lobe list (lambert_wave.c samples these). */
static inline int clr_surface_is_lambertian(const clr_surface *s) {
  return !s->general && !s->metal && !s->plastic && !s->mirror && !s->glass && s->on_b == 0.0f &&
         s->on_a == 1.0f;
}

/* pbrt-v3 Lambertian::Sample_f's direction in the BSDF frame: wi (world) and pdf. */
static inline void clr_lambert_sample_dir(const clr_surface *s, const float wo[3],
                                          const float u_in[2], float wi[3], float *pdf) {
  float u[2] = {rs_fminf(u_in[0], CLR_ONE_MINUS_EPSILON), u_in[1]}, l[3], ss[3], ts[3], n[3];
  clr_cosine_hemisphere(u, l);
  clr_shape_frame(s, ss, ts, n); /* pbrt-v3's frame: the same directions for the same samples */
  if (rs_dot(wo, n) < 0.0f) l[2] = -l[2];
  for (int i = 0; i < 3; ++i) wi[i] = ss[i] * l[0] + ts[i] * l[1] + n[i] * l[2];
  *pdf = fabsf(l[2]) * RS_INV_PI;
}

/* pbrt BSDF::f's reflect rule: wo and wi on the same side of the geometric surface. */
static inline int clr_reflects(const clr_surface *s, const float wo[3], const float wi[3]) {
  return rs_dot(wi, s->ng) * rs_dot(wo, s->ng) > 0.0f;
}

/* Lambertian f / Kd times |cos(wi, ns)| with the reflect rule (0 across the surface). */
static inline float clr_lambert_cos_plain(const clr_surface *s, const float wo[3],
                                          const float wi[3]) {
  if (!clr_reflects(s, wo, wi)) return 0.0f;
  return fabsf(rs_dot(wi, s->ns)) * RS_INV_PI;
}

/* pbrt-v3 Lambertian::Pdf: cosine-weighted when wo and wi are on the same side of ns. */
static inline float clr_lambert_pdf(const clr_surface *s, const float wo[3], const float wi[3]) {
  float a = rs_dot(wo, s->ns), b = rs_dot(wi, s->ns);
  return (a * b > 0.0f) ? fabsf(b) * RS_INV_PI : 0.0f;
}

#endif
