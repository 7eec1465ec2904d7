/* Film output: OpenEXR with metadata and mergeable sums, PNG previews, and merging of films
 * written with their sums. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "atomic_file.h"
#include "clr_internal.h"
#include "exr_io.h"
#include "film_internal.h"
#include "png_io.h"
#include "clrender/version.h"

#define SUM_PLANES 7 /* sum.R sum.G sum.B weight splat.R splat.G splat.B */
static const char *const sum_names[SUM_PLANES] = {"sum.R",   "sum.G",   "sum.B",  "weight",
                                                  "splat.R", "splat.G", "splat.B"};
static const char *const sum_lo_names[SUM_PLANES] = {
    "sum.R.lo", "sum.G.lo", "sum.B.lo", "weight.lo", "splat.R.lo", "splat.G.lo", "splat.B.lo"};

const clr_film_desc *film_get_desc(clr_film film) { return film ? &film->desc : NULL; }

clr_result film_get_geometry(clr_film film, clr_film_geometry *geometry) {
  if (!film || !geometry)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "film_get_geometry: %s is NULL",
                    !film ? "film" : "geometry");
  const clr_film_desc *d = &film->desc;
  geometry->x_resolution = d->x_resolution;
  geometry->y_resolution = d->y_resolution;
  for (int i = 0; i < 4; ++i) geometry->crop_window[i] = d->crop_window[i];
  geometry->filter_radius[0] = d->filter.radius[0];
  geometry->filter_radius[1] = d->filter.radius[1];
  return CLR_SUCCESS;
}

void clr_film_write_options_init(clr_film_write_options *o) {
  if (!o) return;
  memset(o, 0, sizeof *o);
  o->struct_size = sizeof *o;
  o->include_sums = 1;
  o->splat_scale = 1.0f;
  o->render_time_s = -1.0;
}

/* What film_write's rows are computed from (the writer holds the film's lock). */
typedef struct film_rows {
  clr_film film;
  float splat_scale;
  int sums;
} film_rows;

/* Rows of R, G, B (film_get_rgb's values), then of each sum's float and its residual to the
 * double (film_write's channel order), for pixel rows [y, y + lines). */
static void fill_rows(void *user, int32_t y, int32_t lines, float *const *rows) {
  const film_rows *f = user;
  clr_film film = f->film;
  static const double no_splat[3] = {0.0, 0.0, 0.0}; /* a film that was never splatted */
  size_t first = (size_t)(y - film->params.pixel_y0) * (size_t)film->width;
  size_t n = (size_t)lines * (size_t)film->width;
  for (size_t j = 0; j < n; ++j) {
    size_t i = first + j;
    float rgb[3];
    clr_film_resolve_pixel(film, i, f->splat_scale, rgb);
    for (int c = 0; c < 3; ++c) rows[c][j] = rgb[c];
    if (!f->sums) continue;
    const double *splat = film->splat_rgb ? film->splat_rgb + 3 * i : no_splat;
    double v[SUM_PLANES] = {film->rgb_sum[3 * i],
                            film->rgb_sum[3 * i + 1],
                            film->rgb_sum[3 * i + 2],
                            film->weight_sum[i],
                            splat[0],
                            splat[1],
                            splat[2]};
    for (int k = 0; k < SUM_PLANES; ++k) {
      float high = (float)v[k];
      rows[3 + 2 * k][j] = high;
      rows[4 + 2 * k][j] = (float)(v[k] - (double)high);
    }
  }
}

#define MAX_ATTRS 48

typedef struct attr_list {
  clr_exr_attribute a[MAX_ATTRS];
  int n;
  char text[4][256];
} attr_list;

static void add_string(attr_list *l, const char *name, const char *s) {
  if (l->n < MAX_ATTRS && s) l->a[l->n++] = (clr_exr_attribute){name, CLR_EXR_ATTR_STRING, s, 0, 0};
}
static void add_float(attr_list *l, const char *name, float f) {
  if (l->n < MAX_ATTRS) l->a[l->n++] = (clr_exr_attribute){name, CLR_EXR_ATTR_FLOAT, NULL, f, 0};
}
static void add_int(attr_list *l, const char *name, int32_t i) {
  if (l->n < MAX_ATTRS) l->a[l->n++] = (clr_exr_attribute){name, CLR_EXR_ATTR_INT, NULL, 0, i};
}

