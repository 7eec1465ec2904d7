/* Sampler objects: pbrt-v3 parameters and validation, the request layout resolved per sampler
 * family, and sample generation on the device or with the host reference. */
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "clrender/sampler.h"
#include "film_geometry.h"
#include "global_sampler_funcs.h"
#include "halton_host.h"
#include "halton_tables.h"
#include "pbrt_v4_sampler_funcs.h"
#include "pixel_sampler_funcs.h"
#include "pmj02_tables.h"
#include "sampler_device.h"
#include "sobol_tables.h"

/* Upper bound on one batch: values are addressed with 32-bit item indices on the device. */
#define CLR_MAX_BATCH_VALUES ((size_t)1 << 31)
/* 02sequence, maxmindist: most points (spp x array size) one pixel's scratch holds (2 floats
 * each). */
#define CLR_ZEROTWO_MAX_POINTS (1 << 22)

struct clr_sampler_t {
  atomic_int refcount;
  clr_context ctx;
  clr_sampler_desc desc;
  clr_sampler_params base; /* everything but the batch fields */
  clr_bounds2i pixel_bounds, sample_bounds, index_bounds;
  clr_sampler_device *device;   /* kernels and buffers on ctx (NULL without a context) */
  float *pmj_pixels;            /* pmj02bn: GetPixel2D table (clr_pmj02_pixel_table) */
  pthread_mutex_t pairs_lock;   /* guards pairs */
  clr_halton_host_pairs *pairs; /* halton: the host's pair tables (halton_pairs), or NULL */
};

static const char *const sampler_names[CLR_SAMPLER_TYPE_COUNT] = {
    "random",     "stratified",  "halton",      "sobol",  "02sequence",
    "maxmindist", "independent", "paddedsobol", "zsobol", "pmj02bn"};
static const char *const randomization_names[] = {"default", "none", "permutedigits", "fastowen",
                                                  "owen"};
#define RANDOMIZATION_NAME_COUNT ((int)(sizeof randomization_names / sizeof randomization_names[0]))
#define SAMPLER_NAME_COUNT ((int)(sizeof sampler_names / sizeof sampler_names[0]))

const char *clr_sampler_type_name(clr_sampler_type type) {
  return (unsigned)type < (unsigned)SAMPLER_NAME_COUNT ? sampler_names[type] : "unknown";
}

const char *clr_randomization_name(clr_randomization r) {
  return (unsigned)r < (unsigned)RANDOMIZATION_NAME_COUNT ? randomization_names[r] : "unknown";
}

clr_result clr_randomization_from_name(const char *name, clr_randomization *out) {
  if (!name || !out)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_randomization_from_name: NULL argument");
  for (int i = 0; i < RANDOMIZATION_NAME_COUNT; ++i)
    if (strcmp(name, randomization_names[i]) == 0) {
      *out = (clr_randomization)i;
      return CLR_SUCCESS;
    }
  return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                  "unknown randomization \"%s\" (expected none, permutedigits, fastowen or owen)",
                  name);
}

static int32_t round_up_pow2(int32_t v);

int32_t clr_sampler_round_count(clr_sampler_type type, int32_t count) {
  if ((type == CLR_SAMPLER_ZEROTWO || type == CLR_SAMPLER_MAXMINDIST) && count > 0 &&
      count <= (1 << 30))
    return round_up_pow2(count);
  return count;
}

clr_result clr_sampler_type_from_name(const char *name, clr_sampler_type *type) {
  if (!name || !type)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_sampler_type_from_name: NULL argument");
  for (int i = 0; i < SAMPLER_NAME_COUNT; ++i)
    if (strcmp(name, sampler_names[i]) == 0) {
      *type = (clr_sampler_type)i;
      return CLR_SUCCESS;
    }
  if (strcmp(name, "lowdiscrepancy") == 0) { /* pbrt-v3's alias */
    *type = CLR_SAMPLER_ZEROTWO;
    return CLR_SUCCESS;
  }
  return clr_fail(NULL, CLR_ERROR_INVALID_SAMPLER,
                  "unknown sampler \"%s\" (expected random, stratified, halton, sobol, "
                  "02sequence, maxmindist, independent, paddedsobol, zsobol or pmj02bn)",
                  name);
}

void clr_sampler_desc_init(clr_sampler_desc *desc, clr_sampler_type type) {
  if (!desc) return;
  memset(desc, 0, sizeof *desc);
  desc->struct_size = sizeof *desc;
  desc->type = type;
  desc->pixel_samples = type == CLR_SAMPLER_RANDOM || type == CLR_SAMPLER_INDEPENDENT ? 4 : 16;
  desc->x_samples = desc->y_samples = 4;
  desc->jitter = 1;
  desc->dimensions = 4;
  desc->seeding = CLR_SEEDING_PIXEL;
  desc->film.x_resolution = 1280;
  desc->film.y_resolution = 720;
  desc->film.crop_window[1] = desc->film.crop_window[3] = 1.0f;
  desc->film.filter_radius[0] = desc->film.filter_radius[1] = 0.5f;
}

void clr_sample_batch_init(clr_sample_batch *batch) {
  if (!batch) return;
  memset(batch, 0, sizeof *batch);
  batch->struct_size = sizeof *batch;
}

void clr_sample_output_init(clr_sample_output *out) {
  if (!out) return;
  memset(out, 0, sizeof *out);
  out->struct_size = sizeof *out;
}

static int32_t round_up_pow2(int32_t v) {
  int32_t p = 1;
  while (p < v) p <<= 1;
  return p;
}

/* pbrt-v4's algorithm for this sampler, 0 for pbrt-v3's. */
static int v4_sampler_of(const clr_sampler_desc *d) {
  switch (d->type) {
    case CLR_SAMPLER_INDEPENDENT:
      return CLR_V4_INDEPENDENT;
    case CLR_SAMPLER_PADDEDSOBOL:
      return CLR_V4_PADDEDSOBOL;
    case CLR_SAMPLER_ZSOBOL:
      return CLR_V4_ZSOBOL;
    case CLR_SAMPLER_PMJ02BN:
      return CLR_V4_PMJ02BN;
    default:
      break;
  }
  if (d->seeding != CLR_SEEDING_PBRT_V4) return 0;
  switch (d->type) {
    case CLR_SAMPLER_RANDOM:
      return CLR_V4_INDEPENDENT;
    case CLR_SAMPLER_STRATIFIED:
      return CLR_V4_STRATIFIED;
    case CLR_SAMPLER_HALTON:
      return CLR_V4_HALTON;
    case CLR_SAMPLER_SOBOL:
      return CLR_V4_SOBOL;
    default:
      return 0;
  }
}

