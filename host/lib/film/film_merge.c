/* `clrender merge`: films written with their sums (crops of one frame, or independent passes of
 * the same frame) summed into the film a single render would have produced. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "atomic_file.h"
#include "clr_internal.h"
#include "exr_io.h"
#include "film_internal.h"

static const char *const plane_names[7] = {"sum.R",   "sum.G",   "sum.B",  "weight",
                                           "splat.R", "splat.G", "splat.B"};

static const char *const filter_floats[] = {"clrender.filter.xwidth", "clrender.filter.ywidth",
                                            "clrender.filter.alpha",  "clrender.filter.B",
                                            "clrender.filter.C",      "clrender.filter.tau",
                                            "clrender.scale",         "clrender.splat_scale"};
#define FILTER_FLOATS ((int)(sizeof filter_floats / sizeof filter_floats[0]))

/* Reads the film description stored by film_write: resolution, filter, scale. */
static clr_result desc_from_image(const clr_exr_image *im, const char *path, clr_film_desc *d,
                                  float *splat_scale) {
  clr_film_desc_init(d);
  d->x_resolution = im->display_width;
  d->y_resolution = im->display_height;
  const char *filter = clr_exr_image_string_attr(im, "clrender.filter");
  float v[FILTER_FLOATS];
  for (int i = 0; i < FILTER_FLOATS; ++i)
    if (!filter || !clr_exr_image_float_attr(im, filter_floats[i], &v[i]))
      return clr_fail(NULL, CLR_ERROR_FILE_FORMAT,
                      "merge: %s has no clrender film metadata (%s): was it written by clrender?",
                      path, filter ? filter_floats[i] : "clrender.filter");
  CLR_CHECK(clr_filter_type_from_name(filter, &d->filter.type));
  d->filter.radius[0] = v[0];
  d->filter.radius[1] = v[1];
  d->filter.alpha = v[2];
  d->filter.b = v[3];
  d->filter.c = v[4];
  d->filter.tau = v[5];
  d->scale = v[6];
  *splat_scale = v[7];
  int32_t table = 0;
  clr_exr_image_int_attr(im, "clrender.filter.table", &table);
  d->filter.use_table = table;
  return CLR_SUCCESS;
}

static int same_film(const clr_film_desc *a, const clr_film_desc *b, float sa, float sb) {
  return a->x_resolution == b->x_resolution && a->y_resolution == b->y_resolution &&
         a->filter.type == b->filter.type && a->filter.radius[0] == b->filter.radius[0] &&
         a->filter.radius[1] == b->filter.radius[1] && a->filter.alpha == b->filter.alpha &&
         a->filter.b == b->filter.b && a->filter.c == b->filter.c &&
         a->filter.tau == b->filter.tau && a->filter.use_table == b->filter.use_table &&
         a->scale == b->scale && sa == sb;
}

/* A crop window whose pbrt rounding gives exactly the pixel range [lo, hi) of `res`. */
static void crop_for(int32_t lo, int32_t hi, int32_t res, float *c0, float *c1) {
  float *c[2] = {c0, c1};
  int32_t want[2] = {lo, hi};
  for (int i = 0; i < 2; ++i) {
    float v = (float)want[i] / (float)res;
    for (int k = 0; k < 8 && (int32_t)ceilf((float)res * v) > want[i]; ++k) v = nextafterf(v, 0.0f);
    for (int k = 0; k < 8 && (int32_t)ceilf((float)res * v) < want[i]; ++k) v = nextafterf(v, 1.0f);
    *c[i] = v;
  }
}

/* Adds one image's sums (hi + lo planes) into the film. */
static clr_result merge_image(clr_film film, const clr_exr_image *im, const char *path) {
  size_t n = (size_t)im->width * (size_t)im->height;
  double *planes = malloc(n * 7 * sizeof(double));
  if (!planes) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "merge: out of memory for %s", path);
  for (int k = 0; k < 7; ++k) {
    char lo_name[32];
    snprintf(lo_name, sizeof lo_name, "%s.lo", plane_names[k]);
    const float *hi = clr_exr_image_channel(im, plane_names[k]);
    const float *lo = clr_exr_image_channel(im, lo_name);
    if (!hi || !lo) {
      free(planes);
      return clr_fail(NULL, CLR_ERROR_FILE_FORMAT,
                      "merge: %s has no %s channel: write films with their sums to merge them",
                      path, hi ? lo_name : plane_names[k]);
    }
    for (size_t i = 0; i < n; ++i) planes[k * n + i] = (double)hi[i] + (double)lo[i];
  }
  double *rgb = malloc(n * 3 * sizeof(double)), *splat = malloc(n * 3 * sizeof(double));
  clr_result r = CLR_SUCCESS;
  if (!rgb || !splat) {
    r = clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "merge: out of memory for %s", path);
  } else {
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        rgb[3 * i + c] = planes[c * n + i];
        splat[3 * i + c] = planes[(4 + c) * n + i];
      }
    r = film_merge_sums(film, im->data_window, rgb, planes + 3 * n, splat);
  }
  free(rgb);
  free(splat);
  free(planes);
  return r;
}

