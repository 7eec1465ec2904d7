/* What the integrators (ao_integrator.c, direct_integrator.c, path_integrator.c) share inside
 * the renderer: the per-thread scratch, EstimateDirect's jobs, tracing a wave, and small helpers. */
#ifndef CLR_INTEGRATOR_INTERNAL_H
#define CLR_INTEGRATOR_INTERNAL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "grow.h"
#include "integrator.h"
#include "lambert_wave.h"
#include "lambertian.h"
#include "light_wave.h"
#include "pcg32.h"
#include "render_error.h"
#include "render_scene.h"
#include "shape_wave.h"
#include "vec3.h"

#define MAX_NULL_SURFACES 64 /* material "none" surfaces a ray may cross */

enum { SHAPE_NO_RAY = -1, SHAPE_MAY_HIT = -2 }; /* direct_job.shape_entry without a wave entry */

typedef struct direct_job {
  int32_t sample, light;
  float u_light[2], u_scatter[2];
  float scale[3];
  float result[3];
  float bsdf_f[3]; /* f * |cos| / pdf of the BSDF sample (MIS part) */
  float bsdf_pdf;
  int32_t shadow_index, mis_index;
  int32_t lambert_entry; /* the MIS BSDF sample's entry in the scratch's Lambert wave, or -1 */
  int32_t light_entry;   /* the light sample's entry in the scratch's light wave, or -1 */
  int32_t shape_entry;   /* the MIS ray's entry in the scratch's shape wave, or a SHAPE_ code */
  float shadow_contrib[3];
  int32_t continues; /* the path tracer's: its vertex's next direction is the light wave's */
  float u_next[2];   /* and that direction's sample values */
} direct_job;

struct clr_integrator_scratch {
  clr_ray *rays, *rays2;
  const clr_ray_differential *diffs; /* the camera rays' differentials (or NULL), during a call */
  clr_hit *hits;
  uint8_t *occluded;
  clr_surface *surfaces;
  direct_job *jobs;
  int32_t *owner;
  float *beta;
  int32_t *bounces, *active;
  const float **cdfs; /* each path vertex's light cdf (spatial light distribution) */
  size_t *voxels;     /* and its voxel, SIZE_MAX when it samples no light */
  float *ao_terms;    /* AO: 6 arrays of ao_cap: each direction's term, u0, u1 and x, y, z */
  size_t ao_cap;
  clr_lambert_wave lambert; /* a wave's Lambertian BSDF samples, structure of arrays */
  clr_light_wave lights;    /* and its triangle-light samples at Lambertian surfaces */
  clr_light_wave points;    /* and its point-light ones */
  clr_shape_wave shapes;    /* and its MIS rays' triangle-light shape tests */
  /* the light waves' groups: each light's group in this wave (-1: none), each group's light and
   * next entry */
  int32_t *light_group, *group_light, *group_next;
  size_t ray_cap, ray2_cap, job_cap, sample_cap, light_group_cap, group_cap;
};

/* The scene's figures of light `light`. */
static inline clr_light_info light_info(const clr_render_scene *scene, int32_t light) {
  clr_light_info info;
  clr_render_scene_light_info(scene, light, &info);
  return info;
}

/* Non-zero for point, spot and distant lights. */
static inline int light_is_delta(const clr_render_scene *scene, int32_t light) {
  return light_info(scene, light).is_delta;
}

/* Non-zero when the array could not grow. */
static inline int grow(void **p, size_t *cap, size_t need, size_t elem) {
  return clr_grow(p, cap, need, elem, SIZE_MAX) != CLR_SUCCESS;
}

/* Rays (and hits / occlusion flags) for `n` queries. */
static inline clr_result reserve_rays(clr_integrator_scratch *s, size_t n) {
  size_t cap = s->ray_cap, cap2 = s->ray_cap, cap3 = s->ray_cap;
  if (grow((void **)&s->rays, &cap, n, sizeof *s->rays) ||
      grow((void **)&s->hits, &cap2, n, sizeof *s->hits) ||
      grow((void **)&s->occluded, &cap3, n, 1))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
  s->ray_cap = cap;
  return CLR_SUCCESS;
}