/* The randomization a pbrt-v4 sampler runs (its pbrt-v4 default for DEFAULT). */
static int v4_randomization(int v4, clr_randomization r) {
  if (r != CLR_RANDOMIZATION_DEFAULT) return (int)r;
  if (v4 == CLR_V4_HALTON) return CLR_RANDOMIZE_TYPE_PERMUTEDIGITS;
  if (v4 == CLR_V4_SOBOL || v4 == CLR_V4_PADDEDSOBOL || v4 == CLR_V4_ZSOBOL)
    return CLR_RANDOMIZE_TYPE_FASTOWEN;
  return CLR_RANDOMIZE_TYPE_NONE;
}

static clr_result validate_v4(const clr_sampler_desc *d) {
  int v4 = v4_sampler_of(d);
  if (d->seeding == CLR_SEEDING_PBRT_V4 && !v4)
    return clr_fail(NULL, CLR_ERROR_INVALID_SAMPLER,
                    "%s sampler: not a pbrt-v4 sampler (seeding pbrt-v4 takes independent, "
                    "random, stratified, halton, sobol, paddedsobol or zsobol)",
                    clr_sampler_type_name(d->type));
  if ((unsigned)d->randomization > CLR_RANDOMIZATION_OWEN)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "clr_sampler_create: unknown randomization %d", (int)d->randomization);
  int randomizable =
      v4 == CLR_V4_HALTON || v4 == CLR_V4_SOBOL || v4 == CLR_V4_PADDEDSOBOL || v4 == CLR_V4_ZSOBOL;
  if (d->randomization != CLR_RANDOMIZATION_DEFAULT && !randomizable)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "%s sampler: randomization \"%s\" applies only to pbrt-v4's halton, sobol, "
                    "paddedsobol and zsobol (halton and sobol with seeding pbrt-v4)",
                    clr_sampler_type_name(d->type), clr_randomization_name(d->randomization));
  if (v4 == CLR_V4_HALTON && d->randomization == CLR_RANDOMIZATION_FASTOWEN)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "halton sampler: \"fastowen\" randomization not supported by Halton sampler");
  return CLR_SUCCESS;
}

static clr_result validate_desc(const clr_sampler_desc *d) {
  if ((unsigned)d->type >= CLR_SAMPLER_TYPE_COUNT)
    return clr_fail(NULL, CLR_ERROR_INVALID_SAMPLER, "clr_sampler_create: unknown sampler type %d",
                    (int)d->type);
  if (d->type == CLR_SAMPLER_STRATIFIED) {
    if (d->x_samples <= 0 || d->y_samples <= 0 || d->x_samples > 256 || d->y_samples > 256)
      return clr_fail(NULL, CLR_ERROR_INVALID_SPP,
                      "stratified sampler: xsamples %d and ysamples %d must be in 1..256",
                      (int)d->x_samples, (int)d->y_samples);
    if (d->dimensions <= 0 || d->dimensions > 1024)
      return clr_fail(NULL, CLR_ERROR_INVALID_DIMENSIONS,
                      "stratified sampler: dimensions %d must be in 1..1024", (int)d->dimensions);
  } else if ((d->type == CLR_SAMPLER_ZEROTWO || d->type == CLR_SAMPLER_MAXMINDIST) &&
             (d->dimensions <= 0 || d->dimensions > 1024)) {
    return clr_fail(NULL, CLR_ERROR_INVALID_DIMENSIONS,
                    "%s sampler: dimensions %d must be in 1..1024", clr_sampler_type_name(d->type),
                    (int)d->dimensions);
  } else if (d->type == CLR_SAMPLER_MAXMINDIST &&
             (d->pixel_samples <= 0 || d->pixel_samples >= (1 << CLR_MAXMIN_MATRICES))) {
    /* pbrt-v3 has matrices for up to 2^16 samples; from 2^17 on its CHECK aborts. */
    return clr_fail(NULL, CLR_ERROR_INVALID_SPP,
                    "maxmindist sampler: pixelsamples %d must be in 1..%d", (int)d->pixel_samples,
                    (1 << CLR_MAXMIN_MATRICES) - 1);
  } else if (d->type == CLR_SAMPLER_PMJ02BN &&
             (d->pixel_samples <= 0 || d->pixel_samples > CLR_PMJ02_POINTS)) {
    return clr_fail(NULL, CLR_ERROR_INVALID_SPP,
                    "pmj02bn sampler: pixelsamples %d must be in 1..%d", (int)d->pixel_samples,
                    CLR_PMJ02_POINTS);
  } else if (d->pixel_samples <= 0 || d->pixel_samples > (1 << 20)) {
    return clr_fail(NULL, CLR_ERROR_INVALID_SPP, "%s sampler: pixelsamples %d must be in 1..%d",
                    clr_sampler_type_name(d->type), (int)d->pixel_samples, 1 << 20);
  }
  if ((unsigned)d->seeding > CLR_SEEDING_PBRT_V4)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT, "clr_sampler_create: unknown seeding %d",
                    (int)d->seeding);
  return validate_v4(d);
}

static int32_t log2_int(int32_t v) {
  int32_t l = 0;
  while ((v >> (l + 1)) > 0) ++l;
  return l;
}

/* pbrt-v4: spp as given (zsobol: rounded down to a power of two), Halton's scales and Sobol's
 * resolution from the full film resolution, zsobol's digit count. */
static void fill_v4_params(const clr_sampler_desc *d, clr_sampler_params *p) {
  p->randomization = v4_randomization(p->v4_sampler, d->randomization);
  if (p->v4_sampler != CLR_V4_STRATIFIED) p->spp = d->pixel_samples;
  clr_sampler_params full = *p;
  full.sample_x0 = full.sample_y0 = 0;
  full.sample_x1 = d->film.x_resolution;
  full.sample_y1 = d->film.y_resolution;
  clr_halton_setup(&full);
  clr_sobol_setup(&full);
  if (p->v4_sampler == CLR_V4_HALTON) {
    memcpy(p->halton_scale, full.halton_scale, sizeof p->halton_scale);
    memcpy(p->halton_exponent, full.halton_exponent, sizeof p->halton_exponent);
    memcpy(p->halton_mult_inverse, full.halton_mult_inverse, sizeof p->halton_mult_inverse);
    p->halton_stride = full.halton_stride;
  }
  if (p->v4_sampler == CLR_V4_SOBOL || p->v4_sampler == CLR_V4_ZSOBOL) {
    p->sobol_log2_resolution = full.sobol_log2_resolution;
    p->sobol_resolution = full.sobol_resolution;
  }
  if (p->v4_sampler == CLR_V4_PMJ02BN) p->pmj_tile = clr_pmj02_tile_size(p->spp);
  if (p->v4_sampler == CLR_V4_ZSOBOL) {
    p->zsobol_log2_spp = log2_int(d->pixel_samples);
    p->spp = 1 << p->zsobol_log2_spp;
    p->zsobol_base4_digits = full.sobol_log2_resolution + (p->zsobol_log2_spp + 1) / 2;
  }
}

