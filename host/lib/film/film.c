/* Film lifetime, pbrt-v3 bounds (crop window, sample bounds), splats, raw sums, merges and the
 * resolve to RGB (pbrt WriteImage). */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "filter_funcs.h"
#include "film_geometry.h"
#include "film_internal.h"

void clr_film_desc_init(clr_film_desc *desc) {
  if (!desc) return;
  memset(desc, 0, sizeof *desc);
  desc->struct_size = sizeof *desc;
  desc->x_resolution = 1280;
  desc->y_resolution = 720;
  desc->crop_window[1] = desc->crop_window[3] = 1.0f;
  desc->scale = 1.0f;
  desc->max_sample_luminance = INFINITY;
  clr_filter_desc_init(&desc->filter, (clr_filter_type)CLR_FILTER_TYPE_BOX);
  desc->accumulation_tile_size = 16;
}

static clr_result check_desc(clr_context ctx, const clr_film_desc *d) {
  for (int i = 0; i < 2; ++i)
    if (!(d->filter.radius[i] > 0.0f && d->filter.radius[i] <= CLR_FILM_MAX_FILTER_RADIUS))
      return clr_fail(ctx, CLR_ERROR_INVALID_RADIUS,
                      "film_create: filter.radius[%d] = %g (must be in (0, %g])", i,
                      (double)d->filter.radius[i], (double)CLR_FILM_MAX_FILTER_RADIUS);
  if (d->accumulation_tile_size < 4 || d->accumulation_tile_size > 64)
    return clr_fail(ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_create: accumulation_tile_size = %d (must be 4..64)",
                    (int)d->accumulation_tile_size);
  if (!isfinite(d->scale))
    return clr_fail(ctx, CLR_ERROR_INVALID_ARGUMENT, "film_create: scale = %g (must be finite)",
                    (double)d->scale);
  if (!(d->max_sample_luminance > 0.0f))
    return clr_fail(ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_create: max_sample_luminance = %g (must be > 0, INFINITY for none)",
                    (double)d->max_sample_luminance);
  return CLR_SUCCESS;
}

/* pbrt-v3 Film constructor and GetSampleBounds (shared with the samplers: film_geometry.c). */
static clr_result make_params(clr_context ctx, const clr_film_desc *d, const clr_filter_params *f,
                              clr_film_params *p) {
  clr_film_geometry g;
  g.x_resolution = d->x_resolution;
  g.y_resolution = d->y_resolution;
  memcpy(g.crop_window, d->crop_window, sizeof g.crop_window);
  g.filter_radius[0] = f->radius_x;
  g.filter_radius[1] = f->radius_y;
  clr_bounds2i pixels, samples;
  clr_result r = clr_film_geometry_bounds(&g, "film_create", &pixels, &samples);
  if (r != CLR_SUCCESS) {
    char message[512];
    snprintf(message, sizeof message, "%s", clr_last_error_message());
    return clr_fail(ctx, r, "%s", message); /* reaches the context's error callback too */
  }
  memset(p, 0, sizeof *p);
  p->pixel_x0 = pixels.x0;
  p->pixel_y0 = pixels.y0;
  p->pixel_x1 = pixels.x1;
  p->pixel_y1 = pixels.y1;
  p->sample_x0 = samples.x0;
  p->sample_y0 = samples.y0;
  p->sample_x1 = samples.x1;
  p->sample_y1 = samples.y1;
  p->tile_size = d->accumulation_tile_size;
  p->max_luminance = d->max_sample_luminance;
  p->clamp_luminance = isinf(d->max_sample_luminance) ? 0 : 1;
  return CLR_SUCCESS;
}

/* Zeroed sums with every page written now: merges add into them (read, then write), and a first
 * read of untouched memory maps the kernel's shared zero page, which the write then replaces with
 * a copy-on-write fault and a TLB shootdown to every CPU running a worker, once per page (profile:
 * most of a 256x256 render's merge time). Volatile stores: GCC turns malloc + memset into calloc. */
