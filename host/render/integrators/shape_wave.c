/* Structure-of-arrays shape tests: one loop over the wave's arrays, the scalar test's early
 * returns turned into one mask (every step computed, the divisor kept non-zero where det is 0). */
#include "shape_wave.h"
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

/* rs_light_shape_may_hit on a triangle: Moller-Trumbore in doubles, edges included. */
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
    double d0 = dx[k], d1 = dy[k], d2 = dz[k];
    double e10 = (double)b0[k] - a0[k], e11 = (double)b1[k] - a1[k], e12 = (double)b2[k] - a2[k];
    double e20 = (double)c0[k] - a0[k], e21 = (double)c1[k] - a1[k], e22 = (double)c2[k] - a2[k];
    double s0 = (double)ox[k] - a0[k], s1 = (double)oy[k] - a1[k], s2 = (double)oz[k] - a2[k];
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
    m = t > (double)tnear[k] ? m : 0.0;
    hit[k] = t < (double)tfar[k] ? m : 0.0;
  }
}

void clr_shape_wave_test(clr_shape_wave *w) {
  wave_triangle_hits(w->n, w->o[0], w->o[1], w->o[2], w->d[0], w->d[1], w->d[2], w->tnear, w->tfar,
                     w->v0[0], w->v0[1], w->v0[2], w->v1[0], w->v1[1], w->v1[2], w->v2[0], w->v2[1],
                     w->v2[2], w->hit);
}
