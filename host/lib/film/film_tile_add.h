/* Adding samples to a host film tile's float sums: the filter's per-axis factors once per
 * sample (a box filter's are 1 or 0 by comparison, with no table lookup), then one product per
 * pixel; the film's parameters held in locals for the whole batch. */
#ifndef CLR_FILM_TILE_ADD_H
#define CLR_FILM_TILE_ADD_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/film.h"
#include "film_types.h"
#include "filter_types.h"

/* A film's parameters and the factor path its filter takes. */
typedef struct clr_tile_adder {
  clr_film_params params;
  clr_filter_params filter;
  const float *factors; /* the film's 2 x CLR_FILTER_TABLE_SIZE table factors */
  int box;              /* every factor within the radius is exactly 1 */
} clr_tile_adder;

/* Samples a batch accepted, dropped (bad values) and found outside the sample bounds. */
typedef struct clr_tile_counts {
  uint64_t accepted, dropped, outside;
} clr_tile_counts;

void clr_tile_adder_init(clr_tile_adder *a, const clr_film_params *params,
                         const clr_filter_params *filter, const float *factors);

/* Checks samples (clr_film_prepare) in batch order and adds each accepted one to the sums
 * (CLR_FILM_SUM_FLOATS per pixel, row-major over bounds) of the pixels of bounds it reaches;
 * adds to *counts. The same bits and counts as clr_tile_add_samples_per_pixel. */
void clr_tile_add_samples(const clr_tile_adder *a, const clr_film_sample *samples, size_t count,
                          clr_bounds2i bounds, float *sums, clr_tile_counts *counts);

/* The general path: clr_film_accumulate for each pixel of bounds a sample reaches. */
void clr_tile_add_samples_per_pixel(const clr_tile_adder *a, const clr_film_sample *samples,
                                    size_t count, clr_bounds2i bounds, float *sums,
                                    clr_tile_counts *counts);

#endif
