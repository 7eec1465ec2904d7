/* pbrt-v3 AO, direct lighting and path tracing over batches of camera samples. Every sample's
 * contributions are summed in a fixed order, so results do not depend on batching. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "render_error.h"
#include "grow.h"
#include "hemisphere_wave.h"
#include "integrator.h"
#include "lambert_wave.h"
#include "lambertian.h"
#include "light_wave.h"
#include "shape_wave.h"
#include "light_distribution.h"
#include "microfacet.h"
#include "pcg32.h"
#include "render_scene.h"
#include "specular_differentials.h"
#include "vec3.h"

#define ONE_MINUS_EPSILON 0x1.fffffep-1f
#define MAX_NULL_SURFACES 64

/* ---------- request layout ---------- */

static clr_light_info light_info(const clr_render_scene *scene, int32_t light) {
  clr_light_info info;
  clr_render_scene_light_info(scene, light, &info);
  return info;
}

static int light_is_delta(const clr_render_scene *scene, int32_t light) {
  return light_info(scene, light).is_delta;
}

/* Appends a request; returns the offset of its values, -1 when the layout is full. A skipped
 * one (CLR_SAMPLE_REQUEST_SKIPPED) counts towards the limits but has no values (-1). */
static int add_layout_request(clr_integrator *it, int dims, int array_size, int skipped) {
  int32_t values = dims * (array_size > 0 ? array_size : 1);
  if (it->request_count >= CLR_MAX_REQUESTS ||
      it->layout_values + values > CLR_MAX_VALUES_PER_SAMPLE)
    return -1;
  it->requests[it->request_count].dims = dims | (skipped ? CLR_SAMPLE_REQUEST_SKIPPED : 0);
  it->requests[it->request_count].array_size = array_size;
  it->request_count++;
  it->layout_values += values;
  if (skipped) return -1;
  int offset = it->values_per_sample;
  it->values_per_sample += values;
  return offset;
}

static int add_request(clr_integrator *it, int dims, int array_size) {
  return add_layout_request(it, dims, array_size, 0);
}

static clr_result build_light_cdf(clr_integrator *it, const clr_render_scene *scene, int power) {
  it->light_cdf = calloc((size_t)it->light_count + 1, sizeof *it->light_cdf);
  if (!it->light_cdf) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator");
  double total = 0.0;
  for (int i = 0; i < it->light_count; ++i)
    total += power ? fmax(0.0, light_info(scene, i).power) : 1.0;
  if (!(total > 0.0) || !isfinite(total)) {
    power = 0;
    total = it->light_count;
  }
  double acc = 0.0;
  for (int i = 0; i < it->light_count; ++i) {
    acc += power ? fmax(0.0, light_info(scene, i).power) : 1.0;
    it->light_cdf[i + 1] = (float)(acc / total);
  }
  if (it->light_count) it->light_cdf[it->light_count] = 1.0f;
  return CLR_SUCCESS;
}

/* The lights light_wave.h samples (plain triangles and point lights): their kinds and data. */
static clr_result build_wave_lights(clr_integrator *it, const clr_render_scene *scene) {
  int found = 0;
  for (int j = 0; j < it->light_count && !found; ++j) {
    clr_light_triangle t;
    clr_light_point p;
    found =
        clr_render_scene_light_triangle(scene, j, &t) || clr_render_scene_light_point(scene, j, &p);
  }
  if (!found) return CLR_SUCCESS;
  it->light_wave_kind = calloc((size_t)it->light_count, 1);
  it->light_triangles = calloc((size_t)it->light_count, sizeof *it->light_triangles);
  it->light_points = calloc((size_t)it->light_count, sizeof *it->light_points);
  if (!it->light_wave_kind || !it->light_triangles || !it->light_points)
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator");
  for (int j = 0; j < it->light_count; ++j)
    if (clr_render_scene_light_triangle(scene, j, &it->light_triangles[j]))
      it->light_wave_kind[j] = CLR_WAVE_LIGHT_TRIANGLE;
    else if (clr_render_scene_light_point(scene, j, &it->light_points[j]))
      it->light_wave_kind[j] = CLR_WAVE_LIGHT_POINT;
  return CLR_SUCCESS;
}

clr_result clr_integrator_create(const clr_scene_desc *desc, const clr_render_scene *scene,
                                 clr_warn_fn warn, void *wu, clr_integrator *it) {
  return clr_integrator_create_for(desc, scene, CLR_SAMPLER_RANDOM, warn, wu, it);
}

clr_result clr_integrator_create_for(const clr_scene_desc *desc, const clr_render_scene *scene,
                                     clr_sampler_type sampler, clr_warn_fn warn, void *wu,
                                     clr_integrator *it) {
  return clr_integrator_create_layout(desc, scene, sampler, 0, warn, wu, it);
}

clr_result clr_integrator_create_layout(const clr_scene_desc *desc, const clr_render_scene *scene,
                                        clr_sampler_type sampler, int pbrt_v4_camera,
                                        clr_warn_fn warn, void *wu, clr_integrator *it) {
  memset(it, 0, sizeof *it);
  const clr_param_list *p = &desc->integrator.params;
  const char *type = desc->integrator.type ? desc->integrator.type : "path";
  if (pbrt_v4_camera) add_request(it, 1, 0); /* pbrt-v4's wavelength sample */
  it->camera_offset = it->values_per_sample;
  /* camera: film offset, time, lens; skipped where the scene's rays never read them */
  int reads_time = 1, reads_lens = 1;
  if (scene) clr_render_scene_camera_reads(scene, &reads_time, &reads_lens);
  add_request(it, 2, 0);
  it->time_offset = add_layout_request(it, 1, 0, !reads_time);
  it->lens_offset = add_layout_request(it, 2, 0, !reads_lens);
  it->value_offset = it->values_per_sample;
  it->light_count = clr_render_scene_light_count(scene);
  it->max_depth = clr_params_find_int(p, "maxdepth", 5);
  if (strcmp(type, "ambientocclusion") == 0) {
    it->type = CLR_INTEGRATOR_AO;
    it->ao_samples = clr_params_find_int(p, "nsamples", 64);
    it->ao_cos_sample = clr_params_find_bool(p, "cossample", true);
    if (it->ao_samples < 1) it->ao_samples = 1;
    int rounded = clr_sampler_round_count(sampler, it->ao_samples); /* pbrt-v3's AOIntegrator */
    if (rounded != it->ao_samples && warn) {
      char m[128];
      snprintf(m, sizeof m, "Taking %d samples, not %d as specified", rounded, it->ao_samples);
      warn(wu, m);
    }
    it->ao_samples = rounded;
    if (it->ao_samples > (CLR_MAX_VALUES_PER_SAMPLE - it->layout_values) / 2)
      return clr_set_last_error(CLR_ERROR_SCENE, "%s:%d: ambientocclusion nsamples %d above %d",
                                p->file, p->line, it->ao_samples,
                                (CLR_MAX_VALUES_PER_SAMPLE - it->layout_values) / 2);
    add_request(it, 2, it->ao_samples);
    return CLR_SUCCESS;
  }
  if (strcmp(type, "directlighting") == 0) {
    it->type = CLR_INTEGRATOR_DIRECT;
    const char *strategy = clr_params_find_string(p, "strategy", "all");
    it->direct_all = strcmp(strategy, "one") != 0;
    if (it->direct_all) {
      it->light_samples = calloc((size_t)it->light_count + 1, sizeof(int));
      it->light_offsets = calloc((size_t)it->light_count + 1, sizeof(int));
      if (!it->light_samples || !it->light_offsets)
        return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator");
      for (int j = 0; j < it->light_count; ++j) {
        /* DirectLightingIntegrator::Preprocess: sampler.RoundCount(light->nSamples) */
        it->light_samples[j] = clr_sampler_round_count(sampler, light_info(scene, j).nsamples);
        /* depth-0 arrays only: matte surfaces never recurse */
        it->light_offsets[j] = add_request(it, 2, it->light_samples[j]);
        if (it->light_offsets[j] >= 0 && add_request(it, 2, it->light_samples[j]) < 0) {
          it->request_count--;
          it->values_per_sample -= 2 * it->light_samples[j];
          it->layout_values -= 2 * it->light_samples[j];
          it->light_offsets[j] = -1;
        }
      }
    } else {
      add_request(it, 1, 0);
      add_request(it, 2, 0);
      add_request(it, 2, 0);
    }
    CLR_CHECK(build_wave_lights(it, scene));
    return build_light_cdf(it, scene, 0);
  }
  if (strcmp(type, "path") != 0 && warn) {
    char m[512];
    snprintf(m, sizeof m, "%s:%d: integrator \"%s\" not supported: using \"path\"",
             p->file ? p->file : "?", p->line, type);
    warn(wu, m);
  }
  it->type = CLR_INTEGRATOR_PATH;
  it->rr_threshold = clr_params_find_float(p, "rrthreshold", 1.0f);
  const char *strategy = clr_params_find_string(p, "lightsamplestrategy", "spatial");
  /* bounces 0 .. maxdepth - 1 sample (pbrt-v3 stops at maxdepth before drawing a value) */
  for (int b = 0; b < it->max_depth; ++b) {
    int before = it->request_count;
    int32_t values = it->values_per_sample, layout_values = it->layout_values;
    if (add_request(it, 1, 0) < 0 || add_request(it, 2, 0) < 0 || add_request(it, 2, 0) < 0 ||
        add_request(it, 2, 0) < 0 || (b > 3 && add_request(it, 1, 0) < 0)) {
      it->request_count = before;
      it->values_per_sample = values;
      it->layout_values = layout_values;
      break;
    }
    it->path_bounces_in_layout = b + 1;
  }
  CLR_CHECK(build_wave_lights(it, scene));
  if (strcmp(strategy, "spatial") == 0 && it->light_count > 1)
    CLR_CHECK(clr_light_distribution_create(scene, &it->light_spatial));
  clr_result r = build_light_cdf(it, scene, strcmp(strategy, "uniform") != 0);
  if (r != CLR_SUCCESS) {
    clr_light_distribution_free(it->light_spatial);
    it->light_spatial = NULL;
  }
  return r;
}

