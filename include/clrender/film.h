/* clrender film: pbrt-v3's Film/FilmTile reconstruction (filtered sample sums, splats, crop
 * window) with the sample accumulation as OpenCL kernels.
 *
 * Sums and determinism. Each film_add_samples call (or internal chunk of CLR_FILM_CHUNK_SAMPLES
 * samples) first sums, per pixel and in float, the contributions (L*w)*f and filter weights f of
 * the chunk's samples in the CANONICAL ORDER (f = fx*fy, the product of the filter's separable
 * 1D factors with subnormals flushed, clr_filter_eval_1d; in table mode the factors are pbrt's
 * 16-entry tables per axis, whose products are exactly pbrt's 16x16 table entries); the per-chunk float sums are then added into the
 * film's double sums. Canonical order: a sample's bin is the first pixel its filter reaches,
 * pbrt's p0 = (ceil(dx - rx), ceil(dy - ry)) with d = pFilm - 0.5; every pixel adds the samples
 * that reach it sorted by bin row p0.y, then bin column p0.x, then batch order (a stable sort of
 * the chunk by bin). That order does not depend on the accumulation tile size, work-group size,
 * thread count or device, so the film is bit-identical across those and to the host reference
 * (given a device with correctly rounded float division, used only by the luminance clamp; PoCL
 * has it). Splitting samples into different calls, or merging film tiles in a different order,
 * changes float/double rounding only (same result to float tolerance); the same calls or merges
 * in the same order give the same bits. Film tiles (film_tile_add_samples) sum in batch order.
 * Sums merged with film_merge_sums are added in double: exact only when the additions are.
 *
 * Differences from pbrt-v3, all below float tolerance or documented choices:
 * - sums are kept as RGB, not XYZ: pbrt's XYZToRGB(RGBToXYZ(x)) is the identity to ~1e-6;
 * - samples with a NaN/Inf component, non-finite luminance or luminance < -1e-5, or whose L*w
 *   overflows, are DROPPED and counted (pbrt's integrator replaces the radiance by black and
 *   still adds the filter weight);
 * - a splat lands in pixel floor(p) (pbrt truncates toward zero);
 * - the resolve divides in double (pbrt multiplies by a float reciprocal).
 *
 * Thread safety: every film_* call on one film is thread-safe (serialised by the film's mutex);
 * different films work concurrently. A film tile belongs to one thread at a time until it is
 * merged. Lifetime: film_create -> reference count 1, film_retain/film_release; the film retains
 * its context; tiles are released with film_tile_release (after or instead of merging).
 * Ownership: arrays passed in (samples, sums) and filled (rgb, sums) stay the caller's and are
 * not kept. NULL: release calls ignore NULL; bounds accessors return an empty box for NULL;
 * every other call returns CLR_ERROR_NULL_POINTER naming the argument. */
#ifndef CLRENDER_FILM_H
#define CLRENDER_FILM_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/opencl.h"
#include "clrender/context.h"
#include "clrender/filter.h"
#include "clrender/sampler.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Resolution limits: each side at most CLR_FILM_MAX_SIDE, at most CLR_FILM_MAX_PIXELS pixels. */
#define CLR_FILM_MAX_SIDE 32768
#define CLR_FILM_MAX_PIXELS (1 << 28)
/* Filter radii above this are rejected (CLR_ERROR_INVALID_RADIUS): a pixel gathers the samples
 * of its (2r + 1)^2 neighbouring bins. */
#define CLR_FILM_MAX_FILTER_RADIUS 32.0f
/* film_add_samples processes larger calls in consecutive chunks of this many samples; a chunk's
 * binning and kernel scratch (about 200 bytes per chunk sample, plus 30 bytes per pixel the chunk
 * reaches) is what the accumulation holds besides the film's 32 bytes per pixel. */
#define CLR_FILM_CHUNK_SAMPLES (1u << 18)

typedef struct clr_film_t *clr_film;
typedef struct clr_film_tile_t *clr_film_tile;

typedef struct clr_film_desc {
  size_t struct_size;                 /* sizeof(clr_film_desc), set by clr_film_desc_init */
  int32_t x_resolution, y_resolution; /* 1280 x 720 */
  float crop_window[4];           /* x0 x1 y0 y1 in [0,1] (pbrt order, min/max sorted); 0 1 0 1 */
  float scale;                    /* 1 */
  float max_sample_luminance;     /* INFINITY: no clamp; must be > 0 */
  clr_filter_desc filter;         /* pbrt-v3 box, radius 0.5 */
  int32_t accumulation_tile_size; /* 4..64, default 16: pixels of a row one work-item
                                      accumulates; performance only, never the result */
} clr_film_desc;

/* One radiance sample: 24 bytes, six floats, tightly packed (also the layout of device buffers
 * given to film_add_samples_buffer). x, y: raster position (pbrt pFilm, full-resolution pixel
 * coordinates); r, g, b: radiance; weight: the camera ray weight. */
