/* Structure-of-arrays light samples: each step one loop over the wave's arrays, selects instead
 * of branches (lanes a scalar branch would leave early compute on, with divisors kept non-zero,
 * and are dropped by `use`). */
#include "light_wave.h"
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"
#include "shape_wave.h"
#include "wave_block.h"
#include "float_minmax.h"

#define WAVE_FLOATS 40 /* float arrays in clr_light_wave */
#define WAVE_INTS 2    /* and int32_t ones */
#define BSDF_FLOATS 41 /* and float arrays of the BSDF samples (bsdf's own, mis_origin, next) */
#define HIT_COLUMNS 2  /* mis_hit: n doubles */

/* Points the BSDF samples' arrays into the block's columns from `column` on (wo, ns and ng are
 * the light samples'); mis_hit follows them. */
static void bsdf_columns(clr_light_wave *w, float *block, size_t cap, int column) {
  clr_lambert_wave *b = &w->bsdf;
  float **own[BSDF_FLOATS] = {&b->u0,
                              &b->u1,
                              &b->dpdu[0],
                              &b->dpdu[1],
                              &b->dpdu[2],
                              &b->n_geom[0],
                              &b->n_geom[1],
                              &b->n_geom[2],
                              &b->l[0],
                              &b->l[1],
                              &b->l[2],
                              &b->ss[0],
                              &b->ss[1],
                              &b->ss[2],
                              &b->ts[0],
                              &b->ts[1],
                              &b->ts[2],
                              &b->nf[0],
                              &b->nf[1],
                              &b->nf[2],
                              &b->wi[0],
                              &b->wi[1],
                              &b->wi[2],
                              &b->pdf,
                              &b->fcos,
                              &w->mis_origin[0],
                              &w->mis_origin[1],
                              &w->mis_origin[2],
                              &w->next_u0,
                              &w->next_u1,
                              &w->next_l[0],
                              &w->next_l[1],
                              &w->next_l[2],
                              &w->next_wi[0],
                              &w->next_wi[1],
                              &w->next_wi[2],
                              &w->next_pdf,
                              &w->next_fcos,
                              &w->next_origin[0],
                              &w->next_origin[1],
                              &w->next_origin[2]};
  for (int a = 0; a < BSDF_FLOATS; ++a) *own[a] = block + (size_t)(column + a) * cap;
  for (int a = 0; a < 3; ++a) {
    b->wo[a] = w->wo[a];
    b->ns[a] = w->ns[a];
    b->ng[a] = w->ng[a];
  }
  b->owner = NULL;
  b->block = NULL; /* the light wave's */
  b->cap = (int32_t)cap;
  b->n = 0;
  w->mis_hit = (double *)(block + (size_t)(column + BSDF_FLOATS) * cap);
}

clr_result clr_light_wave_reserve(clr_light_wave *w, int32_t n) {
  w->n = w->ngroups = w->with_next = 0;
  if (n <= w->cap) return CLR_SUCCESS;
  size_t cap;
  float *block = clr_wave_block_alloc(n, WAVE_FLOATS + WAVE_INTS + BSDF_FLOATS + HIT_COLUMNS, &cap);
  int32_t *first = block ? malloc(cap * sizeof *first) : NULL;
  const clr_light_triangle **tri = first ? malloc(cap * sizeof *tri) : NULL;
  if (!tri) {
    free(block);
    free(first);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "light wave of %d entries", (int)n);
  }
  clr_light_wave_free(w);
  float **arrays[WAVE_FLOATS] = {
      &w->u0,        &w->u1,        &w->p[0],      &w->p[1],       &w->p[2],       &w->ng[0],
      &w->ng[1],     &w->ng[2],     &w->ns[0],     &w->ns[1],      &w->ns[2],      &w->kd[0],
      &w->kd[1],     &w->kd[2],     &w->wo[0],     &w->wo[1],      &w->wo[2],      &w->pt[0],
      &w->pt[1],     &w->pt[2],     &w->wi[0],     &w->wi[1],      &w->wi[2],      &w->light_pdf,
      &w->fcos,      &w->dist2,     &w->bsdf_pdf,  &w->contrib[0], &w->contrib[1], &w->contrib[2],
      &w->origin[0], &w->origin[1], &w->origin[2], &w->dir[0],     &w->dir[1],     &w->dir[2],
      &w->tfar,      &w->le[0],     &w->le[1],     &w->le[2]};
  for (int a = 0; a < WAVE_FLOATS; ++a) *arrays[a] = block + (size_t)a * cap;
  int32_t *ints = (int32_t *)(block + (size_t)WAVE_FLOATS * cap);
  w->emits = ints;
  w->use = ints + cap;
  bsdf_columns(w, block, cap, WAVE_FLOATS + WAVE_INTS);
  w->block = block;
  w->group_first = first;
  w->group_tri = tri;
  w->cap = (int32_t)cap;
  return CLR_SUCCESS;
}

