/* Separable tile accumulation: samples checked four at a time (film_screen.h), factors per axis
 * once per sample, a box filter's by comparison. The loops are flattened (clr_film_prepare
 * inlined), so the film's parameters and their conversions stay in registers for the batch. */
#include "film_tile_add.h"
#include "film_funcs.h"
#include "film_screen.h"

void clr_tile_adder_init(clr_tile_adder *a, const clr_film_params *params,
                         const clr_filter_params *filter, const float *factors) {
  a->params = *params;
  a->filter = *filter;
  a->factors = factors;
  a->box = filter->type == CLR_FILTER_TYPE_BOX;
  for (int i = 0; a->box && filter->use_table && i < 2 * CLR_FILTER_TABLE_SIZE; ++i)
    a->box = factors[i] == 1.0f;
}

/* clr_film_prepare of one sample; counts it. */
static int prepare(const clr_tile_adder *a, const clr_film_sample *in, clr_film_prepared *s,
                   clr_tile_counts *counts) {
  clr_i32 status =
      clr_film_prepare(&a->params, &a->filter, in->x, in->y, in->r, in->g, in->b, in->weight, s);
  if (status == CLR_FILM_SAMPLE_OK) {
    ++counts->accepted;
    return 1;
  }
  counts->dropped += status == CLR_FILM_SAMPLE_DROPPED;
  counts->outside += status == CLR_FILM_SAMPLE_OUTSIDE;
  return 0;
}

/* The sample's footprint clipped to bounds; 0 when empty. */
static int clip_footprint(const clr_film_prepared *s, clr_bounds2i b, clr_bounds2i *out) {
  out->x0 = s->x0 > b.x0 ? s->x0 : b.x0;
  out->x1 = s->x1 < b.x1 - 1 ? s->x1 : b.x1 - 1;
  out->y0 = s->y0 > b.y0 ? s->y0 : b.y0;
  out->y1 = s->y1 < b.y1 - 1 ? s->y1 : b.y1 - 1;
  return out->x0 <= out->x1 && out->y0 <= out->y1;
}

/* The sums of pixel (x, y) of bounds b, w pixels wide. */
static float *pixel_sums(float *sums, clr_bounds2i b, size_t w, int32_t x, int32_t y) {
  return sums + ((size_t)(y - b.y0) * w + (size_t)(x - b.x0)) * CLR_FILM_SUM_FLOATS;
}

/* clr_film_accumulate for each pixel of the clipped footprint c. */
static void add_per_pixel(const clr_tile_adder *a, const clr_film_prepared *s, clr_bounds2i c,
                          clr_bounds2i bounds, float *sums) {
  size_t w = (size_t)(bounds.x1 - bounds.x0);
  for (int32_t y = c.y0; y <= c.y1; ++y)
    for (int32_t x = c.x0; x <= c.x1; ++x)
      clr_film_accumulate(&a->filter, a->factors, s, x, y, pixel_sums(sums, bounds, w, x, y));
}

void clr_tile_add_samples_per_pixel(const clr_tile_adder *a, const clr_film_sample *samples,
                                    size_t count, clr_bounds2i bounds, float *sums,
                                    clr_tile_counts *counts) {
  for (size_t i = 0; i < count; ++i) {
    clr_film_prepared s;
    clr_bounds2i c;
    if (prepare(a, &samples[i], &s, counts) && clip_footprint(&s, bounds, &c))
      add_per_pixel(a, &s, c, bounds, sums);
  }
}

/* clr_filter_eval_1d of a box filter at offset d: 1 within the radius, else 0 (both modes). */
static float box_factor(int use_table, float d, float radius) {
  float a = use_table ? clr_fabsf(d) : clr_fabsf(clr_flush_subnormal(d));
  return a <= radius ? 1.0f : 0.0f;
}

/* Box filter: a factor is 1 or 0, so a weight is too (clr_film_weight of 1 and 0 is exact).
 * Adds prepared sample s. */
CLR_ALWAYS_INLINE void add_box(const clr_tile_adder *a, const clr_film_prepared *s,
                               clr_bounds2i bounds, float *sums) {
  const size_t w = (size_t)(bounds.x1 - bounds.x0);
  const int use_table = a->filter.use_table;
  const float rx = a->filter.radius_x, ry = a->filter.radius_y;
  clr_bounds2i c;
  if (!clip_footprint(s, bounds, &c)) return;
  const float rw = s->r * s->w, gw = s->g * s->w, bw = s->b * s->w;
  if (c.x0 == c.x1 && c.y0 == c.y1) { /* the common footprint of a radius up to 1/2 */
    float f = clr_film_weight(box_factor(use_table, (float)c.x0 - s->dx, rx),
                              box_factor(use_table, (float)c.y0 - s->dy, ry));
    clr_film_add(rw, gw, bw, f, pixel_sums(sums, bounds, w, c.x0, c.y0));
    return;
  }
  for (int32_t y = c.y0; y <= c.y1; ++y) {
    float fy = box_factor(use_table, (float)y - s->dy, ry);
    float *acc = pixel_sums(sums, bounds, w, c.x0, y);
    for (int32_t x = c.x0; x <= c.x1; ++x, acc += CLR_FILM_SUM_FLOATS)
      clr_film_add(rw, gw, bw, clr_film_weight(box_factor(use_table, (float)x - s->dx, rx), fy),
                   acc);
  }
}