static void fill_base_params(clr_sampler s) {
  const clr_sampler_desc *d = &s->desc;
  clr_sampler_params *p = &s->base;
  memset(p, 0, sizeof *p);
  p->type = (clr_i32)d->type;
  p->spp = d->type == CLR_SAMPLER_STRATIFIED ? d->x_samples * d->y_samples
           : d->type == CLR_SAMPLER_SOBOL || d->type == CLR_SAMPLER_ZEROTWO ||
                   d->type == CLR_SAMPLER_MAXMINDIST
               ? round_up_pow2(d->pixel_samples)
               : d->pixel_samples;
  p->x_samples = d->x_samples;
  p->y_samples = d->y_samples;
  p->jitter = d->jitter ? 1 : 0;
  p->dimensions = d->dimensions;
  p->sample_pixel_center = d->sample_pixel_center ? 1 : 0;
  p->seeding = (clr_i32)d->seeding;
  p->seed = d->seed;
  p->inv_x_samples = 1.0f / (float)d->x_samples;
  p->inv_y_samples = 1.0f / (float)d->y_samples;
  p->inv_spp = 1.0f / (float)p->spp;
  p->sample_x0 = s->index_bounds.x0;
  p->sample_y0 = s->index_bounds.y0;
  p->sample_x1 = s->index_bounds.x1;
  p->sample_y1 = s->index_bounds.y1;
  p->pixel_x0 = s->pixel_bounds.x0;
  p->pixel_y0 = s->pixel_bounds.y0;
  p->pixel_x1 = s->pixel_bounds.x1;
  p->pixel_y1 = s->pixel_bounds.y1;
  p->tiles_x =
      (s->index_bounds.x1 - s->index_bounds.x0 + CLR_PBRT_TILE_SIZE - 1) / CLR_PBRT_TILE_SIZE;
  if (d->type == CLR_SAMPLER_MAXMINDIST) { /* pbrt-v3: Log2Int of pixelsamples as given */
    p->maxmin_matrix = 0;
    while ((d->pixel_samples >> (p->maxmin_matrix + 1)) > 0) ++p->maxmin_matrix;
  }
  p->v4_sampler = v4_sampler_of(d);
  if (p->v4_sampler) {
    fill_v4_params(d, p);
    return;
  }
  if (d->type == CLR_SAMPLER_HALTON) clr_halton_setup(p);
  if (d->type == CLR_SAMPLER_SOBOL) clr_sobol_setup(p);
}

/* pbrt-v4's Sobol' indices must stay below 2^52 (the generator matrices' columns). */
static clr_result check_v4_limits(const clr_sampler_params *p) {
  if (p->v4_sampler == CLR_V4_SOBOL && (p->sobol_log2_resolution > CLR_SOBOL_VDC_MATRICES ||
                                        p->spp > clr_sobol_max_samples(p->sobol_log2_resolution)))
    return clr_fail(NULL, CLR_ERROR_INVALID_SPP,
                    "sobol sampler: %d samples per pixel at resolution 2^%d exceed pbrt-v4's "
                    "52-bit Sobol' indices",
                    (int)p->spp, (int)p->sobol_log2_resolution);
  if (p->v4_sampler == CLR_V4_ZSOBOL && 2 * p->zsobol_base4_digits > CLR_SOBOL_INDEX_BITS)
    return clr_fail(NULL, CLR_ERROR_INVALID_SPP,
                    "zsobol sampler: %d samples per pixel at resolution 2^%d exceed pbrt-v4's "
                    "52-bit Sobol' indices",
                    (int)p->spp, (int)p->sobol_log2_resolution);
  return CLR_SUCCESS;
}

clr_result clr_sampler_create(clr_context ctx, const clr_sampler_desc *desc, clr_sampler *out) {
  clr_clear_error();
  if (!desc || !out)
    return clr_fail(ctx, CLR_ERROR_NULL_POINTER, "clr_sampler_create: desc or out is NULL");
  *out = NULL;
  clr_sampler_desc adopted;
  int has_type = desc->struct_size >= offsetof(clr_sampler_desc, type) + sizeof desc->type;
  clr_sampler_desc_init(&adopted, has_type ? desc->type : CLR_SAMPLER_RANDOM);
  CLR_CHECK(clr_desc_adopt(&adopted, sizeof adopted, desc, "clr_sampler_create: desc"));
  desc = &adopted;
  CLR_CHECK(validate_desc(desc));
  clr_bounds2i pixel_bounds, sample_bounds, full_sample_bounds;
  CLR_CHECK(
      clr_film_geometry_bounds(&desc->film, "clr_sampler_create", &pixel_bounds, &sample_bounds));
  clr_film_geometry full = desc->film;
  full.crop_window[0] = full.crop_window[2] = 0.0f;
  full.crop_window[1] = full.crop_window[3] = 1.0f;
  CLR_CHECK(clr_film_geometry_bounds(&full, "clr_sampler_create", NULL, &full_sample_bounds));
  clr_sampler s = calloc(1, sizeof *s);
  if (!s) return clr_fail(ctx, CLR_ERROR_OUT_OF_MEMORY, "clr_sampler_create: out of memory");
  atomic_init(&s->refcount, 1);
  s->desc = *desc;
  s->pixel_bounds = pixel_bounds;
  s->sample_bounds = sample_bounds;
  /* Our mode indexes over the full frame so crops reproduce the full render; pbrt-v3 re-indexes
   * over the cropped sample bounds. */
  s->index_bounds = desc->seeding == CLR_SEEDING_PBRT_V3 ? sample_bounds : full_sample_bounds;
  fill_base_params(s);
  clr_result limits = check_v4_limits(&s->base);
  if (limits != CLR_SUCCESS) {
    free(s);
    return limits;
  }
  if (desc->type == CLR_SAMPLER_SOBOL && !s->base.v4_sampler &&
      s->base.sobol_log2_resolution > CLR_SOBOL_VDC_MATRICES) {
    free(s);
    return clr_fail(ctx, CLR_ERROR_INVALID_RESOLUTION,
                    "sobol sampler: sample bounds of %dx%d exceed the 2^%d supported",
                    (int)(sample_bounds.x1 - sample_bounds.x0),
                    (int)(sample_bounds.y1 - sample_bounds.y0), CLR_SOBOL_VDC_MATRICES);
  }
  if (desc->type == CLR_SAMPLER_SOBOL && !s->base.v4_sampler &&
      s->base.spp > clr_sobol_max_samples(s->base.sobol_log2_resolution)) {
    int64_t most = clr_sobol_max_samples(s->base.sobol_log2_resolution);
    free(s);
    return clr_fail(ctx, CLR_ERROR_INVALID_SPP,
                    "sobol sampler: %d samples per pixel exceed the %lld that 52-bit indices "
                    "give at this resolution",
                    (int)desc->pixel_samples, (long long)most);
  }
  if (s->base.v4_sampler == CLR_V4_PMJ02BN &&
      !(s->pmj_pixels = clr_pmj02_pixel_table(s->base.spp, s->base.pmj_tile))) {
    free(s);
    return clr_fail(ctx, CLR_ERROR_OUT_OF_MEMORY, "clr_sampler_create: out of memory");
  }
  if (ctx) {
    clr_result r = clr_sampler_device_create(ctx, &s->device);
    if (r != CLR_SUCCESS) {
      free(s->pmj_pixels);
      free(s);
      return r;
    }
    clr_context_retain(ctx);
  }
  pthread_mutex_init(&s->pairs_lock, NULL);
  s->ctx = ctx;
  *out = s;
  return CLR_SUCCESS;
}

