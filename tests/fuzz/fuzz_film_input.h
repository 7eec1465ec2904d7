/* The film fuzz targets' input: a film and its filter from 16 header bytes, then samples of 8
 * bytes (over the sample bounds, with NaN, Inf, negative and boundary values) or, with
 * FUZZ_FLAG_RAW, of 24 raw float bytes. fuzz_film and fuzz_tile read the same layout. */
#ifndef CLR_FUZZ_FILM_INPUT_H
#define CLR_FUZZ_FILM_INPUT_H

#include <math.h>
#include "clrender.h"
#include "fuzz_common.h"

#define FUZZ_FLAG_TABLE 1u    /* pbrt-v3's filter table */
#define FUZZ_FLAG_PORTABLE 2u /* fuzz_film: the portable kernels, else SIMD */
#define FUZZ_FLAG_CLAMP 4u    /* a maximum sample luminance */
#define FUZZ_FLAG_RAW 8u      /* samples as raw floats */
#define FUZZ_FLAG_SPLIT 16u   /* two calls */
#define FUZZ_FLAG_BUFFER 32u  /* fuzz_film: samples from a device buffer; fuzz_tile: tile bytes */
#define FUZZ_MAX_SAMPLES 4096

typedef struct fuzz_film_input {
  clr_film_desc desc;
  unsigned flags;
  int threads;  /* fuzz_film: host binning threads */
  size_t group; /* fuzz_film: gather work-group size (0: automatic) */
  float split;  /* with FUZZ_FLAG_SPLIT: the first call's share of the samples */
} fuzz_film_input;

static inline float fuzz_unit(fuzz_reader *r) { return (float)fuzz_next(r) / 255.0f; }

/* The film and its filter from 16 bytes. */
static inline void fuzz_read_film(fuzz_reader *r, fuzz_film_input *in) {
  static const size_t groups[] = {0, 1, 2, 4, 8, 16, 64};
  clr_film_desc *d = &in->desc;
  clr_film_desc_init(d);
  clr_filter_desc_init(&d->filter, (clr_filter_type)(fuzz_next(r) % 7));
  in->flags = fuzz_next(r);
  d->filter.use_table = (in->flags & FUZZ_FLAG_TABLE) != 0;
  d->filter.radius[0] = (float)(1 + fuzz_next(r) % 64) / 8.0f; /* 0.125 .. 8: reaches up to 17 */
  d->filter.radius[1] = (float)(1 + fuzz_next(r) % 64) / 8.0f;
  d->filter.b = ((float)fuzz_next(r) - 128.0f) / 32.0f;
  d->filter.c = ((float)fuzz_next(r) - 128.0f) / 32.0f;
  d->x_resolution = 1 + fuzz_next(r) % 40;
  d->y_resolution = 1 + fuzz_next(r) % 40;
  float cx0 = fuzz_unit(r), cx1 = fuzz_unit(r), cy0 = fuzz_unit(r), cy1 = fuzz_unit(r);
  d->crop_window[0] = fminf(cx0, cx1);
  d->crop_window[1] = fmaxf(cx0, cx1);
  d->crop_window[2] = fminf(cy0, cy1);
  d->crop_window[3] = fmaxf(cy0, cy1);
  d->accumulation_tile_size = 4 + fuzz_next(r) % 61;
  uint8_t clamp = fuzz_next(r);
  if (in->flags & FUZZ_FLAG_CLAMP) d->max_sample_luminance = 0.25f + (float)clamp / 16.0f;
  uint8_t t = fuzz_next(r);
  in->threads = 1 + t % 3;
  in->group = groups[(t >> 2) % 7];
  in->split = fuzz_unit(r);
}

/* A coordinate over the sample bounds and a little beyond, or, for the top 16th of the range,
 * on a quarter-pixel grid (pixel centres, edges and radius boundaries exactly). */
static inline float fuzz_read_coordinate(fuzz_reader *r, int32_t resolution, float radius) {
  unsigned v = (unsigned)fuzz_next(r) | (unsigned)fuzz_next(r) << 8;
  if ((v & 0xf000u) == 0xf000u) return (float)(v & 0xffu) / 4.0f - 8.0f;
  return -radius - 1.0f + (float)v / 65535.0f * ((float)resolution + 2.0f * radius + 2.0f);
}

