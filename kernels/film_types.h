/* Film structures shared by the accumulation kernels and the host: 32-bit scalars only, so the
 * layout is identical on every device and on the host. */
#ifndef CLR_FILM_TYPES_H
#define CLR_FILM_TYPES_H

#include "clr_platform.h"

/* A sample in memory: x, y (raster position), r, g, b, weight: the public clr_film_sample. */
#define CLR_FILM_SAMPLE_FLOATS 6
/* A binned sample: dx, dy (pbrt pFilmDiscrete), r, g, b (after the luminance clamp), weight. */
#define CLR_FILM_BINNED_FLOATS 6
/* A weighed sample (clr_film_weigh): rw, gw, bw, 1 (radiance times camera weight, and the
 * weight sum's factor), x0 and y0 (as int bits), then reach_x x-factors (pixels x0, x0 + 1, ...)
 * and reach_y y-factors, 0 past the sample's last reached pixel. */
#define CLR_FILM_WEIGHED_HEAD 6
/* The SIMD shape's weighed sample (clr_film_weigh8, clr_film_gather8), for reaches up to
 * CLR_FILM_LANES: rw, gw, bw, 1, x0, y0 and gx (the first pixel of the 8-pixel run of the
 * chunk's output region that holds x0; as int bits), one pad, then the x-factors of the 16
 * pixels gx .. gx + 15 (0 where the sample does not reach), then CLR_FILM_LANES y-factors of
 * pixels y0 .. y0 + 7 (0 past its reach). */
#define CLR_FILM_LANES 8
/* Reach up to which clr_film_weigh8 evaluates the x- and y-factors in one vector. */
#define CLR_FILM_QUAD 4
#define CLR_FILM_WEIGHED8_X 8
#define CLR_FILM_WEIGHED8_Y 24
#define CLR_FILM_WEIGHED8_FLOATS 32
/* Keeps the dividend of the weigh kernels' run start (gx) positive: x0 - out_x0 is above
 * -CLR_FILM_REACH_MAX. */
#define CLR_FILM_RUN_BIAS 128
/* Most pixels a sample reaches along an axis: 2 * CLR_FILM_MAX_FILTER_RADIUS + 1. */
#define CLR_FILM_REACH_MAX 65
/* Per-pixel sums a kernel writes: r, g, b, filter weight. */
#define CLR_FILM_SUM_FLOATS 4
/* Largest work-group of the gather kernel. */
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
  clr_i32 tile_size;       /* pixels of a row one gather work-item accumulates */
  clr_i32 clamp_luminance; /* 1 when max_luminance is finite */
  float max_luminance;
  clr_i32 pad[5];
} clr_film_params;

/* One chunk's bins: a bin is a pixel (x0, y0) = pbrt's first reached pixel p0 = ceil(d - r) of
 * its samples; bins [bin_x0, bin_x0 + bins_x) x [bin_y0, bin_y0 + bins_y), row-major; reach_x,
 * reach_y: the most pixels one of the chunk's samples reaches along x / y (x1 - x0 + 1), so a
 * pixel px gathers the bins x0 in [px - reach_x + 1, px]; the gather writes the pixels
 * [out_x0, out_x0 + out_w) x [out_y0, out_y0 + out_h) the samples reach. */
typedef struct clr_film_grid {
  clr_i32 bin_x0, bin_y0, bins_x, bins_y;
  clr_i32 out_x0, out_y0, out_w, out_h;
  clr_i32 reach_x, reach_y;
  clr_i32 weighed_floats; /* floats per weighed sample: CLR_FILM_WEIGHED_HEAD + reach_x +
                             reach_y, rounded up to a multiple of 4 */
  clr_i32 pad;
} clr_film_grid;

/* A sample ready to be added: pbrt's pFilmDiscrete (d = p - 0.5), radiance after the luminance
 * clamp, weight, and the inclusive range of pixels its filter reaches (before clipping). */
typedef struct clr_film_prepared {
  float dx, dy;
  float r, g, b, w;
  clr_i32 x0, x1, y0, y1;
} clr_film_prepared;

#endif