void clr_sampler_retain(clr_sampler s) {
  if (s) atomic_fetch_add(&s->refcount, 1);
}

void clr_sampler_release(clr_sampler s) {
  if (!s || atomic_fetch_sub(&s->refcount, 1) != 1) return;
  clr_sampler_device_release(s->device);
  clr_context_release(s->ctx);
  free(s->pmj_pixels);
  clr_halton_host_pairs_free(s->pairs);
  pthread_mutex_destroy(&s->pairs_lock);
  free(s);
}

int32_t clr_sampler_spp(clr_sampler s) { return s ? s->base.spp : 0; }
clr_bounds2i clr_sampler_sample_bounds(clr_sampler s) {
  clr_bounds2i none = {0, 0, 0, 0};
  return s ? s->sample_bounds : none;
}
clr_bounds2i clr_sampler_pixel_bounds(clr_sampler s) {
  clr_bounds2i none = {0, 0, 0, 0};
  return s ? s->pixel_bounds : none;
}
int clr_sampler_has_global_index(clr_sampler s) {
  return s && !s->base.v4_sampler &&
         (s->desc.type == CLR_SAMPLER_HALTON || s->desc.type == CLR_SAMPLER_SOBOL);
}

/* A request's dims without CLR_SAMPLE_REQUEST_SKIPPED, and whether it is skipped. */
static int32_t request_dims(const clr_sample_request *r) {
  return r->dims & ~CLR_SAMPLE_REQUEST_SKIPPED;
}
static int request_skipped(const clr_sample_request *r) {
  return (r->dims & CLR_SAMPLE_REQUEST_SKIPPED) != 0;
}

/* The values the layout stores (skipped requests have none); *film_request receives the index
 * of the 2D film offset: the first request, or with leading_1d (pbrt-v4 samplers, whose
 * integrators may take 1D values such as the wavelengths before GetPixel2D) the first 2D
 * request. The limits count every request, skipped or not. */
static clr_result layout_values(const clr_sample_request *requests, int32_t count, int leading_1d,
                                int32_t *values_per_sample, int32_t *film_request) {
  if (!values_per_sample || (count > 0 && !requests))
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "sample layout: NULL requests or result");
  if (count <= 0 || count > CLR_MAX_REQUESTS)
    return clr_fail(NULL, CLR_ERROR_INVALID_REQUESTS, "sample layout: %d requests (must be 1..%d)",
                    (int)count, CLR_MAX_REQUESTS);
  int32_t f = 0;
  while (leading_1d && f + 1 < count && request_dims(&requests[f]) == 1) ++f;
  if (request_dims(&requests[f]) != 2 || requests[f].array_size != 0)
    return clr_fail(NULL, CLR_ERROR_INVALID_REQUESTS,
                    "sample layout: the %s request must be the 2D film offset (got dims %d, "
                    "array %d)",
                    leading_1d ? "first 2D" : "first", (int)requests[f].dims,
                    (int)requests[f].array_size);
  if (request_skipped(&requests[f]))
    return clr_fail(NULL, CLR_ERROR_INVALID_REQUESTS,
                    "sample layout: request %d, the film offset, cannot be skipped (dims 0x%x)",
                    (int)f, (unsigned)requests[f].dims);
  *film_request = f;
  int64_t total = 0, stored = 0;
  for (int32_t i = 0; i < count; ++i) {
    const clr_sample_request *r = &requests[i];
    if (request_dims(r) != 1 && request_dims(r) != 2)
      return clr_fail(NULL, CLR_ERROR_INVALID_REQUESTS,
                      "sample layout: request %d has dims %d (0x%x; must be 1 or 2, optionally "
                      "| CLR_SAMPLE_REQUEST_SKIPPED)",
                      (int)i, (int)r->dims, (unsigned)r->dims);
    if (r->array_size < 0 || r->array_size > CLR_MAX_VALUES_PER_SAMPLE)
      return clr_fail(NULL, CLR_ERROR_REQUEST_TOO_LARGE,
                      "sample layout: request %d has array size %d (must be 0..%d)", (int)i,
                      (int)r->array_size, CLR_MAX_VALUES_PER_SAMPLE);
    int64_t values = (int64_t)request_dims(r) * (r->array_size ? r->array_size : 1);
    total += values;
    stored += request_skipped(r) ? 0 : values;
  }
  if (total > CLR_MAX_VALUES_PER_SAMPLE)
    return clr_fail(NULL, CLR_ERROR_REQUEST_TOO_LARGE,
                    "sample layout: %lld values per sample exceed the limit of %d",
                    (long long)total, CLR_MAX_VALUES_PER_SAMPLE);
  *values_per_sample = (int32_t)stored;
  return CLR_SUCCESS;
}

clr_result clr_sample_layout_values(const clr_sample_request *requests, int32_t count,
                                    int32_t *values_per_sample) {
  int32_t film_request = 0;
  return layout_values(requests, count, 0, values_per_sample, &film_request);
}

