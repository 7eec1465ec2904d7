/* Film structures shared by the accumulation kernels and the host: 32-bit scalars only, so the
 * layout is identical on every device and on the host. */
#ifndef CLR_FILM_TYPES_H
#define CLR_FILM_TYPES_H

#include "clr_platform.h"

/* A sample in memory: x, y (raster position), r, g, b, weight: the public clr_film_sample. */
#define CLR_FILM_SAMPLE_FLOATS 6
/* Per-pixel sums a kernel writes: r, g, b, filter weight. */
#define CLR_FILM_SUM_FLOATS 4
/* Largest work-group of the accumulation kernel (size of its local sample cache). */
#define CLR_FILM_GROUP_MAX 256
/* pbrt-v3's check on radiance: luminance below this is a bad sample. */
#define CLR_FILM_MIN_LUMINANCE (-1e-5f)

/* Outcome of checking one sample. */
#define CLR_FILM_SAMPLE_OK 0
#define CLR_FILM_SAMPLE_DROPPED 1 /* NaN/Inf component, non-finite or negative luminance */
#define CLR_FILM_SAMPLE_OUTSIDE 2 /* position outside the film's sample bounds */

typedef struct clr_film_params {
  clr_i32 pixel_x0, pixel_y0, pixel_x1, pixel_y1;     /* cropped pixel bounds, half-open */
  clr_i32 sample_x0, sample_y0, sample_x1, sample_y1; /* pbrt GetSampleBounds, half-open */
  clr_i32 tile_size;                                  /* accumulation tile side T */
  clr_i32 tiles_x, tiles_y;                           /* tiles over the pixel bounds */
  clr_i32 clamp_luminance;                            /* 1 when max_luminance is finite */
  float max_luminance;
  clr_i32 pad[3];
} clr_film_params;

/* A sample ready to be added: pbrt's pFilmDiscrete (d = p - 0.5), radiance after the luminance
 * clamp, weight, and the inclusive range of pixels its filter reaches (before clipping). */
typedef struct clr_film_prepared {
  float dx, dy;
  float r, g, b, w;
  clr_i32 x0, x1, y0, y1;
} clr_film_prepared;

#endif
