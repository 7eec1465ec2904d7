/* pbrt-v3 SpatialLightDistribution (lightdistrib.cpp), re-implemented from its definition; the
 * voxel cdfs are published with an atomic compare-and-swap instead of pbrt-v3's hash table. */
#define _DEFAULT_SOURCE /* posix_memalign, madvise */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif
#include "light_distribution.h"
#include "float_minmax.h"

#define POINTS 128
#define MAX_FIXED_LIGHTS 256

/* A light's 128 emitter points (when they do not depend on the voxel), by coordinate. */
typedef struct fixed_points {
  float x[POINTS], y[POINTS], z[POINTS], nx[POINTS], ny[POINTS], nz[POINTS];
  float pdf;
  int two_sided;
  double y_le; /* luminance of what the light sends toward its front */
} fixed_points;

struct clr_light_distribution {
  const clr_render_scene *scene;
  int nlights;
  int n[3];
  float lo[3], hi[3];
  clr_voxel_grid grid;
  float halton[POINTS][5]; /* the 128 Halton points (bases 2, 3, 5, 7, 11) every voxel uses */
  fixed_points **fixed;    /* per light, or NULL (then sampled per voxel) */
  _Atomic(float *) *voxels;
};

static double luminance(const float c[3]) {
  return 0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2];
}

/* The lights' emitter points that every voxel shares (at most MAX_FIXED_LIGHTS lights). */
static clr_result fix_points(clr_light_distribution *d) {
  if (d->nlights > MAX_FIXED_LIGHTS) return CLR_SUCCESS;
  d->fixed = calloc((size_t)d->nlights, sizeof *d->fixed);
  if (!d->fixed) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "light distribution");
  for (int j = 0; j < d->nlights; ++j) {
    fixed_points f;
    for (int s = 0; s < POINTS; ++s) {
      clr_emitter_point e;
      float u[2] = {d->halton[s][3], d->halton[s][4]};
      if (!clr_render_scene_light_emitter_point(d->scene, j, u, &e)) break;
      f.x[s] = e.p[0];
      f.y[s] = e.p[1];
      f.z[s] = e.p[2];
      f.nx[s] = e.n[0];
      f.ny[s] = e.n[1];
      f.nz[s] = e.n[2];
      f.pdf = e.pdf;
      f.two_sided = e.two_sided;
      f.y_le = luminance(e.le);
      if (s + 1 < POINTS) continue;
      d->fixed[j] = malloc(sizeof f);
      if (!d->fixed[j]) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "light distribution");
      *d->fixed[j] = f;
    }
  }
  return CLR_SUCCESS;
}

/* The voxel grid (2 MB for a cube): every path vertex reads a random slot, so a big grid goes on
 * 2 MB-aligned memory that Linux may back with transparent huge pages (one TLB entry). */
static void *alloc_grid(size_t bytes) {
  const size_t huge = (size_t)2 << 20;
  if (bytes < huge / 2) return malloc(bytes);
  void *p = NULL;
  size_t rounded = (bytes + huge - 1) / huge * huge;
  if (posix_memalign(&p, huge, rounded) != 0) return NULL;
#if defined(MADV_HUGEPAGE)
  madvise(p, rounded, MADV_HUGEPAGE); /* a hint: no huge pages is fine */
#endif
  return p;
}

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
    bmax = rs_fmaxf(bmax, diag[i]);
  }
  size_t count = 1;
  for (int i = 0; i < 3; ++i) {
    int v = bmax > 0.0f ? (int)lroundf(diag[i] / bmax * 64.0f) : 1;
    d->n[i] = v < 1 ? 1 : v;
    count *= (size_t)d->n[i];
  }
  d->voxels = count <= SIZE_MAX / sizeof *d->voxels ? alloc_grid(count * sizeof *d->voxels) : NULL;
  if (!d->voxels) {
    free(d);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "light distribution");
  }
  for (size_t i = 0; i < count; ++i) atomic_init(&d->voxels[i], NULL);
  clr_voxel_grid_init(&d->grid, d->lo, d->hi, d->n);
  d->grid.slots = (const void *)d->voxels;
  static const int bases[5] = {2, 3, 5, 7, 11};
  for (unsigned s = 0; s < POINTS; ++s)
    for (int b = 0; b < 5; ++b) d->halton[s][b] = radical_inverse(bases[b], s);
  clr_result r = fix_points(d);
  if (r != CLR_SUCCESS) {
    clr_light_distribution_free(d);
    return r;
  }
  *out = d;
  return CLR_SUCCESS;
}

