/* Structure-of-arrays Lambertian sampling: each step one loop over the wave's arrays, selects
 * instead of branches (both sides computed, the same operations as the scalar code's taken side). */
#include "lambert_wave.h"
#include <stdlib.h>
#include "hemisphere_wave.h"
#include "render_error.h"
#include "wave_block.h"

#define WAVE_ARRAYS 34 /* float arrays in clr_lambert_wave */

clr_result clr_lambert_wave_reserve(clr_lambert_wave *w, int32_t n) {
  w->n = 0;
  if (n <= w->cap) return CLR_SUCCESS;
  size_t cap;
  float *block = clr_wave_block_alloc(n, WAVE_ARRAYS, &cap);
  int32_t *owner = malloc(cap * sizeof(int32_t));
  if (!block || !owner) {
    free(block);
    free(owner);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "lambert wave of %d entries", (int)n);
  }
  clr_lambert_wave_free(w);
  float **arrays[WAVE_ARRAYS] = {
      &w->u0,        &w->u1,        &w->wo[0],     &w->wo[1], &w->wo[2], &w->dpdu[0], &w->dpdu[1],
      &w->dpdu[2],   &w->ns[0],     &w->ns[1],     &w->ns[2], &w->ng[0], &w->ng[1],   &w->ng[2],
      &w->n_geom[0], &w->n_geom[1], &w->n_geom[2], &w->l[0],  &w->l[1],  &w->l[2],    &w->ss[0],
      &w->ss[1],     &w->ss[2],     &w->ts[0],     &w->ts[1], &w->ts[2], &w->nf[0],   &w->nf[1],
      &w->nf[2],     &w->wi[0],     &w->wi[1],     &w->wi[2], &w->pdf,   &w->fcos};
  for (int a = 0; a < WAVE_ARRAYS; ++a) *arrays[a] = block + (size_t)a * cap;
  w->block = block;
  w->owner = owner;
  w->cap = (int32_t)cap;
  w->n = 0;
  return CLR_SUCCESS;
}

void clr_lambert_wave_free(clr_lambert_wave *w) {
  free(w->block);
  free(w->owner);
  w->block = NULL;
  w->owner = NULL;
  w->cap = w->n = 0;
}

/* clr_shading_frame's ss: dpdu less its ns part, an axis-made vector when that vanishes,
 * normalized (dividing by 1 when its length is 0 leaves it as rs_normalize does). */
static void wave_tangent(int32_t n, const float *restrict d0, const float *restrict d1,
                         const float *restrict d2, const float *restrict n0,
                         const float *restrict n1, const float *restrict n2, float *restrict s0,
                         float *restrict s1, float *restrict s2) {
  for (int32_t k = 0; k < n; ++k) {
    float d = d0[k] * n0[k] + d1[k] * n1[k] + d2[k] * n2[k];
    float a = d0[k] - d * n0[k], b = d1[k] - d * n1[k], c = d2[k] - d * n2[k];
    int flat = !(a * a + b * b + c * c > 1e-20f), wide = fabsf(n0[k]) > fabsf(n1[k]);
    a = flat ? (wide ? -n2[k] : 0.0f) : a;
    b = flat ? (wide ? 0.0f : n2[k]) : b;
    c = flat ? (wide ? n0[k] : -n1[k]) : c;
    float len = sqrtf(a * a + b * b + c * c);
    float div = len > 0.0f ? len : 1.0f;
    s0[k] = a / div;
    s1[k] = b / div;
    s2[k] = c / div;
  }
}

/* clr_shape_frame from the tangents: ts = ns x ss, then ns and ts flipped where ns faces away
 * from the shape's normal n_geom (g). */
static void wave_shape_frame(int32_t n, const float *restrict n0, const float *restrict n1,
                             const float *restrict n2, const float *restrict g0,
                             const float *restrict g1, const float *restrict g2,
                             const float *restrict s0, const float *restrict s1,
                             const float *restrict s2, float *restrict t0, float *restrict t1,
                             float *restrict t2, float *restrict f0, float *restrict f1,
                             float *restrict f2) {
  for (int32_t k = 0; k < n; ++k) {
    float a = n1[k] * s2[k] - n2[k] * s1[k], b = n2[k] * s0[k] - n0[k] * s2[k],
          c = n0[k] * s1[k] - n1[k] * s0[k];
    int flip = n0[k] * g0[k] + n1[k] * g1[k] + n2[k] * g2[k] < 0.0f;
    f0[k] = flip ? -n0[k] : n0[k];
    f1[k] = flip ? -n1[k] : n1[k];
    f2[k] = flip ? -n2[k] : n2[k];
    t0[k] = flip ? -a : a;
    t1[k] = flip ? -b : b;
    t2[k] = flip ? -c : c;
  }
}

