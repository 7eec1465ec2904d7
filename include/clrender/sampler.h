/* clrender samplers: pbrt-v3's random, stratified, halton and sobol samplers as OpenCL kernels,
 * with a host reference built from the same kernel headers.
 *
 * Thread safety: a sampler may be used from several threads; clr_sampler_generate calls on one
 * sampler are serialised (its device buffers are reused), calls on different samplers run
 * concurrently. clr_sampler_generate_reference needs no lock and is thread-safe.
 * Lifetime: create -> reference count 1; retain/release; the sampler retains its context.
 * Ownership: output buffers (host arrays, cl_mem) stay the caller's; the sampler never keeps
 * pointers to them after the call returns.
 * NULL: a NULL context creates a host-only sampler: clr_sampler_generate_reference works,
 * clr_sampler_generate returns CLR_ERROR_INVALID_ARGUMENT. retain/release ignore NULL; other NULL
 * pointers return CLR_ERROR_NULL_POINTER. */
#ifndef CLRENDER_SAMPLER_H
#define CLRENDER_SAMPLER_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/opencl.h"
#include "clrender/context.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum clr_sampler_type {
  CLR_SAMPLER_RANDOM = 0,
  CLR_SAMPLER_STRATIFIED = 1,
  CLR_SAMPLER_HALTON = 2,
  CLR_SAMPLER_SOBOL = 3,
  /* pbrt-v3's ZeroTwoSequenceSampler ("02sequence", alias "lowdiscrepancy"). Values never change;
   * new samplers are appended. */
  CLR_SAMPLER_ZEROTWO = 4,
  /* pbrt-v3's MaxMinDistSampler ("maxmindist"): pixelsamples below 2^17. */
  CLR_SAMPLER_MAXMINDIST = 5,
  /* pbrt-v4's IndependentSampler, PaddedSobolSampler and ZSobolSampler (always pbrt-v4's
   * algorithms, whatever the seeding). */
  CLR_SAMPLER_INDEPENDENT = 6,
  CLR_SAMPLER_PADDEDSOBOL = 7,
  CLR_SAMPLER_ZSOBOL = 8,
  /* pbrt-v4's PMJ02BNSampler structure with point sets of our own (not pbrt-v4's tables): see
   * README. pixelsamples 1..65536. */
  CLR_SAMPLER_PMJ02BN = 9
} clr_sampler_type;

/* Number of sampler types: every value in [0, CLR_SAMPLER_TYPE_COUNT) is a sampler, named by
 * clr_sampler_type_name. */
#define CLR_SAMPLER_TYPE_COUNT 10

/* pbrt-v4's RandomizeStrategy ("randomization"): DEFAULT is the sampler's pbrt-v4 default
 * (halton: permutedigits; sobol, paddedsobol, zsobol: fastowen). Only pbrt-v4 samplers use it. */
typedef enum clr_randomization {
  CLR_RANDOMIZATION_DEFAULT = 0,
  CLR_RANDOMIZATION_NONE = 1,
  CLR_RANDOMIZATION_PERMUTEDIGITS = 2,
  CLR_RANDOMIZATION_FASTOWEN = 3, /* not for halton (pbrt-v4 refuses it too) */
  CLR_RANDOMIZATION_OWEN = 4
} clr_randomization;

typedef enum clr_seeding {
  /* pbrt-v3: the RNG stream of a pixel sampler is the index of its 16x16 render tile over the
   * sample bounds, and the stream runs through the tile's pixels in row-major order. */
  CLR_SEEDING_PBRT_V3 = 0,
  /* One RNG stream per pixel (hash of pixel and seed): independent of tiling and visiting order. */
  CLR_SEEDING_PIXEL = 1,
  /* pbrt-v4: every sampler name runs pbrt-v4's algorithm (random = independent, stratified,
   * halton, sobol; 02sequence and maxmindist are refused), seeded by pixel, sample and `seed`,
   * with the full film resolution where pbrt-v4 uses it (halton, sobol, zsobol). */
  CLR_SEEDING_PBRT_V4 = 2
} clr_seeding;

/* Film geometry the sampler needs: the sample bounds are the film's (cropped) pixel bounds grown
 * by the filter radius exactly as pbrt-v3's Film::GetSampleBounds. */
typedef struct clr_film_geometry {
  int32_t x_resolution, y_resolution;
  float crop_window[4]; /* x0, x1, y0, y1 in NDC, pbrt-v3 "cropwindow" order; default 0 1 0 1 */
  float filter_radius[2];
} clr_film_geometry;

typedef struct clr_bounds2i {
  int32_t x0, y0, x1, y1; /* half-open [x0,x1) x [y0,y1) */
} clr_bounds2i;