void clr_light_wave_free(clr_light_wave *w) {
  free(w->block);
  free(w->group_first);
  free(w->group_tri);
  w->block = NULL;
  w->group_first = NULL;
  w->group_tri = NULL;
  w->cap = w->n = w->ngroups = 0;
  memset(&w->bsdf, 0, sizeof w->bsdf);
  w->mis_hit = NULL;
  for (int a = 0; a < 3; ++a) w->mis_origin[a] = w->next_l[a] = w->next_wi[a] = NULL;
  for (int a = 0; a < 3; ++a) w->next_origin[a] = NULL;
  w->next_u0 = w->next_u1 = w->next_pdf = w->next_fcos = NULL;
}

int32_t clr_light_wave_group(clr_light_wave *w, int32_t count, const clr_light_triangle *t) {
  int32_t g = w->ngroups++, first = w->n;
  w->group_first[g] = first;
  w->group_tri[g] = t;
  w->n += count;
  return first;
}

/* lights.c sample_emitter on a triangle: the point of barycentrics from u. */
static void wave_triangle_points(int32_t n, const float *restrict u0, const float *restrict u1,
                                 const float a[3], const float b[3], const float c[3],
                                 float *restrict x, float *restrict y, float *restrict z) {
  const float a0 = a[0], a1 = a[1], a2 = a[2], b0 = b[0], b1 = b[1], b2 = b[2], c0 = c[0],
              c1 = c[1], c2 = c[2];
  for (int32_t k = 0; k < n; ++k) {
    float su0 = sqrtf(u0[k]);
    float w0 = 1.0f - su0, w1 = u1[k] * su0, w2 = 1.0f - w0 - w1;
    x[k] = w0 * a0 + w1 * b0 + w2 * c0;
    y[k] = w0 * a1 + w1 * b1 + w2 * c1;
    z[k] = w0 * a2 + w1 * b2 + w2 * c2;
  }
}

/* lights.c sample_li on an area light: wi toward the point, the solid-angle pdf (0 when the
 * point is p itself, seen edge-on, or the pdf is not finite) and whether it emits toward p. */
static void wave_light_li(int32_t n, const float *restrict t0, const float *restrict t1,
                          const float *restrict t2, const float *restrict p0,
                          const float *restrict p1, const float *restrict p2, const float ln[3],
                          float inv_area, int32_t two_sided, float *restrict w0, float *restrict w1,
                          float *restrict w2, float *restrict pdf, int32_t *restrict emits) {
  const float n0 = ln[0], n1 = ln[1], n2 = ln[2];
  const int32_t both = two_sided != 0;
  for (int32_t k = 0; k < n; ++k) {
    float d0 = t0[k] - p0[k], d1 = t1[k] - p1[k], d2 = t2[k] - p2[k];
    float dd = d0 * d0 + d1 * d1 + d2 * d2;
    int valid = dd > 0.0f;
    float dist = valid ? sqrtf(dd) : 1.0f;
    float x = d0 / dist, y = d1 / dist, z = d2 / dist;
    float c = fabsf(n0 * x + n1 * y + n2 * z);
    float q = inv_area * dd / (c > 0.0f ? c : 1.0f);
    q = c > 0.0f ? q : 0.0f;
    q = fabsf(q) <= FLT_MAX ? q : 0.0f; /* isfinite */
    w0[k] = x;
    w1[k] = y;
    w2[k] = z;
    pdf[k] = valid ? q : 0.0f;
    emits[k] = both | (n0 * -x + n1 * -y + n2 * -z > 0.0f);
  }
}

/* lights.c sample_li on a point light: wi toward it, the squared distance, pdf 1 (0 when p is
 * the light's position). */
