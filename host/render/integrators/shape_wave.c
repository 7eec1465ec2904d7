/* Structure-of-arrays shape tests: one loop over the wave's arrays, the scalar test's early
 * returns turned into one mask (every step computed, the divisor kept non-zero where det is 0). */
#include "shape_wave.h"
#include <math.h>
#include <stdlib.h>
#include "render_error.h"
#include "wave_block.h"

#define WAVE_FLOATS 17 /* float arrays in clr_shape_wave */

clr_result clr_shape_wave_reserve(clr_shape_wave *w, int32_t n) {
  w->n = 0;
  if (n <= w->cap) return CLR_SUCCESS;
  size_t cap;
  float *block = clr_wave_block_alloc(n, WAVE_FLOATS + 2, &cap); /* + hit, doubles */
  if (!block)
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "shape wave of %d entries", (int)n);
  clr_shape_wave_free(w);
  float **arrays[WAVE_FLOATS] = {&w->o[0],  &w->o[1],  &w->o[2],  &w->d[0],  &w->d[1],  &w->d[2],
                                 &w->tnear, &w->tfar,  &w->v0[0], &w->v0[1], &w->v0[2], &w->v1[0],
                                 &w->v1[1], &w->v1[2], &w->v2[0], &w->v2[1], &w->v2[2]};
  for (int a = 0; a < WAVE_FLOATS; ++a) *arrays[a] = block + (size_t)a * cap;
  w->hit = (double *)(block + (size_t)WAVE_FLOATS * cap);
  w->block = block;
  w->cap = (int32_t)cap;
  return CLR_SUCCESS;
}

void clr_shape_wave_free(clr_shape_wave *w) {
  free(w->block);
  w->block = NULL;
  w->cap = w->n = 0;
}

/* rs_light_shape_may_hit on a triangle: Moller-Trumbore in doubles, edges included; 1 or 0 for
 * direction d, the edges e1 = b - a and e2 = c - a and s = origin - a. */
static inline double triangle_mask(double d0, double d1, double d2, double e10, double e11,
                                   double e12, double e20, double e21, double e22, double s0,
                                   double s1, double s2, double tnear, double tfar) {
  double p0 = d1 * e22 - d2 * e21, p1 = d2 * e20 - d0 * e22, p2 = d0 * e21 - d1 * e20;
  double det = e10 * p0 + e11 * p1 + e12 * p2;
  double inv = 1.0 / (det != 0.0 ? det : 1.0);
  double u = (s0 * p0 + s1 * p1 + s2 * p2) * inv;
  double q0 = s1 * e12 - s2 * e11, q1 = s2 * e10 - s0 * e12, q2 = s0 * e11 - s1 * e10;
  double v = (d0 * q0 + d1 * q1 + d2 * q2) * inv;
  double t = (e20 * q0 + e21 * q1 + e22 * q2) * inv;
  double m = det != 0.0 ? 1.0 : 0.0;
  m = u < 0.0 || u > 1.0 ? 0.0 : m;
  m = v < 0.0 || u + v > 1.0 ? 0.0 : m;
  m = t > tnear ? m : 0.0;
  return t < tfar ? m : 0.0;
}

/* Each entry's ray against its own triangle (a, b, c). */
static void wave_triangle_hits(int32_t n, const float *restrict ox, const float *restrict oy,
                               const float *restrict oz, const float *restrict dx,
                               const float *restrict dy, const float *restrict dz,
                               const float *restrict tnear, const float *restrict tfar,
                               const float *restrict a0, const float *restrict a1,
                               const float *restrict a2, const float *restrict b0,
                               const float *restrict b1, const float *restrict b2,
                               const float *restrict c0, const float *restrict c1,
                               const float *restrict c2, double *restrict hit) {
  for (int32_t k = 0; k < n; ++k) {
    double e10 = (double)b0[k] - a0[k], e11 = (double)b1[k] - a1[k], e12 = (double)b2[k] - a2[k];
    double e20 = (double)c0[k] - a0[k], e21 = (double)c1[k] - a1[k], e22 = (double)c2[k] - a2[k];
    double s0 = (double)ox[k] - a0[k], s1 = (double)oy[k] - a1[k], s2 = (double)oz[k] - a2[k];
    hit[k] = triangle_mask(dx[k], dy[k], dz[k], e10, e11, e12, e20, e21, e22, s0, s1, s2, tnear[k],
                           tfar[k]);
  }
}

void clr_shape_wave_triangle(int32_t n, const float *const o[3], const float *const d[3],
                             const clr_light_triangle *t, double *restrict hit) {
  const float *restrict ox = o[0], *restrict oy = o[1], *restrict oz = o[2];
  const float *restrict dx = d[0], *restrict dy = d[1], *restrict dz = d[2];
  const double a0 = t->p0[0], a1 = t->p0[1], a2 = t->p0[2];
  const double e10 = (double)t->p1[0] - a0, e11 = (double)t->p1[1] - a1,
               e12 = (double)t->p1[2] - a2;
  const double e20 = (double)t->p2[0] - a0, e21 = (double)t->p2[1] - a1,
               e22 = (double)t->p2[2] - a2;
  for (int32_t k = 0; k < n; ++k) {
    double s0 = (double)ox[k] - a0, s1 = (double)oy[k] - a1, s2 = (double)oz[k] - a2;
    hit[k] = triangle_mask(dx[k], dy[k], dz[k], e10, e11, e12, e20, e21, e22, s0, s1, s2, 0.0,
                           (double)INFINITY);
  }
}

void clr_shape_wave_test(clr_shape_wave *w) {
  wave_triangle_hits(w->n, w->o[0], w->o[1], w->o[2], w->d[0], w->d[1], w->d[2], w->tnear, w->tfar,
                     w->v0[0], w->v0[1], w->v0[2], w->v1[0], w->v1[1], w->v1[2], w->v2[0], w->v2[1],
                     w->v2[2], w->hit);
}