void clr_light_distribution_free(clr_light_distribution *d) {
  if (!d) return;
  size_t count = (size_t)d->n[0] * (size_t)d->n[1] * (size_t)d->n[2];
  for (size_t i = 0; i < count; ++i) free(atomic_load(&d->voxels[i]));
  for (int j = 0; d->fixed && j < d->nlights; ++j) free(d->fixed[j]);
  free(d->fixed);
  free(d->voxels);
  free(d);
}

/* Sample_Li's pdf toward each fixed emitter point from the voxel's points po (0 where the sample
 * is unusable or the light sends nothing that way), as lights.c computes it, in a loop the
 * compiler can vectorise; then the Li.y / pdf sum in the same order as per-sample calls. */
static double fixed_contrib(const fixed_points *f, const float po[3][POINTS]) {
  float pdf[POINTS];
  for (int s = 0; s < POINTS; ++s) {
    float dx = f->x[s] - po[0][s], dy = f->y[s] - po[1][s], dz = f->z[s] - po[2][s];
    float d2 = dx * dx + dy * dy + dz * dz, dist = sqrtf(d2);
    float cn = f->nx[s] * (dx / dist) + f->ny[s] * (dy / dist) + f->nz[s] * (dz / dist);
    float c = fabsf(cn), p = f->pdf * d2 / c;
    int seen = f->two_sided | (cn < 0.0f); /* the light faces the point */
    pdf[s] = (d2 > 0.0f) & (c > 0.0f) & (p > 0.0f) & (p < INFINITY) & seen ? p : 0.0f;
  }
  double contrib = 0.0;
  for (int s = 0; s < POINTS; ++s)
    if (pdf[s] > 0.0f) contrib += f->y_le / pdf[s];
  return contrib;
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
  float pts[3][POINTS];
  for (int i = 0; i < 3; ++i)
    for (int s = 0; s < POINTS; ++s)
      pts[i][s] = (1.0f - d->halton[s][i]) * p0[i] + d->halton[s][i] * p1[i];
  for (int j = 0; j < n; ++j)
    if (d->fixed && d->fixed[j]) contrib[j] = fixed_contrib(d->fixed[j], pts);
  for (unsigned s = 0; s < POINTS; ++s) {
    const float *h = d->halton[s];
    float po[3] = {pts[0][s], pts[1][s], pts[2][s]}, u[2] = {h[3], h[4]};
    for (int j = 0; j < n; ++j) {
      if (d->fixed && d->fixed[j]) continue;
      clr_light_sample ls;
      clr_render_scene_sample_light_li(d->scene, j, po, u, &ls);
      if (ls.pdf > 0.0f) contrib[j] += luminance(ls.li) / ls.pdf;
    }
  }
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += contrib[j];
  double avg = sum / ((double)POINTS * n), floor_c = avg > 0.0 ? 0.001 * avg : 1.0;
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

void clr_voxel_grid_init(clr_voxel_grid *g, const float lo[3], const float hi[3], const int n[3]) {
  for (int i = 0; i < 4; ++i) {
    g->lo[i] = 0.0f;
    g->extent[i] = g->cells[i] = 1.0f;
    g->last[i] = 0.0f;
  }
  for (int i = 0; i < 3; ++i) {
    g->lo[i] = lo[i];
    g->extent[i] = hi[i] > lo[i] ? hi[i] - lo[i] : 1.0f;
    g->cells[i] = (float)n[i];
    g->last[i] = (float)(n[i] - 1);
  }
  g->n0 = (size_t)n[0];
  g->n1 = (size_t)n[1];
  g->slots = NULL;
}

const clr_voxel_grid *clr_light_distribution_grid(const clr_light_distribution *d) {
  return &d->grid;
}

/* The index in d->voxels of the voxel holding p. */
size_t clr_light_distribution_voxel(const clr_light_distribution *d, const float p[3]) {
  return clr_voxel_grid_index(&d->grid, p);
}

void clr_light_distribution_prefetch(const clr_light_distribution *d, size_t index) {
  clr_voxel_grid_prefetch(&d->grid, index);
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