typedef struct clr_film_sample {
  float x, y;
  float r, g, b;
  float weight;
} clr_film_sample;

CLR_API void clr_film_desc_init(clr_film_desc *desc);

/* Errors: NULL pointers; struct_size mismatch or tile size outside 4..64 or bad scale/max
 * luminance -> CLR_ERROR_INVALID_ARGUMENT; resolution < 1 or beyond the limits ->
 * CLR_ERROR_INVALID_RESOLUTION; crop values NaN or outside [0,1], or an empty cropped image ->
 * CLR_ERROR_INVALID_CROP_WINDOW; radius not in (0, CLR_FILM_MAX_FILTER_RADIUS] ->
 * CLR_ERROR_INVALID_RADIUS; filter errors from clr_filter_params_make. */
/* ctx NULL makes a host film, which never needs an OpenCL implementation: film_add_samples runs
 * the host reference of the kernels (the same bits), film_add_samples_buffer is refused
 * (CLR_ERROR_INVALID_ARGUMENT); tiles, merges and output work as with a context. */
CLR_API clr_result film_create(clr_context ctx, const clr_film_desc *desc, clr_film *out);
CLR_API void film_retain(clr_film film);
CLR_API void film_release(clr_film film);

/* pbrt croppedPixelBounds: [ceil(W*cx0), ceil(H*cy0)) to [ceil(W*cx1), ceil(H*cy1)) in float. */
CLR_API clr_bounds2i film_pixel_bounds(clr_film film);
/* pbrt GetSampleBounds: [floor(pMin + .5 - r), ceil(pMax - .5 + r)). */
CLR_API clr_bounds2i film_sample_bounds(clr_film film);

/* Adds samples (host memory) through the accumulation kernels. count 0 ->
 * CLR_ERROR_INVALID_ARGUMENT. Bad samples are dropped (film_dropped_samples), samples outside
 * the sample bounds ignored (film_outside_samples). Thread-safe (serialised per film). */
CLR_API clr_result film_add_samples(clr_film film, const clr_film_sample *samples, size_t count);
/* Same for a device buffer of `count` clr_film_sample on the film's context. The host bins the
 * samples: it maps the buffer for reading chunk by chunk (a copy to the host on a GPU). */
CLR_API clr_result film_add_samples_buffer(clr_film film, cl_mem samples, size_t count);

/* pbrt AddSplat: drops NaN/Inf/negative-luminance values (counted as dropped), ignores points
 * outside the pixel bounds, clamps the luminance, adds to pixel floor(x), floor(y). Thread-safe;
 * deterministic for a fixed call order. */
CLR_API clr_result film_add_splat(clr_film film, float x, float y, float r, float g, float b);

/* Host-thread film tiles (pbrt GetFilmTile/MergeFilmTile). The tile covers the pixels samples
 * in `sample_region` reach: [ceil(s0 - .5 - r), floor(s1 - .5 + r) + 1) clipped to the pixel
 * bounds. An empty or inverted region -> CLR_ERROR_INVALID_PIXEL_RANGE. */
CLR_API clr_result film_get_tile(clr_film film, clr_bounds2i sample_region, clr_film_tile *out);
CLR_API clr_bounds2i film_tile_pixel_bounds(clr_film_tile tile);
/* Same math and checks as film_add_samples, on the host, into the tile's float sums. */
CLR_API clr_result film_tile_add_samples(clr_film_tile tile, const clr_film_sample *samples,
                                         size_t count);
/* Adds the tile's per-pixel sums (float, into the film's double sums) and counters under the
 * film's mutex. A tile merges once (again -> CLR_ERROR_INVALID_TILE), into its own film only.
 * Merging tiles in a fixed order is deterministic; the result equals one film_add_samples call
 * with the same samples to float tolerance. */
CLR_API clr_result film_merge_tile(clr_film film, clr_film_tile tile);
CLR_API void film_tile_release(clr_film_tile tile);
/* A tile's contents as bytes (pixel bounds, counters, float sums; native byte order), e.g. to
 * send it to another process: film_tile_serialize writes film_tile_serialized_size(tile) bytes
 * (0 for NULL); film_tile_deserialize makes from them a tile of `film` (a film with the same
 * pixel bounds) that merges bit for bit as the original would. Bounds outside the film ->
 * CLR_ERROR_INVALID_TILE, a size that does not match -> CLR_ERROR_INVALID_ARGUMENT. */
CLR_API size_t film_tile_serialized_size(clr_film_tile tile);
CLR_API clr_result film_tile_serialize(clr_film_tile tile, void *buf, size_t size);
CLR_API clr_result film_tile_deserialize(clr_film film, const void *buf, size_t size,
                                         clr_film_tile *out);

/* pbrt WriteImage: per pixel of the pixel bounds (row-major, w*h*3 floats):
 * rgb = max(0, sum/weight) (sum itself where weight is 0), += splat_scale * splat, *= scale. */