/* Any filter: the clipped footprint's x and y factors, then their products. Adds prepared
 * sample s. */
CLR_ALWAYS_INLINE void add_separable(const clr_tile_adder *a, const clr_film_prepared *s,
                                     clr_bounds2i bounds, float *sums) {
  const size_t w = (size_t)(bounds.x1 - bounds.x0);
  float fx[CLR_FILM_REACH_MAX], fy[CLR_FILM_REACH_MAX];
  clr_bounds2i c;
  if (!clip_footprint(s, bounds, &c)) return;
  int32_t nx = c.x1 - c.x0 + 1, ny = c.y1 - c.y0 + 1;
  if (nx > CLR_FILM_REACH_MAX || ny > CLR_FILM_REACH_MAX) { /* beyond the largest radius */
    add_per_pixel(a, s, c, bounds, sums);
    return;
  }
  for (int32_t k = 0; k < nx; ++k)
    fx[k] = clr_film_filter_factor(&a->filter, a->factors, 0, s->dx, c.x0 + k);
  for (int32_t k = 0; k < ny; ++k)
    fy[k] = clr_film_filter_factor(&a->filter, a->factors, 1, s->dy, c.y0 + k);
  const float rw = s->r * s->w, gw = s->g * s->w, bw = s->b * s->w;
  for (int32_t j = 0; j < ny; ++j) {
    float *acc = pixel_sums(sums, bounds, w, c.x0, c.y0 + j);
    for (int32_t k = 0; k < nx; ++k, acc += CLR_FILM_SUM_FLOATS)
      clr_film_add(rw, gw, bw, clr_film_weight(fx[k], fy[j]), acc);
  }
}

/* Prepares the batch's samples in order, four at a time where clr_film_screen4 passes them
 * all, else one by one (prepare: its drops and counts), and adds each accepted one (box: the
 * box path). */
CLR_ALWAYS_INLINE void add_batch(const clr_tile_adder *a, int box, const clr_film_sample *samples,
                                 size_t count, clr_bounds2i bounds, float *sums,
                                 clr_tile_counts *counts) {
  clr_film_screen sc;
  clr_film_screen_init(&sc, &a->params, &a->filter);
  clr_film_prepared s[CLR_FILM_SCREEN_LANES];
  size_t i = 0;
  for (; i + CLR_FILM_SCREEN_LANES <= count; i += CLR_FILM_SCREEN_LANES) {
    int all = clr_film_screen4(&sc, samples + i, s);
    for (int k = 0; k < CLR_FILM_SCREEN_LANES; ++k) {
      if (all)
        ++counts->accepted;
      else if (!prepare(a, &samples[i + (size_t)k], &s[k], counts))
        continue;
      if (box)
        add_box(a, &s[k], bounds, sums);
      else
        add_separable(a, &s[k], bounds, sums);
    }
  }
  for (; i < count; ++i) {
    if (!prepare(a, &samples[i], &s[0], counts)) continue;
    if (box)
      add_box(a, &s[0], bounds, sums);
    else
      add_separable(a, &s[0], bounds, sums);
  }
}

__attribute__((flatten)) static void add_box_batch(const clr_tile_adder *a,
                                                   const clr_film_sample *samples, size_t count,
                                                   clr_bounds2i bounds, float *sums,
                                                   clr_tile_counts *counts) {
  add_batch(a, 1, samples, count, bounds, sums, counts);
}

__attribute__((flatten)) static void add_separable_batch(const clr_tile_adder *a,
                                                         const clr_film_sample *samples,
                                                         size_t count, clr_bounds2i bounds,
                                                         float *sums, clr_tile_counts *counts) {
  add_batch(a, 0, samples, count, bounds, sums, counts);
}

void clr_tile_add_samples(const clr_tile_adder *a, const clr_film_sample *samples, size_t count,
                          clr_bounds2i bounds, float *sums, clr_tile_counts *counts) {
  const clr_tile_adder local = *a; /* in registers: the sums' stores cannot alias it */
  clr_tile_counts n = {0, 0, 0};
  if (local.box)
    add_box_batch(&local, samples, count, bounds, sums, &n);
  else
    add_separable_batch(&local, samples, count, bounds, sums, &n);
  counts->accepted += n.accepted;
  counts->dropped += n.dropped;
  counts->outside += n.outside;
}
