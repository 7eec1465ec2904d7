/* Film binning across host thread counts: film_add_samples (host samples and device buffers) and
 * the host reference give, for 1..CLR_FILM_BIN_THREADS_MAX binning threads, the same sums (memcmp)
 * as an independent oracle: every chunk's checked samples stably sorted by their first reached
 * pixel (row, then column), each adding to every pixel it reaches in that order in float, the
 * chunk's float sums then added into double sums; the same accepted, dropped and outside counts;
 * and (host reference) the same binned samples: every float of the last chunk's samples in bin
 * order (memcmp), with and without a luminance clamp. Every filter, odd film sizes, crops, samples
 * on the sample bounds' edges, at the filter radius, outside, NaN/Inf and negative luminance,
 * calls of one part, several parts and two chunks. Runs the real kernels on the default device. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "clrender/film.h"
#include "film_funcs.h"
#include "film_internal.h"

#include "context_fixture.h"

/* One film configuration. */
typedef struct config {
  int xres, yres;
  float crop[4];
  clr_filter_type type;
  float rx, ry;
  int use_table;
  float max_lum;
} config;

static clr_film make_film(const config *c) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = c->xres;
  d.y_resolution = c->yres;
  memcpy(d.crop_window, c->crop, sizeof d.crop_window);
  clr_filter_desc_init(&d.filter, c->type);
  d.filter.radius[0] = c->rx;
  d.filter.radius[1] = c->ry;
  d.filter.use_table = c->use_table;
  d.max_sample_luminance = c->max_lum;
  clr_film film = NULL;
  assert_int_equal(film_create(ctx, &d, &film), CLR_SUCCESS);
  return film;
}

static uint32_t rng_next(uint32_t *s) {
  *s ^= *s << 13;
  *s ^= *s >> 17;
  *s ^= *s << 5;
  return *s;
}

static float rnd(uint32_t *s) { return (float)(rng_next(s) >> 8) * 0x1p-24f; }

/* Sample i of a test batch: mostly uniform over the sample bounds grown by one pixel; every 37th
 * a special case (edges of the sample bounds, a pixel centre at the filter radius, NaN, Inf,
 * negative luminance, huge radiance). */
static clr_film_sample test_sample(clr_film film, const config *c, size_t i, uint32_t *st) {
  clr_bounds2i sb = film_sample_bounds(film), pb = film_pixel_bounds(film);
  float w = (float)(sb.x1 - sb.x0) + 2, h = (float)(sb.y1 - sb.y0) + 2;
  clr_film_sample s = {(float)sb.x0 - 1 + rnd(st) * w,
                       (float)sb.y0 - 1 + rnd(st) * h,
                       rnd(st) * 4.0f,
                       rnd(st),
                       rnd(st) * 0.25f,
                       0.5f + rnd(st)};
  if (i % 37 != 0) return s;
  int32_t px = pb.x0 + (int32_t)(rng_next(st) % (uint32_t)(pb.x1 - pb.x0));
  switch ((i / 37) % 10) {
    case 0:
      s.x = (float)sb.x0;
      break;
    case 1:
      s.y = (float)sb.y1;
      break; /* outside (half-open) */
    case 2:
      s.x = (float)pb.x1 - 0.5f + c->rx;
      break; /* reaches the last pixel */
    case 3:
      s.x = (float)px + 0.5f + c->rx;
      break; /* a pixel centre at the radius */
    case 4:
      s.y = (float)px + 0.5f - c->ry;
      break;
    case 5:
      s.x = NAN;
      break;
    case 6:
      s.g = INFINITY;
      break;
    case 7:
      s.r = -1.0f;
      break; /* negative luminance: dropped */
    case 8:
      s.b = 1e6f;
      break; /* clamped where max_lum is finite */
    default:
      s.weight = 0.0f;
      break;
  }
  return s;
}

/* A checked sample of the oracle and its place in the batch (the stable sort's tie-break). */
typedef struct keyed {
  clr_film_prepared p;
  size_t index;
} keyed;

static int by_first_pixel(const void *a, const void *b) {
  const keyed *x = a, *y = b;
  if (x->p.y0 != y->p.y0) return x->p.y0 < y->p.y0 ? -1 : 1;
  if (x->p.x0 != y->p.x0) return x->p.x0 < y->p.x0 ? -1 : 1;
  return x->index < y->index ? -1 : x->index > y->index;
}