void clr_integrator_free(clr_integrator *it) {
  free(it->light_cdf);
  clr_light_distribution_free(it->light_spatial);
  free(it->light_samples);
  free(it->light_offsets);
  free(it->light_wave_kind);
  free(it->light_triangles);
  free(it->light_points);
  memset(it, 0, sizeof *it);
}

/* ---------- scratch ---------- */

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

clr_integrator_scratch *clr_integrator_scratch_create(void) {
  return calloc(1, sizeof(clr_integrator_scratch));
}

void clr_integrator_scratch_free(clr_integrator_scratch *s) {
  if (!s) return;
  free(s->rays);
  free(s->rays2);
  free(s->hits);
  free(s->occluded);
  free(s->surfaces);
  free(s->jobs);
  free(s->owner);
  free(s->ao_terms);
  free(s->beta);
  free(s->bounces);
  free(s->active);
  free(s->cdfs);
  free(s->voxels);
  clr_lambert_wave_free(&s->lambert);
  clr_light_wave_free(&s->lights);
  clr_light_wave_free(&s->points);
  clr_shape_wave_free(&s->shapes);
  free(s->light_group);
  free(s->group_light);
  free(s->group_next);
  free(s);
}

/* Non-zero when the array could not grow. */
static int grow(void **p, size_t *cap, size_t need, size_t elem) {
  return clr_grow(p, cap, need, elem, SIZE_MAX) != CLR_SUCCESS;
}

/* Rays (and hits / occlusion flags) for `n` queries. */
static clr_result reserve_rays(clr_integrator_scratch *s, size_t n) {
  size_t cap = s->ray_cap, cap2 = s->ray_cap, cap3 = s->ray_cap;
  if (grow((void **)&s->rays, &cap, n, sizeof *s->rays) ||
      grow((void **)&s->hits, &cap2, n, sizeof *s->hits) ||
      grow((void **)&s->occluded, &cap3, n, 1))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
  s->ray_cap = cap;
  return CLR_SUCCESS;
}