static inline void fuzz_read_sample(fuzz_reader *r, const clr_film_desc *d, clr_film_sample *s) {
  s->x = fuzz_read_coordinate(r, d->x_resolution, d->filter.radius[0]);
  s->y = fuzz_read_coordinate(r, d->y_resolution, d->filter.radius[1]);
  s->r = ((float)fuzz_next(r) - 32.0f) / 16.0f; /* some negative: luminance below the threshold */
  s->g = ((float)fuzz_next(r) - 32.0f) / 16.0f;
  s->b = ((float)fuzz_next(r) - 32.0f) / 16.0f;
  uint8_t w = fuzz_next(r);
  s->weight = w == 255 ? NAN : w == 254 ? INFINITY : (float)w / 64.0f;
}

/* The rest of the input as samples (at most FUZZ_MAX_SAMPLES); *count gets their number. The
 * caller frees the array (never NULL; aborts without memory). */
static inline clr_film_sample *fuzz_read_samples(fuzz_reader *r, const fuzz_film_input *in,
                                                 size_t *count) {
  size_t per = (in->flags & FUZZ_FLAG_RAW) ? sizeof(clr_film_sample) : 8, n = r->n / per;
  if (n > FUZZ_MAX_SAMPLES) n = FUZZ_MAX_SAMPLES;
  clr_film_sample *samples = malloc((n ? n : 1) * sizeof *samples);
  if (!samples) abort();
  for (size_t i = 0; i < n; ++i) {
    if (in->flags & FUZZ_FLAG_RAW) {
      memcpy(&samples[i], r->p, sizeof samples[i]);
      r->p += sizeof samples[i];
      r->n -= sizeof samples[i];
    } else {
      fuzz_read_sample(r, &in->desc, &samples[i]);
    }
  }
  *count = n;
  return samples;
}

/* With FUZZ_FLAG_SPLIT, the number of samples of the first of two calls; else all of them. */
static inline size_t fuzz_first_call(const fuzz_film_input *in, size_t n) {
  size_t first = (in->flags & FUZZ_FLAG_SPLIT) ? (size_t)(in->split * (float)n) : n;
  return first > n ? n : first;
}

/* The input's film twice: *first on ctx (NULL: the host), *host on the host. Returns 0, with
 * neither made, when the description is refused; aborts when only the host film refuses it. */
static inline int fuzz_create_films(clr_context ctx, const clr_film_desc *d, clr_film *first,
                                    clr_film *host) {
  clr_result made = film_create(ctx, d, first);
  fuzz_report("film_create", made);
  if (made != CLR_SUCCESS) return 0;
  if (film_create(NULL, d, host) != CLR_SUCCESS) {
    fprintf(stderr, "fuzz: the host film refused the description: %s\n", clr_last_error_message());
    abort();
  }
  return 1;
}

/* What differs between two films of one description: "accepted samples", "dropped samples",
 * "outside samples", "sums" (double sums, bitwise) or "images" (film_get_rgb, bitwise); NULL when
 * nothing does. Aborts when the films cannot be read. */
static inline const char *fuzz_films_differ(clr_film a, clr_film b) {
  if (film_sample_count(a) != film_sample_count(b)) return "accepted samples";
  if (film_dropped_samples(a) != film_dropped_samples(b)) return "dropped samples";
  if (film_outside_samples(a) != film_outside_samples(b)) return "outside samples";
  clr_bounds2i bounds = film_pixel_bounds(a);
  size_t pixels = (size_t)(bounds.x1 - bounds.x0) * (size_t)(bounds.y1 - bounds.y0);
  double *sums = calloc(pixels * 8 + 1, sizeof *sums);
  float *rgb = calloc(pixels * 6 + 1, sizeof *rgb);
  if (!sums || !rgb) abort();
  if (film_get_sums(a, sums, sums + 3 * pixels, NULL) != CLR_SUCCESS ||
      film_get_sums(b, sums + 4 * pixels, sums + 7 * pixels, NULL) != CLR_SUCCESS ||
      film_get_rgb(a, rgb, 1.0f) != CLR_SUCCESS ||
      film_get_rgb(b, rgb + 3 * pixels, 1.0f) != CLR_SUCCESS) {
    fprintf(stderr, "fuzz: cannot read a film: %s\n", clr_last_error_message());
    abort();
  }
  const char *what = memcmp(sums, sums + 4 * pixels, 4 * pixels * sizeof *sums) ? "sums"
                     : memcmp(rgb, rgb + 3 * pixels, 3 * pixels * sizeof *rgb)  ? "images"
                                                                                : NULL;
  free(sums);
  free(rgb);
  return what;
}

#endif