/* Monotonic seconds, for the counters' trace time. */
static inline double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Counts a wave of n rays traced since t0, keeping the first error. */
static inline void count_wave(clr_integrator_counters *c, clr_result e, double t0, size_t n) {
  if (e != CLR_SUCCESS && c->error == CLR_SUCCESS) c->error = e;
  c->trace_seconds += now_seconds() - t0;
  c->rays += n;
}

/* Closest hits of rays r[0..n) into h, counted in c. */
static inline void trace(const clr_render_scene *sc, const clr_ray *r, clr_hit *h, size_t n,
                         clr_integrator_counters *c) {
  if (!n) return;
  double t0 = now_seconds();
  count_wave(c, clr_tracer_intersect(clr_render_scene_tracer(sc), r, h, (int32_t)n), t0, n);
}

/* Occlusion flags of shadow rays r[0..n) into o, counted in c. */
static inline void occlude(const clr_render_scene *sc, const clr_ray *r, uint8_t *o, size_t n,
                           clr_integrator_counters *c) {
  if (!n) return;
  double t0 = now_seconds();
  count_wave(c, clr_tracer_occluded(clr_render_scene_tracer(sc), r, o, (int32_t)n), t0, n);
}

/* Value `k` of a per-sample vector, or the documented hash fallback past the layout. */
static inline float fallback(uint64_t key, int dim) {
  return clr_hash_float(key ^ clr_mix64(0x5bd1e995u + (uint64_t)dim));
}

/* pbrt-v3 PowerHeuristic with one sample each: f^2 / (f^2 + g^2). */
static inline float power_heuristic(float f, float g) {
  float f2 = f * f, g2 = g * g;
  return (f2 + g2) > 0.0f ? f2 / (f2 + g2) : 0.0f;
}

/* Non-zero when every component of c is 0. */
static inline int is_black(const float c[3]) {
  return c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f;
}

/* A Lambertian sample's f = Kd f |cos| / Kd at surface sf; 1 when the sample is usable. */
static inline int lambert_value(const clr_surface *sf, float fc, float pdf, float f[3]) {
  for (int k = 0; k < 3; ++k) f[k] = sf->kd[k] * fc;
  return fc > 0.0f && pdf > 0.0f && !is_black(f);
}

/* bsdf_sample's outputs for entry e of a sampled wave at surface sf; 1 when usable. */
static inline int lambert_wave_result(const clr_lambert_wave *lw, int32_t e, const clr_surface *sf,
                                      float wi[3], float *pdf, float f[3]) {
  for (int a = 0; a < 3; ++a) wi[a] = lw->wi[a][e];
  *pdf = lw->pdf[e];
  return lambert_value(sf, lw->fcos[e], *pdf, f);
}

/* Room for n direct lighting jobs. */
static inline clr_result reserve_jobs(clr_integrator_scratch *s, size_t n) {
  if (grow((void **)&s->jobs, &s->job_cap, n, sizeof *s->jobs))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
  return CLR_SUCCESS;
}

/* pbrt Distribution1D::SampleDiscrete over a light cdf (the integrator's when NULL). */
static inline int choose_light(const clr_integrator *it, const float *cdf, float u, float *pdf) {
  if (!cdf) cdf = it->light_cdf;
  /* the last entry in [0, count) with cdf <= u (cdf[0] = 0), halving without branches: a
   * mispredicted branch per halving cost more than the search */
  int lo = 0;
  for (int n = it->light_count; n > 1; n -= n / 2) lo = cdf[lo + n / 2] <= u ? lo + n / 2 : lo;
  while (lo < it->light_count - 1 && cdf[lo + 1] - cdf[lo] <= 0.0f) ++lo;
  *pdf = cdf[lo + 1] - cdf[lo];
  return lo;
}

/* Adds beta times what an escaped ray r sees (infinite lights) to L. */
static inline void add_escaped(const clr_render_scene *sc, const clr_ray *r, const float beta[3],
                               float *L) {
  float le[3];
  clr_render_scene_escaped(sc, r, le);
  for (int k = 0; k < 3; ++k) L[k] += beta[k] * le[k];
}