/* What the oracle expects of a film: its sums (rgb, 3 per pixel, and w), its sample counts, and
 * the last chunk's binned samples (CLR_FILM_BINNED_FLOATS each, in the canonical order). */
typedef struct expected {
  double *rgb, *w;
  uint64_t accepted, dropped, outside;
  float *binned;
  size_t binned_count;
} expected;

/* The oracle's sums of samples[0..n), chunk by chunk, its counts and last chunk's bins. */
static void oracle(clr_film film, const clr_film_sample *samples, size_t n, expected *e) {
  const clr_film_params *fp = &film->params;
  const size_t width = (size_t)(fp->pixel_x1 - fp->pixel_x0);
  const size_t pixels = width * (size_t)(fp->pixel_y1 - fp->pixel_y0);
  double *rgb = e->rgb, *w = e->w;
  memset(rgb, 0, pixels * 3 * sizeof *rgb);
  memset(w, 0, pixels * sizeof *w);
  e->accepted = e->dropped = e->outside = 0;
  float *sums = malloc(pixels * CLR_FILM_SUM_FLOATS * sizeof *sums);
  keyed *k = malloc((n < CLR_FILM_CHUNK_SAMPLES ? n : CLR_FILM_CHUNK_SAMPLES) * sizeof *k);
  assert_true(sums && k);
  for (size_t at = 0; at < n; at += CLR_FILM_CHUNK_SAMPLES) {
    size_t end = n - at < CLR_FILM_CHUNK_SAMPLES ? n : at + CLR_FILM_CHUNK_SAMPLES, m = 0;
    for (size_t i = at; i < end; ++i) {
      const clr_film_sample *s = &samples[i];
      clr_film_prepared p;
      clr_i32 status =
          clr_film_prepare(fp, &film->filter, s->x, s->y, s->r, s->g, s->b, s->weight, &p);
      e->dropped += status == CLR_FILM_SAMPLE_DROPPED;
      e->outside += status == CLR_FILM_SAMPLE_OUTSIDE;
      if (status != CLR_FILM_SAMPLE_OK) continue;
      ++e->accepted;
      if (p.x1 >= fp->pixel_x0 && p.x0 < fp->pixel_x1 && p.y1 >= fp->pixel_y0 &&
          p.y0 < fp->pixel_y1)
        k[m++] = (keyed){p, i};
    }
    qsort(k, m, sizeof *k, by_first_pixel);
    for (size_t j = 0; j < m; ++j) {
      const clr_film_prepared *p = &k[j].p;
      const float v[CLR_FILM_BINNED_FLOATS] = {p->dx, p->dy, p->r, p->g, p->b, p->w};
      memcpy(e->binned + j * CLR_FILM_BINNED_FLOATS, v, sizeof v);
    }
    e->binned_count = m;
    memset(sums, 0, pixels * CLR_FILM_SUM_FLOATS * sizeof *sums);
    for (size_t j = 0; j < m; ++j) {
      const clr_film_prepared *p = &k[j].p;
      for (int32_t y = p->y0 > fp->pixel_y0 ? p->y0 : fp->pixel_y0; y <= p->y1 && y < fp->pixel_y1;
           ++y)
        for (int32_t x = p->x0 > fp->pixel_x0 ? p->x0 : fp->pixel_x0;
             x <= p->x1 && x < fp->pixel_x1; ++x) {
          size_t pix = (size_t)(y - fp->pixel_y0) * width + (size_t)(x - fp->pixel_x0);
          clr_film_accumulate(&film->filter, film->factors, p, x, y,
                              sums + pix * CLR_FILM_SUM_FLOATS);
        }
    }
    for (size_t pix = 0; pix < pixels; ++pix) {
      for (int c = 0; c < 3; ++c) rgb[3 * pix + c] += (double)sums[pix * CLR_FILM_SUM_FLOATS + c];
      w[pix] += (double)sums[pix * CLR_FILM_SUM_FLOATS + 3];
    }
  }
  free(k);
  free(sums);
}

typedef enum add_path { HOST_SAMPLES, DEVICE_BUFFER, REFERENCE } add_path;

/* Adds samples through `path` with `threads` binning threads; asserts the oracle's sums and
 * counts, and on the host reference its last chunk's binned samples (the binning's output). */
