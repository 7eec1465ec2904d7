/* pbrt-v3 Light::Pdf_Li's test of the light's own shape for the MIS (BSDF-sampled) rays of a wave
 * toward triangle lights, in structure-of-arrays form: the double-precision Moller-Trumbore test
 * with closed edges of lights.c rs_light_shape_may_hit, branch-free in one loop GCC vectorises,
 * with exactly its double operations in the same order: the same answers. */
#ifndef CLR_SHAPE_WAVE_H
#define CLR_SHAPE_WAVE_H

#include <stdint.h>
#include "lambertian.h"

typedef struct clr_shape_wave {
  int32_t n, cap;
  /* inputs: the ray (origin, direction, tnear, tfar) and the light's triangle */
  float *o[3], *d[3], *tnear, *tfar, *v0[3], *v1[3], *v2[3];
  double *hit; /* output: 1 where the ray may hit the triangle, else 0 (doubles: GCC 12
                * vectorises no loop mixing float loads, double maths and int stores) */
  float *block;
} clr_shape_wave;

/* Room for n entries (n reset to 0). */
clr_result clr_shape_wave_reserve(clr_shape_wave *w, int32_t n);
void clr_shape_wave_free(clr_shape_wave *w);

/* Appends ray r toward triangle t; returns its index. */
static inline int32_t clr_shape_wave_push(clr_shape_wave *w, const clr_ray *r,
                                          const clr_light_triangle *t) {
  int32_t k = w->n++;
  w->o[0][k] = r->ox;
  w->o[1][k] = r->oy;
  w->o[2][k] = r->oz;
  w->d[0][k] = r->dx;
  w->d[1][k] = r->dy;
  w->d[2][k] = r->dz;
  w->tnear[k] = r->tnear;
  w->tfar[k] = r->tfar;
  for (int a = 0; a < 3; ++a) {
    w->v0[a][k] = t->p0[a];
    w->v1[a][k] = t->p1[a];
    w->v2[a][k] = t->p2[a];
  }
  return k;
}

/* hit of entries 0 .. n. */
void clr_shape_wave_test(clr_shape_wave *w);

/* The same test for n rays (origins o, directions d, tnear 0, tfar infinite: spawned rays)
 * against one triangle, into hit. */
void clr_shape_wave_triangle(int32_t n, const float *const o[3], const float *const d[3],
                             const clr_light_triangle *t, double *hit);

#endif