/* The same file given twice (by any name: compared by device and inode) would count its samples
 * twice. */
static clr_result check_distinct(const char *const *paths, int32_t count) {
  struct stat *st = calloc((size_t)count, sizeof *st);
  if (!st) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "merge: out of memory");
  clr_result r = CLR_SUCCESS;
  for (int32_t i = 0; r == CLR_SUCCESS && i < count; ++i) {
    if (!paths[i]) {
      r = clr_fail(NULL, CLR_ERROR_NULL_POINTER, "merge: path %d is NULL", (int)i);
      break;
    }
    if (stat(paths[i], &st[i]) != 0) continue; /* the reader reports it */
    for (int32_t k = 0; k < i; ++k)
      if (paths[k] && st[k].st_ino == st[i].st_ino && st[k].st_dev == st[i].st_dev &&
          st[k].st_ino != 0) {
        r = clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                     "merge: %s and %s are the same file: its samples would be counted twice",
                     paths[k], paths[i]);
        break;
      }
  }
  free(st);
  return r;
}

static clr_result read_all(const char *const *paths, int32_t count, clr_exr_image **images,
                           clr_film_desc *desc, float *splat_scale, clr_bounds2i *window) {
  CLR_CHECK(check_distinct(paths, count));
  for (int32_t i = 0; i < count; ++i) {
    CLR_CHECK(clr_exr_read(paths[i], &images[i]));
    clr_film_desc d;
    float s = 1.0f;
    CLR_CHECK(desc_from_image(images[i], paths[i], &d, &s));
    if (i == 0) {
      *desc = d;
      *splat_scale = s;
      *window = images[i]->data_window;
    } else if (!same_film(desc, &d, *splat_scale, s)) {
      return clr_fail(NULL, CLR_ERROR_INVALID_FILM,
                      "merge: %s (%dx%d, filter %s %gx%g) does not match %s (%dx%d, filter %s "
                      "%gx%g): resolutions, filters and scales must be equal",
                      paths[i], (int)d.x_resolution, (int)d.y_resolution,
                      clr_filter_type_name(d.filter.type), (double)d.filter.radius[0],
                      (double)d.filter.radius[1], paths[0], (int)desc->x_resolution,
                      (int)desc->y_resolution, clr_filter_type_name(desc->filter.type),
                      (double)desc->filter.radius[0], (double)desc->filter.radius[1]);
    } else {
      clr_bounds2i b = images[i]->data_window;
      window->x0 = b.x0 < window->x0 ? b.x0 : window->x0;
      window->y0 = b.y0 < window->y0 ? b.y0 : window->y0;
      window->x1 = b.x1 > window->x1 ? b.x1 : window->x1;
      window->y1 = b.y1 > window->y1 ? b.y1 : window->y1;
    }
  }
  return CLR_SUCCESS;
}

clr_result film_merge_files(clr_context ctx, const char *const *paths, int32_t count,
                            const char *out_path) {
  clr_clear_error();
  if (!ctx || !paths || !out_path)
    return clr_fail(ctx, CLR_ERROR_NULL_POINTER, "film_merge_files: NULL argument");
  if (count < 1 || count > 4096)
    return clr_fail(ctx, CLR_ERROR_INVALID_ARGUMENT, "film_merge_files: %d inputs (1..4096)",
                    (int)count);
  CLR_CHECK(clr_check_writable(out_path)); /* refuse a bad output before reading anything */
  clr_exr_image **images = calloc((size_t)count, sizeof *images);
  if (!images) return clr_fail(ctx, CLR_ERROR_OUT_OF_MEMORY, "film_merge_files: out of memory");
  clr_film_desc desc;
  float splat_scale = 1.0f;
  clr_bounds2i window = {0, 0, 0, 0};
  clr_film film = NULL;
  clr_result r = read_all(paths, count, images, &desc, &splat_scale, &window);
  if (r == CLR_SUCCESS) {
    crop_for(window.x0, window.x1, desc.x_resolution, &desc.crop_window[0], &desc.crop_window[1]);
    crop_for(window.y0, window.y1, desc.y_resolution, &desc.crop_window[2], &desc.crop_window[3]);
    r = film_create(ctx, &desc, &film);
  }
  for (int32_t i = 0; r == CLR_SUCCESS && i < count; ++i)
    r = merge_image(film, images[i], paths[i]);
  if (r == CLR_SUCCESS) {
    /* The merged film holds the inputs' samples: record their sum, not 0. */
    uint64_t samples = 0, dropped = 0;
    for (int32_t i = 0; i < count; ++i) {
      int32_t v = 0;
      if (clr_exr_image_int_attr(images[i], "clrender.samples", &v) && v > 0)
        samples += (uint64_t)v;
      if (clr_exr_image_int_attr(images[i], "clrender.dropped_samples", &v) && v > 0)
        dropped += (uint64_t)v;
    }
    pthread_mutex_lock(&film->lock);
    film->accepted += samples;
    film->dropped += dropped;
    pthread_mutex_unlock(&film->lock);
  }
  if (r == CLR_SUCCESS) {
    clr_film_write_options o;
    clr_film_write_options_init(&o);
    o.splat_scale = splat_scale;
    const char *sampler = clr_exr_image_string_attr(images[0], "clrender.sampler");
    o.sampler = sampler;
    int32_t spp = 0;
    if (clr_exr_image_int_attr(images[0], "clrender.spp", &spp)) o.spp = spp;
    char merged[32];
    snprintf(merged, sizeof merged, "%d", (int)count);
    const char *keys[] = {"clrender.merged_from"};
    const char *values[] = {merged};
    o.metadata_keys = keys;
    o.metadata_values = values;
    o.metadata_count = 1;
    r = film_write(film, out_path, &o);
  }
  film_release(film);
  for (int32_t i = 0; i < count; ++i) clr_exr_image_free(images[i]);
  free(images);
  return r;
}