static clr_result reserve_samples(clr_integrator_scratch *s, size_t n) {
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

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Counts a wave of n rays traced since t0, keeping the first error. */
static void count_wave(clr_integrator_counters *c, clr_result e, double t0, size_t n) {
  if (e != CLR_SUCCESS && c->error == CLR_SUCCESS) c->error = e;
  c->trace_seconds += now_seconds() - t0;
  c->rays += n;
}

static void trace(const clr_render_scene *sc, const clr_ray *r, clr_hit *h, size_t n,
                  clr_integrator_counters *c) {
  if (!n) return;
  double t0 = now_seconds();
  count_wave(c, clr_tracer_intersect(clr_render_scene_tracer(sc), r, h, (int32_t)n), t0, n);
}

static void occlude(const clr_render_scene *sc, const clr_ray *r, uint8_t *o, size_t n,
                    clr_integrator_counters *c) {
  if (!n) return;
  double t0 = now_seconds();
  count_wave(c, clr_tracer_occluded(clr_render_scene_tracer(sc), r, o, (int32_t)n), t0, n);
}

/* ---------- sampling helpers ---------- */

/* Value `k` of a per-sample vector, or the documented hash fallback past the layout. */
static float fallback(uint64_t key, int dim) {
  return clr_hash_float(key ^ clr_mix64(0x5bd1e995u + (uint64_t)dim));
}

static void uniform_hemisphere(const float u[2], float w[3]) {
  float z = u[0], r = sqrtf(fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * RS_PI * u[1];
  w[0] = r * cosf(phi);
  w[1] = r * sinf(phi);
  w[2] = z;
}

/* pbrt-v3 OrenNayar::f / R * pi: A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta), in the
 * shading frame (1 for a Lambertian surface). */
static float oren_nayar_factor(const clr_surface *s, const float wo[3], const float wi[3]) {
  if (s->on_b == 0.0f) return s->on_a;
  float ss[3], ts[3];
  clr_shading_frame(s, ss, ts);
  float o[3] = {rs_dot(wo, ss), rs_dot(wo, ts), rs_dot(wo, s->ns)};
  float i[3] = {rs_dot(wi, ss), rs_dot(wi, ts), rs_dot(wi, s->ns)};
  float sin_o = sqrtf(fmaxf(0.0f, 1.0f - o[2] * o[2])),
        sin_i = sqrtf(fmaxf(0.0f, 1.0f - i[2] * i[2]));
  float max_cos = 0.0f;
  if (sin_i > 1e-4f && sin_o > 1e-4f) {
    float cpi = fminf(1.0f, fmaxf(-1.0f, i[0] / sin_i)),
          spi = fminf(1.0f, fmaxf(-1.0f, i[1] / sin_i));
    float cpo = fminf(1.0f, fmaxf(-1.0f, o[0] / sin_o)),
          spo = fminf(1.0f, fmaxf(-1.0f, o[1] / sin_o));
    max_cos = fmaxf(0.0f, cpi * cpo + spi * spo);
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

/* ---------- material BSDFs (pbrt-v3 BSDF: components summed, pdfs averaged) ---------- */

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
static int bsdf_eval(const clr_surface *s, const float wo[3], const float wi[3], float f[3]) {
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

static float bsdf_pdf(const clr_surface *s, const float wo[3], const float wi[3]) {
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
static int bsdf_sample(const clr_surface *s, const float wo[3], const float u_in[2], float wi[3],
                       float *pdf, float f[3]) {
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
    return bsdf_eval(s, wo, wi, f) && *pdf > 0.0f;
  }
  if (!s->plastic) {
    float fc = lambert_sample(s, wo, u_in, wi, pdf);
    for (int k = 0; k < 3; ++k) f[k] = s->kd[k] * fc;
    return fc > 0.0f && *pdf > 0.0f && !is_black_c(f);
  }
  int d, g, n = plastic_components(s, &d, &g);
  *pdf = 0.0f;
  if (!n) return 0;
  int comp = (int)fminf(floorf(u_in[0] * (float)n), (float)(n - 1));
  float u[2] = {fminf(u_in[0] * (float)n - (float)comp, ONE_MINUS_EPSILON), u_in[1]};
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
  *pdf = bsdf_pdf(s, wo, wi);
  return bsdf_eval(s, wo, wi, f) && *pdf > 0.0f;
}

static float power_heuristic(float f, float g) {
  float f2 = f * f, g2 = g * g;
  return (f2 + g2) > 0.0f ? f2 / (f2 + g2) : 0.0f;
}

static int is_black(const float c[3]) { return c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f; }

/* ---------- primary hits (material "none" surfaces are skipped) ---------- */

/* Intersects rays[0..count) (in scratch->rays2) and fills surfaces; hit[i].geom_id says miss.
 * diffs (or NULL): the rays' differentials, lost past a material "none" as in pbrt-v3. geometry:
 * only what AO reads (clr_render_scene_surface_geometry). */
static void intersect_visible(const clr_render_scene *sc, clr_integrator_scratch *s, int count,
                              const clr_ray_differential *diffs, int geometry,
                              clr_integrator_counters *c) {
  int pending = count;
  for (int i = 0; i < count; ++i) s->owner[i] = i;
  for (int round = 0; pending > 0 && round < MAX_NULL_SURFACES; ++round) {
    for (int k = 0; k < pending; ++k) s->rays[k] = s->rays2[s->owner[k]];
    clr_hit *h = s->hits;
    trace(sc, s->rays, h, (size_t)pending, c);
    int next = 0;
    for (int k = 0; k < pending; ++k) {
      int i = s->owner[k];
      s->surfaces[i].has_material = -1; /* miss marker */
      if (h[k].geom_id == CLR_TRACER_INVALID_ID) continue;
      if (geometry)
        clr_render_scene_surface_geometry(sc, &s->rays[k], &h[k], &s->surfaces[i]);
      else
        clr_render_scene_surface_differential(
            sc, &s->rays[k], round == 0 && diffs ? &diffs[i] : NULL, &h[k], &s->surfaces[i]);
      if (!s->surfaces[i].has_material) {
        float d[3] = {s->rays[k].dx, s->rays[k].dy, s->rays[k].dz};
        clr_render_scene_spawn_ray(&s->surfaces[i], d, &s->rays2[i]);
        s->owner[next++] = i;
      }
    }
    pending = next;
  }
  for (int k = 0; k < pending; ++k) s->surfaces[s->owner[k]].has_material = -1;
}

/* ---------- Lambertian samples of a wave (lambert_wave.h) ---------- */

/* A Lambertian sample's f = Kd f |cos| / Kd at surface sf; 1 when the sample is usable. */
static int lambert_value(const clr_surface *sf, float fc, float pdf, float f[3]) {
  for (int k = 0; k < 3; ++k) f[k] = sf->kd[k] * fc;
  return fc > 0.0f && pdf > 0.0f && !is_black(f);
}

/* bsdf_sample's outputs for entry e of a sampled wave at surface sf; 1 when usable. */
static int lambert_wave_result(const clr_lambert_wave *lw, int32_t e, const clr_surface *sf,
                               float wi[3], float *pdf, float f[3]) {
  for (int a = 0; a < 3; ++a) wi[a] = lw->wi[a][e];
  *pdf = lw->pdf[e];
  return lambert_value(sf, lw->fcos[e], *pdf, f);
}

/* ---------- EstimateDirect for a batch of jobs ---------- */

/* Light sample j's shadow ray and contribution from entry e of the sampled light wave. */
static void light_wave_result(const clr_light_wave *lv, int32_t e, float time, clr_ray *ray,
                              float contrib[3]) {
  ray->ox = lv->origin[0][e];
  ray->oy = lv->origin[1][e];
  ray->oz = lv->origin[2][e];
  ray->tnear = 0.0f;
  ray->dx = lv->dir[0][e];
  ray->dy = lv->dir[1][e];
  ray->dz = lv->dir[2][e];
  ray->tfar = lv->tfar[e];
  ray->time = time;
  for (int k = 0; k < 3; ++k) contrib[k] = lv->contrib[k][e];
}

/* Job jb's BSDF sample from entry e of the sampled light wave (at surface sf): when usable, its f
 * and pdf, and when it may hit the light, its ray in *ray and shape_entry SHAPE_MAY_HIT. */
static void light_wave_bsdf(const clr_light_wave *lv, int32_t e, const clr_surface *sf,
                            direct_job *jb, clr_ray *ray) {
  float wi[3], pdf, f3[3];
  if (!lambert_wave_result(&lv->bsdf, e, sf, wi, &pdf, f3)) return;
  for (int k = 0; k < 3; ++k) jb->bsdf_f[k] = f3[k];
  jb->bsdf_pdf = pdf;
  if (lv->mis_hit[e] == 0.0) return;
  *ray = (clr_ray){lv->mis_origin[0][e],
                   lv->mis_origin[1][e],
                   lv->mis_origin[2][e],
                   0.0f,
                   wi[0],
                   wi[1],
                   wi[2],
                   INFINITY,
                   sf->time};
  jb->shape_entry = SHAPE_MAY_HIT;
}

/* Room for the light waves' groups of njobs jobs among nlights lights. */
static clr_result reserve_groups(clr_integrator_scratch *s, int nlights, int njobs) {
  size_t c0 = s->light_group_cap, c1 = s->group_cap, c2 = c1;
  if (grow((void **)&s->light_group, &c0, (size_t)nlights, sizeof(int32_t)) ||
      grow((void **)&s->group_light, &c1, (size_t)njobs, sizeof(int32_t)) ||
      grow((void **)&s->group_next, &c2, (size_t)njobs, sizeof(int32_t)))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
  for (size_t i = s->light_group_cap; i < c0; ++i) s->light_group[i] = -1;
  s->light_group_cap = c0;
  s->group_cap = c1;
  return CLR_SUCCESS;
}

/* The jobs whose light samples the light waves compute (Lambertian surfaces, plain triangle
 * and point lights), put and sampled; triangle lights' grouped by light (a counting sort: sizes,
 * first entries, entries; light_entry holds -2 - group meanwhile), point lights' in job order. */
static clr_result light_wave_jobs(const clr_integrator *it, clr_integrator_scratch *s,
                                  direct_job *jobs, int njobs, const float *wo_all) {
  clr_light_wave *tris = &s->lights, *points = &s->points;
  CLR_CHECK(clr_light_wave_reserve(tris, njobs));
  CLR_CHECK(clr_light_wave_reserve(points, njobs));
  CLR_CHECK(reserve_groups(s, it->light_count, njobs));
  int32_t ngroups = 0;
  for (int j = 0; j < njobs; ++j) {
    direct_job *jb = &jobs[j];
    const clr_surface *sf = &s->surfaces[jb->sample];
    int kind = it->light_wave_kind && clr_surface_is_lambertian(sf) ? it->light_wave_kind[jb->light]
                                                                    : CLR_WAVE_LIGHT_NONE;
    jb->light_entry = -1;
    if (kind == CLR_WAVE_LIGHT_POINT)
      jb->light_entry = clr_light_wave_push_point(points, sf, wo_all + 3 * jb->sample,
                                                  &it->light_points[jb->light]);
    if (kind != CLR_WAVE_LIGHT_TRIANGLE) continue;
    int32_t g = s->light_group[jb->light];
    if (g < 0) {
      g = s->light_group[jb->light] = ngroups++;
      s->group_light[g] = jb->light;
      s->group_next[g] = 0;
    }
    s->group_next[g]++;
    jb->light_entry = -2 - g;
  }
  for (int32_t g = 0; g < ngroups; ++g) {
    int light = s->group_light[g];
    s->group_next[g] = clr_light_wave_group(tris, s->group_next[g], &it->light_triangles[light]);
    s->light_group[light] = -1;
  }
  for (int j = 0; ngroups && j < njobs; ++j) {
    direct_job *jb = &jobs[j];
    if (jb->light_entry > -2) continue;
    int32_t k = s->group_next[-2 - jb->light_entry]++;
    clr_light_wave_put(tris, k, &s->surfaces[jb->sample], wo_all + 3 * jb->sample, jb->u_light,
                       jb->u_scatter, jb->continues ? jb->u_next : NULL);
    jb->light_entry = k;
  }
  clr_light_wave_sample(tris);
  clr_light_wave_sample_points(points);
  return CLR_SUCCESS;
}

static clr_result estimate_direct(const clr_integrator *it, const clr_render_scene *sc,
                                  clr_integrator_scratch *s, direct_job *jobs, int njobs,
                                  const float *wo_all, clr_integrator_counters *c) {
  CLR_CHECK(reserve_rays(s, (size_t)njobs * 2));
  clr_lambert_wave *lw = &s->lambert;
  CLR_CHECK(clr_lambert_wave_reserve(lw, njobs));
  CLR_CHECK(light_wave_jobs(it, s, jobs, njobs, wo_all));
  int nshadow = 0;
  for (int j = 0; j < njobs; ++j) {
    direct_job *jb = &jobs[j];
    const clr_surface *sf = &s->surfaces[jb->sample];
    const float *wo = wo_all + 3 * jb->sample;
    memset(jb->result, 0, sizeof jb->result);
    jb->shadow_index = -1;
    jb->mis_index = -1;
    if (jb->light_entry >= 0) { /* a triangle light's BSDF sample is the light wave's too */
      int point = it->light_wave_kind[jb->light] == CLR_WAVE_LIGHT_POINT; /* a delta light */
      const clr_light_wave *lv = point ? &s->points : &s->lights;
      jb->lambert_entry = -1;
      if (lv->use[jb->light_entry]) {
        light_wave_result(lv, jb->light_entry, sf->time, &s->rays[nshadow], jb->shadow_contrib);
        jb->shadow_index = nshadow++;
      }
      continue;
    }
    clr_light_sample ls;
    clr_render_scene_sample_light(sc, jb->light, sf->p, sf->ng, jb->u_light, &ls);
    jb->lambert_entry = !ls.is_delta && clr_surface_is_lambertian(sf)
                            ? clr_lambert_wave_push(lw, sf, wo, jb->u_scatter, j)
                            : -1;
    if (ls.pdf > 0.0f && !is_black(ls.li)) {
      float f3[3];
      if (bsdf_eval(sf, wo, ls.wi, f3)) {
        float w = 1.0f;
        if (!ls.is_delta) w = power_heuristic(ls.pdf, bsdf_pdf(sf, wo, ls.wi));
        for (int k = 0; k < 3; ++k) jb->shadow_contrib[k] = f3[k] * ls.li[k] * w / ls.pdf;
        jb->shadow_index = nshadow;
        ls.shadow.time = sf->time; /* pbrt-v3: spawned rays keep the camera ray's time */
        s->rays[nshadow++] = ls.shadow;
      }
    }
  }
  occlude(sc, s->rays, s->occluded, (size_t)nshadow, c);
  for (int j = 0; j < njobs; ++j)
    if (jobs[j].shadow_index >= 0 && !s->occluded[jobs[j].shadow_index])
      memcpy(jobs[j].result, jobs[j].shadow_contrib, sizeof jobs[j].result);
  /* BSDF sampling with MIS, for non-delta lights (Lambertian surfaces': the light wave's toward
   * triangle lights, else the Lambertian wave's); job j's ray waits in cand[j] for its light's
   * shape test (the light wave's done; other triangle lights': the shape wave's) */
  clr_lambert_wave_sample(lw);
  clr_shape_wave *sw = &s->shapes;
  CLR_CHECK(clr_shape_wave_reserve(sw, njobs));
  clr_ray *cand = s->rays + njobs;
  for (int j = 0; j < njobs; ++j) {
    direct_job *jb = &jobs[j];
    jb->shape_entry = SHAPE_NO_RAY;
    const clr_surface *sf = &s->surfaces[jb->sample];
    if (jb->light_entry >= 0) { /* the light wave's BSDF sample, its shape test done */
      if (it->light_wave_kind[jb->light] == CLR_WAVE_LIGHT_TRIANGLE) /* point lights are delta */
        light_wave_bsdf(&s->lights, jb->light_entry, sf, jb, &cand[j]);
      continue;
    }
    if (light_is_delta(sc, jb->light)) continue;
    const float *wo = wo_all + 3 * jb->sample;
    float wi[3], pdf;
    float f3[3];
    if (jb->lambert_entry >= 0) {
      if (!lambert_wave_result(lw, jb->lambert_entry, sf, wi, &pdf, f3)) continue;
    } else if (!bsdf_sample(sf, wo, jb->u_scatter, wi, &pdf, f3)) {
      continue;
    }
    for (int k = 0; k < 3; ++k) jb->bsdf_f[k] = f3[k];
    jb->bsdf_pdf = pdf;
    clr_render_scene_spawn_ray(sf, wi, &cand[j]);
    /* pbrt-v3 asks the light's shape for the pdf first and traces nothing when it is 0 */
    if (it->light_wave_kind && it->light_wave_kind[jb->light] == CLR_WAVE_LIGHT_TRIANGLE)
      jb->shape_entry = clr_shape_wave_push(sw, &cand[j], &it->light_triangles[jb->light]);
    else if (clr_render_scene_light_may_hit(sc, jb->light, &cand[j]))
      jb->shape_entry = SHAPE_MAY_HIT;
  }
  clr_shape_wave_test(sw);
  int nmis = 0; /* the rays that may hit their light, in job order, packed into rays[0 .. nmis) */
  for (int j = 0; j < njobs; ++j) {
    direct_job *jb = &jobs[j];
    int32_t e = jb->shape_entry;
    if (e == SHAPE_NO_RAY || (e >= 0 && sw->hit[e] == 0.0)) continue;
    s->rays[nmis] = cand[j];
    jb->mis_index = nmis++;
  }
  trace(sc, s->rays, s->hits, (size_t)nmis, c);
  for (int j = 0; j < njobs; ++j) {
    direct_job *jb = &jobs[j];
    if (jb->mis_index < 0) continue;
    const clr_ray *r = &s->rays[jb->mis_index];
    const clr_hit *h = &s->hits[jb->mis_index];
    const clr_surface *sf = &s->surfaces[jb->sample];
    float wi[3] = {r->dx, r->dy, r->dz}, le[3] = {0, 0, 0}, light_pdf = 0.0f;
    if (h->geom_id != CLR_TRACER_INVALID_ID) {
      clr_surface hs;
      clr_render_scene_surface(sc, r, h, &hs);
      if (hs.area_light != jb->light) continue;
      light_pdf = clr_render_scene_light_pdf(sc, jb->light, sf->p, wi, h->t, hs.n_geom);
      memcpy(le, hs.le, sizeof le);
    } else {
      if (!light_info(sc, jb->light).is_infinite) continue;
      light_pdf = clr_render_scene_light_pdf(sc, jb->light, sf->p, wi, 0.0f, NULL);
      clr_render_scene_light_le(sc, jb->light, wi, le);
    }
    if (!(light_pdf > 0.0f)) continue;
    float w = power_heuristic(jb->bsdf_pdf, light_pdf);
    for (int k = 0; k < 3; ++k) jb->result[k] += jb->bsdf_f[k] * le[k] * w / jb->bsdf_pdf;
  }
  return CLR_SUCCESS;
}

static clr_result reserve_jobs(clr_integrator_scratch *s, size_t n) {
  if (grow((void **)&s->jobs, &s->job_cap, n, sizeof *s->jobs))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
  return CLR_SUCCESS;
}

/* pbrt Distribution1D::SampleDiscrete over a light cdf (the integrator's when NULL). */
static int choose_light(const clr_integrator *it, const float *cdf, float u, float *pdf) {
  if (!cdf) cdf = it->light_cdf;
  /* the last entry in [0, count) with cdf <= u (cdf[0] = 0), halving without branches: a
   * mispredicted branch per halving cost more than the search */
  int lo = 0;
  for (int n = it->light_count; n > 1; n -= n / 2) lo = cdf[lo + n / 2] <= u ? lo + n / 2 : lo;
  while (lo < it->light_count - 1 && cdf[lo + 1] - cdf[lo] <= 0.0f) ++lo;
  *pdf = cdf[lo + 1] - cdf[lo];
  return lo;
}

/* ---------- integrators ---------- */

static clr_result li_ao(const clr_integrator *it, const clr_render_scene *sc,
                        clr_integrator_scratch *s, const float *values, int count, float *L,
                        clr_integrator_counters *c) {
  intersect_visible(sc, s, count, NULL, 1, c);
  int n = it->ao_samples;
  CLR_CHECK(reserve_rays(s, (size_t)count * (size_t)n));
  /* directions first, with each one's Dot(wi,n)/(pdf n) term, then one occlusion query; the
   * cosine-hemisphere directions of the whole wave in one vector loop */
  size_t total = (size_t)count * (size_t)n;
  if (total > s->ao_cap) {
    float *block = realloc(s->ao_terms, total * 6 * sizeof *block);
    if (!block) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
    s->ao_terms = block;
    s->ao_cap = total;
  }
  float *term = s->ao_terms, *u0 = term + s->ao_cap, *u1 = u0 + s->ao_cap, *dx = u1 + s->ao_cap,
        *dy = dx + s->ao_cap, *dz = dy + s->ao_cap;
  if (it->ao_cos_sample) {
    int32_t m = 0;
    for (int i = 0; i < count; ++i) {
      if (s->surfaces[i].has_material < 0) continue;
      const float *u = values + (size_t)i * (size_t)it->values_per_sample + it->value_offset;
      for (int k = 0; k < n; ++k, ++m) {
        u0[m] = u[2 * k];
        u1[m] = u[2 * k + 1];
      }
    }
    clr_wave_cosine_hemisphere(m, u0, u1, dx, dy, dz);
  }
  size_t q = 0;
  for (int i = 0; i < count; ++i) {
    const clr_surface *sf = &s->surfaces[i];
    if (sf->has_material < 0) continue;
    const float *u = values + (size_t)i * (size_t)it->values_per_sample + it->value_offset;
    float ss[3], ts[3], up[3], down[3];
    memcpy(ss, sf->dpdu, sizeof ss);
    rs_normalize(ss);
    rs_cross(sf->n_geom, ss, ts);
    /* clr_render_scene_spawn_ray's two possible origins, computed once per point */
    float e = 1e-4f * (1.0f + fmaxf(fabsf(sf->p[0]), fmaxf(fabsf(sf->p[1]), fabsf(sf->p[2]))));
    for (int a = 0; a < 3; ++a) {
      up[a] = sf->p[a] + sf->ng[a] * e;
      down[a] = sf->p[a] + sf->ng[a] * -e;
    }
    for (int k = 0; k < n; ++k, ++q) {
      float w[3] = {0.0f, 0.0f, 0.0f}, wi[3];
      if (it->ao_cos_sample) {
        w[0] = dx[q];
        w[1] = dy[q];
        w[2] = dz[q];
      } else {
        uniform_hemisphere(u + 2 * k, w);
      }
      for (int a = 0; a < 3; ++a) wi[a] = ss[a] * w[0] + ts[a] * w[1] + sf->ng[a] * w[2];
      float pdf = it->ao_cos_sample ? fabsf(w[2]) * RS_INV_PI : 1.0f / (2.0f * RS_PI);
      float cos_n = rs_dot(wi, sf->ng);
      term[q] = pdf > 0.0f ? cos_n / (pdf * (float)n) : 0.0f;
      const float *o = cos_n < 0.0f ? down : up;
      clr_ray *r = &s->rays[q];
      r->ox = o[0];
      r->oy = o[1];
      r->oz = o[2];
      r->tnear = 0.0f;
      r->dx = wi[0];
      r->dy = wi[1];
      r->dz = wi[2];
      r->tfar = INFINITY;
      r->time = sf->time;
    }
  }
  occlude(sc, s->rays, s->occluded, q, c);
  q = 0;
  for (int i = 0; i < count; ++i) {
    const clr_surface *sf = &s->surfaces[i];
    L[3 * i] = L[3 * i + 1] = L[3 * i + 2] = 0.0f;
    if (sf->has_material < 0) continue;
    float sum = 0.0f;
    for (int k = 0; k < n; ++k, ++q)
      if (!s->occluded[q]) sum += term[q];
    L[3 * i] = L[3 * i + 1] = L[3 * i + 2] = sum;
  }
  return CLR_SUCCESS;
}

static void add_escaped(const clr_render_scene *sc, const clr_ray *r, const float beta[3],
                        float *L) {
  float le[3];
  clr_render_scene_escaped(sc, r, le);
  for (int k = 0; k < 3; ++k) L[k] += beta[k] * le[k];
}

static void add_jobs(const direct_job *jobs, int njobs, float *L) {
  for (int j = 0; j < njobs; ++j)
    for (int k = 0; k < 3; ++k) L[3 * jobs[j].sample + k] += jobs[j].scale[k] * jobs[j].result[k];
}

/* pbrt-v3 SpecularReflection::Sample_f: wi is wo mirrored about the shading normal. */
static void mirror_direction(const clr_surface *sf, const float wo[3], float wi[3]) {
  float d = 2.0f * rs_dot(wo, sf->ns);
  for (int a = 0; a < 3; ++a) wi[a] = -wo[a] + d * sf->ns[a];
}

/* pbrt-v3 SpecularReflect and SpecularTransmit for a lobe BSDF: each followed when it has such
 * a component, with f |cos| / pdf as the factor (sample values hashed); rd (or NULL): the
 * incoming ray's differentials, propagated into nextd (transmission with BSDF::eta as pbrt-v3's
 * SpecularTransmit). */
static void general_specular(const clr_surface *sf, const float wo[3], uint64_t key, int depth,
                             const clr_ray_differential *rd, clr_ray next[2],
                             clr_ray_differential *nextd, float factor[6], int cont[2]) {
  for (int q = 0; q < 2; ++q) {
    int mask = q ? CLR_BXDF_SPECULAR_TRANSMISSION : CLR_BXDF_SPECULAR_REFLECTION, flags;
    if (!clr_bsdf_count(&sf->bsdf, mask)) continue;
    float u[2] = {fallback(key, 9000 + 16 * depth + 2 * q),
                  fallback(key, 9001 + 16 * depth + 2 * q)};
    float wi[3], pdf, f[3];
    if (!clr_bsdf_sample(&sf->bsdf, wo, u, mask, wi, &pdf, f, &flags)) continue;
    if (rs_dot(wi, sf->ns) == 0.0f) continue;
    for (int a = 0; a < 3; ++a) factor[3 * q + a] = f[a] / pdf;
    clr_render_scene_spawn_ray(sf, wi, &next[q]);
    if (nextd) {
      nextd[q].has = 0;
      float eta = rs_dot(wo, sf->n_geom) > 0.0f ? 1.0f / sf->bsdf.eta : sf->bsdf.eta;
      if (!q) rs_reflect_differential(sf, rd, wo, wi, &nextd[q]);
      if (q) rs_transmit_differential(sf, rd, wo, wi, eta, &nextd[q]);
    }
    cont[q] = 1;
  }
}

/* Direct lighting of the surfaces s->surfaces[0..n) hit by s->rays2[0..n) (n samples mapped to
 * the caller's samples by map) into Lk; mirror surfaces continue into next[] (pbrt-v3
 * SpecularReflect while depth + 1 < maxdepth) with their differentials in nextd when diffs (the
 * rays2' differentials) is not NULL. Light sample values: the layout's depth-0 arrays,
 * hashed values deeper. */
static clr_result direct_wave(const clr_integrator *it, const clr_render_scene *sc,
                              clr_integrator_scratch *s, const float *values, const uint64_t *keys,
                              int n, const int *map, int depth, float *Lk, int *cont, clr_ray *next,
                              const clr_ray_differential *diffs, clr_ray_differential *nextd,
                              float *factor, clr_integrator_counters *c) {
  float *wo = s->beta;
  int nj = 0;
  for (int k = 0; k < n; ++k) {
    const clr_surface *sf = &s->surfaces[k];
    int i = map[k];
    const float *v = values + (size_t)i * (size_t)it->values_per_sample;
    const float one[3] = {1, 1, 1};
    const clr_ray_differential *rd = diffs ? &diffs[k] : NULL;
    Lk[3 * k] = Lk[3 * k + 1] = Lk[3 * k + 2] = 0.0f;
    cont[2 * k] = cont[2 * k + 1] = 0;
    if (sf->has_material < 0) {
      add_escaped(sc, &s->rays2[k], one, Lk + 3 * k);
      continue;
    }
    wo[3 * k] = -s->rays2[k].dx;
    wo[3 * k + 1] = -s->rays2[k].dy;
    wo[3 * k + 2] = -s->rays2[k].dz;
    for (int a = 0; a < 3; ++a) Lk[3 * k + a] += sf->le[a];
    if (sf->glass) { /* pbrt-v3 without multiple lobes: SpecularReflection + SpecularTransmission,
                      * SpecularReflect and SpecularTransmit both followed */
      if (depth + 1 >= it->max_depth) continue;
      const float *w = wo + 3 * k;
      float wi[3], cos_o = rs_dot(w, sf->ns);
      int entering = rs_dot(w, sf->n_geom) > 0.0f;
      float F = clr_fr_dielectric(entering ? cos_o : -cos_o, 1.0f, sf->eta);
      mirror_direction(sf, w, wi);
      for (int a = 0; a < 3; ++a) factor[6 * k + a] = sf->kr[a] * F;
      if (!is_black(factor + 6 * k) && rs_dot(wi, sf->ns) != 0.0f) {
        clr_render_scene_spawn_ray(sf, wi, &next[2 * k]);
        if (nextd) rs_reflect_differential(sf, rd, w, wi, &nextd[2 * k]);
        cont[2 * k] = 1;
      }
      float eta = entering ? 1.0f / sf->eta : sf->eta;
      float sin2_t = eta * eta * fmaxf(0.0f, 1.0f - cos_o * cos_o);
      if (sin2_t < 1.0f) {
        float cos_t = sqrtf(1.0f - sin2_t);
        for (int a = 0; a < 3; ++a) wi[a] = -eta * w[a] + (eta * cos_o - cos_t) * sf->ns[a];
        for (int a = 0; a < 3; ++a) factor[6 * k + 3 + a] = sf->kt[a] * (1.0f - F) * eta * eta;
        if (!is_black(factor + 6 * k + 3)) {
          clr_render_scene_spawn_ray(sf, wi, &next[2 * k + 1]);
          if (nextd) rs_transmit_differential(sf, rd, w, wi, eta, &nextd[2 * k + 1]);
          cont[2 * k + 1] = 1;
        }
      }
      continue;
    }
    if (sf->mirror) { /* no non-specular component: no light sampling */
      if (depth + 1 < it->max_depth && !is_black(sf->kr)) {
        float wi[3];
        mirror_direction(sf, wo + 3 * k, wi);
        if (rs_dot(wi, sf->ns) != 0.0f) {
          clr_render_scene_spawn_ray(sf, wi, &next[2 * k]);
          if (nextd) rs_reflect_differential(sf, rd, wo + 3 * k, wi, &nextd[2 * k]);
          for (int a = 0; a < 3; ++a) factor[6 * k + a] = sf->kr[a]; /* f |cos| / pdf */
          cont[2 * k] = 1;
        }
      }
      continue;
    }
    if (sf->general && depth + 1 < it->max_depth)
      general_specular(sf, wo + 3 * k, keys[i], depth, rd, next + 2 * k,
                       nextd ? nextd + 2 * k : NULL, factor + 6 * k, cont + 2 * k);
    if (!it->light_count) continue;
    if (it->direct_all) {
      int dim = 0;
      for (int j = 0; j < it->light_count; ++j) {
        int ns = it->light_samples[j], off = depth == 0 ? it->light_offsets[j] : -1;
        for (int q = 0; q < ns; ++q) {
          direct_job *jb = &s->jobs[nj++];
          jb->sample = k;
          jb->light = j;
          jb->continues = 0;
          int base = depth == 0 ? 100 : 5000 + 1000 * depth;
          for (int a = 0; a < 2; ++a) {
            jb->u_light[a] = off >= 0 ? v[off + 2 * q + a] : fallback(keys[i], base + dim++);
            jb->u_scatter[a] =
                off >= 0 ? v[off + 2 * ns + 2 * q + a] : fallback(keys[i], base + dim++);
          }
          jb->scale[0] = jb->scale[1] = jb->scale[2] = 1.0f / (float)ns;
        }
      }
    } else {
      float u[5];
      for (int a = 0; a < 5; ++a)
        u[a] = depth == 0 ? v[it->value_offset + a] : fallback(keys[i], 5000 + 1000 * depth + a);
      direct_job *jb = &s->jobs[nj++];
      jb->continues = 0;
      int nl = it->light_count;
      jb->light = (int)fminf(u[0] * (float)nl, (float)(nl - 1));
      jb->sample = k;
      memcpy(jb->u_light, u + 1, 2 * sizeof(float));
      memcpy(jb->u_scatter, u + 3, 2 * sizeof(float));
      jb->scale[0] = jb->scale[1] = jb->scale[2] = (float)nl;
    }
  }
  CLR_CHECK(estimate_direct(it, sc, s, s->jobs, nj, wo, c));
  add_jobs(s->jobs, nj, Lk);
  return CLR_SUCCESS;
}

static clr_result li_direct(const clr_integrator *it, const clr_render_scene *sc,
                            clr_integrator_scratch *s, const float *values, const uint64_t *keys,
                            int count, float *L, clr_integrator_counters *c) {
  size_t per = 0;
  if (it->direct_all)
    for (int j = 0; j < it->light_count; ++j) per += (size_t)it->light_samples[j];
  else
    per = it->light_count ? 1 : 0;
  /* entries: a camera sample's path through mirrors and glass (glass splits one in two) */
  size_t cap = (size_t)(count > 0 ? count : 1);
  float *Lk = NULL, *weight = NULL, *factor = NULL;
  int *map = NULL, *cont = NULL;
  clr_ray *next = NULL;
  /* the entries' differentials and their continuations' (only when the camera rays have them) */
  clr_ray_differential *diffs = NULL, *nextd = NULL;
  const clr_ray_differential *cur = clr_render_scene_uses_differentials(sc) ? s->diffs : NULL;
  clr_result r = CLR_SUCCESS;
  int n = count;
  for (int depth = 0; r == CLR_SUCCESS && n > 0; ++depth) {
    if (depth == 0 || (size_t)n > cap || !Lk) {
      cap = (size_t)n > cap ? (size_t)n : cap;
      float *a = realloc(Lk, cap * 3 * sizeof *a),
            *b = a ? realloc(weight, cap * 3 * sizeof *b) : NULL;
      if (a) Lk = a;
      if (b) weight = b;
      float *f = b ? realloc(factor, cap * 6 * sizeof *f) : NULL;
      if (f) factor = f;
      int *m1 = f ? realloc(map, cap * sizeof *m1) : NULL;
      if (m1) map = m1;
      int *c1 = m1 ? realloc(cont, cap * 2 * sizeof *c1) : NULL;
      if (c1) cont = c1;
      clr_ray *nx = c1 ? realloc(next, cap * 2 * sizeof *nx) : NULL;
      if (nx) next = nx;
      clr_ray_differential *nd = nx && cur ? realloc(nextd, cap * 2 * sizeof *nd) : NULL;
      if (nd) nextd = nd;
      if (!nx || (cur && !nd)) {
        r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "direct lighting integrator");
        break;
      }
    }
    if (depth == 0)
      for (int i = 0; i < count; ++i) { /* s->rays2[0..count) holds the camera rays */
        map[i] = i;
        L[3 * i] = L[3 * i + 1] = L[3 * i + 2] = 0.0f;
        weight[3 * i] = weight[3 * i + 1] = weight[3 * i + 2] = 1.0f;
      }
    r = reserve_samples(s, (size_t)n);
    if (r == CLR_SUCCESS) r = reserve_rays(s, (size_t)n);
    if (r == CLR_SUCCESS) r = reserve_jobs(s, (size_t)n * per + 1);
    if (r != CLR_SUCCESS) break;
    intersect_visible(sc, s, n, cur, 0, c);
    r = direct_wave(it, sc, s, values, keys, n, map, depth, Lk, cont, next, cur, cur ? nextd : NULL,
                    factor, c);
    if (r != CLR_SUCCESS) break;
    int m = 0;
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < 3; ++a) L[3 * map[k] + a] += weight[3 * k + a] * Lk[3 * k + a];
    for (int k = 0; k < n; ++k) m += cont[2 * k] + cont[2 * k + 1];
    if (m == 0) break;
    r = reserve_samples(s, (size_t)m);
    float *nw = r == CLR_SUCCESS ? malloc((size_t)m * 3 * sizeof *nw) : NULL;
    int *nm = nw ? malloc((size_t)m * sizeof *nm) : NULL;
    clr_ray_differential *ndf = nm && cur ? malloc((size_t)m * sizeof *ndf) : NULL;
    if (!nm || (cur && !ndf)) {
      free(nw);
      free(nm);
      if (r == CLR_SUCCESS)
        r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "direct lighting integrator");
      break;
    }
    int at = 0;
    for (int k = 0; k < n; ++k)
      for (int q = 0; q < 2; ++q) {
        if (!cont[2 * k + q]) continue;
        const float *f = factor + 6 * k + 3 * q;
        s->rays2[at] = next[2 * k + q];
        if (ndf) ndf[at] = nextd[2 * k + q];
        for (int a = 0; a < 3; ++a) nw[3 * at + a] = weight[3 * k + a] * f[a];
        nm[at++] = map[k];
      }
    free(weight);
    free(map);
    weight = nw;
    map = nm;
    free(diffs);
    diffs = ndf;
    cur = ndf;
    if ((size_t)m > cap) { /* the other per-entry arrays are grown at the top of the loop */
      float *a = realloc(Lk, (size_t)m * 3 * sizeof *a);
      if (!a) {
        r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "direct lighting integrator");
        break;
      }
      Lk = a;
    }
    n = m;
  }
  free(Lk);
  free(weight);
  free(factor);
  free(map);
  free(cont);
  free(next);
  free(diffs);
  free(nextd);
  return r;
}

/* First value of a bounce: light choice, light 2D, scattering 2D, BSDF 2D, then Russian
 * roulette's, which pbrt-v3's PathIntegrator draws only past bounce 3 (7 values a bounce until
 * then). */
static int32_t path_bounce_offset(const clr_integrator *it, int bounce) {
  return it->value_offset + bounce * (CLR_PATH_VALUES_PER_BOUNCE - 1) +
         (bounce > 4 ? bounce - 4 : 0);
}

static int32_t path_bounce_values(int bounce) {
  return CLR_PATH_VALUES_PER_BOUNCE - (bounce > 3 ? 0 : 1);
}

clr_integrator_values clr_integrator_values_whole(const clr_integrator *it, const float *values) {
  clr_integrator_values v = {values, it->values_per_sample, it->path_bounces_in_layout, NULL, NULL};
  return v;
}

int32_t clr_integrator_path_prefix(const clr_integrator *it, int32_t bounces, int32_t *values) {
  *values = 0;
  if (it->type != CLR_INTEGRATOR_PATH) return 0;
  if (bounces > it->path_bounces_in_layout) bounces = it->path_bounces_in_layout;
  if (bounces < 0) bounces = 0;
  int32_t requests = it->request_count - (it->path_bounces_in_layout - bounces) * 4;
  for (int b = bounces; b < it->path_bounces_in_layout; ++b) requests -= b > 3;
  *values = path_bounce_offset(it, bounces);
  return requests;
}

/* The values of bounce `bounce` of sample i: in its vector, fetched into deep, or NULL past the
 * layout (hashed values). */
static const float *path_bounce(const clr_integrator *it, const clr_integrator_values *sv,
                                const float *deep, int i, int bounce) {
  if (bounce >= it->path_bounces_in_layout) return NULL;
  if (bounce < sv->path_bounces)
    return sv->values + (size_t)i * (size_t)sv->stride + path_bounce_offset(it, bounce);
  return deep + (size_t)i * CLR_PATH_VALUES_PER_BOUNCE;
}

/* Value k of a bounce (bv: path_bounce's). */
static float path_value(const float *bv, uint64_t key, int bounce, int k) {
  if (bv) return bv[k];
  return fallback(key, 1000 + bounce * CLR_PATH_VALUES_PER_BOUNCE + k);
}

/* pbrt-v3 Russian roulette after bounce 3, on beta * etaScale. */
static void path_roulette(const clr_integrator *it, const float *bv, uint64_t key, int bounces,
                          float eta_scale, float b[3], int32_t *active) {
  float m = fmaxf(b[0] * eta_scale, fmaxf(b[1] * eta_scale, b[2] * eta_scale));
  if (m < it->rr_threshold && bounces > 3) {
    float q = fmaxf(0.05f, 1.0f - m);
    if (path_value(bv, key, bounces, 7) < q) {
      *active = 0;
    } else {
      for (int a = 0; a < 3; ++a) b[a] /= 1.0f - q;
    }
  }
}

/* Whether the path tracer samples a light at this vertex (pbrt-v3: not past maxdepth, not at
 * specular-only surfaces). */
static int path_samples_light(const clr_integrator *it, const clr_surface *sf, int bounces) {
  return it->light_count && sf->has_material && bounces < it->max_depth && !sf->glass &&
         !sf->mirror && (!sf->general || clr_bsdf_count(&sf->bsdf, CLR_BXDF_NON_SPECULAR) > 0);
}

/* Surfaces of a wave's hits, then the light cdfs of the vertices that sample a light: the voxel
 * grid and the cdfs miss the cache, so their loads are issued ahead of the shading loop. */
static void path_surfaces(const clr_integrator *it, const clr_render_scene *sc,
                          clr_integrator_scratch *s, const int *idx, int n, int wave) {
  clr_light_distribution *d = it->light_spatial;
  const clr_voxel_grid *grid = d ? clr_light_distribution_grid(d) : NULL;
  for (int k = 0; k < n; ++k) {
    int i = idx[k];
    s->cdfs[i] = NULL;
    s->voxels[i] = SIZE_MAX;
    if (s->hits[k].geom_id == CLR_TRACER_INVALID_ID) continue;
    const clr_ray_differential *rd = wave == 0 && s->diffs ? &s->diffs[i] : NULL;
    clr_render_scene_surface_differential(sc, &s->rays[k], rd, &s->hits[k], &s->surfaces[i]);
    if (d && path_samples_light(it, &s->surfaces[i], s->bounces[i])) {
      s->voxels[i] = clr_voxel_grid_index(grid, s->surfaces[i].p);
      clr_voxel_grid_prefetch(grid, s->voxels[i]);
    }
  }
  if (!d) return;
  for (int k = 0; k < n; ++k) {
    int i = idx[k];
    if (s->voxels[i] == SIZE_MAX) continue;
    s->cdfs[i] = clr_light_distribution_lookup_voxel(d, s->voxels[i]);
    if (s->cdfs[i]) __builtin_prefetch(s->cdfs[i]);
  }
}

/* The nv values of one vertex's bounce: fixed-size copies for the two counts
 * path_bounce_values gives (inlined, not a libc call per vertex). */
static void copy_bounce_values(float *to, const float *from, int32_t nv) {
  if (nv == CLR_PATH_VALUES_PER_BOUNCE)
    memcpy(to, from, CLR_PATH_VALUES_PER_BOUNCE * sizeof *to);
  else if (nv == CLR_PATH_VALUES_PER_BOUNCE - 1)
    memcpy(to, from, (CLR_PATH_VALUES_PER_BOUNCE - 1) * sizeof *to);
  else
    memcpy(to, from, (size_t)nv * sizeof *to);
}

/* The values of the wave's vertices that sample (material surfaces below maxdepth) at bounces
 * past those the vectors hold, into deep (CLR_PATH_VALUES_PER_BOUNCE per sample); picked and
 * got: scratch of 2 * count entries and count * CLR_PATH_VALUES_PER_BOUNCE floats. One pass
 * picks them (a wave's vertices mostly share one bounce), then one fetch per bounce. */
static clr_result fetch_deep_values(const clr_integrator *it, const clr_integrator_values *sv,
                                    const clr_integrator_scratch *s, const int *idx, int n,
                                    int32_t *picked, float *got, float *deep) {
  int32_t first = sv->path_bounces, last = it->path_bounces_in_layout, m = 0, lo = last, hi = -1;
  for (int k = 0; k < n; ++k) {
    int i = idx[k], b = s->bounces[i];
    if (b < first || b >= last || s->hits[k].geom_id == CLR_TRACER_INVALID_ID ||
        !s->surfaces[i].has_material)
      continue;
    picked[m++] = i;
    lo = b < lo ? b : lo;
    hi = b > hi ? b : hi;
  }
  int32_t *one = picked + n; /* one bounce's, when the wave holds several */
  for (int bounce = lo; bounce <= hi; ++bounce) {
    const int32_t *list = picked;
    int32_t mb = m;
    if (lo != hi) {
      mb = 0;
      for (int32_t j = 0; j < m; ++j)
        if (s->bounces[picked[j]] == bounce) one[mb++] = picked[j];
      list = one;
    }
    if (!mb) continue;
    int32_t nv = path_bounce_values(bounce);
    CLR_CHECK(sv->fetch(sv->fetch_user, list, mb, path_bounce_offset(it, bounce), nv, got));
    for (int32_t j = 0; j < mb; ++j)
      copy_bounce_values(deep + (size_t)list[j] * CLR_PATH_VALUES_PER_BOUNCE,
                         got + (size_t)j * (size_t)nv, nv);
  }
  return CLR_SUCCESS;
}

/* A path leaving vertex `bounces` goes on (its next ray is traced) unless that ray cannot change
 * L: at maxdepth pbrt-v3 only adds what a specular bounce sees, so after a non-specular one the
 * ray is dropped untraced (the same L, fewer rays). */
static void path_next_vertex(const clr_integrator *it, clr_integrator_scratch *s, int i,
                             int bounces, int specular) {
  s->bounces[i] = bounces + 1;
  if (bounces + 1 >= it->max_depth && !specular) s->active[i] = 0;
}

/* One li_path call: its inputs, and its per-sample state besides the scratch's (beta, bounces,
 * active, rays2, surfaces). */
typedef struct path_call {
  const clr_integrator *it;
  const clr_render_scene *sc;
  clr_integrator_scratch *s;
  const clr_integrator_values *sv;
  const uint64_t *keys;
  float *L;
  clr_integrator_counters *c;
  int count;
  float *wos;       /* each sample's wo at its vertex */
  int *idx;         /* the wave's samples */
  int *specular;    /* the last bounce was specular (pbrt-v3 specularBounce) */
  float *eta_scale; /* pbrt-v3 etaScale */
  int lazy;         /* the vectors hold a prefix: deeper bounces' values are fetched into deep */
  size_t deep_floats;
  float *deep;     /* then deep_floats floats of the fetch's output */
  int32_t *picked; /* fetch_deep_values' scratch */
  int nulls;       /* interfaces crossed, all samples together */
  int njobs;       /* the wave's light sampling jobs (scratch jobs) */
} path_call;

/* The values of bounce `bounces` of sample i (path_bounce's). */
static const float *path_values(const path_call *pc, int i, int bounces) {
  return path_bounce(pc->it, pc->sv, pc->deep, i, bounces);
}

/* The rest of li_path's bounce at a Lambertian vertex i whose sample (f |cos|, pdf) is usable and
 * whose next ray is set: pbrt-v3's beta *= f |cos| / pdf, Russian roulette, the next vertex. */
static void path_lambert_bounce(const path_call *pc, int i, int bounces, const float f3[3],
                                float pdf) {
  clr_integrator_scratch *s = pc->s;
  float *b = s->beta + 3 * i;
  for (int a = 0; a < 3; ++a) b[a] *= f3[a] / pdf;
  path_roulette(pc->it, path_values(pc, i, bounces), pc->keys[i], bounces, pc->eta_scale[i], b,
                &s->active[i]);
  path_next_vertex(pc->it, s, i, bounces, 0);
}

/* The Lambertian vertices of a wave, pushed by path_shade: their BSDF samples in
 * structure-of-arrays form, then the rest of li_path's bounce for each (pbrt-v3: beta *= f |cos|
 * / pdf, the next ray, Russian roulette). */
static void path_lambert_wave(const path_call *pc) {
  clr_integrator_scratch *s = pc->s;
  clr_lambert_wave *lw = &s->lambert;
  clr_lambert_wave_sample(lw);
  for (int32_t e = 0; e < lw->n; ++e) {
    int i = lw->owner[e];
    const clr_surface *sf = &s->surfaces[i];
    float wi[3], pdf, f3[3];
    if (!lambert_wave_result(lw, e, sf, wi, &pdf, f3)) {
      s->active[i] = 0;
      continue;
    }
    clr_render_scene_spawn_ray(sf, wi, &s->rays2[i]);
    path_lambert_bounce(pc, i, s->bounces[i], f3, pdf);
  }
}

/* The rest of li_path's bounce (as path_lambert_wave) for the vertices whose next direction the
 * light wave sampled with their light sample (the wave's jobs that continue). */
static void path_light_wave_next(const path_call *pc) {
  clr_integrator_scratch *s = pc->s;
  const clr_light_wave *lv = &s->lights;
  for (int j = 0; j < pc->njobs; ++j) {
    const direct_job *jb = &s->jobs[j];
    if (!jb->continues) continue;
    int i = jb->sample;
    int32_t e = jb->light_entry;
    const clr_surface *sf = &s->surfaces[i];
    float pdf = lv->next_pdf[e], f3[3];
    if (!lambert_value(sf, lv->next_fcos[e], pdf, f3)) {
      s->active[i] = 0;
      continue;
    }
    s->rays2[i] = (clr_ray){lv->next_origin[0][e],
                            lv->next_origin[1][e],
                            lv->next_origin[2][e],
                            0.0f,
                            lv->next_wi[0][e],
                            lv->next_wi[1][e],
                            lv->next_wi[2][e],
                            INFINITY,
                            sf->time};
    path_lambert_bounce(pc, i, s->bounces[i], f3, pdf);
  }
}

/* The bounce's end for a sample i whose next ray is set and beta updated: Russian roulette and
 * the next vertex. */
static void path_continue(const path_call *pc, int i, int bounces, const float *bv, int specular) {
  clr_integrator_scratch *s = pc->s;
  path_roulette(pc->it, bv, pc->keys[i], bounces, pc->eta_scale[i], s->beta + 3 * i, &s->active[i]);
  path_next_vertex(pc->it, s, i, bounces, specular);
}

/* A glass vertex: pbrt-v3 FresnelSpecular::Sample_f, reflection or refraction by the Fresnel
 * term. */
static void path_glass(const path_call *pc, int i, int bounces, const float *bv,
                       const clr_surface *sf, const float w[3]) {
  clr_integrator_scratch *s = pc->s;
  float *b = s->beta + 3 * i;
  float wi[3], cos_o = rs_dot(w, sf->ns);
  int entering = rs_dot(w, sf->n_geom) > 0.0f;
  float F = clr_fr_dielectric(entering ? cos_o : -cos_o, 1.0f, sf->eta);
  if (path_value(bv, pc->keys[i], bounces, 5) < F) {
    mirror_direction(sf, w, wi);
    for (int a = 0; a < 3; ++a) b[a] *= sf->kr[a]; /* Kr F / F */
  } else {
    float eta = entering ? 1.0f / sf->eta : sf->eta; /* eta_i / eta_t */
    float sin2_t = eta * eta * fmaxf(0.0f, 1.0f - cos_o * cos_o);
    if (sin2_t >= 1.0f) {
      s->active[i] = 0;
      return;
    }
    float cos_t = sqrtf(1.0f - sin2_t);
    for (int a = 0; a < 3; ++a) wi[a] = -eta * w[a] + (eta * cos_o - cos_t) * sf->ns[a];
    for (int a = 0; a < 3; ++a) b[a] *= sf->kt[a] * eta * eta; /* T (1-F) (eta_i/eta_t)^2 / (1-F) */
    pc->eta_scale[i] *= entering ? sf->eta * sf->eta : 1.0f / (sf->eta * sf->eta);
  }
  if (is_black(b)) {
    s->active[i] = 0;
    return;
  }
  clr_render_scene_spawn_ray(sf, wi, &s->rays2[i]);
  path_continue(pc, i, bounces, bv, 1);
}

/* A mirror vertex: pbrt-v3 samples no light there; beta *= Kr (f |cos| / pdf). */
static void path_mirror(const path_call *pc, int i, int bounces, const float *bv,
                        const clr_surface *sf, const float w[3]) {
  clr_integrator_scratch *s = pc->s;
  float *b = s->beta + 3 * i;
  float wi[3];
  mirror_direction(sf, w, wi);
  if (is_black(sf->kr) || rs_dot(wi, sf->ns) == 0.0f) {
    s->active[i] = 0;
    return;
  }
  for (int a = 0; a < 3; ++a) b[a] *= sf->kr[a];
  clr_render_scene_spawn_ray(sf, wi, &s->rays2[i]);
  path_continue(pc, i, bounces, bv, 1);
}

/* pbrt-v3's UniformSampleOneLight at vertex i: a job for estimate_direct when the chosen light's
 * pdf is not 0 (else NULL). */
static direct_job *path_light_job(path_call *pc, int i, int bounces, const float *bv) {
  const clr_integrator *it = pc->it;
  clr_integrator_scratch *s = pc->s;
  if (!path_samples_light(it, &s->surfaces[i], bounces)) return NULL;
  uint64_t key = pc->keys[i];
  float lpdf;
  int light = choose_light(it, s->cdfs[i], path_value(bv, key, bounces, 0), &lpdf);
  if (!(lpdf > 0.0f)) return NULL;
  direct_job *jb = &s->jobs[pc->njobs++];
  jb->sample = i;
  jb->light = light;
  jb->continues = 0;
  for (int a = 0; a < 2; ++a) {
    jb->u_light[a] = path_value(bv, key, bounces, 1 + a);
    jb->u_scatter[a] = path_value(bv, key, bounces, 3 + a);
  }
  const float *b = s->beta + 3 * i;
  for (int a = 0; a < 3; ++a) jb->scale[a] = b[a] / lpdf;
  return jb;
}

/* A Lambertian vertex's next direction from values u: sampled in its light sample's frame when
 * the light wave samples its job (path_light_wave_next), else with the wave's others
 * (path_lambert_wave). */
static void path_lambert(const path_call *pc, direct_job *jb, int i, const clr_surface *sf,
                         const float w[3], const float u[2]) {
  const clr_integrator *it = pc->it;
  if (jb && it->light_wave_kind && it->light_wave_kind[jb->light] == CLR_WAVE_LIGHT_TRIANGLE) {
    jb->continues = 1;
    memcpy(jb->u_next, u, 2 * sizeof *u);
  } else {
    clr_lambert_wave_push(&pc->s->lambert, sf, w, u, i);
  }
}

/* Any other material: its BSDF's sample from values u (pbrt-v3 BSDF::Sample_f), etaScale after a
 * specular transmission. */
static void path_bsdf(const path_call *pc, int i, int bounces, const float *bv,
                      const clr_surface *sf, const float w[3], const float u[2]) {
  clr_integrator_scratch *s = pc->s;
  float wi[3], pdf, f3[3];
  int flags = 0;
  if (sf->general ? !clr_bsdf_sample(&sf->bsdf, w, u, CLR_BXDF_ALL, wi, &pdf, f3, &flags)
                  : !bsdf_sample(sf, w, u, wi, &pdf, f3)) {
    s->active[i] = 0;
    return;
  }
  int specular = pc->specular[i] = (flags & CLR_BSDF_SPECULAR) != 0;
  if (specular && (flags & CLR_BSDF_TRANSMISSION)) { /* pbrt-v3 etaScale */
    float e2 = sf->bsdf.eta * sf->bsdf.eta;
    pc->eta_scale[i] *= rs_dot(w, sf->n_geom) > 0.0f ? e2 : 1.0f / e2;
  }
  float *b = s->beta + 3 * i;
  for (int a = 0; a < 3; ++a) b[a] *= f3[a] / pdf;
  clr_render_scene_spawn_ray(sf, wi, &s->rays2[i]);
  path_continue(pc, i, bounces, bv, specular);
}

/* An interface (material "none"): pbrt-v3 adds its emission first, then the ray goes on. */
static void path_interface(path_call *pc, int i, int seen, const clr_ray *ray,
                           const clr_surface *sf) {
  clr_integrator_scratch *s = pc->s;
  const float *b = s->beta + 3 * i;
  float *Li = pc->L + 3 * i;
  if (seen)
    for (int a = 0; a < 3; ++a) Li[a] += b[a] * sf->le[a];
  float d[3] = {ray->dx, ray->dy, ray->dz};
  clr_render_scene_spawn_ray(sf, d, &s->rays2[i]);
  if (++pc->nulls > MAX_NULL_SURFACES * pc->count) s->active[i] = 0;
}

/* pbrt-v3 PathIntegrator::Li's loop body for the wave's k-th sample: its hit's emission, then
 * the bounce by material (light sampling jobs and Lambertian samples wait for the wave's end). */
static void path_shade(path_call *pc, int k) {
  const clr_integrator *it = pc->it;
  clr_integrator_scratch *s = pc->s;
  int i = pc->idx[k];
  const float *b = s->beta + 3 * i;
  float *Li = pc->L + 3 * i;
  const clr_ray *ray = &s->rays[k];
  int bounces = s->bounces[i];
  int seen = bounces == 0 || pc->specular[i]; /* pbrt-v3: emission counted here, else by MIS */
  if (s->hits[k].geom_id == CLR_TRACER_INVALID_ID) {
    if (seen) add_escaped(pc->sc, ray, b, Li);
    s->active[i] = 0;
    return;
  }
  const clr_surface *sf = &s->surfaces[i];
  if (!sf->has_material) {
    path_interface(pc, i, seen, ray, sf);
    return;
  }
  if (seen)
    for (int a = 0; a < 3; ++a) Li[a] += b[a] * sf->le[a];
  if (bounces >= it->max_depth) {
    s->active[i] = 0;
    return;
  }
  pc->c->bounce_vertices[bounces < CLR_COUNTED_BOUNCES ? bounces : CLR_COUNTED_BOUNCES - 1]++;
  const float *bv = path_values(pc, i, bounces);
  float *w = pc->wos + 3 * i;
  w[0] = -ray->dx;
  w[1] = -ray->dy;
  w[2] = -ray->dz;
  pc->specular[i] = sf->mirror || sf->glass;
  if (sf->glass) {
    path_glass(pc, i, bounces, bv, sf, w);
    return;
  }
  if (sf->mirror) {
    path_mirror(pc, i, bounces, bv, sf, w);
    return;
  }
  direct_job *jb = path_light_job(pc, i, bounces, bv);
  uint64_t key = pc->keys[i];
  float u[2] = {path_value(bv, key, bounces, 5), path_value(bv, key, bounces, 6)};
  if (clr_surface_is_lambertian(sf))
    path_lambert(pc, jb, i, sf, w, u);
  else
    path_bsdf(pc, i, bounces, bv, sf, w, u);
}

/* One wave of li_path: the active samples' rays traced and their vertices shaded, then the
 * wave's Lambertian samples and light sampling jobs. */
static clr_result path_wave(path_call *pc, int wave) {
  clr_integrator_scratch *s = pc->s;
  int n = 0;
  for (int i = 0; i < pc->count; ++i)
    if (s->active[i]) pc->idx[n++] = i;
  CLR_CHECK(reserve_rays(s, (size_t)n));
  for (int k = 0; k < n; ++k) s->rays[k] = s->rays2[pc->idx[k]];
  trace(pc->sc, s->rays, s->hits, (size_t)n, pc->c);
  path_surfaces(pc->it, pc->sc, s, pc->idx, n, wave);
  if (pc->lazy)
    CLR_CHECK(fetch_deep_values(pc->it, pc->sv, s, pc->idx, n, pc->picked,
                                pc->deep + pc->deep_floats, pc->deep));
  CLR_CHECK(clr_lambert_wave_reserve(&s->lambert, n));
  pc->njobs = 0;
  for (int k = 0; k < n; ++k) path_shade(pc, k);
  path_lambert_wave(pc);
  if (!pc->njobs) return CLR_SUCCESS;
  CLR_CHECK(estimate_direct(pc->it, pc->sc, s, s->jobs, pc->njobs, pc->wos, pc->c));
  add_jobs(s->jobs, pc->njobs, pc->L);
  path_light_wave_next(pc);
  return CLR_SUCCESS;
}

/* Frees li_path's per-call buffers. */
static void free_path_buffers(path_call *pc) {
  free(pc->wos);
  free(pc->idx);
  free(pc->specular);
  free(pc->eta_scale);
  free(pc->deep);
  free(pc->picked);
}

/* li_path's per-call buffers for count samples. */
static clr_result alloc_path_buffers(path_call *pc, int count) {
  size_t one = (size_t)(count > 0 ? count : 1);
  pc->wos = malloc(one * 3 * sizeof(float));
  pc->idx = malloc(one * sizeof(int));
  pc->specular = calloc(one, sizeof(int));
  pc->eta_scale = malloc(one * sizeof(float));
  pc->deep_floats = pc->lazy ? one * CLR_PATH_VALUES_PER_BOUNCE : 1;
  pc->deep = malloc(2 * pc->deep_floats * sizeof(float));
  pc->picked = malloc(2 * one * sizeof(int32_t));
  if (pc->wos && pc->idx && pc->specular && pc->eta_scale && pc->deep && pc->picked)
    return CLR_SUCCESS;
  free_path_buffers(pc);
  return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "path integrator");
}