static void check_path(const config *c, const clr_film_sample *samples, size_t n, int threads,
                       add_path path, const expected *e) {
  clr_film film = make_film(c);
  assert_int_equal(film_set_bin_threads(film, threads), CLR_SUCCESS);
  if (path == DEVICE_BUFFER) {
    cl_int err = 0;
    cl_mem buf =
        clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                       n * sizeof *samples, (void *)samples, &err);
    assert_int_equal(err, CL_SUCCESS);
    assert_int_equal(film_add_samples_buffer(film, buf, n), CLR_SUCCESS);
    clReleaseMemObject(buf);
  } else if (path == REFERENCE) {
    assert_int_equal(film_add_samples_reference(film, samples, n), CLR_SUCCESS);
  } else {
    assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
  }
  clr_bounds2i pb = film_pixel_bounds(film);
  size_t pixels = (size_t)(pb.x1 - pb.x0) * (size_t)(pb.y1 - pb.y0);
  double *got_rgb = malloc(pixels * 3 * sizeof *got_rgb), *got_w = malloc(pixels * sizeof *got_w);
  assert_true(got_rgb && got_w);
  assert_int_equal(film_get_sums(film, got_rgb, got_w, NULL), CLR_SUCCESS);
  assert_memory_equal(got_rgb, e->rgb, pixels * 3 * sizeof *e->rgb);
  assert_memory_equal(got_w, e->w, pixels * sizeof *e->w);
  assert_int_equal(film_sample_count(film), e->accepted);
  assert_int_equal(film->accepted, e->accepted);
  assert_int_equal(film->dropped, e->dropped);
  assert_int_equal(film->outside, e->outside);
  if (path == REFERENCE)
    assert_memory_equal(film->bins.binned, e->binned,
                        e->binned_count * CLR_FILM_BINNED_FLOATS * sizeof *e->binned);
  free(got_rgb);
  free(got_w);
  film_release(film);
}

/* n test samples of configuration c through every thread count (host samples), and through the
 * device buffer and the host reference with 3 threads, against the oracle. */
static void check_config(const config *c, size_t n, uint32_t seed) {
  clr_film film = make_film(c);
  clr_film_sample *samples = malloc(n * sizeof *samples);
  assert_non_null(samples);
  for (size_t i = 0; i < n; ++i) samples[i] = test_sample(film, c, i, &seed);
  clr_bounds2i pb = film_pixel_bounds(film);
  size_t pixels = (size_t)(pb.x1 - pb.x0) * (size_t)(pb.y1 - pb.y0);
  size_t chunk = n < CLR_FILM_CHUNK_SAMPLES ? n : CLR_FILM_CHUNK_SAMPLES;
  expected e = {malloc(pixels * 3 * sizeof *e.rgb),
                malloc(pixels * sizeof *e.w),
                0,
                0,
                0,
                malloc(chunk * CLR_FILM_BINNED_FLOATS * sizeof *e.binned),
                0};
  assert_true(e.rgb && e.w && e.binned);
  oracle(film, samples, n, &e);
  film_release(film);
  double total = 0;
  for (size_t i = 0; i < pixels; ++i) total += e.w[i];
  assert_true(e.accepted > n / 2 && total > 0 && e.binned_count > 0); /* real work */
  assert_true(e.dropped > 0 && e.outside > 0);
  const int threads[] = {0, 1, 2, 3, 5, 8, CLR_FILM_BIN_THREADS_MAX};
  for (size_t t = 0; t < sizeof threads / sizeof threads[0]; ++t)
    check_path(c, samples, n, threads[t], HOST_SAMPLES, &e);
  check_path(c, samples, n, 3, DEVICE_BUFFER, &e);
  check_path(c, samples, n, 3, REFERENCE, &e);
  check_path(c, samples, n, 1, REFERENCE, &e);
  free(e.rgb);
  free(e.w);
  free(e.binned);
  free(samples);
}

