/* TEMPORARY stand-in for the filter helper's kernel functions (film branch only; replaced at
 * merge): box and triangle, exact and through pbrt-v3's 16x16 table. */
#ifndef CLR_FILTER_FUNCS_H
#define CLR_FILTER_FUNCS_H

#include "filter_types.h"

/* pbrt-v3 FilmTile::AddSample: min(floor(|d * invRadius * 16|), 15). */
CLR_INLINE clr_i32 clr_filter_table_index(float d, float inv_radius) {
  float f = clr_fabsf(d * inv_radius * (float)CLR_FILTER_TABLE_SIZE);
  clr_i32 i = (clr_i32)clr_floorf(f);
  return i < CLR_FILTER_TABLE_SIZE - 1 ? i : CLR_FILTER_TABLE_SIZE - 1;
}

CLR_INLINE float clr_filter_eval_exact(const clr_filter_params *f, float x, float y) {
  if (f->type == CLR_FILTER_TYPE_TRIANGLE)
    return clr_fmaxf(0.0f, f->radius_x - clr_fabsf(x)) * clr_fmaxf(0.0f, f->radius_y - clr_fabsf(y));
  return 1.0f;
}

CLR_INLINE float clr_filter_eval(const clr_filter_params *f, float x, float y,
                                 CLR_GLOBAL const float *table) {
  if (f->use_table) {
    clr_i32 ix = clr_filter_table_index(x, f->inv_radius_x);
    clr_i32 iy = clr_filter_table_index(y, f->inv_radius_y);
    return table[iy * CLR_FILTER_TABLE_SIZE + ix];
  }
  return clr_filter_eval_exact(f, x, y);
}

#endif