/* Adds each job's result, times its scale, to its sample's L. */
static inline void add_jobs(const direct_job *jobs, int njobs, float *L) {
  for (int j = 0; j < njobs; ++j)
    for (int k = 0; k < 3; ++k) L[3 * jobs[j].sample + k] += jobs[j].scale[k] * jobs[j].result[k];
}

/* pbrt-v3 SpecularReflection::Sample_f: wi is wo mirrored about the shading normal. */
static inline void mirror_direction(const clr_surface *sf, const float wo[3], float wi[3]) {
  float d = 2.0f * rs_dot(wo, sf->ns);
  for (int a = 0; a < 3; ++a) wi[a] = -wo[a] + d * sf->ns[a];
}

/* First value of a bounce: light choice, light 2D, scattering 2D, BSDF 2D, then Russian
 * roulette's, which pbrt-v3's PathIntegrator draws only past bounce 3 (7 values a bounce until
 * then). */
static inline int32_t path_bounce_offset(const clr_integrator *it, int bounce) {
  return it->value_offset + bounce * (CLR_PATH_VALUES_PER_BOUNCE - 1) +
         (bounce > 4 ? bounce - 4 : 0);
}

/* Room for n samples' records (surfaces, beta, bounces, active, owner, rays2, cdfs, voxels). */
static inline clr_result reserve_samples(clr_integrator_scratch *s, size_t n) {
  if (n <= s->sample_cap) return CLR_SUCCESS;
  size_t c1 = s->sample_cap, c2 = c1, c3 = c1, c4 = c1, c5 = c1, c6 = c1, c7 = c1, c8 = c1;
  if (grow((void **)&s->surfaces, &c1, n, sizeof *s->surfaces) ||
      grow((void **)&s->beta, &c2, n, 3 * sizeof(float)) ||
      grow((void **)&s->bounces, &c3, n, sizeof(int32_t)) ||
      grow((void **)&s->active, &c4, n, sizeof(int32_t)) ||
      grow((void **)&s->owner, &c5, n, sizeof(int32_t)) ||
      grow((void **)&s->rays2, &c6, n, sizeof(clr_ray)) ||
      grow((void **)&s->cdfs, &c7, n, sizeof(const float *)) ||
      grow((void **)&s->voxels, &c8, n, sizeof(size_t)))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
  s->sample_cap = c1;
  s->ray2_cap = c6;
  return CLR_SUCCESS;
}

/* The integrators (the scratch holds count samples and their rays in rays2). */
clr_result clr_li_ao(const clr_integrator *it, const clr_render_scene *sc,
                     clr_integrator_scratch *s, const float *values, int count, float *L,
                     clr_integrator_counters *c);
clr_result clr_li_direct(const clr_integrator *it, const clr_render_scene *sc,
                         clr_integrator_scratch *s, const float *values, const uint64_t *keys,
                         int count, float *L, clr_integrator_counters *c);
clr_result clr_li_path(const clr_integrator *it, const clr_render_scene *sc,
                       clr_integrator_scratch *s, const clr_integrator_values *sv,
                       const uint64_t *keys, int count, float *L, clr_integrator_counters *c);

/* Intersects rays[0..count) (in scratch->rays2) and fills surfaces; hit[i].geom_id says miss.
 * diffs (or NULL): the rays' differentials, lost past a material "none" as in pbrt-v3. geometry:
 * only what AO reads (clr_render_scene_surface_geometry). */
void clr_integrator_intersect_visible(const clr_render_scene *sc, clr_integrator_scratch *s,
                                      int count, const clr_ray_differential *diffs, int geometry,
                                      clr_integrator_counters *c);

/* EstimateDirect (pbrt-v3) for jobs[0..njobs) at the scratch's surfaces seen from wo_all (3
 * floats per sample): each job's result, f Li / pdf with MIS, unscaled. */
clr_result clr_estimate_direct(const clr_integrator *it, const clr_render_scene *sc,
                               clr_integrator_scratch *s, direct_job *jobs, int njobs,
                               const float *wo_all, clr_integrator_counters *c);

#endif