/* Three parts at most (CLR_FILM_BIN_PART_MIN samples each), on small odd films. */
static void test_every_filter_few_parts(void **state) {
  (void)state;
  const clr_filter_type types[] = {
      CLR_FILTER_BOX,  CLR_FILTER_TRIANGLE,       CLR_FILTER_GAUSSIAN,  CLR_FILTER_MITCHELL,
      CLR_FILTER_SINC, CLR_FILTER_BLACKMANHARRIS, CLR_FILTER_CATMULLROM};
  for (size_t t = 0; t < sizeof types / sizeof types[0]; ++t)
    for (int table = 0; table < 2; ++table) {
      config c = {37, 23, {0, 1, 0, 1}, types[t], 2.0f, 1.5f, table, INFINITY};
      check_config(&c, 3 * CLR_FILM_BIN_PART_MIN + 123,
                   1000u + (uint32_t)(2 * t) + (uint32_t)table);
    }
}

/* Wide filters (reach past the 8-lane kernels), a crop, a luminance clamp. */
static void test_wide_filter_crop_clamp(void **state) {
  (void)state;
  config sinc = {41, 29, {0.1f, 0.83f, 0.2f, 0.9f}, CLR_FILTER_SINC, 4.0f, 4.0f, 0, 2.0f};
  check_config(&sinc, 2 * CLR_FILM_BIN_PART_MIN + 7, 77u);
  config gauss = {19, 31, {0, 1, 0, 1}, CLR_FILTER_GAUSSIAN, 5.5f, 0.75f, 1, 1.5f};
  check_config(&gauss, 5 * CLR_FILM_BIN_PART_MIN + 1, 78u);
}

/* The 8-lane kernels at the widest filters they take: radius 3.5, where devices that share the
 * host's memory and compute in double add the chunk sums into the film's double sums themselves
 * (also on a crop, whose pixel bounds start inside the image, with a luminance clamp), and 3.75
 * (still at most 8 pixels), where the host adds them. */
static void test_lane_filters_device_and_host_add(void **state) {
  (void)state;
  config widest = {45, 27, {0, 1, 0, 1}, CLR_FILTER_MITCHELL, 3.5f, 3.5f, 0, INFINITY};
  check_config(&widest, 3 * CLR_FILM_BIN_PART_MIN + 5, 91u);
  config cropped = {45, 27, {0.1f, 0.83f, 0.2f, 0.9f}, CLR_FILTER_GAUSSIAN, 2.0f, 3.5f, 1, 3.0f};
  check_config(&cropped, 3 * CLR_FILM_BIN_PART_MIN + 5, 93u);
  config past = {45, 27, {0, 1, 0, 1}, CLR_FILTER_TRIANGLE, 3.75f, 3.0f, 0, INFINITY};
  check_config(&past, 3 * CLR_FILM_BIN_PART_MIN + 5, 92u);
}

/* Every thread count gets its parts (16 of them), and a call of two chunks (the second one
 * part). */
static void test_many_parts_and_chunks(void **state) {
  (void)state;
  config c = {53, 17, {0, 1, 0, 1}, CLR_FILTER_MITCHELL, 2.0f, 2.0f, 0, INFINITY};
  check_config(&c, CLR_FILM_BIN_THREADS_MAX * CLR_FILM_BIN_PART_MIN + 999, 5u);
  config t = {29, 13, {0, 1, 0, 1}, CLR_FILTER_TRIANGLE, 1.25f, 2.0f, 0, INFINITY};
  check_config(&t, CLR_FILM_CHUNK_SAMPLES + CLR_FILM_BIN_PART_MIN + 1, 6u);
}

static void test_bad_thread_counts(void **state) {
  (void)state;
  config c = {8, 8, {0, 1, 0, 1}, CLR_FILTER_BOX, 0.5f, 0.5f, 0, INFINITY};
  clr_film film = make_film(&c);
  assert_int_equal(film_set_bin_threads(film, -1), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "threads = -1"));
  assert_int_equal(film_set_bin_threads(film, CLR_FILM_BIN_THREADS_MAX + 1),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(film_set_bin_threads(NULL, 2), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_set_bin_threads(film, 4), CLR_SUCCESS);
  assert_int_equal(clr_film_host_threads(film), 4);
  assert_int_equal(film_set_bin_threads(film, 0), CLR_SUCCESS);
  int automatic = clr_film_host_threads(film);
  assert_true(automatic >= 1 && automatic <= 8);
  film_release(film);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bad_thread_counts),
      cmocka_unit_test(test_every_filter_few_parts),
      cmocka_unit_test(test_wide_filter_crop_clamp),
      cmocka_unit_test(test_lane_filters_device_and_host_add),
      cmocka_unit_test(test_many_parts_and_chunks),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