static clr_result li_path(const clr_integrator *it, const clr_render_scene *sc,
                          clr_integrator_scratch *s, const clr_integrator_values *sv,
                          const uint64_t *keys, int count, float *L, clr_integrator_counters *c) {
  CLR_CHECK(reserve_jobs(s, (size_t)count + 1));
  path_call pc = {
      .it = it, .sc = sc, .s = s, .sv = sv, .keys = keys, .L = L, .c = c, .count = count};
  pc.lazy = sv->path_bounces < it->path_bounces_in_layout;
  CLR_CHECK(alloc_path_buffers(&pc, count));
  c->samples += (uint64_t)count;
  for (int i = 0; i < count; ++i) {
    pc.eta_scale[i] = 1.0f;
    s->beta[3 * i] = s->beta[3 * i + 1] = s->beta[3 * i + 2] = 1.0f;
    L[3 * i] = L[3 * i + 1] = L[3 * i + 2] = 0.0f;
    s->bounces[i] = 0;
    s->active[i] = 1;
  }
  clr_result r = CLR_SUCCESS;
  int nactive = count;
  for (int wave = 0; nactive > 0 && r == CLR_SUCCESS; ++wave) {
    r = path_wave(&pc, wave);
    nactive = 0;
    for (int i = 0; i < count; ++i) nactive += s->active[i];
  }
  free_path_buffers(&pc);
  return r;
}