static double *zeroed_sums(size_t count) {
  double *sums = calloc(count, sizeof *sums);
  volatile unsigned char *bytes = (volatile unsigned char *)sums;
  size_t size = count * sizeof *sums;
  for (size_t i = 0; sums && i < size; i += 4096) bytes[i] = 0;
  if (sums && size) bytes[size - 1] = 0; /* the last page, when the start is not page-aligned */
  return sums;
}

clr_result film_create(clr_context ctx, const clr_film_desc *desc, clr_film *out) {
  clr_clear_error();
  if (!desc || !out)
    return clr_fail(ctx, CLR_ERROR_NULL_POINTER, "film_create: %s is NULL", !desc ? "desc" : "out");
  *out = NULL;
  clr_film_desc full;
  clr_film_desc_init(&full);
  CLR_CHECK(clr_desc_adopt(&full, sizeof full, desc, "film_create: desc"));
  desc = &full;
  CLR_CHECK(check_desc(ctx, desc));
  clr_filter_params filter;
  CLR_CHECK(clr_filter_params_make(&desc->filter, &filter));
  clr_film_params params;
  CLR_CHECK(make_params(ctx, desc, &filter, &params));

  clr_film film = calloc(1, sizeof *film);
  if (!film) return clr_fail(ctx, CLR_ERROR_OUT_OF_MEMORY, "film_create: out of memory");
  atomic_init(&film->refcount, 1);
  film->ctx = ctx;
  clr_context_retain(ctx);
  film->params = params;
  film->filter = filter;
  film->scale = desc->scale;
  film->desc = *desc;
  film->width = params.pixel_x1 - params.pixel_x0;
  film->height = params.pixel_y1 - params.pixel_y0;
  film->pixel_count = (size_t)film->width * (size_t)film->height;
  pthread_mutex_init(&film->lock, NULL);
  clr_result r = clr_filter_params_table(&filter, film->table);
  for (int axis = 0; axis < 2; ++axis)
    for (int i = 0; i < CLR_FILTER_TABLE_SIZE; ++i)
      film->factors[axis * CLR_FILTER_TABLE_SIZE + i] = clr_filter_table_factor(&filter, axis, i);
  if (r != CLR_SUCCESS) {
    film_release(film);
    return r;
  }
  film->rgb_sum = zeroed_sums(film->pixel_count * 3);
  film->weight_sum = zeroed_sums(film->pixel_count);
  if (!film->rgb_sum || !film->weight_sum) {
    size_t n = film->pixel_count;
    film_release(film);
    return clr_fail(ctx, CLR_ERROR_OUT_OF_MEMORY, "film_create: no memory for %zu pixels", n);
  }
  *out = film;
  return CLR_SUCCESS;
}

void film_retain(clr_film film) {
  if (film) atomic_fetch_add(&film->refcount, 1);
}

void film_release(clr_film film) {
  if (!film || atomic_fetch_sub(&film->refcount, 1) != 1) return;
  clr_film_accumulate_release(film);
  free(film->rgb_sum);
  free(film->weight_sum);
  free(film->splat_rgb);
  pthread_mutex_destroy(&film->lock);
  clr_context_release(film->ctx);
  free(film);
}

clr_bounds2i film_pixel_bounds(clr_film film) {
  clr_bounds2i b = {0, 0, 0, 0};
  if (!film) return b;
  b.x0 = film->params.pixel_x0;
  b.y0 = film->params.pixel_y0;
  b.x1 = film->params.pixel_x1;
  b.y1 = film->params.pixel_y1;
  return b;
}

clr_bounds2i film_sample_bounds(clr_film film) {
  clr_bounds2i b = {0, 0, 0, 0};
  if (!film) return b;
  b.x0 = film->params.sample_x0;
  b.y0 = film->params.sample_y0;
  b.x1 = film->params.sample_x1;
  b.y1 = film->params.sample_y1;
  return b;
}

/* Rows [y_begin, y_end) of clr_film_add_block, already clipped to the pixel bounds. */
typedef struct add_rows_job {
  clr_film film;
  clr_bounds2i block;
  const float *sums;
  int32_t y_begin, y_end;
} add_rows_job;