/* pbrt-v3 GlobalSampler: singles take consecutive dimensions, skipping the array block that
 * starts at dimension 5; 1D arrays then 2D arrays occupy that block. */
static void resolve_global_slots(const clr_sample_batch *b, clr_request_slot *slots) {
  int n1 = 0, n2 = 0;
  for (int i = 0; i < b->request_count; ++i)
    if (slots[i].array_size) ++*(slots[i].dims == 1 ? &n1 : &n2);
  int array_end = CLR_GLOBAL_ARRAY_START_DIM + n1 + 2 * n2;
  int dimension = 0, a1 = 0, a2 = 0;
  for (int i = 0; i < b->request_count; ++i) {
    clr_request_slot *s = &slots[i];
    if (s->array_size) {
      s->source = s->dims == 1 ? CLR_GLOBAL_ARRAY_START_DIM + a1++
                               : CLR_GLOBAL_ARRAY_START_DIM + n1 + 2 * a2++;
    } else if (s->dims == 1) {
      if (dimension >= CLR_GLOBAL_ARRAY_START_DIM && dimension < array_end) dimension = array_end;
      s->source = dimension++;
    } else {
      if (dimension + 1 >= CLR_GLOBAL_ARRAY_START_DIM && dimension < array_end)
        dimension = array_end;
      s->source = dimension;
      dimension += 2;
    }
  }
}

/* pbrt-v3 PixelSampler: singles read the next 1D/2D stream while any is left, then draw from
 * the RNG; RandomSampler draws every single value. Returns the RNG draws per sample. */
static int resolve_pixel_slots(const clr_sample_batch *b, const clr_sampler_params *p,
                               clr_request_slot *slots) {
  int streams = p->type == CLR_SAMPLER_STRATIFIED || p->type == CLR_SAMPLER_ZEROTWO ||
                        p->type == CLR_SAMPLER_MAXMINDIST
                    ? p->dimensions
                    : 0;
  int n1 = 0, n2 = 0, a1 = 0, a2 = 0, draws = 0;
  for (int i = 0; i < b->request_count; ++i) {
    clr_request_slot *s = &slots[i];
    if (s->array_size) {
      s->source = s->dims == 1 ? a1++ : a2++;
      continue;
    }
    int *used = s->dims == 1 ? &n1 : &n2;
    if (*used < streams) {
      s->source = (*used)++;
    } else {
      s->source = -1;
      s->rng_offset = draws;
      draws += s->dims;
    }
  }
  return draws;
}

static clr_result prepare_batch(clr_sampler s, const clr_sample_batch *b, clr_sampler_params *p,
                                clr_request_slot *slots) {
  if (!b) return clr_fail(s->ctx, CLR_ERROR_NULL_POINTER, "clr_sampler_generate: batch is NULL");
  clr_sample_batch full;
  clr_sample_batch_init(&full);
  CLR_CHECK(clr_desc_adopt(&full, sizeof full, b, "clr_sampler_generate: batch"));
  b = &full;
  int32_t values = 0;
  int32_t film_request = 0;
  CLR_CHECK(layout_values(b->requests, b->request_count, s->base.v4_sampler != 0, &values,
                          &film_request));
  const clr_bounds2i r = b->pixels, ib = s->index_bounds;
  if (r.x1 <= r.x0 || r.y1 <= r.y0 || r.x0 < ib.x0 || r.y0 < ib.y0 || r.x1 > ib.x1 || r.y1 > ib.y1)
    return clr_fail(s->ctx, CLR_ERROR_INVALID_PIXEL_RANGE,
                    "clr_sampler_generate: pixels [%d,%d)x[%d,%d) are empty or outside the "
                    "sample bounds [%d,%d)x[%d,%d)",
                    (int)r.x0, (int)r.x1, (int)r.y0, (int)r.y1, (int)ib.x0, (int)ib.x1, (int)ib.y0,
                    (int)ib.y1);
  *p = s->base;
  int32_t count = b->sample_count ? b->sample_count : p->spp;
  if (b->first_sample < 0 || count < 0 || b->first_sample + (int64_t)count > p->spp)
    return clr_fail(s->ctx, CLR_ERROR_INVALID_SPP,
                    "clr_sampler_generate: samples [%d, %d) outside the %d samples per pixel",
                    (int)b->first_sample, (int)(b->first_sample + count), (int)p->spp);
  size_t total = (size_t)(r.x1 - r.x0) * (size_t)(r.y1 - r.y0) * (size_t)count * (size_t)values;
  if (total > CLR_MAX_BATCH_VALUES)
    return clr_fail(s->ctx, CLR_ERROR_REQUEST_TOO_LARGE,
                    "clr_sampler_generate: batch of %zu values exceeds the limit of %zu", total,
                    CLR_MAX_BATCH_VALUES);
  p->batch_x0 = r.x0;
  p->batch_y0 = r.y0;
  p->batch_width = r.x1 - r.x0;
  p->batch_height = r.y1 - r.y0;
  p->first_sample = b->first_sample;
  p->sample_count = count;
  p->values_per_sample = values;
  p->request_count = b->request_count;
  p->film_request = film_request;
  int offset = 0, max_array = 0;
  for (int i = 0; i < b->request_count; ++i) {
    clr_request_slot *sl = &slots[i];
    memset(sl, 0, sizeof *sl);
    sl->dims = request_dims(&b->requests[i]);
    sl->array_size = b->requests[i].array_size;
    sl->skipped = request_skipped(&b->requests[i]);
    sl->first_value = offset;
    sl->inv_array_size = sl->array_size ? 1.0f / (float)sl->array_size : 0.0f;
    if (!sl->skipped) offset += sl->dims * (sl->array_size ? sl->array_size : 1);
    if (sl->array_size > max_array) max_array = sl->array_size;
  }
  if (p->type == CLR_SAMPLER_TYPE_SOBOL && (int64_t)p->spp * (max_array ? max_array : 1) >
                                               clr_sobol_max_samples(p->sobol_log2_resolution))
    return clr_fail(s->ctx, CLR_ERROR_REQUEST_TOO_LARGE,
                    "sobol sampler: arrays of %d elements x %d spp exceed the 52-bit index space",
                    max_array, (int)p->spp);
  /* 02sequence, maxmindist: a pixel's VanDerCorput/Sobol2D of an array holds size * spp points. */
  if ((p->type == CLR_SAMPLER_TYPE_ZEROTWO || p->type == CLR_SAMPLER_TYPE_MAXMINDIST) &&
      (int64_t)p->spp * (max_array ? max_array : 1) > CLR_ZEROTWO_MAX_POINTS)
    return clr_fail(s->ctx, CLR_ERROR_REQUEST_TOO_LARGE,
                    "%s sampler: arrays of %d elements x %d spp exceed the %d points one "
                    "pixel may hold",
                    clr_sampler_type_name(s->desc.type), max_array, (int)p->spp,
                    CLR_ZEROTWO_MAX_POINTS);
  if (p->v4_sampler) {
    /* pbrt-v4 samplers walk the layout in order (pbrt_v4_sampler_funcs.h). */
  } else if (clr_sampler_has_global_index(s)) {
    resolve_global_slots(b, slots);
  } else {
    p->fallback_draws_per_sample = resolve_pixel_slots(b, p, slots);
    p->scratch_floats = clr_pixel_sampler_scratch_need(p, slots);
  }
  return CLR_SUCCESS;
}