static void wave_point_li(int32_t n, const float *restrict t0, const float *restrict t1,
                          const float *restrict t2, const float *restrict p0,
                          const float *restrict p1, const float *restrict p2, float *restrict w0,
                          float *restrict w1, float *restrict w2, float *restrict dist2,
                          float *restrict pdf) {
  for (int32_t k = 0; k < n; ++k) {
    float d0 = t0[k] - p0[k], d1 = t1[k] - p1[k], d2 = t2[k] - p2[k];
    float dd = d0 * d0 + d1 * d1 + d2 * d2;
    float len = sqrtf(dd); /* rs_normalize recomputes dd: the same bits */
    float div = len > 0.0f ? len : 1.0f;
    w0[k] = d0 / div;
    w1[k] = d1 / div;
    w2[k] = d2 / div;
    dist2[k] = dd > 0.0f ? dd : 1.0f;
    pdf[k] = dd > 0.0f ? 1.0f : 0.0f;
  }
}

/* integrator.c bsdf_eval and bsdf_pdf of a Lambertian surface: f |cos| / Kd with the reflect
 * rule, and the pdf of wi. */
static void wave_lambert_eval(int32_t n, const float *restrict o0, const float *restrict o1,
                              const float *restrict o2, const float *restrict w0,
                              const float *restrict w1, const float *restrict w2,
                              const float *restrict g0, const float *restrict g1,
                              const float *restrict g2, const float *restrict m0,
                              const float *restrict m1, const float *restrict m2,
                              float *restrict fcos, float *restrict pdf) {
  for (int32_t k = 0; k < n; ++k) {
    float side = (w0[k] * g0[k] + w1[k] * g1[k] + w2[k] * g2[k]) *
                 (o0[k] * g0[k] + o1[k] * g1[k] + o2[k] * g2[k]);
    float a = o0[k] * m0[k] + o1[k] * m1[k] + o2[k] * m2[k],
          b = w0[k] * m0[k] + w1[k] * m1[k] + w2[k] * m2[k];
    float f = fabsf(b) * RS_INV_PI;
    fcos[k] = side > 0.0f ? f : 0.0f;
    pdf[k] = a * b > 0.0f ? f : 0.0f;
  }
}

/* estimate_direct's light-sampling term: f Li w / pdf with the power heuristic w, used when the
 * light's pdf and Li and the BSDF value are not zero. */
static void wave_contributions(int32_t n, const float *restrict kd0, const float *restrict kd1,
                               const float *restrict kd2, const float le[3],
                               const float *restrict fcos, const float *restrict bsdf_pdf,
                               const float *restrict light_pdf, const int32_t *restrict emits,
                               int32_t *restrict use, float *restrict c0, float *restrict c1,
                               float *restrict c2) {
  const float le0 = le[0], le1 = le[1], le2 = le[2];
  const int32_t lit = (le0 != 0.0f) | (le1 != 0.0f) | (le2 != 0.0f);
  for (int32_t k = 0; k < n; ++k) {
    float fc = fcos[k], lp = light_pdf[k], bp = bsdf_pdf[k];
    float f0 = kd0[k] * fc, f1 = kd1[k] * fc, f2 = kd2[k] * fc;
    int li = (emits[k] != 0) & lit;
    int f = (fc > 0.0f) & ((f0 != 0.0f) | (f1 != 0.0f) | (f2 != 0.0f));
    float l2 = lp * lp, b2 = bp * bp, sum = l2 + b2;
    float w = l2 / (sum > 0.0f ? sum : 1.0f);
    w = sum > 0.0f ? w : 0.0f;
    float div = lp > 0.0f ? lp : 1.0f;
    use[k] = (lp > 0.0f) & li & f;
    c0[k] = f0 * le0 * w / div;
    c1[k] = f1 * le1 * w / div;
    c2[k] = f2 * le2 * w / div;
  }
}

/* estimate_direct's term for a delta light: f Li (weight 1, pdf 1), Li = I / distance^2, used
 * when the pdf, Li and the BSDF value are not zero. */