static void *add_rows(void *arg) {
  const add_rows_job *j = arg;
  clr_film film = j->film;
  const clr_film_params *p = &film->params;
  const int32_t bw = j->block.x1 - j->block.x0;
  const int32_t x0 = j->block.x0 > p->pixel_x0 ? j->block.x0 : p->pixel_x0;
  const int32_t x1 = j->block.x1 < p->pixel_x1 ? j->block.x1 : p->pixel_x1;
  for (int32_t y = j->y_begin; y < j->y_end; ++y) {
    const float *s =
        j->sums + ((size_t)(y - j->block.y0) * bw + (x0 - j->block.x0)) * CLR_FILM_SUM_FLOATS;
    size_t i = (size_t)(y - p->pixel_y0) * film->width + (x0 - p->pixel_x0);
    for (int32_t x = x0; x < x1; ++x, ++i, s += CLR_FILM_SUM_FLOATS) {
      film->rgb_sum[3 * i] += (double)s[0];
      film->rgb_sum[3 * i + 1] += (double)s[1];
      film->rgb_sum[3 * i + 2] += (double)s[2];
      film->weight_sum[i] += (double)s[3];
    }
  }
  return NULL;
}

/* Each thread of clr_film_add_block adds at least this many pixels (each pixel by one thread). */
#define ADD_BLOCK_PART_PIXELS (1 << 15)

void clr_film_add_block(clr_film film, clr_bounds2i block, const float *sums, int threads) {
  const clr_film_params *p = &film->params;
  const int32_t y0 = block.y0 > p->pixel_y0 ? block.y0 : p->pixel_y0;
  const int32_t y1 = block.y1 < p->pixel_y1 ? block.y1 : p->pixel_y1;
  if (y0 >= y1 || block.x0 >= block.x1) return;
  int64_t parts = (int64_t)(y1 - y0) * (block.x1 - block.x0) / ADD_BLOCK_PART_PIXELS;
  int n = threads < 1 ? 1 : threads > CLR_FILM_BIN_THREADS_MAX ? CLR_FILM_BIN_THREADS_MAX : threads;
  if (parts < n) n = parts < 1 ? 1 : (int)parts;
  if (n > y1 - y0) n = y1 - y0;
  add_rows_job jobs[CLR_FILM_BIN_THREADS_MAX];
  pthread_t helpers[CLR_FILM_BIN_THREADS_MAX];
  int started[CLR_FILM_BIN_THREADS_MAX] = {0};
  for (int i = 0; i < n; ++i)
    jobs[i] = (add_rows_job){film, block, sums, y0 + (int32_t)((int64_t)(y1 - y0) * i / n),
                             y0 + (int32_t)((int64_t)(y1 - y0) * (i + 1) / n)};
  for (int i = 1; i < n; ++i)
    started[i] = pthread_create(&helpers[i], NULL, add_rows, &jobs[i]) == 0;
  add_rows(&jobs[0]);
  for (int i = 1; i < n; ++i) {
    if (started[i])
      pthread_join(helpers[i], NULL);
    else
      add_rows(&jobs[i]);
  }
}

/* The splat sums are allocated by the first splat (most renders never splat): the film holds
 * 32 bytes per pixel until then. Caller holds the lock. */
static int ensure_splats(clr_film film) {
  if (!film->splat_rgb) film->splat_rgb = zeroed_sums(film->pixel_count * 3);
  return film->splat_rgb != NULL;
}

clr_result film_add_splat(clr_film film, float x, float y, float r, float g, float b) {
  if (!film) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "film_add_splat: film is NULL");
  const clr_film_params *p = &film->params;
  float lum = 0.212671f * r + 0.715160f * g + 0.072169f * b;
  int bad = isnan(r) || isnan(g) || isnan(b) || isnan(x) || isnan(y) || !(lum >= 0.0f) ||
            isinf(lum) || isinf(r) || isinf(g) || isinf(b);
  pthread_mutex_lock(&film->lock);
  if (bad) {
    ++film->dropped;
  } else if (!ensure_splats(film)) {
    pthread_mutex_unlock(&film->lock);
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_add_splat: no memory for splats");
  } else {
    float fx = floorf(x), fy = floorf(y);
    if (fx >= (float)p->pixel_x0 && fx < (float)p->pixel_x1 && fy >= (float)p->pixel_y0 &&
        fy < (float)p->pixel_y1) {
      if (p->clamp_luminance && lum > p->max_luminance) {
        float s = p->max_luminance / lum;
        r *= s;
        g *= s;
        b *= s;
      }
      size_t i = (size_t)((int32_t)fy - p->pixel_y0) * film->width + ((int32_t)fx - p->pixel_x0);
      film->splat_rgb[3 * i] += (double)r;
      film->splat_rgb[3 * i + 1] += (double)g;
      film->splat_rgb[3 * i + 2] += (double)b;
    }
  }
  pthread_mutex_unlock(&film->lock);
  return CLR_SUCCESS;
}