static size_t batch_items(const clr_sampler_params *p) {
  return (size_t)p->batch_width * (size_t)p->batch_height * (size_t)p->sample_count;
}

static int pbrt_tiles(const clr_sampler_params *p, int *tx0, int *ty0, int *wide, int *high) {
  *tx0 = (p->batch_x0 - p->sample_x0) / CLR_PBRT_TILE_SIZE;
  *ty0 = (p->batch_y0 - p->sample_y0) / CLR_PBRT_TILE_SIZE;
  int tx1 = (p->batch_x0 + p->batch_width - 1 - p->sample_x0) / CLR_PBRT_TILE_SIZE;
  int ty1 = (p->batch_y0 + p->batch_height - 1 - p->sample_y0) / CLR_PBRT_TILE_SIZE;
  *wide = tx1 - *tx0 + 1;
  *high = ty1 - *ty0 + 1;
  return *wide * *high;
}

/* The host's pair tables for a halton layout (its dimensions; indices below stride x spp x the
 * largest array), built on first need and kept by the sampler (older sets too: other threads may
 * still read them); NULL when out of memory (the chunk loop then serves every value). */
static const clr_halton_host_pairs *halton_pairs(clr_sampler s, const clr_sampler_params *p,
                                                 const clr_request_slot *slots) {
  int dims = clr_halton_layout_dimensions(slots, p->request_count);
  if (dims > CLR_HALTON_PRIMES) dims = CLR_HALTON_PRIMES; /* past them: no tables */
  uint64_t elements = 1;
  for (int r = 0; r < p->request_count; ++r)
    if ((uint64_t)slots[r].array_size > elements) elements = (uint64_t)slots[r].array_size;
  uint64_t limit = (uint64_t)s->base.halton_stride * (uint64_t)s->base.spp;
  limit = limit > UINT64_MAX / elements ? UINT64_MAX : limit * elements;
  pthread_mutex_lock(&s->pairs_lock);
  clr_halton_host_pairs *hp = s->pairs;
  if (!hp || hp->dimensions < dims || hp->index_limit < limit) {
    clr_halton_host_pairs *made = clr_halton_host_pairs_create(
        hp && hp->dimensions > dims ? hp->dimensions : dims,
        hp && hp->index_limit > limit ? hp->index_limit : limit, (clr_u32)s->base.halton_scale[1]);
    if (made) {
      made->older = hp;
      s->pairs = made;
    }
    hp = made ? made : hp && hp->dimensions >= dims ? hp : NULL;
  }
  pthread_mutex_unlock(&s->pairs_lock);
  return hp;
}

clr_result clr_sampler_generate_reference(clr_sampler s, const clr_sample_batch *batch,
                                          const clr_sample_output *out) {
  clr_clear_error();
  if (!s || !out)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_sampler_generate_reference: NULL argument");
  clr_sample_output full;
  clr_sample_output_init(&full);
  CLR_CHECK(clr_desc_adopt(&full, sizeof full, out, "clr_sampler_generate_reference: out"));
  out = &full;
  clr_sampler_params p;
  clr_request_slot slots[CLR_MAX_REQUESTS];
  CLR_CHECK(prepare_batch(s, batch, &p, slots));
  size_t items = batch_items(&p);
  float *values = out->host_values;
  float *owned = NULL;
  if (!values) values = owned = malloc(items * (size_t)p.values_per_sample * sizeof(float));
  if (!values) return clr_fail(s->ctx, CLR_ERROR_OUT_OF_MEMORY, "reference: out of memory");
  const clr_halton_host_pairs *pairs = NULL;
  if (p.v4_sampler) {
    clr_v4_tables t = {clr_sobol_matrices32,
                       &clr_vdc_sobol_matrices[0][0],
                       &clr_vdc_sobol_matrices_inv[0][0],
                       clr_halton_primes(),
                       s->pmj_pixels,
                       s->pmj_pixels ? s->pmj_pixels + clr_v4_pmj02_pixel_floats(&p) : NULL,
                       NULL, /* halton's digit permutations computed per digit */
                       NULL,
                       0,
                       NULL}; /* sobol by its columns */
    for (size_t i = 0; i < items; ++i)
      clr_v4_sample_vector(&p, slots, &t, (clr_i32)i, values + i * (size_t)p.values_per_sample);
    if (out->host_indices)
      for (size_t i = 0; i < items; ++i) out->host_indices[i] = UINT64_MAX;
  } else if (p.type == CLR_SAMPLER_TYPE_HALTON && (pairs = halton_pairs(s, &p, slots)) != NULL) {
    clr_halton_host_batch(pairs, &p, slots, values, out->host_indices);
  } else if (clr_sampler_has_global_index(s)) {
    const clr_halton_prime *primes = NULL;
    const clr_u16 *perms = NULL;
    if (p.type == CLR_SAMPLER_TYPE_HALTON) {
      const clr_halton_tables *t =
          clr_halton_tables_covering(clr_halton_layout_dimensions(slots, p.request_count));
      primes = t->primes;
      perms = t->permutations;
    }
    uint64_t dummy = 0;
    for (size_t i = 0; i < items; ++i)
      clr_global_sample_vector(&p, slots, clr_sobol_matrices32, &clr_vdc_sobol_matrices[0][0],
                               &clr_vdc_sobol_matrices_inv[0][0], primes, perms, (clr_i32)i,
                               values + i * (size_t)p.values_per_sample,
                               out->host_indices ? &out->host_indices[i] : &dummy);
  } else {
    float *scratch = malloc((size_t)p.scratch_floats * sizeof(float) + 4);
    if (!scratch) {
      free(owned);
      return clr_fail(s->ctx, CLR_ERROR_OUT_OF_MEMORY, "reference: out of memory");
    }
    size_t per_pixel = (size_t)p.sample_count * (size_t)p.values_per_sample;
    if (p.seeding == CLR_SEEDING_TYPE_PIXEL) {
      for (int y = 0; y < p.batch_height; ++y)
        for (int x = 0; x < p.batch_width; ++x)
          clr_pixel_sampler_pixel(&p, slots, p.batch_x0 + x, p.batch_y0 + y,
                                  values + ((size_t)y * p.batch_width + x) * per_pixel, scratch);
    } else {
      int tx0, ty0, wide, high;
      int tiles = pbrt_tiles(&p, &tx0, &ty0, &wide, &high);
      for (int t = 0; t < tiles; ++t)
        clr_pixel_sampler_tile(&p, slots, tx0 + t % wide, ty0 + t / wide, values, scratch);
    }
    free(scratch);
    if (out->host_indices)
      for (size_t i = 0; i < items; ++i) out->host_indices[i] = UINT64_MAX;
  }
  free(owned);
  return CLR_SUCCESS;
}

