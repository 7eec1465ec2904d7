/* Structures shared by the sampler kernels and their host reference: 32-bit scalars only, so the
 * layout is identical on every device and on the host. */
#ifndef CLR_SAMPLER_TYPES_H
#define CLR_SAMPLER_TYPES_H

#include "clr_platform.h"

#define CLR_SAMPLER_TYPE_RANDOM 0
#define CLR_SAMPLER_TYPE_STRATIFIED 1
#define CLR_SAMPLER_TYPE_HALTON 2
#define CLR_SAMPLER_TYPE_SOBOL 3
#define CLR_SAMPLER_TYPE_ZEROTWO 4
#define CLR_SAMPLER_TYPE_MAXMINDIST 5
#define CLR_SAMPLER_TYPE_INDEPENDENT 6
#define CLR_SAMPLER_TYPE_PADDEDSOBOL 7
#define CLR_SAMPLER_TYPE_ZSOBOL 8
#define CLR_SAMPLER_TYPE_PMJ02BN 9

/* pbrt-v4's sampler algorithms (clr_sampler_params.v4_sampler; 0: not a pbrt-v4 sampler). */
#define CLR_V4_INDEPENDENT 1
#define CLR_V4_STRATIFIED 2
#define CLR_V4_HALTON 3
#define CLR_V4_SOBOL 4
#define CLR_V4_PADDEDSOBOL 5
#define CLR_V4_ZSOBOL 6
#define CLR_V4_PMJ02BN 7

/* pmj02bn: progressive (0,2) point sets and the points each of them holds (pbrt-v4's
 * nPMJ02bnSets, nPMJ02bnSamples). */
#define CLR_PMJ02_SETS 5
#define CLR_PMJ02_POINTS 65536

/* pbrt-v4's RandomizeStrategy (clr_sampler_params.randomization). */
#define CLR_RANDOMIZE_TYPE_NONE 1
#define CLR_RANDOMIZE_TYPE_PERMUTEDIGITS 2
#define CLR_RANDOMIZE_TYPE_FASTOWEN 3
#define CLR_RANDOMIZE_TYPE_OWEN 4

#define CLR_SEEDING_TYPE_PBRT_V3 0
#define CLR_SEEDING_TYPE_PIXEL 1
#define CLR_SEEDING_TYPE_PBRT_V4 2

/* pbrt-v3's render tiles (over the sample bounds) that seed the pixel samplers' RNG streams. */
#define CLR_PBRT_TILE_SIZE 16

/* GlobalSampler::arrayStartDim in pbrt-v3: arrays start after the camera's five dimensions. */
#define CLR_GLOBAL_ARRAY_START_DIM 5

#define CLR_SOBOL_DIMENSIONS 1024
#define CLR_SOBOL_MATRIX_SIZE 52
#define CLR_HALTON_PRIMES 1000
#define CLR_HALTON_MAX_RESOLUTION 128

typedef struct clr_sampler_params {
  clr_i32 type;                 /* CLR_SAMPLER_TYPE_* */
  clr_i32 spp;                  /* effective samples per pixel */
  clr_i32 x_samples, y_samples; /* stratified strata */
  clr_i32 jitter;
  clr_i32 dimensions;          /* stratified: number of 1D and of 2D streams */
  clr_i32 sample_pixel_center; /* halton */
  clr_i32 seeding;             /* CLR_SEEDING_TYPE_* */
  clr_u32 seed;
  clr_i32 tiles_x; /* pbrt-v3 16x16 tiles across the sample bounds */
  clr_i32 sample_x0, sample_y0, sample_x1, sample_y1; /* sample bounds, half-open */
  clr_i32 pixel_x0, pixel_y0, pixel_x1, pixel_y1;     /* (cropped) pixel bounds, half-open */
  float inv_x_samples, inv_y_samples, inv_spp;        /* 1/n rounded on the host */
  /* halton */
  clr_i32 halton_scale[2], halton_exponent[2];
  clr_u32 halton_mult_inverse[2];
  clr_i32 halton_stride;
  /* sobol */
  clr_i32 sobol_log2_resolution;
  float sobol_resolution;
  /* batch */
  clr_i32 batch_x0, batch_y0, batch_width, batch_height;
  clr_i32 first_sample, sample_count, values_per_sample, request_count;
  /* pixel samplers: RNG draws each rendered sample makes past the precomputed streams */
  clr_i32 fallback_draws_per_sample;
  clr_i32 scratch_floats; /* per work-item scratch the pixel samplers need */
  clr_i32 maxmin_matrix;  /* maxmindist: index of its generator matrix (pbrt-v3's Cindex) */
  /* pbrt-v4 samplers (clr_sampler_params.halton_* and sobol_* then hold pbrt-v4's values, from
   * the full film resolution) */
  clr_i32 v4_sampler;    /* CLR_V4_*, 0 for the other samplers */
  clr_i32 randomization; /* CLR_RANDOMIZE_TYPE_* */
  clr_i32 zsobol_log2_spp, zsobol_base4_digits;
  clr_i32 pmj_tile;     /* pmj02bn: side of the tile of pixels its GetPixel2D table covers */
  clr_i32 film_request; /* pbrt-v4 samplers: the request that is GetPixel2D (1D ones before it) */
  clr_i32 sobol_frame_bits; /* sobol device launch: its sample numbers are below 2^it */
  clr_i32 pad;
} clr_sampler_params;

/* One request of the layout, resolved for the sampler family. */
typedef struct clr_request_slot {
  clr_i32 dims;        /* 1 or 2 */
  clr_i32 array_size;  /* 0: a single value; n >= 1: array of n elements */
  clr_i32 first_value; /* offset of its first value in the sample vector */
  /* Global samplers: first dimension. Pixel samplers: index of the 1D/2D stream (single values)
   * or of the 1D/2D array (arrays); -1 when a single value falls past `dimensions` and comes from
   * the RNG (random: always). */
  clr_i32 source;
  clr_i32 rng_offset;   /* pixel samplers, source -1: index of its first per-sample RNG draw */
  float inv_array_size; /* 1/array_size rounded on the host */
  /* 1: a skipped request (CLR_SAMPLE_REQUEST_SKIPPED): its dimensions and RNG draws count, its
   * values are not stored (first_value: where they would start; they take no room) */
  clr_i32 skipped;
  clr_i32 pad;
} clr_request_slot;

#endif