static void wave_point_contributions(int32_t n, const float *restrict kd0,
                                     const float *restrict kd1, const float *restrict kd2,
                                     const float *restrict i0, const float *restrict i1,
                                     const float *restrict i2, const float *restrict dist2,
                                     const float *restrict fcos, const float *restrict light_pdf,
                                     int32_t *restrict use, float *restrict c0, float *restrict c1,
                                     float *restrict c2) {
  for (int32_t k = 0; k < n; ++k) {
    float fc = fcos[k], lp = light_pdf[k];
    float f0 = kd0[k] * fc, f1 = kd1[k] * fc, f2 = kd2[k] * fc;
    float l0 = i0[k] / dist2[k], l1 = i1[k] / dist2[k], l2 = i2[k] / dist2[k];
    int li = (l0 != 0.0f) | (l1 != 0.0f) | (l2 != 0.0f);
    int f = (fc > 0.0f) & ((f0 != 0.0f) | (f1 != 0.0f) | (f2 != 0.0f));
    use[k] = (lp > 0.0f) & li & f;
    c0[k] = f0 * l0;
    c1[k] = f1 * l1;
    c2[k] = f2 * l2;
  }
}

/* lights.c shadow_to: from p, offset along ng toward the point, to short of the point. */
static void wave_shadow_rays(int32_t n, const float *restrict p0, const float *restrict p1,
                             const float *restrict p2, const float *restrict g0,
                             const float *restrict g1, const float *restrict g2,
                             const float *restrict t0, const float *restrict t1,
                             const float *restrict t2, float *restrict o0, float *restrict o1,
                             float *restrict o2, float *restrict d0, float *restrict d1,
                             float *restrict d2, float *restrict tfar) {
  for (int32_t k = 0; k < n; ++k) {
    float side = g0[k] * (t0[k] - p0[k]) + g1[k] * (t1[k] - p1[k]) + g2[k] * (t2[k] - p2[k]) < 0
                     ? -1.0f
                     : 1.0f;
    float a0 = fabsf(p0[k]), a1 = fabsf(p1[k]), a2 = fabsf(p2[k]);
    float m12 = a1 > a2 ? a1 : a2, m = a0 > m12 ? a0 : m12; /* fmaxf, but for NaNs */
    m12 = a2 != a2 ? a1 : m12;
    m = m12 != m12 ? a0 : m;
    float e = 1e-4f * (1.0f + m) * side;
    float x = p0[k] + g0[k] * e, y = p1[k] + g1[k] * e, z = p2[k] + g2[k] * e;
    float dx = t0[k] - x, dy = t1[k] - y, dz = t2[k] - z;
    float dist = sqrtf(dx * dx + dy * dy + dz * dz);
    o0[k] = x;
    o1[k] = y;
    o2[k] = z;
    d0[k] = dx / dist;
    d1[k] = dy / dist;
    d2[k] = dz / dist;
    tfar[k] = dist * (1.0f - 1e-3f);
  }
}

/* clr_render_scene_spawn_ray's origins for directions w from p: offset along ng to w's side
 * (rs_spawn_eps, its fmaxf's NaN rule kept). */
static void wave_spawn_origins(int32_t n, const float *restrict p0, const float *restrict p1,
                               const float *restrict p2, const float *restrict g0,
                               const float *restrict g1, const float *restrict g2,
                               const float *restrict w0, const float *restrict w1,
                               const float *restrict w2, float *restrict o0, float *restrict o1,
                               float *restrict o2) {
  for (int32_t k = 0; k < n; ++k) {
    float side = g0[k] * w0[k] + g1[k] * w1[k] + g2[k] * w2[k] < 0.0f ? -1.0f : 1.0f;
    float a0 = fabsf(p0[k]), a1 = fabsf(p1[k]), a2 = fabsf(p2[k]);
    float m12 = a1 > a2 ? a1 : a2, m = a0 > m12 ? a0 : m12;
    m12 = a2 != a2 ? a1 : m12;
    m = m12 != m12 ? a0 : m;
    float e = 1e-4f * (1.0f + m) * side;
    o0[k] = p0[k] + g0[k] * e;
    o1[k] = p1[k] + g1[k] * e;
    o2[k] = p2[k] + g2[k] * e;
  }
}

/* The entry after group g's last. */
static int32_t group_end(const clr_light_wave *w, int32_t g) {
  return g + 1 < w->ngroups ? w->group_first[g + 1] : w->n;
}