clr_result clr_sampler_generate(clr_sampler s, const clr_sample_batch *batch,
                                const clr_sample_output *out) {
  clr_clear_error();
  if (!s || !out)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_sampler_generate: NULL argument");
  if (!s->ctx)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "clr_sampler_generate: sampler was created without a context (reference only)");
  clr_sample_output full;
  clr_sample_output_init(&full);
  CLR_CHECK(clr_desc_adopt(&full, sizeof full, out, "clr_sampler_generate: out"));
  out = &full;
  if (!out->device_values && !out->host_values)
    return clr_fail(s->ctx, CLR_ERROR_NULL_POINTER,
                    "clr_sampler_generate: neither device_values nor host_values given");
  clr_sampler_params p;
  clr_request_slot slots[CLR_MAX_REQUESTS];
  CLR_CHECK(prepare_batch(s, batch, &p, slots));
  return clr_sampler_device_generate(s->device, &p, slots, s->pmj_pixels, out);
}

/* The checks of one point of call `fn`: inside the sample bounds and the spp. */
static clr_result check_point(clr_sampler s, const char *fn, const clr_sample_point *pt,
                              int32_t i) {
  const clr_bounds2i ib = s->index_bounds;
  if (pt->x < ib.x0 || pt->x >= ib.x1 || pt->y < ib.y0 || pt->y >= ib.y1)
    return clr_fail(s->ctx, CLR_ERROR_INVALID_PIXEL_RANGE,
                    "%s: points[%d] pixel (%d, %d) outside the sample bounds [%d,%d)x[%d,%d)", fn,
                    (int)i, (int)pt->x, (int)pt->y, (int)ib.x0, (int)ib.x1, (int)ib.y0, (int)ib.y1);
  if (pt->sample < 0 || pt->sample >= s->base.spp)
    return clr_fail(s->ctx, CLR_ERROR_INVALID_SPP,
                    "%s: points[%d] sample %d outside the %d samples per pixel", fn, (int)i,
                    (int)pt->sample, (int)s->base.spp);
  return CLR_SUCCESS;
}

/* Values a request stores: dims times its elements, none when skipped. */
static int32_t slot_values(const clr_request_slot *sl) {
  return sl->skipped ? 0 : sl->dims * (sl->array_size ? sl->array_size : 1);
}

/* Points per block of global_values_at: their indices on the stack. */
#define AT_BLOCK 256

/* index[i] = clr_global_index of points[i]'s sample number sample * scale + offset; halton:
 * a pixel's offset (sample number 0) once per run of points in that pixel, plus the sample
 * number times the stride (clr_halton_sampler_index's sum, so the same index). */
static void point_indices(const clr_sampler_params *p, const clr_u64 *vdc, const clr_u64 *vdc_inv,
                          const clr_sample_point *points, int32_t n, int32_t scale, int32_t offset,
                          clr_u64 *index) {
  if (p->type != CLR_SAMPLER_TYPE_HALTON) {
    for (int32_t i = 0; i < n; ++i)
      index[i] = clr_global_index(p, vdc, vdc_inv, points[i].x, points[i].y,
                                  (clr_i64)points[i].sample * scale + offset);
    return;
  }
  const clr_u64 stride = (clr_u64)(clr_u32)p->halton_stride;
  clr_u64 pixel_offset = 0;
  for (int32_t i = 0; i < n; ++i) {
    const clr_sample_point *pt = &points[i];
    if (i == 0 || pt->x != points[i - 1].x || pt->y != points[i - 1].y)
      pixel_offset = clr_halton_sampler_index(p, pt->x, pt->y, 0);
    index[i] = pixel_offset + (clr_u64)((clr_i64)pt->sample * scale + offset) * stride;
  }
}

/* Values [first, end) of the vectors of points[0 .. n) (n <= AT_BLOCK; global samplers) into
 * out[i * (end - first) + k]: the same calls as clr_global_sample_vector, for the requests r0...
 * that the range overlaps, value by value over the points (each dimension's tables stay in
 * cache); halton with `pairs`: their values from clr_halton_host_values (the same bits). */
static void global_values_at(const clr_sampler_params *p, const clr_request_slot *slots, int32_t r0,
                             const clr_halton_host_pairs *pairs, const clr_sample_point *points,
                             int32_t n, int32_t first, int32_t end, float *out) {
  const clr_halton_prime *primes = NULL;
  const clr_u16 *perms = NULL;
  if (p->type == CLR_SAMPLER_TYPE_HALTON && !pairs) {
    const clr_halton_tables *t =
        clr_halton_tables_covering(clr_halton_layout_dimensions(slots, p->request_count));
    primes = t->primes;
    perms = t->permutations;
  }
  const clr_u64 *vdc = &clr_vdc_sobol_matrices[0][0], *vdc_inv = &clr_vdc_sobol_matrices_inv[0][0];
  clr_u64 index[AT_BLOCK], element[AT_BLOCK];
  size_t stride = (size_t)(end - first);
  point_indices(p, vdc, vdc_inv, points, n, 1, 0, index);
  for (int32_t r = r0; r < p->request_count && slots[r].first_value < end; ++r) {
    const clr_request_slot *sl = &slots[r];
    int32_t elements = sl->skipped ? 0 : sl->array_size ? sl->array_size : 1;
    for (int32_t j = 0; j < elements; ++j)
      for (int32_t c = 0; c < sl->dims; ++c) {
        int32_t v = sl->first_value + j * sl->dims + c;
        if (v < first || v >= end) continue;
        if (pairs) {
          if (sl->array_size) point_indices(p, vdc, vdc_inv, points, n, sl->array_size, j, element);
          clr_halton_host_values(pairs, p, sl->source + c, sl->array_size ? element : index, n,
                                 out + (v - first), stride);
          continue;
        }
        for (int32_t i = 0; i < n; ++i) {
          const clr_sample_point *pt = &points[i];
          clr_u64 at = sl->array_size ? clr_global_index(p, vdc, vdc_inv, pt->x, pt->y,
                                                         (clr_i64)pt->sample * sl->array_size + j)
                                      : index[i];
          out[(size_t)i * stride + (size_t)(v - first)] = clr_global_value(
              p, clr_sobol_matrices32, primes, perms, at, sl->source + c, pt->x, pt->y);
        }
      }
  }
}

