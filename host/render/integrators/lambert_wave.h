/* Lambertian BSDF sampling across a wave in structure-of-arrays form: the surfaces' frames, the
 * cosine-hemisphere directions and f |cos| in branch-free loops over float arrays (one per
 * component) that GCC vectorises, with exactly the float operations of clr_lambert_sample_dir
 * and clr_lambert_cos_plain (lambertian.h), in the same order: the same bits. */
#ifndef CLR_LAMBERT_WAVE_H
#define CLR_LAMBERT_WAVE_H

#include <math.h>
#include <stdint.h>
#include "lambertian.h"
#include "float_minmax.h"

typedef struct clr_lambert_wave {
  int32_t n, cap;
  int32_t *owner; /* the caller's index of each entry */
  /* inputs: sample values (u0 clamped below 1), wo, and the surface's dpdu, ns, ng, n_geom */
  float *u0, *u1, *wo[3], *dpdu[3], *ns[3], *ng[3], *n_geom[3];
  /* the local direction, and the BSDF frame (ss, ts, nf) */
  float *l[3], *ss[3], *ts[3], *nf[3];
  /* outputs: clr_lambert_sample_dir's wi and pdf, clr_lambert_cos_plain of (wo, wi) */
  float *wi[3], *pdf, *fcos;
  float *block;
} clr_lambert_wave;

/* Room for n entries (n reset to 0). */
clr_result clr_lambert_wave_reserve(clr_lambert_wave *w, int32_t n);
void clr_lambert_wave_free(clr_lambert_wave *w);

/* Appends surface s seen from wo with sample values u; returns the entry's index. */
static inline int32_t clr_lambert_wave_push(clr_lambert_wave *w, const clr_surface *s,
                                            const float wo[3], const float u[2], int32_t owner) {
  int32_t k = w->n++;
  w->owner[k] = owner;
  w->u0[k] = rs_fminf(u[0], CLR_ONE_MINUS_EPSILON);
  w->u1[k] = u[1];
  for (int a = 0; a < 3; ++a) {
    w->wo[a][k] = wo[a];
    w->dpdu[a][k] = s->dpdu[a];
    w->ns[a][k] = s->ns[a];
    w->ng[a][k] = s->ng[a];
    w->n_geom[a][k] = s->n_geom[a];
  }
  return k;
}

/* wi, pdf and fcos of entries 0 .. n. */
void clr_lambert_wave_sample(clr_lambert_wave *w);

/* After clr_lambert_wave_sample: another direction per entry from the same frames, for values
 * u0 (clamped below 1) and u1: wi, pdf and fcos (l: scratch), the bits of a wave of their own. */
void clr_lambert_wave_sample_more(const clr_lambert_wave *w, const float *u0, const float *u1,
                                  float *const l[3], float *const wi[3], float *pdf, float *fcos);

#endif
