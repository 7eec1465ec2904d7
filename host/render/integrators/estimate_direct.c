/* pbrt-v3's EstimateDirect for a batch of jobs: light samples (in light waves where the surface
 * is Lambertian and the light a triangle or a point), shadow rays, and BSDF samples with MIS. */
#include "integrator_internal.h"
#include "surface_bsdf.h"

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

/* Job j's light sample (pbrt-v3 Light::Sample_Li, f, the power heuristic), its shadow ray
 * appended to rays at *nshadow when it contributes; Lambertian surfaces' BSDF samples for MIS
 * pushed to the Lambertian wave (jobs the light waves sampled are only read). */
static void light_sample(const clr_integrator *it, const clr_render_scene *sc,
                         clr_integrator_scratch *s, direct_job *jobs, int j, const float *wo_all,
                         int *nshadow) {
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
      light_wave_result(lv, jb->light_entry, sf->time, &s->rays[*nshadow], jb->shadow_contrib);
      jb->shadow_index = (*nshadow)++;
    }
    return;
  }
  clr_light_sample ls;
  clr_render_scene_sample_light(sc, jb->light, sf->p, sf->ng, jb->u_light, &ls);
  jb->lambert_entry = !ls.is_delta && clr_surface_is_lambertian(sf)
                          ? clr_lambert_wave_push(&s->lambert, sf, wo, jb->u_scatter, j)
                          : -1;
  if (!(ls.pdf > 0.0f) || is_black(ls.li)) return;
  float f3[3];
  if (!clr_surface_bsdf_eval(sf, wo, ls.wi, f3)) return;
  float w = 1.0f;
  if (!ls.is_delta) w = power_heuristic(ls.pdf, clr_surface_bsdf_pdf(sf, wo, ls.wi));
  for (int k = 0; k < 3; ++k) jb->shadow_contrib[k] = f3[k] * ls.li[k] * w / ls.pdf;
  jb->shadow_index = *nshadow;
  ls.shadow.time = sf->time; /* pbrt-v3: spawned rays keep the camera ray's time */
  s->rays[(*nshadow)++] = ls.shadow;
}

/* Job j's BSDF sample for MIS toward a non-delta light (Lambertian surfaces': the light wave's
 * toward triangle lights, else the Lambertian wave's): its f and pdf, and its ray in *cand with
 * the light's shape test pending (the light wave's is done; other triangle lights' go to the
 * shape wave). */
static void bsdf_sample(const clr_integrator *it, const clr_render_scene *sc,
                        clr_integrator_scratch *s, direct_job *jb, const float *wo_all,
                        clr_ray *cand) {
  jb->shape_entry = SHAPE_NO_RAY;
  const clr_surface *sf = &s->surfaces[jb->sample];
  if (jb->light_entry >= 0) {
    if (it->light_wave_kind[jb->light] == CLR_WAVE_LIGHT_TRIANGLE) /* point lights are delta */
      light_wave_bsdf(&s->lights, jb->light_entry, sf, jb, cand);
    return;
  }
  if (light_is_delta(sc, jb->light)) return;
  const float *wo = wo_all + 3 * jb->sample;
  float wi[3], pdf;
  float f3[3];
  if (jb->lambert_entry >= 0) {
    if (!lambert_wave_result(&s->lambert, jb->lambert_entry, sf, wi, &pdf, f3)) return;
  } else if (!clr_surface_bsdf_sample(sf, wo, jb->u_scatter, wi, &pdf, f3)) {
    return;
  }
  for (int k = 0; k < 3; ++k) jb->bsdf_f[k] = f3[k];
  jb->bsdf_pdf = pdf;
  clr_render_scene_spawn_ray(sf, wi, cand);
  /* pbrt-v3 asks the light's shape for the pdf first and traces nothing when it is 0 */
  if (it->light_wave_kind && it->light_wave_kind[jb->light] == CLR_WAVE_LIGHT_TRIANGLE)
    jb->shape_entry = clr_shape_wave_push(&s->shapes, cand, &it->light_triangles[jb->light]);
  else if (clr_render_scene_light_may_hit(sc, jb->light, cand))
    jb->shape_entry = SHAPE_MAY_HIT;
}