CLR_API clr_result film_get_rgb(clr_film film, float *rgb, float splat_scale);
/* Raw sums over the pixel bounds (row-major): rgb_sum and splat_rgb 3 per pixel, weight_sum 1;
 * any may be NULL (not all). */
CLR_API clr_result film_get_sums(clr_film film, double *rgb_sum, double *weight_sum,
                                 double *splat_rgb);
/* Adds sums laid out over `region` (row-major, region-sized, same layout as film_get_sums) into
 * dst; the region must lie inside dst's pixel bounds (else CLR_ERROR_INVALID_PIXEL_RANGE). Any
 * array may be NULL (not all). A pixel with a NaN or infinite value is skipped and counted in
 * film_dropped_samples, as film_add_samples drops such samples. */
CLR_API clr_result film_merge_sums(clr_film dst, clr_bounds2i region, const double *rgb_sum,
                                   const double *weight_sum, const double *splat_rgb);

/* The film's geometry as a sampler needs it (resolution, crop window, filter radius), e.g.
 * film_get_geometry(film, &sampler_desc.film): the sampler's sample bounds are then the film's. */
CLR_API clr_result film_get_geometry(clr_film film, clr_film_geometry *geometry);

/* The description the film was created with. */
CLR_API const clr_film_desc *film_get_desc(clr_film film);

/* Film output. The EXR holds R, G, B (float32, or half with `half`) over the film's pixel
 * bounds as data window inside the full-resolution display window, and metadata: software
 * version, sampler, spp, filter and its parameters, scale, crop window, render time, partial
 * flag, plus the caller's string pairs. With `include_sums` it also holds the raw sums so films
 * can be merged later (`clrender merge`, film_merge_file): channels sum.R/G/B, weight and
 * splat.R/G/B as float32, each with a ".lo" float32 residual (value = channel + channel.lo), so
 * the double sums survive to ~48 bits. Files are written to a temporary name and renamed. */
typedef struct clr_film_write_options {
  size_t struct_size;               /* sizeof, set by clr_film_write_options_init */
  int32_t half;                     /* 0: float32 RGB (default); 1: half RGB */
  int32_t include_sums;             /* 1 (default): raw sum channels for merging */
  float splat_scale;                /* 1 */
  const char *sampler;              /* e.g. "sobol" (metadata; NULL: omitted) */
  int32_t spp;                      /* metadata; 0: omitted */
  double render_time_s;             /* metadata; < 0: omitted */
  int32_t partial;                  /* 1: marks an interrupted render */
  const char *const *metadata_keys; /* extra string attributes */
  const char *const *metadata_values;
  int32_t metadata_count;
} clr_film_write_options;

CLR_API void clr_film_write_options_init(clr_film_write_options *opts);
CLR_API clr_result film_write(clr_film film, const char *path, const clr_film_write_options *opts);
/* Checks, before any work, that film_write / film_write_png could write `path`: its folder exists
 * and is writable, and the name is new or an existing regular file the user may write (never a
 * directory, symlink, device, FIFO, socket or read-only file; film_write checks again right
 * before it renames its temporary file onto the name). CLR_ERROR_IO naming the path and the
 * reason otherwise. */
CLR_API clr_result film_check_output_path(const char *path);
/* 8-bit sRGB preview with pbrt-v3's gamma and rounding. */
CLR_API clr_result film_write_png(clr_film film, const char *path, float splat_scale);

/* Merges films written with include_sums (crops of one frame, or independent passes of the same
 * frame) into the image a single render would have produced and writes it (with sums) to
 * `out_path`. Refuses mismatched resolutions or filters and files without sum channels. */
CLR_API clr_result film_merge_files(clr_context ctx, const char *const *paths, int32_t count,
                                    const char *out_path);

/* Adds the sums and sample counts of an image film_write wrote with its sums into `film` (to
 * resume a render): the file's resolution, pixel bounds (data window), filter and scale must be
 * the film's, else CLR_ERROR_INVALID_FILM naming both. On success the header attributes
 * attr_names[0..attr_count) are returned as text (strings as written, ints %d, floats %.9g, ""
 * when absent) in attr_values, value_size bytes each. */
CLR_API clr_result film_merge_file(clr_film film, const char *path, int32_t attr_count,
                                   const char *const *attr_names, char *attr_values,
                                   size_t value_size);
/* Adds src's sums and counters into dst (same resolution, pixel bounds and filter, else
 * CLR_ERROR_INVALID_FILM): a render pass merged into the frame. */
CLR_API clr_result film_merge_film(clr_film dst, clr_film src);

CLR_API uint64_t film_sample_count(clr_film film);    /* accepted samples */
CLR_API uint64_t film_dropped_samples(clr_film film); /* NaN/Inf/negative samples and splats */
CLR_API uint64_t film_outside_samples(clr_film film); /* samples outside the sample bounds */

#ifdef __cplusplus
}
#endif
#endif