/* A header attribute as text: strings as written, ints with %d, floats with %.9g; "" if absent. */
static void attribute_text(const clr_exr_image *im, const char *name, char *out, size_t size) {
  const char *s = clr_exr_image_string_attr(im, name);
  int32_t i = 0;
  float f = 0.0f;
  if (s)
    snprintf(out, size, "%s", s);
  else if (clr_exr_image_int_attr(im, name, &i))
    snprintf(out, size, "%d", (int)i);
  else if (clr_exr_image_float_attr(im, name, &f))
    snprintf(out, size, "%.9g", (double)f);
  else if (size)
    out[0] = 0;
}

clr_result film_merge_file(clr_film film, const char *path, int32_t attr_count,
                           const char *const *attr_names, char *attr_values, size_t value_size) {
  if (!film || !path || (attr_count > 0 && (!attr_names || !attr_values)))
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_merge_file: %s is NULL",
                    !film   ? "film"
                    : !path ? "path"
                            : "attribute");
  clr_exr_image *im = NULL;
  CLR_CHECK(clr_exr_read(path, &im));
  clr_film_desc d;
  float splat_scale = 1.0f;
  clr_result r = desc_from_image(im, path, &d, &splat_scale);
  const clr_film_params *p = &film->params;
  clr_bounds2i w = im->data_window;
  if (r == CLR_SUCCESS && (!same_film(&film->desc, &d, 1.0f, 1.0f) || w.x0 != p->pixel_x0 ||
                           w.y0 != p->pixel_y0 || w.x1 != p->pixel_x1 || w.y1 != p->pixel_y1))
    r = clr_fail(film->ctx, CLR_ERROR_INVALID_FILM,
                 "%s: its film (%dx%d, pixels [%d,%d)x[%d,%d), filter %s %gx%g) is not this one "
                 "(%dx%d, pixels [%d,%d)x[%d,%d), filter %s %gx%g)",
                 path, (int)d.x_resolution, (int)d.y_resolution, w.x0, w.x1, w.y0, w.y1,
                 clr_filter_type_name(d.filter.type), (double)d.filter.radius[0],
                 (double)d.filter.radius[1], (int)film->desc.x_resolution,
                 (int)film->desc.y_resolution, p->pixel_x0, p->pixel_x1, p->pixel_y0, p->pixel_y1,
                 clr_filter_type_name(film->desc.filter.type), (double)film->desc.filter.radius[0],
                 (double)film->desc.filter.radius[1]);
  if (r == CLR_SUCCESS) r = merge_image(film, im, path);
  if (r == CLR_SUCCESS) {
    int32_t samples = 0, dropped = 0;
    clr_exr_image_int_attr(im, "clrender.samples", &samples);
    clr_exr_image_int_attr(im, "clrender.dropped_samples", &dropped);
    pthread_mutex_lock(&film->lock);
    film->accepted += samples > 0 ? (uint64_t)samples : 0;
    film->dropped += dropped > 0 ? (uint64_t)dropped : 0;
    pthread_mutex_unlock(&film->lock);
    for (int32_t i = 0; i < attr_count; ++i)
      attribute_text(im, attr_names[i], attr_values + (size_t)i * value_size, value_size);
  }
  clr_exr_image_free(im);
  return r;
}