static void sample_triangle_group(clr_light_wave *w, int32_t a, int32_t n,
                                  const clr_light_triangle *t) {
  wave_triangle_points(n, w->u0 + a, w->u1 + a, t->p0, t->p1, t->p2, w->pt[0] + a, w->pt[1] + a,
                       w->pt[2] + a);
  wave_light_li(n, w->pt[0] + a, w->pt[1] + a, w->pt[2] + a, w->p[0] + a, w->p[1] + a, w->p[2] + a,
                t->n, t->inv_area, t->two_sided, w->wi[0] + a, w->wi[1] + a, w->wi[2] + a,
                w->light_pdf + a, w->emits + a);
  wave_lambert_eval(n, w->wo[0] + a, w->wo[1] + a, w->wo[2] + a, w->wi[0] + a, w->wi[1] + a,
                    w->wi[2] + a, w->ng[0] + a, w->ng[1] + a, w->ng[2] + a, w->ns[0] + a,
                    w->ns[1] + a, w->ns[2] + a, w->fcos + a, w->bsdf_pdf + a);
  wave_contributions(n, w->kd[0] + a, w->kd[1] + a, w->kd[2] + a, t->le, w->fcos + a,
                     w->bsdf_pdf + a, w->light_pdf + a, w->emits + a, w->use + a, w->contrib[0] + a,
                     w->contrib[1] + a, w->contrib[2] + a);
}

/* The BSDF samples' rays (spawned from p along bsdf's wi) and their test against each group's
 * triangle. */
static void sample_bsdf(clr_light_wave *w) {
  clr_lambert_wave *b = &w->bsdf;
  b->n = w->n;
  clr_lambert_wave_sample(b);
  wave_spawn_origins(w->n, w->p[0], w->p[1], w->p[2], w->ng[0], w->ng[1], w->ng[2], b->wi[0],
                     b->wi[1], b->wi[2], w->mis_origin[0], w->mis_origin[1], w->mis_origin[2]);
  for (int32_t g = 0; g < w->ngroups; ++g) {
    int32_t a = w->group_first[g];
    const float *o[3] = {w->mis_origin[0] + a, w->mis_origin[1] + a, w->mis_origin[2] + a};
    const float *d[3] = {b->wi[0] + a, b->wi[1] + a, b->wi[2] + a};
    clr_shape_wave_triangle(group_end(w, g) - a, o, d, w->group_tri[g], w->mis_hit + a);
  }
  if (!w->with_next) return;
  clr_lambert_wave_sample_more(b, w->next_u0, w->next_u1, w->next_l, w->next_wi, w->next_pdf,
                               w->next_fcos);
  wave_spawn_origins(w->n, w->p[0], w->p[1], w->p[2], w->ng[0], w->ng[1], w->ng[2], w->next_wi[0],
                     w->next_wi[1], w->next_wi[2], w->next_origin[0], w->next_origin[1],
                     w->next_origin[2]);
}

void clr_light_wave_sample(clr_light_wave *w) {
  for (int32_t g = 0; g < w->ngroups; ++g) {
    int32_t a = w->group_first[g];
    sample_triangle_group(w, a, group_end(w, g) - a, w->group_tri[g]);
  }
  wave_shadow_rays(w->n, w->p[0], w->p[1], w->p[2], w->ng[0], w->ng[1], w->ng[2], w->pt[0],
                   w->pt[1], w->pt[2], w->origin[0], w->origin[1], w->origin[2], w->dir[0],
                   w->dir[1], w->dir[2], w->tfar);
  sample_bsdf(w);
}

void clr_light_wave_sample_points(clr_light_wave *w) {
  int32_t n = w->n;
  wave_point_li(n, w->pt[0], w->pt[1], w->pt[2], w->p[0], w->p[1], w->p[2], w->wi[0], w->wi[1],
                w->wi[2], w->dist2, w->light_pdf);
  wave_lambert_eval(n, w->wo[0], w->wo[1], w->wo[2], w->wi[0], w->wi[1], w->wi[2], w->ng[0],
                    w->ng[1], w->ng[2], w->ns[0], w->ns[1], w->ns[2], w->fcos, w->bsdf_pdf);
  wave_point_contributions(n, w->kd[0], w->kd[1], w->kd[2], w->le[0], w->le[1], w->le[2], w->dist2,
                           w->fcos, w->light_pdf, w->use, w->contrib[0], w->contrib[1],
                           w->contrib[2]);
  wave_shadow_rays(n, w->p[0], w->p[1], w->p[2], w->ng[0], w->ng[1], w->ng[2], w->pt[0], w->pt[1],
                   w->pt[2], w->origin[0], w->origin[1], w->origin[2], w->dir[0], w->dir[1],
                   w->dir[2], w->tfar);
}