/* The local direction (x, y, z) with z turned toward wo's (o) side, into world space with the
 * frame (s, t, f); its pdf. */
static void wave_directions(int32_t n, const float *restrict o0, const float *restrict o1,
                            const float *restrict o2, const float *restrict x,
                            const float *restrict y, const float *restrict z,
                            const float *restrict s0, const float *restrict s1,
                            const float *restrict s2, const float *restrict t0,
                            const float *restrict t1, const float *restrict t2,
                            const float *restrict f0, const float *restrict f1,
                            const float *restrict f2, float *restrict w0, float *restrict w1,
                            float *restrict w2, float *restrict pdf) {
  for (int32_t k = 0; k < n; ++k) {
    float lz = o0[k] * f0[k] + o1[k] * f1[k] + o2[k] * f2[k] < 0.0f ? -z[k] : z[k];
    w0[k] = s0[k] * x[k] + t0[k] * y[k] + f0[k] * lz;
    w1[k] = s1[k] * x[k] + t1[k] * y[k] + f1[k] * lz;
    w2[k] = s2[k] * x[k] + t2[k] * y[k] + f2[k] * lz;
    pdf[k] = fabsf(lz) * RS_INV_PI;
  }
}

/* clr_lambert_cos_plain of wo (o), wi (w) with normals ng (g) and ns (m). */
static void wave_lambert_cos(int32_t n, const float *restrict o0, const float *restrict o1,
                             const float *restrict o2, const float *restrict w0,
                             const float *restrict w1, const float *restrict w2,
                             const float *restrict g0, const float *restrict g1,
                             const float *restrict g2, const float *restrict m0,
                             const float *restrict m1, const float *restrict m2,
                             float *restrict fcos) {
  for (int32_t k = 0; k < n; ++k) {
    float side = (w0[k] * g0[k] + w1[k] * g1[k] + w2[k] * g2[k]) *
                 (o0[k] * g0[k] + o1[k] * g1[k] + o2[k] * g2[k]);
    float f = fabsf(w0[k] * m0[k] + w1[k] * m1[k] + w2[k] * m2[k]) * RS_INV_PI;
    fcos[k] = side > 0.0f ? f : 0.0f;
  }
}

void clr_lambert_wave_sample(clr_lambert_wave *w) {
  int32_t n = w->n;
  clr_wave_cosine_hemisphere(n, w->u0, w->u1, w->l[0], w->l[1], w->l[2]);
  wave_tangent(n, w->dpdu[0], w->dpdu[1], w->dpdu[2], w->ns[0], w->ns[1], w->ns[2], w->ss[0],
               w->ss[1], w->ss[2]);
  wave_shape_frame(n, w->ns[0], w->ns[1], w->ns[2], w->n_geom[0], w->n_geom[1], w->n_geom[2],
                   w->ss[0], w->ss[1], w->ss[2], w->ts[0], w->ts[1], w->ts[2], w->nf[0], w->nf[1],
                   w->nf[2]);
  wave_directions(n, w->wo[0], w->wo[1], w->wo[2], w->l[0], w->l[1], w->l[2], w->ss[0], w->ss[1],
                  w->ss[2], w->ts[0], w->ts[1], w->ts[2], w->nf[0], w->nf[1], w->nf[2], w->wi[0],
                  w->wi[1], w->wi[2], w->pdf);
  wave_lambert_cos(n, w->wo[0], w->wo[1], w->wo[2], w->wi[0], w->wi[1], w->wi[2], w->ng[0],
                   w->ng[1], w->ng[2], w->ns[0], w->ns[1], w->ns[2], w->fcos);
}

void clr_lambert_wave_sample_more(const clr_lambert_wave *w, const float *u0, const float *u1,
                                  float *const l[3], float *const wi[3], float *pdf, float *fcos) {
  int32_t n = w->n;
  clr_wave_cosine_hemisphere(n, u0, u1, l[0], l[1], l[2]);
  wave_directions(n, w->wo[0], w->wo[1], w->wo[2], l[0], l[1], l[2], w->ss[0], w->ss[1], w->ss[2],
                  w->ts[0], w->ts[1], w->ts[2], w->nf[0], w->nf[1], w->nf[2], wi[0], wi[1], wi[2],
                  pdf);
  wave_lambert_cos(n, w->wo[0], w->wo[1], w->wo[2], wi[0], wi[1], wi[2], w->ng[0], w->ng[1],
                   w->ng[2], w->ns[0], w->ns[1], w->ns[2], fcos);
}
