/* pbrt-v3's PathIntegrator over a batch of camera samples, in waves: every active path's next ray
 * traced together, its vertices shaded by material, light sampling and Lambertian samples batched
 * at the wave's end. */
#include "integrator_internal.h"
#include "microfacet.h"
#include "light_distribution.h"
#include "surface_bsdf.h"
#include "float_minmax.h"

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

/* pbrt-v3 Russian roulette after bounce 3, on beta * etaScale. Inlined, so that a beta just
 * computed is read from registers: its reload, 8 bytes at once, could not be forwarded from the
 * three 4-byte stores (a store-forwarding stall). */
static inline __attribute__((always_inline)) void path_roulette(const clr_integrator *it,
                                                                const float *bv, uint64_t key,
                                                                int bounces, float eta_scale,
                                                                float b[3], int32_t *active) {
  float m = rs_fmaxf(b[0] * eta_scale, rs_fmaxf(b[1] * eta_scale, b[2] * eta_scale));
  if (m < it->rr_threshold && bounces > 3) {
    float q = rs_fmaxf(0.05f, 1.0f - m);
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
  const float *bv = path_values(pc, i, bounces);
  float *b = s->beta + 3 * i;
  float b0 = b[0] * (f3[0] / pdf), b1 = b[1] * (f3[1] / pdf), b2 = b[2] * (f3[2] / pdf);
  b[0] = b0, b[1] = b1, b[2] = b2;
  path_roulette(pc->it, bv, pc->keys[i], bounces, pc->eta_scale[i], b, &s->active[i]);
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
    float sin2_t = eta * eta * rs_fmaxf(0.0f, 1.0f - cos_o * cos_o);
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
                  : !clr_surface_bsdf_sample(sf, w, u, wi, &pdf, f3)) {
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
  CLR_CHECK(clr_estimate_direct(pc->it, pc->sc, s, s->jobs, pc->njobs, pc->wos, pc->c));
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

clr_result clr_li_path(const clr_integrator *it, const clr_render_scene *sc,
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
