/* pbrt-v3 SpatialLightDistribution (lightdistrib.cpp), re-implemented from its definition; the
 * voxel cdfs are published with an atomic compare-and-swap instead of pbrt-v3's hash table. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include "light_distribution.h"

struct clr_light_distribution {
  const clr_render_scene *scene;
  int nlights;
  int n[3];
  float lo[3], hi[3];
  float halton[128][5]; /* the 128 Halton points (bases 2, 3, 5, 7, 11) every voxel uses */
  _Atomic(float *) *voxels;
};

static float radical_inverse(int base, unsigned i) {
  double inv = 1.0 / base, f = inv, r = 0.0;
  for (; i; i /= (unsigned)base, f *= inv) r += (double)(i % (unsigned)base) * f;
  return (float)fmin(r, 0x1.fffffep-1);
}

clr_result clr_light_distribution_create(const clr_render_scene *scene,
                                         clr_light_distribution **out) {
  *out = NULL;
  clr_light_distribution *d = calloc(1, sizeof *d);
  if (!d) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "light distribution");
  d->scene = scene;
  d->nlights = clr_render_scene_light_count(scene);
  clr_render_scene_world_bounds(scene, d->lo, d->hi);
  float diag[3], bmax = 0.0f;
  for (int i = 0; i < 3; ++i) {
    diag[i] = d->hi[i] - d->lo[i];
    bmax = fmaxf(bmax, diag[i]);
  }
  size_t count = 1;
  for (int i = 0; i < 3; ++i) {
    int v = bmax > 0.0f ? (int)lroundf(diag[i] / bmax * 64.0f) : 1;
    d->n[i] = v < 1 ? 1 : v;
    count *= (size_t)d->n[i];
  }
  d->voxels = calloc(count, sizeof *d->voxels);
  if (!d->voxels) {
    free(d);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "light distribution");
  }
  for (size_t i = 0; i < count; ++i) atomic_init(&d->voxels[i], NULL);
  static const int bases[5] = {2, 3, 5, 7, 11};
  for (unsigned s = 0; s < 128; ++s)
    for (int b = 0; b < 5; ++b) d->halton[s][b] = radical_inverse(bases[b], s);
  *out = d;
  return CLR_SUCCESS;
}

void clr_light_distribution_free(clr_light_distribution *d) {
  if (!d) return;
  size_t count = (size_t)d->n[0] * (size_t)d->n[1] * (size_t)d->n[2];
  for (size_t i = 0; i < count; ++i) free(atomic_load(&d->voxels[i]));
  free(d->voxels);
  free(d);
}

/* pbrt-v3 SpatialLightDistribution::ComputeDistribution for the voxel at index v. */
static float *compute(const clr_light_distribution *d, const int v[3]) {
  int n = d->nlights;
  double *contrib = calloc((size_t)n, sizeof *contrib);
  float *cdf = malloc((size_t)(n + 1) * sizeof *cdf);
  if (!contrib || !cdf) {
    free(contrib);
    free(cdf);
    return NULL;
  }
  float p0[3], p1[3];
  for (int i = 0; i < 3; ++i) {
    float t0 = (float)v[i] / (float)d->n[i], t1 = (float)(v[i] + 1) / (float)d->n[i];
    p0[i] = (1.0f - t0) * d->lo[i] + t0 * d->hi[i];
    p1[i] = (1.0f - t1) * d->lo[i] + t1 * d->hi[i];
  }
  for (unsigned s = 0; s < 128; ++s) {
    const float *h = d->halton[s];
    float po[3], u[2] = {h[3], h[4]};
    for (int i = 0; i < 3; ++i) po[i] = (1.0f - h[i]) * p0[i] + h[i] * p1[i];
    for (int j = 0; j < n; ++j) {
      clr_light_sample ls;
      clr_render_scene_sample_light_li(d->scene, j, po, u, &ls);
      if (ls.pdf > 0.0f)
        contrib[j] += (0.212671 * ls.li[0] + 0.715160 * ls.li[1] + 0.072169 * ls.li[2]) / ls.pdf;
    }
  }
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += contrib[j];
  double avg = sum / (128.0 * n), floor_c = avg > 0.0 ? 0.001 * avg : 1.0;
  sum = 0.0;
  for (int j = 0; j < n; ++j) {
    contrib[j] = fmax(contrib[j], floor_c);
    if (!isfinite(contrib[j])) contrib[j] = floor_c;
    sum += contrib[j];
  }
  double acc = 0.0;
  cdf[0] = 0.0f;
  for (int j = 0; j < n; ++j) {
    acc += contrib[j];
    cdf[j + 1] = (float)(acc / sum);
  }
  cdf[n] = 1.0f;
  free(contrib);
  return cdf;
}

/* The index in d->voxels of the voxel holding p. */
size_t clr_light_distribution_voxel(const clr_light_distribution *d, const float p[3]) {
  int v[3];
  for (int i = 0; i < 3; ++i) {
    float o = p[i] - d->lo[i];
    if (d->hi[i] > d->lo[i]) o /= d->hi[i] - d->lo[i];
    float f = o * (float)d->n[i];
    v[i] = !(f > 0.0f) ? 0 : f >= (float)(d->n[i] - 1) ? d->n[i] - 1 : (int)f;
  }
  return ((size_t)v[2] * (size_t)d->n[1] + (size_t)v[1]) * (size_t)d->n[0] + (size_t)v[0];
}

void clr_light_distribution_prefetch(const clr_light_distribution *d, size_t index) {
  __builtin_prefetch(&d->voxels[index]);
}

const float *clr_light_distribution_lookup(clr_light_distribution *d, const float p[3]) {
  return clr_light_distribution_lookup_voxel(d, clr_light_distribution_voxel(d, p));
}

const float *clr_light_distribution_lookup_voxel(clr_light_distribution *d, size_t index) {
  float *cdf = atomic_load_explicit(&d->voxels[index], memory_order_acquire);
  if (cdf) return cdf;
  size_t nx = (size_t)d->n[0], ny = (size_t)d->n[1];
  int v[3] = {(int)(index % nx), (int)(index / nx % ny), (int)(index / nx / ny)};
  float *mine = compute(d, v);
  if (!mine) return NULL;
  float *expected = NULL;
  if (atomic_compare_exchange_strong_explicit(&d->voxels[index], &expected, mine,
                                              memory_order_acq_rel, memory_order_acquire))
    return mine;
  free(mine);
  return expected;
}
