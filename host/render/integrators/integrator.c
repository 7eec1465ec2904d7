/* The integrators' sample layouts (pbrt-v3's requests in its order), their scratch, and
 * clr_integrator_li's dispatch to AO, direct lighting or path tracing (ao_integrator.c,
 * direct_integrator.c, path_integrator.c). Every sample's contributions are summed in a fixed
 * order, so results do not depend on batching. */
#include <stdio.h>
#include "integrator_internal.h"
#include "light_distribution.h"

/* ---------- request layout ---------- */

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

/* ---------- primary hits (material "none" surfaces are skipped) ---------- */

/* Intersects rays[0..count) (in scratch->rays2) and fills surfaces; hit[i].geom_id says miss.
 * diffs (or NULL): the rays' differentials, lost past a material "none" as in pbrt-v3. geometry:
 * only what AO reads (clr_render_scene_surface_geometry). */
void clr_integrator_intersect_visible(const clr_render_scene *sc, clr_integrator_scratch *s,
                                      int count, const clr_ray_differential *diffs, int geometry,
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
      r = clr_li_ao(it, sc, s, values, count, L, c);
      break;
    case CLR_INTEGRATOR_DIRECT:
      r = clr_li_direct(it, sc, s, values, keys, count, L, c);
      break;
    default:
      r = clr_li_path(it, sc, s, sv, keys, count, L, c);
      break;
  }
  s->diffs = NULL;
  return r != CLR_SUCCESS ? r : c->error;
}