clr_result clr_integrator_li(const clr_integrator *it, const clr_render_scene *sc,
                             clr_integrator_scratch *s, const clr_ray *rays,
                             const clr_ray_differential *diffs, const clr_integrator_values *sv,
                             const uint64_t *keys, int count, float *L,
                             clr_integrator_counters *c) {
  if (sv->stride != it->values_per_sample &&
      (it->type != CLR_INTEGRATOR_PATH || !sv->fetch ||
       sv->stride != path_bounce_offset(it, sv->path_bounces)))
    return clr_set_last_error(CLR_ERROR_INTERNAL, "integrator: %d of %d values per sample",
                              (int)sv->stride, (int)it->values_per_sample);
  const float *values = sv->values;
  CLR_CHECK(reserve_samples(s, (size_t)count));
  CLR_CHECK(reserve_rays(s, (size_t)count));
  memcpy(s->rays2, rays, (size_t)count * sizeof *rays);
  s->diffs = diffs;
  clr_result r;
  switch (it->type) {
    case CLR_INTEGRATOR_AO:
      r = li_ao(it, sc, s, values, count, L, c);
      break;
    case CLR_INTEGRATOR_DIRECT:
      r = li_direct(it, sc, s, values, keys, count, L, c);
      break;
    default:
      r = li_path(it, sc, s, sv, keys, count, L, c);
      break;
  }
  s->diffs = NULL;
  return r != CLR_SUCCESS ? r : c->error;
}