/* A layout's checked slots for fetching (clr_sample_fetch_create, clr_sampler_generate_at). */
struct clr_sample_fetch_t {
  clr_sampler sampler; /* retained */
  clr_sampler_params p;
  clr_request_slot slots[CLR_MAX_REQUESTS];
  int32_t per_sample;
  const clr_halton_host_pairs *pairs; /* halton: the sampler's pair tables (halton_pairs) */
};

/* The layout's checks and slots, without the handle's allocation. */
static clr_result fetch_prepare(clr_sampler s, const char *fn, const clr_sample_request *requests,
                                int32_t request_count, struct clr_sample_fetch_t *f) {
  if (!clr_sampler_has_global_index(s))
    return clr_fail(s->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "%s: the %s sampler has no global index (only pbrt-v3's halton and sobol)", fn,
                    clr_sampler_type_name(s->desc.type));
  int32_t film_request = 0;
  f->per_sample = 0;
  CLR_CHECK(layout_values(requests, request_count, 0, &f->per_sample, &film_request));
  clr_sample_batch b; /* a one-sample batch gives the slots and the layout's checks */
  clr_sample_batch_init(&b);
  b.requests = requests;
  b.request_count = request_count;
  b.pixels = (clr_bounds2i){s->index_bounds.x0, s->index_bounds.y0, s->index_bounds.x0 + 1,
                            s->index_bounds.y0 + 1};
  b.sample_count = 1;
  CLR_CHECK(prepare_batch(s, &b, &f->p, f->slots));
  f->sampler = s;
  f->pairs = NULL;
  return CLR_SUCCESS;
}

/* Values [first_value, + value_count) of `count` points through a prepared layout; halton with
 * `own_pairs`: the pair tables looked up now (else f's, read only: handles are shared). */
static clr_result fetch_run(const struct clr_sample_fetch_t *f, const char *fn, int own_pairs,
                            const clr_sample_point *points, int32_t count, int32_t first_value,
                            int32_t value_count, float *values) {
  clr_sampler s = f->sampler;
  if (count < 0 || first_value < 0 || value_count < 0 ||
      (int64_t)first_value + value_count > f->per_sample)
    return clr_fail(s->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "%s: %d points, values [%d, %d + %d) outside the layout's %d values", fn,
                    (int)count, (int)first_value, (int)first_value, (int)value_count,
                    (int)f->per_sample);
  for (int32_t i = 0; i < count; ++i) CLR_CHECK(check_point(s, fn, &points[i], i));
  if (count == 0 || value_count == 0) return CLR_SUCCESS;
  const clr_request_slot *slots = f->slots;
  int32_t r0 = 0, end = first_value + value_count;
  while (r0 < f->p.request_count && slots[r0].first_value + slot_values(&slots[r0]) <= first_value)
    ++r0;
  const clr_halton_host_pairs *pairs = f->pairs;
  if (own_pairs && f->p.type == CLR_SAMPLER_TYPE_HALTON) pairs = halton_pairs(s, &f->p, slots);
  for (int32_t i = 0; i < count; i += AT_BLOCK)
    global_values_at(&f->p, slots, r0, pairs, points + i,
                     count - i < AT_BLOCK ? count - i : AT_BLOCK, first_value, end,
                     values + (size_t)i * (size_t)value_count);
  return CLR_SUCCESS;
}

clr_result clr_sampler_generate_at(clr_sampler s, const clr_sample_request *requests,
                                   int32_t request_count, const clr_sample_point *points,
                                   int32_t count, int32_t first_value, int32_t value_count,
                                   float *values) {
  static const char fn[] = "clr_sampler_generate_at";
  clr_clear_error();
  if (!s || (count > 0 && (!points || (value_count > 0 && !values))))
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_sampler_generate_at: NULL argument");
  struct clr_sample_fetch_t f;
  CLR_CHECK(fetch_prepare(s, fn, requests, request_count, &f));
  return fetch_run(&f, fn, 1, points, count, first_value, value_count, values);
}

clr_result clr_sample_fetch_create(clr_sampler s, const clr_sample_request *requests,
                                   int32_t request_count, clr_sample_fetch *out) {
  static const char fn[] = "clr_sample_fetch_create";
  clr_clear_error();
  if (!out) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_sample_fetch_create: NULL out");
  *out = NULL;
  if (!s) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_sample_fetch_create: NULL sampler");
  struct clr_sample_fetch_t *f = malloc(sizeof *f);
  if (!f) return clr_fail(s->ctx, CLR_ERROR_OUT_OF_MEMORY, "clr_sample_fetch_create: handle");
  clr_result r = fetch_prepare(s, fn, requests, request_count, f);
  if (r != CLR_SUCCESS) {
    free(f);
    return r;
  }
  if (f->p.type == CLR_SAMPLER_TYPE_HALTON) f->pairs = halton_pairs(s, &f->p, f->slots);
  clr_sampler_retain(s);
  *out = f;
  return CLR_SUCCESS;
}

clr_result clr_sample_fetch_values(clr_sample_fetch f, const clr_sample_point *points,
                                   int32_t count, int32_t first_value, int32_t value_count,
                                   float *values) {
  clr_clear_error();
  if (!f || (count > 0 && (!points || (value_count > 0 && !values))))
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_sample_fetch_values: NULL %s",
                    !f        ? "fetch"
                    : !points ? "points"
                              : "values");
  return fetch_run(f, "clr_sample_fetch_values", 0, points, count, first_value, value_count,
                   values);
}

void clr_sample_fetch_release(clr_sample_fetch f) {
  if (!f) return;
  clr_sampler_release(f->sampler);
  free(f);
}
