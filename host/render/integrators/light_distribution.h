/* pbrt-v3's SpatialLightDistribution (lightsamplestrategy "spatial", the path tracer's default):
 * the scene bounds cut into up to 64 voxels along the longest axis; each voxel's light choice
 * probabilities are the summed Li.y / pdf of every light sampled from 128 Halton points in the
 * voxel (no visibility), with a floor of 0.001 of the average, computed on first use. */
#ifndef CLR_RENDER_LIGHT_DISTRIBUTION_H
#define CLR_RENDER_LIGHT_DISTRIBUTION_H

#include <stddef.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "clrender/result.h"
#include "render_scene.h"

typedef struct clr_light_distribution clr_light_distribution;

/* The voxel grid's constants for clr_voxel_grid_index, a fourth lane (0) padding each axis array. */
typedef struct clr_voxel_grid {
  _Alignas(16) float lo[4];
  _Alignas(16) float extent[4]; /* hi - lo, or 1 on a flat axis (o / 1 == o: not dividing) */
  _Alignas(16) float cells[4];  /* the voxel counts n */
  _Alignas(16) float last[4];   /* n - 1 */
  size_t n0, n1;
  const void *slots; /* the cdf slots (one pointer per voxel), for prefetches */
} clr_voxel_grid;

void clr_voxel_grid_init(clr_voxel_grid *g, const float lo[3], const float hi[3], const int n[3]);

/* The index of the voxel holding p: f = (p - lo) / (hi - lo) * n per axis, 0 when !(f > 0), n - 1
 * when f >= n - 1, else truncated (pbrt-v3's clamp of the offset, NaN to 0). */
static inline size_t clr_voxel_grid_index_scalar(const clr_voxel_grid *g, const float p[3]) {
  size_t v[3];
  for (int i = 0; i < 3; ++i) {
    float f = (p[i] - g->lo[i]) / g->extent[i] * g->cells[i];
    v[i] = !(f > 0.0f) ? 0 : f >= g->last[i] ? (size_t)g->last[i] : (size_t)f;
  }
  return (v[2] * g->n1 + v[1]) * g->n0 + v[0];
}

/* The same float operations on the three axes at once, the clamp as maxps (a > b ? a : b, NaN
 * to 0) and minps instead of branches: the same index for every p. */
static inline size_t clr_voxel_grid_index(const clr_voxel_grid *g, const float p[3]) {
#if defined(__SSE2__)
  __m128 f = _mm_sub_ps(_mm_setr_ps(p[0], p[1], p[2], 0.0f), _mm_load_ps(g->lo));
  f = _mm_mul_ps(_mm_div_ps(f, _mm_load_ps(g->extent)), _mm_load_ps(g->cells));
  f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), _mm_load_ps(g->last));
  __m128i v = _mm_cvttps_epi32(f);
  size_t v0 = (size_t)_mm_cvtsi128_si32(v), v1 = (size_t)_mm_cvtsi128_si32(_mm_srli_si128(v, 4)),
         v2 = (size_t)_mm_cvtsi128_si32(_mm_srli_si128(v, 8));
  return (v2 * g->n1 + v1) * g->n0 + v0;
#else
  return clr_voxel_grid_index_scalar(g, p);
#endif
}

static inline void clr_voxel_grid_prefetch(const clr_voxel_grid *g, size_t index) {
  __builtin_prefetch((const char *)g->slots + index * sizeof(void *));
}

clr_result clr_light_distribution_create(const clr_render_scene *scene,
                                         clr_light_distribution **out);
void clr_light_distribution_free(clr_light_distribution *d);
/* The cdf (light count + 1 values, 0 to 1) of the voxel holding p; NULL when out of memory
 * (the caller then uses its own). Safe to call from several threads. */
const float *clr_light_distribution_lookup(clr_light_distribution *d, const float p[3]);
/* The same by the voxel's index (clr_light_distribution_voxel of p). */
const float *clr_light_distribution_lookup_voxel(clr_light_distribution *d, size_t index);
size_t clr_light_distribution_voxel(const clr_light_distribution *d, const float p[3]);
/* The grid clr_light_distribution_voxel uses, for the inline index in a caller's loop. */
const clr_voxel_grid *clr_light_distribution_grid(const clr_light_distribution *d);
/* Asks the cache for a voxel's slot ahead of its lookup (the grid is too big to stay cached). */
void clr_light_distribution_prefetch(const clr_light_distribution *d, size_t index);

#endif