void clr_film_resolve_pixel(clr_film film, size_t i, float splat_scale, float rgb[3]) {
  double w = film->weight_sum[i];
  for (int c = 0; c < 3; ++c) {
    double v = film->rgb_sum[3 * i + c];
    if (w != 0.0) {
      v /= w;
      if (!(v > 0.0)) v = 0.0;
    }
    if (film->splat_rgb) v += (double)splat_scale * film->splat_rgb[3 * i + c];
    rgb[c] = (float)(v * (double)film->scale);
  }
}

clr_result film_get_rgb(clr_film film, float *rgb, float splat_scale) {
  if (!film || !rgb)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_get_rgb: %s is NULL",
                    !film ? "film" : "rgb");
  if (!isfinite(splat_scale))
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "film_get_rgb: splat_scale = %g",
                    (double)splat_scale);
  pthread_mutex_lock(&film->lock);
  for (size_t i = 0; i < film->pixel_count; ++i)
    clr_film_resolve_pixel(film, i, splat_scale, rgb + 3 * i);
  pthread_mutex_unlock(&film->lock);
  return CLR_SUCCESS;
}

clr_result film_get_sums(clr_film film, double *rgb_sum, double *weight_sum, double *splat_rgb) {
  if (!film || (!rgb_sum && !weight_sum && !splat_rgb))
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_get_sums: %s is NULL",
                    !film ? "film" : "every output");
  pthread_mutex_lock(&film->lock);
  size_t n = film->pixel_count;
  if (rgb_sum) memcpy(rgb_sum, film->rgb_sum, n * 3 * sizeof(double));
  if (weight_sum) memcpy(weight_sum, film->weight_sum, n * sizeof(double));
  if (splat_rgb && film->splat_rgb) memcpy(splat_rgb, film->splat_rgb, n * 3 * sizeof(double));
  if (splat_rgb && !film->splat_rgb) memset(splat_rgb, 0, n * 3 * sizeof(double));
  pthread_mutex_unlock(&film->lock);
  return CLR_SUCCESS;
}

static int any_nonzero(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (v[i] != 0.0) return 1;
  return 0;
}