static void film_attributes(clr_film film, const clr_film_write_options *o, attr_list *l) {
  const clr_film_desc *d = &film->desc;
  add_string(l, "software", "clrender " CLR_VERSION_STRING);
  add_string(l, "clrender.filter", clr_filter_type_name(d->filter.type));
  add_float(l, "clrender.filter.xwidth", d->filter.radius[0]);
  add_float(l, "clrender.filter.ywidth", d->filter.radius[1]);
  add_float(l, "clrender.filter.alpha", d->filter.alpha);
  add_float(l, "clrender.filter.B", d->filter.b);
  add_float(l, "clrender.filter.C", d->filter.c);
  add_float(l, "clrender.filter.tau", d->filter.tau);
  add_int(l, "clrender.filter.table", d->filter.use_table);
  add_float(l, "clrender.scale", d->scale);
  add_float(l, "clrender.maxsampleluminance", d->max_sample_luminance);
  add_float(l, "clrender.splat_scale", o->splat_scale);
  snprintf(l->text[0], sizeof l->text[0], "%.9g %.9g %.9g %.9g", (double)d->crop_window[0],
           (double)d->crop_window[1], (double)d->crop_window[2], (double)d->crop_window[3]);
  add_string(l, "clrender.cropwindow", l->text[0]);
  add_string(l, "clrender.sampler", o->sampler);
  if (o->spp > 0) add_int(l, "clrender.spp", o->spp);
  if (o->render_time_s >= 0) add_float(l, "clrender.render_time_s", (float)o->render_time_s);
  add_int(l, "clrender.partial", o->partial ? 1 : 0);
  add_int(l, "clrender.samples",
          (int32_t)(film->accepted > INT32_MAX ? INT32_MAX : film->accepted));
  add_int(l, "clrender.dropped_samples",
          (int32_t)(film->dropped > INT32_MAX ? INT32_MAX : film->dropped));
  for (int i = 0; i < o->metadata_count; ++i)
    if (o->metadata_keys && o->metadata_values && o->metadata_keys[i] && o->metadata_values[i])
      add_string(l, o->metadata_keys[i], o->metadata_values[i]);
}

static clr_bounds2i pixel_bounds(clr_film film) {
  clr_bounds2i b = {film->params.pixel_x0, film->params.pixel_y0, film->params.pixel_x1,
                    film->params.pixel_y1};
  return b;
}

clr_result film_write(clr_film film, const char *path, const clr_film_write_options *opts) {
  clr_clear_error();
  if (!film || !path)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_write: %s is NULL",
                    film ? "path" : "film");
  clr_film_write_options full;
  clr_film_write_options_init(&full);
  if (opts) CLR_CHECK(clr_desc_adopt(&full, sizeof full, opts, "film_write: opts"));
  opts = &full;
  if (opts->metadata_count < 0 || opts->metadata_count > 16)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "film_write: metadata_count %d (0..16)",
                    (int)opts->metadata_count);
  if (!isfinite(opts->splat_scale)) /* film_get_rgb's check */
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "film_get_rgb: splat_scale = %g",
                    (double)opts->splat_scale);
  clr_exr_channel ch[3 + 2 * SUM_PLANES];
  static const char *const rgb_names[3] = {"R", "G", "B"};
  int n = 0;
  for (int c = 0; c < 3; ++c) ch[n++] = (clr_exr_channel){rgb_names[c], NULL, opts->half};
  for (int k = 0; opts->include_sums && k < SUM_PLANES; ++k) {
    ch[n++] = (clr_exr_channel){sum_names[k], NULL, 0};
    ch[n++] = (clr_exr_channel){sum_lo_names[k], NULL, 0};
  }
  attr_list attrs;
  memset(&attrs, 0, sizeof attrs);
  film_attributes(film, opts, &attrs);
  film_rows rows = {film, opts->splat_scale, opts->include_sums};
  pthread_mutex_lock(&film->lock);
  clr_result r = clr_exr_write_rows(path, film->desc.x_resolution, film->desc.y_resolution,
                                    pixel_bounds(film), ch, n, fill_rows, &rows, attrs.a, attrs.n);
  pthread_mutex_unlock(&film->lock);
  return r;
}

/* Pixels [first, end) of film_write_png's 8-bit sRGB values (the caller holds the film's lock). */
typedef struct srgb_part {
  clr_film film;
  float splat_scale;
  uint8_t *srgb;
  size_t first, end;
} srgb_part;

static void *fill_srgb(void *arg) {
  const srgb_part *part = arg;
  for (size_t i = part->first; i < part->end; ++i) {
    float rgb[3];
    clr_film_resolve_pixel(part->film, i, part->splat_scale, rgb);
    for (int c = 0; c < 3; ++c) part->srgb[3 * i + c] = clr_to_srgb8(rgb[c]);
  }
  return NULL;
}

/* Images of at least this many pixels convert on two threads (powf is most of the preview's time). */
#define SRGB_SPLIT_PIXELS (1 << 15)

clr_result film_write_png(clr_film film, const char *path, float splat_scale) {
  clr_clear_error();
  if (!film || !path)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_write_png: %s is NULL",
                    film ? "path" : "film");
  if (!isfinite(splat_scale)) /* film_get_rgb's check */
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "film_get_rgb: splat_scale = %g",
                    (double)splat_scale);
  uint8_t *srgb = malloc(film->pixel_count * 3);
  if (!srgb) return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_write_png: out of memory");
  size_t half = film->pixel_count >= SRGB_SPLIT_PIXELS ? film->pixel_count / 2 : 0;
  srgb_part parts[2] = {{film, splat_scale, srgb, half, film->pixel_count},
                        {film, splat_scale, srgb, 0, half}};
  pthread_t helper;
  pthread_mutex_lock(&film->lock);
  int started = half && pthread_create(&helper, NULL, fill_srgb, &parts[1]) == 0;
  fill_srgb(&parts[0]);
  if (started)
    pthread_join(helper, NULL);
  else
    fill_srgb(&parts[1]);
  pthread_mutex_unlock(&film->lock);
  clr_result r = clr_png_write_srgb8(path, film->width, film->height, srgb);
  free(srgb);
  return r;
}

clr_result film_check_output_path(const char *path) {
  if (!path) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "film_check_output_path: path is NULL");
  return clr_check_writable(path);
}