/* The MIS term of job jb whose BSDF ray r was traced to h: Le of its light where the ray hits it
 * (or escapes to it, for an infinite light), weighted by the power heuristic. */
static void bsdf_sample_result(const clr_render_scene *sc, const clr_integrator_scratch *s,
                               direct_job *jb, const clr_ray *r, const clr_hit *h) {
  const clr_surface *sf = &s->surfaces[jb->sample];
  float wi[3] = {r->dx, r->dy, r->dz}, le[3] = {0, 0, 0}, light_pdf = 0.0f;
  if (h->geom_id != CLR_TRACER_INVALID_ID) {
    clr_surface hs;
    clr_render_scene_surface(sc, r, h, &hs);
    if (hs.area_light != jb->light) return;
    light_pdf = clr_render_scene_light_pdf(sc, jb->light, sf->p, wi, h->t, hs.n_geom);
    memcpy(le, hs.le, sizeof le);
  } else {
    if (!light_info(sc, jb->light).is_infinite) return;
    light_pdf = clr_render_scene_light_pdf(sc, jb->light, sf->p, wi, 0.0f, NULL);
    clr_render_scene_light_le(sc, jb->light, wi, le);
  }
  if (!(light_pdf > 0.0f)) return;
  float w = power_heuristic(jb->bsdf_pdf, light_pdf);
  for (int k = 0; k < 3; ++k) jb->result[k] += jb->bsdf_f[k] * le[k] * w / jb->bsdf_pdf;
}

clr_result clr_estimate_direct(const clr_integrator *it, const clr_render_scene *sc,
                               clr_integrator_scratch *s, direct_job *jobs, int njobs,
                               const float *wo_all, clr_integrator_counters *c) {
  CLR_CHECK(reserve_rays(s, (size_t)njobs * 2));
  CLR_CHECK(clr_lambert_wave_reserve(&s->lambert, njobs));
  CLR_CHECK(light_wave_jobs(it, s, jobs, njobs, wo_all));
  int nshadow = 0;
  for (int j = 0; j < njobs; ++j) light_sample(it, sc, s, jobs, j, wo_all, &nshadow);
  occlude(sc, s->rays, s->occluded, (size_t)nshadow, c);
  for (int j = 0; j < njobs; ++j)
    if (jobs[j].shadow_index >= 0 && !s->occluded[jobs[j].shadow_index])
      memcpy(jobs[j].result, jobs[j].shadow_contrib, sizeof jobs[j].result);
  clr_lambert_wave_sample(&s->lambert);
  CLR_CHECK(clr_shape_wave_reserve(&s->shapes, njobs));
  clr_ray *cand = s->rays + njobs; /* job j's BSDF ray, until its shape test */
  for (int j = 0; j < njobs; ++j) bsdf_sample(it, sc, s, &jobs[j], wo_all, &cand[j]);
  clr_shape_wave_test(&s->shapes);
  int nmis = 0; /* the rays that may hit their light, in job order, packed into rays[0 .. nmis) */
  for (int j = 0; j < njobs; ++j) {
    direct_job *jb = &jobs[j];
    int32_t e = jb->shape_entry;
    if (e == SHAPE_NO_RAY || (e >= 0 && s->shapes.hit[e] == 0.0)) continue;
    s->rays[nmis] = cand[j];
    jb->mis_index = nmis++;
  }
  trace(sc, s->rays, s->hits, (size_t)nmis, c);
  for (int j = 0; j < njobs; ++j)
    if (jobs[j].mis_index >= 0)
      bsdf_sample_result(sc, s, &jobs[j], &s->rays[jobs[j].mis_index], &s->hits[jobs[j].mis_index]);
  return CLR_SUCCESS;
}