clr_result film_merge_sums(clr_film dst, clr_bounds2i region, const double *rgb_sum,
                           const double *weight_sum, const double *splat_rgb) {
  if (!dst || (!rgb_sum && !weight_sum && !splat_rgb))
    return clr_fail(dst ? dst->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_merge_sums: %s is NULL",
                    !dst ? "dst" : "every input");
  const clr_film_params *p = &dst->params;
  if (region.x0 >= region.x1 || region.y0 >= region.y1 || region.x0 < p->pixel_x0 ||
      region.y0 < p->pixel_y0 || region.x1 > p->pixel_x1 || region.y1 > p->pixel_y1)
    return clr_fail(dst->ctx, CLR_ERROR_INVALID_PIXEL_RANGE,
                    "film_merge_sums: region [%d,%d)x[%d,%d) is empty or outside the pixel "
                    "bounds [%d,%d)x[%d,%d)",
                    region.x0, region.x1, region.y0, region.y1, p->pixel_x0, p->pixel_x1,
                    p->pixel_y0, p->pixel_y1);
  pthread_mutex_lock(&dst->lock);
  size_t rw = (size_t)(region.x1 - region.x0);
  if (splat_rgb && !dst->splat_rgb &&
      any_nonzero(splat_rgb, rw * (size_t)(region.y1 - region.y0) * 3) && !ensure_splats(dst)) {
    pthread_mutex_unlock(&dst->lock);
    return clr_fail(dst->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_merge_sums: no memory for splats");
  }
  for (int32_t y = region.y0; y < region.y1; ++y)
    for (int32_t x = region.x0; x < region.x1; ++x) {
      size_t s = (size_t)(y - region.y0) * rw + (size_t)(x - region.x0);
      size_t d = (size_t)(y - p->pixel_y0) * dst->width + (size_t)(x - p->pixel_x0);
      /* Like film_add_samples: a pixel with a NaN/Inf sum or weight is dropped and counted. */
      int finite = !weight_sum || isfinite(weight_sum[s]);
      for (int c = 0; c < 3; ++c) {
        if (rgb_sum) finite &= isfinite(rgb_sum[3 * s + c]);
        if (splat_rgb) finite &= isfinite(splat_rgb[3 * s + c]);
      }
      if (!finite) {
        ++dst->dropped;
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        if (rgb_sum) dst->rgb_sum[3 * d + c] += rgb_sum[3 * s + c];
        if (splat_rgb && dst->splat_rgb) dst->splat_rgb[3 * d + c] += splat_rgb[3 * s + c];
      }
      if (weight_sum) dst->weight_sum[d] += weight_sum[s];
    }
  pthread_mutex_unlock(&dst->lock);
  return CLR_SUCCESS;
}

clr_result film_merge_film(clr_film dst, clr_film src) {
  if (!dst || !src)
    return clr_fail(dst ? dst->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_merge_film: %s is NULL",
                    !dst ? "dst" : "src");
  const clr_film_params *a = &dst->params, *b = &src->params;
  if (dst == src || a->pixel_x0 != b->pixel_x0 || a->pixel_y0 != b->pixel_y0 ||
      a->pixel_x1 != b->pixel_x1 || a->pixel_y1 != b->pixel_y1 ||
      dst->desc.x_resolution != src->desc.x_resolution ||
      dst->desc.y_resolution != src->desc.y_resolution ||
      dst->desc.filter.type != src->desc.filter.type ||
      dst->desc.filter.radius[0] != src->desc.filter.radius[0] ||
      dst->desc.filter.radius[1] != src->desc.filter.radius[1])
    return clr_fail(dst->ctx, CLR_ERROR_INVALID_FILM,
                    "film_merge_film: the films differ (resolution, pixel bounds or filter)");
  pthread_mutex_lock(&src->lock);
  pthread_mutex_lock(&dst->lock);
  if (src->splat_rgb && !ensure_splats(dst)) {
    pthread_mutex_unlock(&dst->lock);
    pthread_mutex_unlock(&src->lock);
    return clr_fail(dst->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_merge_film: no memory for splats");
  }
  for (size_t i = 0; i < dst->pixel_count; ++i) {
    for (int c = 0; c < 3; ++c) dst->rgb_sum[3 * i + c] += src->rgb_sum[3 * i + c];
    if (src->splat_rgb)
      for (int c = 0; c < 3; ++c) dst->splat_rgb[3 * i + c] += src->splat_rgb[3 * i + c];
    dst->weight_sum[i] += src->weight_sum[i];
  }
  dst->accepted += src->accepted;
  dst->dropped += src->dropped;
  dst->outside += src->outside;
  pthread_mutex_unlock(&dst->lock);
  pthread_mutex_unlock(&src->lock);
  return CLR_SUCCESS;
}

static uint64_t read_counter(clr_film film, const uint64_t *counter) {
  pthread_mutex_lock(&film->lock);
  uint64_t v = *counter;
  pthread_mutex_unlock(&film->lock);
  return v;
}

uint64_t film_sample_count(clr_film film) { return film ? read_counter(film, &film->accepted) : 0; }
uint64_t film_dropped_samples(clr_film film) {
  return film ? read_counter(film, &film->dropped) : 0;
}
uint64_t film_outside_samples(clr_film film) {
  return film ? read_counter(film, &film->outside) : 0;
}