typedef struct clr_sampler_desc {
  size_t struct_size; /* sizeof(clr_sampler_desc), set by clr_sampler_desc_init */
  clr_sampler_type type;
  int32_t pixel_samples;        /* random 4, halton 16, sobol, 02sequence and maxmindist 16
                                  (rounded up to a power of two) */
  int32_t x_samples, y_samples; /* stratified 4 x 4 */
  int32_t jitter;               /* stratified, default 1 */
  int32_t dimensions;           /* stratified, 02sequence, maxmindist, default 4 */
  int32_t sample_pixel_center;  /* halton, default 0 */
  clr_seeding seeding;          /* default CLR_SEEDING_PIXEL; CLR_SEEDING_PBRT_V3 matches pbrt-v3 */
  uint32_t seed;                /* mixed into CLR_SEEDING_PIXEL streams; default 0 */
  clr_film_geometry film;       /* default 1280x720, full crop, radius 0.5 (pbrt-v3 box) */
  clr_randomization randomization; /* pbrt-v4 samplers; default CLR_RANDOMIZATION_DEFAULT */
} clr_sampler_desc;

/* Defaults of pbrt-v3's scene format for `type`. */
CLR_API void clr_sampler_desc_init(clr_sampler_desc *desc, clr_sampler_type type);
/* "random", "stratified", "halton", "sobol", "02sequence" (alias "lowdiscrepancy"),
 * "maxmindist", "independent", "paddedsobol", "zsobol", "pmj02bn" -> type;
 * CLR_ERROR_INVALID_SAMPLER otherwise. */
CLR_API clr_result clr_sampler_type_from_name(const char *name, clr_sampler_type *type);
CLR_API const char *clr_sampler_type_name(clr_sampler_type type);
/* "default", "none", "permutedigits", "fastowen", "owen" <-> clr_randomization;
 * CLR_ERROR_INVALID_ARGUMENT for another name. */
CLR_API clr_result clr_randomization_from_name(const char *name, clr_randomization *out);
CLR_API const char *clr_randomization_name(clr_randomization randomization);
/* pbrt-v3's Sampler::RoundCount: the array size an integrator should request for `count`
 * values (02sequence, maxmindist: rounded up to a power of two; the others: count). */
CLR_API int32_t clr_sampler_round_count(clr_sampler_type type, int32_t count);

/* One request of the layout. The camera's requests come first: 2D film offset, 1D time, 2D lens;
 * then the integrator's 1D/2D requests and arrays in the order it makes them. pbrt-v4 samplers
 * (CLR_SEEDING_PBRT_V4, independent, paddedsobol, zsobol, pmj02bn) also accept 1D requests before
 * the film offset (pbrt-v4 takes the wavelength sample first): the first 2D request is then the
 * film offset (GetPixel2D). clr_sample_layout_values checks the strict form. */
typedef struct clr_sample_request {
  int32_t dims;       /* 1 or 2, optionally | CLR_SAMPLE_REQUEST_SKIPPED */
  int32_t array_size; /* 0: one value (Get1D/Get2D); n >= 1: an array (Get1DArray/Get2DArray) */
} clr_sample_request;

/* Or-ed into a request's dims ({2 | CLR_SAMPLE_REQUEST_SKIPPED, 0}): nobody reads its values,
 * e.g. a pinhole camera's time (1D) and lens (2D) requests. A skipped request keeps its place:
 * it still takes its dimensions (halton, sobol, pbrt-v4 samplers) and its RNG draws (pixel
 * samplers), so every other value is bit for bit the one the layout without the flag gives. It
 * has no values in the sample vector: the values of the requests after it move up, and
 * clr_sample_layout_values, the output layout and clr_sampler_generate_at's value range count
 * only the values of requests that are not skipped. Samplers whose values are a function of
 * (pixel, sample, dimension) do not compute it; pbrt-v3's pixel samplers (stratified, random,
 * 02sequence, maxmindist) make its RNG draws and only skip its stores. The film offset request
 * cannot be skipped, and the limits (CLR_MAX_VALUES_PER_SAMPLE, array sizes) count skipped
 * requests too. Any other bit in dims is an error (CLR_ERROR_INVALID_REQUESTS). */
#define CLR_SAMPLE_REQUEST_SKIPPED 0x100

#define CLR_MAX_REQUESTS 1024
#define CLR_MAX_VALUES_PER_SAMPLE 4096

typedef struct clr_sampler_t *clr_sampler;

CLR_API clr_result clr_sampler_create(clr_context ctx, const clr_sampler_desc *desc,
                                      clr_sampler *out);
CLR_API void clr_sampler_retain(clr_sampler sampler);
CLR_API void clr_sampler_release(clr_sampler sampler);

/* Effective samples per pixel (after rounding: stratified x*y, sobol, 02sequence and maxmindist
 * power of two). */
CLR_API int32_t clr_sampler_spp(clr_sampler sampler);
CLR_API clr_bounds2i clr_sampler_sample_bounds(clr_sampler sampler);
CLR_API clr_bounds2i clr_sampler_pixel_bounds(clr_sampler sampler);
/* 1 if the sampler has a global sample index (halton, sobol). */
CLR_API int clr_sampler_has_global_index(clr_sampler sampler);

