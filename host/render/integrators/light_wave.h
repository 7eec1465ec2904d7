/* EstimateDirect's light sample for Lambertian surfaces and triangle area lights across a wave
 * in structure-of-arrays form: the point on the triangle, wi, Li and the solid-angle pdf
 * (pbrt-v3 Triangle::Sample, DiffuseAreaLight::Sample_Li), the Lambertian f |cos| and pdf, the
 * power heuristic, the contribution and the shadow ray, in branch-free loops GCC vectorises, with
 * exactly the float operations of the scalar code (lights.c sample_li and shadow_to,
 * integrator.c estimate_direct) in the same order: the same bits. */
#ifndef CLR_LIGHT_WAVE_H
#define CLR_LIGHT_WAVE_H

#include <stdint.h>
#include "lambert_wave.h"
#include "lambertian.h"
#include "float_minmax.h"

/* How the light wave samples a light. */
typedef enum {
  CLR_WAVE_LIGHT_NONE,
  CLR_WAVE_LIGHT_TRIANGLE,
  CLR_WAVE_LIGHT_POINT
} clr_wave_light_kind;

/* A wave holds samples of triangle lights, grouped by light (the light's fields are the loops'
 * constants), or of point lights (pbrt-v3 PointLight::Sample_Li: pt the light's position, le its
 * I, no MIS weight), in push order, not both. */
typedef struct clr_light_wave {
  int32_t n, cap, ngroups;
  /* triangle group g: entries group_first[g] .. group_first[g + 1] (n for the last) of one light */
  int32_t *group_first;
  const clr_light_triangle **group_tri;
  /* inputs: sample values, the surface's p, ng, ns, Kd and wo */
  float *u0, *u1, *p[3], *ng[3], *ns[3], *kd[3], *wo[3];
  /* the point on the light, wi, the light's pdf, the Lambertian f |cos| / Kd and pdf */
  float *pt[3], *wi[3], *light_pdf, *fcos, *bsdf_pdf, *dist2;
  float *le[3];   /* point lights: each entry's I */
  int32_t *emits; /* the light sends Li toward the surface */
  /* outputs: whether the sample contributes (then its shadow ray is traced), f Li w / pdf, the
   * shadow ray's origin, direction and tfar */
  int32_t *use;
  float *contrib[3], *origin[3], *dir[3], *tfar;
  /* triangle entries' BSDF samples for MIS (EstimateDirect's second half): a Lambertian wave of
   * their own values (u0 clamped) and the surfaces' dpdu and n_geom that shares this wave's wo,
   * ns and ng; then the sampled ray's origin (clr_render_scene_spawn_ray's) and whether it may
   * hit the group's triangle (clr_shape_wave's test, tnear 0, tfar infinite) */
  clr_lambert_wave bsdf;
  float *mis_origin[3];
  double *mis_hit;
  /* the path tracer's next direction at each surface (its own BSDF sample) from the same frame:
   * values (0 where put got none), wi, pdf, fcos and the spawned ray's origin; with_next: some
   * entry has one */
  int32_t with_next;
  float *next_u0, *next_u1, *next_l[3], *next_wi[3], *next_pdf, *next_fcos, *next_origin[3];
  float *block;
} clr_light_wave;

/* Room for n entries (n reset to 0). */
clr_result clr_light_wave_reserve(clr_light_wave *w, int32_t n);
void clr_light_wave_free(clr_light_wave *w);

/* Adds a group of count entries (count > 0) sampling triangle light t; returns its first
 * entry, to fill with clr_light_wave_put. */
int32_t clr_light_wave_group(clr_light_wave *w, int32_t count, const clr_light_triangle *t);

/* Entry k's shading point: surface s seen from wo. */
static inline void clr_light_wave_put_surface(clr_light_wave *w, int32_t k, const clr_surface *s,
                                              const float wo[3]) {
  for (int a = 0; a < 3; ++a) {
    w->p[a][k] = s->p[a];
    w->ng[a][k] = s->ng[a];
    w->ns[a][k] = s->ns[a];
    w->kd[a][k] = s->kd[a];
    w->wo[a][k] = wo[a];
  }
}

/* Entry k of a triangle group: a sample u of its light from surface s seen from wo, a sample
 * u_bsdf of the surface's BSDF, and u_next (or NULL) of the path's next direction. */
static inline void clr_light_wave_put(clr_light_wave *w, int32_t k, const clr_surface *s,
                                      const float wo[3], const float u[2], const float u_bsdf[2],
                                      const float *u_next) {
  w->u0[k] = u[0];
  w->u1[k] = u[1];
  clr_light_wave_put_surface(w, k, s, wo);
  clr_lambert_wave *b = &w->bsdf;
  b->u0[k] = rs_fminf(u_bsdf[0], CLR_ONE_MINUS_EPSILON);
  b->u1[k] = u_bsdf[1];
  for (int a = 0; a < 3; ++a) {
    b->dpdu[a][k] = s->dpdu[a];
    b->n_geom[a][k] = s->n_geom[a];
  }
  w->with_next |= u_next != NULL;
  w->next_u0[k] = u_next ? rs_fminf(u_next[0], CLR_ONE_MINUS_EPSILON) : 0.0f;
  w->next_u1[k] = u_next ? u_next[1] : 0.0f;
}

/* Appends a sample of point light l from surface s seen from wo; returns its index. */
static inline int32_t clr_light_wave_push_point(clr_light_wave *w, const clr_surface *s,
                                                const float wo[3], const clr_light_point *l) {
  int32_t k = w->n++;
  clr_light_wave_put_surface(w, k, s, wo);
  for (int a = 0; a < 3; ++a) {
    w->pt[a][k] = l->pos[a];
    w->le[a][k] = l->intensity[a];
  }
  return k;
}

/* use, contrib and the shadow rays of entries 0 .. n of triangle lights, group by group; then
 * their BSDF samples (bsdf's wi, pdf and fcos), mis_origin and mis_hit, and with_next the next
 * directions. */
void clr_light_wave_sample(clr_light_wave *w);
/* The same for point lights. */
void clr_light_wave_sample_points(clr_light_wave *w);

#endif