/* A batch: the pixels of `pixels` (must lie inside the sample bounds) x samples
 * [first_sample, first_sample + sample_count) x the request layout. */
typedef struct clr_sample_batch {
  size_t struct_size; /* sizeof(clr_sample_batch), set by clr_sample_batch_init */
  clr_bounds2i pixels;
  int32_t first_sample; /* default 0 */
  int32_t sample_count; /* default 0 meaning all spp */
  const clr_sample_request *requests;
  int32_t request_count;
} clr_sample_batch;

CLR_API void clr_sample_batch_init(clr_sample_batch *batch);
/* Values per sample vector: sum of dims * max(1, array_size) over the requests not skipped. */
CLR_API clr_result clr_sample_layout_values(const clr_sample_request *requests, int32_t count,
                                            int32_t *values_per_sample);

/* Output layout, for pixel (px,py), sample s (relative to first_sample) and value k:
 *   values [((py - y0) * width + (px - x0)) * sample_count + s) * values_per_sample + k]
 *   indices[((py - y0) * width + (px - x0)) * sample_count + s]   (global index, halton/sobol)
 * Values of an array request are element-major: element j's 2 values are adjacent. */
typedef struct clr_sample_output {
  size_t struct_size;     /* sizeof(clr_sample_output), set by clr_sample_output_init */
  cl_mem device_values;   /* optional: float buffer of at least the batch's size */
  float *host_values;     /* optional host copy */
  uint64_t *host_indices; /* optional host copy of global indices (halton, sobol only) */
} clr_sample_output;

CLR_API void clr_sample_output_init(clr_sample_output *out);

/* Generate on the context's device. If device_values is NULL a temporary buffer is used (needs
 * host_values). */
CLR_API clr_result clr_sampler_generate(clr_sampler sampler, const clr_sample_batch *batch,
                                        const clr_sample_output *out);
/* Same values computed on the host by the C build of the kernel headers (single thread): the
 * reference the device output is compared against. device_values is ignored. */
CLR_API clr_result clr_sampler_generate_reference(clr_sampler sampler,
                                                  const clr_sample_batch *batch,
                                                  const clr_sample_output *out);

/* One sample of one pixel, for clr_sampler_generate_at. */
typedef struct clr_sample_point {
  int32_t x, y;   /* the pixel, inside the sample bounds */
  int32_t sample; /* 0 .. clr_sampler_spp - 1 */
} clr_sample_point;

/* Values [first_value, first_value + value_count) of the sample vectors of `count` samples in
 * the layout `requests`: values[i * value_count + k] is value first_value + k of the vector of
 * points[i], the same float that clr_sampler_generate_reference (and so clr_sampler_generate)
 * writes for that pixel and sample with that layout. Computed on the host by the C build of the
 * kernel headers, only the values asked for: an integrator can fetch the values of a path's
 * deeper bounces when the path gets there. Only for samplers with a global index
 * (clr_sampler_has_global_index: pbrt-v3's halton and sobol), whose values are a function of
 * (pixel, sample, dimension); CLR_ERROR_INVALID_ARGUMENT for the others. Errors name the
 * argument (a point outside the sample bounds or spp, a value range outside the layout).
 * Thread-safe, no lock (as clr_sampler_generate_reference). */
CLR_API clr_result clr_sampler_generate_at(clr_sampler sampler, const clr_sample_request *requests,
                                           int32_t request_count, const clr_sample_point *points,
                                           int32_t count, int32_t first_value, int32_t value_count,
                                           float *values);

/* A layout prepared for repeated fetches (clr_sampler_generate_at without the per-call layout
 * checks, slot setup and table lookup): create once per layout, fetch from any number of threads
 * at the same time (the handle is read only after creation; no lock), release when done. The
 * handle retains its sampler. clr_sample_fetch_create fails as clr_sampler_generate_at does for
 * the sampler or the layout (NULL sampler or out, a sampler without a global index, a bad
 * request), naming the argument; *out is NULL then. */
typedef struct clr_sample_fetch_t *clr_sample_fetch;
CLR_API clr_result clr_sample_fetch_create(clr_sampler sampler, const clr_sample_request *requests,
                                           int32_t request_count, clr_sample_fetch *out);
/* The same floats as clr_sampler_generate_at(sampler, requests, request_count, points, count,
 * first_value, value_count, values) with the handle's sampler and layout; each point and the
 * value range are still checked (errors name them). */
CLR_API clr_result clr_sample_fetch_values(clr_sample_fetch fetch, const clr_sample_point *points,
                                           int32_t count, int32_t first_value, int32_t value_count,
                                           float *values);
CLR_API void clr_sample_fetch_release(clr_sample_fetch fetch);

#ifdef __cplusplus
}
#endif
#endif
