/* Film: pbrt-v3 bounds, reconstruction sums bit-identical across accumulation tile sizes,
 * work-group sizes and the host reference, against a double brute force, bad samples, tiles,
 * splats, sums and resolve. Runs the real kernels on the default device (PoCL on CI). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "clrender/film.h"
#include "film_internal.h"
#include "xorshift_test_random.h"

#include "context_fixture.h"

typedef struct film_setup {
  int xres, yres;
  float crop[4];
  int filter_type;
  float rx, ry;
  int use_table;
  int tile;
  float max_lum;
  float scale;
} film_setup;

static film_setup basic(int xres, int yres, int filter_type, float radius) {
  film_setup s = {xres, yres, {0, 1, 0, 1}, filter_type, radius, radius, 1, 16, INFINITY, 1.0f};
  return s;
}

static clr_film make_film(const film_setup *s) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = s->xres;
  d.y_resolution = s->yres;
  memcpy(d.crop_window, s->crop, sizeof d.crop_window);
  clr_filter_desc_init(&d.filter, (clr_filter_type)s->filter_type);
  d.filter.radius[0] = s->rx;
  d.filter.radius[1] = s->ry;
  d.filter.use_table = s->use_table;
  d.accumulation_tile_size = s->tile;
  d.max_sample_luminance = s->max_lum;
  d.scale = s->scale;
  clr_film film = NULL;
  assert_int_equal(film_create(ctx, &d, &film), CLR_SUCCESS);
  return film;
}

/* Random samples over the film's sample bounds grown by `margin` (so some fall outside). */
static clr_film_sample *random_samples(clr_film film, size_t n, float margin, uint32_t seed) {
  clr_bounds2i sb = film_sample_bounds(film);
  clr_film_sample *s = malloc(n * sizeof *s);
  assert_non_null(s);
  rng_state = seed;
  float w = (float)(sb.x1 - sb.x0) + 2 * margin, h = (float)(sb.y1 - sb.y0) + 2 * margin;
  for (size_t i = 0; i < n; ++i) {
    s[i].x = (float)sb.x0 - margin + rnd() * w;
    s[i].y = (float)sb.y0 - margin + rnd() * h;
    s[i].r = rnd() * 4.0f;
    s[i].g = rnd();
    s[i].b = rnd() * 0.25f;
    s[i].weight = 0.5f + rnd();
  }
  return s;
}

/* 16 jittered samples (4x4 strata) in every pixel of the film's sample bounds, all of radiance
 * (0.25, 0.5, 2) and weight 1; their count in *n. */
static clr_film_sample *constant_jittered_samples(clr_film film, uint32_t seed, size_t *n) {
  clr_bounds2i sb = film_sample_bounds(film);
  size_t cap = (size_t)(sb.x1 - sb.x0) * (sb.y1 - sb.y0) * 16;
  clr_film_sample *samples = malloc(cap * sizeof *samples);
  assert_non_null(samples);
  rng_state = seed;
  *n = 0;
  for (int y = sb.y0; y < sb.y1; ++y)
    for (int x = sb.x0; x < sb.x1; ++x)
      for (int k = 0; k < 16; ++k) {
        clr_film_sample smp = {(float)x + ((float)(k % 4) + rnd()) * 0.25f,
                               (float)y + ((float)(k / 4) + rnd()) * 0.25f,
                               0.25f,
                               0.5f,
                               2.0f,
                               1.0f};
        samples[(*n)++] = smp;
      }
  return samples;
}

/* Adds the samples from a device buffer (film_add_samples_buffer). */
static void add_samples_from_buffer(clr_film film, clr_film_sample *samples, size_t n) {
  cl_int err = 0;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              n * sizeof *samples, samples, &err);
  assert_int_equal(err, CL_SUCCESS);
  assert_int_equal(film_add_samples_buffer(film, buf, n), CLR_SUCCESS);
  clReleaseMemObject(buf);
}

typedef struct sums {
  size_t n;
  double *rgb, *w, *splat;
} sums;

static sums get_sums(clr_film film) {
  clr_bounds2i b = film_pixel_bounds(film);
  sums s;
  s.n = (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0);
  s.rgb = malloc(s.n * 3 * sizeof(double));
  s.w = malloc(s.n * sizeof(double));
  s.splat = malloc(s.n * 3 * sizeof(double));
  assert_true(s.rgb && s.w && s.splat);
  assert_int_equal(film_get_sums(film, s.rgb, s.w, s.splat), CLR_SUCCESS);
  return s;
}

static void free_sums(sums *s) {
  free(s->rgb);
  free(s->w);
  free(s->splat);
}

static void assert_sums_identical(const sums *a, const sums *b) {
  assert_int_equal(a->n, b->n);
  assert_memory_equal(a->rgb, b->rgb, a->n * 3 * sizeof(double));
  assert_memory_equal(a->w, b->w, a->n * sizeof(double));
  assert_memory_equal(a->splat, b->splat, a->n * 3 * sizeof(double));
}

static float *get_rgb(clr_film film, float splat_scale) {
  clr_bounds2i b = film_pixel_bounds(film);
  size_t n = (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0);
  float *rgb = malloc(n * 3 * sizeof *rgb);
  assert_non_null(rgb);
  assert_int_equal(film_get_rgb(film, rgb, splat_scale), CLR_SUCCESS);
  return rgb;
}

/* |a - b| <= tol * max(|b|, image mean) for every value. */
static void assert_rgb_close(const float *a, const float *b, size_t n, double tol) {
  double mean = 0;
  for (size_t i = 0; i < n; ++i) mean += fabs((double)b[i]);
  mean /= (double)n;
  for (size_t i = 0; i < n; ++i) {
    double ref = fmax(fabs((double)b[i]), mean);
    if (fabs((double)a[i] - (double)b[i]) > tol * ref)
      fail_msg("value %zu: %.9g vs %.9g (tolerance %g of %g)", i, (double)a[i], (double)b[i], tol,
               ref);
  }
}

static void test_bounds_match_pbrt(void **state) {
  (void)state;
  film_setup s = basic(1280, 720, CLR_FILTER_TYPE_BOX, 0.5f);
  clr_film film = make_film(&s);
  clr_bounds2i b = film_pixel_bounds(film);
  assert_true(b.x0 == 0 && b.y0 == 0 && b.x1 == 1280 && b.y1 == 720);
  b = film_sample_bounds(film);
  assert_true(b.x0 == 0 && b.y0 == 0 && b.x1 == 1280 && b.y1 == 720);
  film_release(film);

  float crop[4] = {0.25f, 0.75f, 0.1f, 0.9f};
  memcpy(s.crop, crop, sizeof crop);
  film = make_film(&s);
  b = film_pixel_bounds(film);
  assert_true(b.x0 == 320 && b.y0 == 72 && b.x1 == 960 && b.y1 == 648);
  film_release(film);

  /* Triangle radius 2: [floor(p0 + .5 - 2), ceil(p1 - .5 + 2)). Swapped crop values are sorted. */
  film_setup t = basic(1280, 720, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  float swapped[4] = {0.75f, 0.25f, 0.9f, 0.1f};
  memcpy(t.crop, swapped, sizeof swapped);
  film = make_film(&t);
  b = film_pixel_bounds(film);
  assert_true(b.x0 == 320 && b.y0 == 72 && b.x1 == 960 && b.y1 == 648);
  b = film_sample_bounds(film);
  assert_true(b.x0 == 318 && b.y0 == 70 && b.x1 == 962 && b.y1 == 650);
  film_release(film);

  /* pbrt multiplies in float: 1280 * 0.3f rounds to exactly 384 (in double it is 384.0000153). */
  float crop3[4] = {0.3f, 1.0f, 0.0f, 0.5f};
  memcpy(s.crop, crop3, sizeof crop3);
  film = make_film(&s);
  b = film_pixel_bounds(film);
  assert_true(b.x0 == 384 && b.x1 == 1280 && b.y0 == 0 && b.y1 == 360);
  film_release(film);
}

/* A caller built against an older, smaller clr_film_desc: the fields past its struct_size get
 * their defaults, whatever the memory beyond holds. */
static void test_older_desc_gets_defaults(void **state) {
  (void)state;
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = 32;
  d.y_resolution = 8;
  d.struct_size = offsetof(clr_film_desc, accumulation_tile_size);
  d.accumulation_tile_size = 999; /* beyond the old struct: must be ignored */
  clr_film film = NULL;
  assert_int_equal(film_create(ctx, &d, &film), CLR_SUCCESS);
  const clr_film_desc *got = film_get_desc(film);
  assert_int_equal(got->struct_size, sizeof(clr_film_desc));
  assert_int_equal(got->accumulation_tile_size, 16);
  assert_int_equal(got->x_resolution, 32);
  assert_int_equal(got->y_resolution, 8);
  film_release(film);
}

static void test_bad_inputs(void **state) {
  (void)state;
  clr_film_desc d;
  clr_film_desc_init(&d);
  assert_int_equal(d.x_resolution, 1280);
  assert_int_equal(d.y_resolution, 720);
  assert_true(isinf(d.max_sample_luminance));
  assert_int_equal(d.accumulation_tile_size, 16);
  clr_film film = NULL;
  assert_int_equal(film_create(ctx, NULL, &film), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_create(ctx, &d, NULL), CLR_ERROR_NULL_POINTER);

  clr_film_desc bad = d;
  size_t bad_sizes[] = {0, 4, 6, sizeof d + 4, sizeof d + 1};
  for (size_t i = 0; i < sizeof bad_sizes / sizeof bad_sizes[0]; ++i) {
    bad.struct_size = bad_sizes[i];
    assert_int_equal(film_create(ctx, &bad, &film), CLR_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(clr_last_error_message(), "struct_size"));
  }
  int32_t resolutions[][2] = {{0, 10}, {10, -1}, {40000, 10}, {32768, 32768}};
  for (size_t i = 0; i < 4; ++i) {
    bad = d;
    bad.x_resolution = resolutions[i][0];
    bad.y_resolution = resolutions[i][1];
    assert_int_equal(film_create(ctx, &bad, &film), CLR_ERROR_INVALID_RESOLUTION);
    assert_null(film);
  }
  float crops[][4] = {
      {-0.1f, 1, 0, 1}, {0, 1.5f, 0, 1}, {0, 1, NAN, 1}, {0.5f, 0.5f, 0, 1}, {0, 1, 0.2f, 0.2f}};
  for (size_t i = 0; i < 5; ++i) {
    bad = d;
    memcpy(bad.crop_window, crops[i], sizeof bad.crop_window);
    assert_int_equal(film_create(ctx, &bad, &film), CLR_ERROR_INVALID_CROP_WINDOW);
  }
  bad = d;
  bad.crop_window[0] = 1.5f;
  assert_int_equal(film_create(ctx, &bad, &film), CLR_ERROR_INVALID_CROP_WINDOW);
  assert_non_null(strstr(clr_last_error_message(), "1.5"));
  float radii[] = {-1.0f, 0.0f, NAN, INFINITY, 100.0f};
  for (size_t i = 0; i < 5; ++i) {
    bad = d;
    bad.filter.radius[i % 2] = radii[i];
    assert_int_equal(film_create(ctx, &bad, &film), CLR_ERROR_INVALID_RADIUS);
  }
  int tiles[] = {3, 65, 0, -16};
  for (size_t i = 0; i < 4; ++i) {
    bad = d;
    bad.accumulation_tile_size = tiles[i];
    assert_int_equal(film_create(ctx, &bad, &film), CLR_ERROR_INVALID_ARGUMENT);
  }
  bad = d;
  bad.max_sample_luminance = NAN;
  assert_int_equal(film_create(ctx, &bad, &film), CLR_ERROR_INVALID_ARGUMENT);

  d.x_resolution = 8;
  d.y_resolution = 8;
  assert_int_equal(film_create(ctx, &d, &film), CLR_SUCCESS);
  clr_film_sample one = {4, 4, 1, 1, 1, 1};
  assert_int_equal(film_add_samples(NULL, &one, 1), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_add_samples(film, NULL, 1), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_add_samples(film, &one, 0), CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(film_add_samples_buffer(film, NULL, 1), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_add_splat(NULL, 1, 1, 1, 1, 1), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_get_rgb(film, NULL, 1.0f), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_get_sums(film, NULL, NULL, NULL), CLR_ERROR_NULL_POINTER);
  double w[4] = {0};
  clr_bounds2i outside = {6, 6, 10, 7};
  assert_int_equal(film_merge_sums(film, outside, NULL, w, NULL), CLR_ERROR_INVALID_PIXEL_RANGE);
  clr_bounds2i empty = {2, 2, 2, 4};
  clr_film_tile tile = NULL;
  assert_int_equal(film_get_tile(film, empty, &tile), CLR_ERROR_INVALID_PIXEL_RANGE);
  /* A buffer smaller than count samples. */
  cl_int err = 0;
  cl_mem small = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_ONLY, 48, NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  assert_int_equal(film_add_samples_buffer(film, small, 3), CLR_ERROR_INVALID_ARGUMENT);
  clReleaseMemObject(small);
  assert_int_equal(film_sample_count(film), 0);
  film_release(film);
}

/* Same samples through every tile size, some work-group sizes, the device-buffer path and the
 * host reference: identical sums. */
static void check_invariance(film_setup s, size_t n, uint32_t seed) {
  s.tile = 16;
  clr_film ref = make_film(&s);
  clr_film_sample *samples = random_samples(ref, n, 1.0f, seed);
  assert_int_equal(film_add_samples_reference(ref, samples, n), CLR_SUCCESS);
  sums expect = get_sums(ref);
  uint64_t accepted = film_sample_count(ref), outside = film_outside_samples(ref);
  assert_true(accepted > n / 2 && outside > 0);
  double total_weight = 0;
  for (size_t i = 0; i < expect.n; ++i) total_weight += expect.w[i];
  assert_true(total_weight > 0);

  const int tiles[] = {4, 8, 16, 33, 64};
  for (size_t t = 0; t < 5; ++t) {
    s.tile = tiles[t];
    clr_film film = make_film(&s);
    assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
    sums got = get_sums(film);
    assert_sums_identical(&got, &expect);
    assert_int_equal(film_sample_count(film), accepted);
    assert_int_equal(film_outside_samples(film), outside);
    free_sums(&got);
    film_release(film);
  }
  /* Work-group sizes (threads per tile) that do not divide the tile. */
  const size_t groups[] = {37, 64};
  for (size_t g = 0; g < 2; ++g) {
    s.tile = 16;
    clr_film film = make_film(&s);
    assert_int_equal(film_set_group_size(film, groups[g]), CLR_SUCCESS);
    assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
    sums got = get_sums(film);
    assert_sums_identical(&got, &expect);
    free_sums(&got);
    film_release(film);
  }
  /* Device-resident samples. */
  clr_film film = make_film(&s);
  add_samples_from_buffer(film, samples, n);
  sums got = get_sums(film);
  assert_sums_identical(&got, &expect);
  free_sums(&got);
  film_release(film);

  free_sums(&expect);
  free(samples);
  film_release(ref);
}

static void test_tile_size_invariance_box(void **state) {
  (void)state;
  film_setup s = basic(61, 47, CLR_FILTER_TYPE_BOX, 0.5f);
  check_invariance(s, 20000, 1u);
  s.rx = 1.3f;
  s.ry = 0.7f;
  s.use_table = 0;
  check_invariance(s, 8000, 2u);
}

static void test_tile_size_invariance_triangle(void **state) {
  (void)state;
  film_setup s = basic(80, 60, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  float crop[4] = {0.1f, 0.9f, 0.2f, 0.85f};
  memcpy(s.crop, crop, sizeof crop);
  check_invariance(s, 20000, 3u);
  s.rx = 1.5f;
  s.ry = 2.5f;
  s.use_table = 0;
  s.max_lum = 1.5f;
  check_invariance(s, 10000, 4u);
}

static void test_split_calls(void **state) {
  (void)state;
  film_setup s = basic(50, 40, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  clr_film one = make_film(&s), split = make_film(&s), split_ref = make_film(&s);
  size_t n = 30000;
  clr_film_sample *samples = random_samples(one, n, 0.0f, 5u);
  assert_int_equal(film_add_samples(one, samples, n), CLR_SUCCESS);
  const size_t cuts[] = {0, 1000, 1001, 9000, 17000, 30000};
  for (size_t i = 0; i + 1 < 6; ++i) {
    assert_int_equal(film_add_samples(split, samples + cuts[i], cuts[i + 1] - cuts[i]),
                     CLR_SUCCESS);
    assert_int_equal(
        film_add_samples_reference(split_ref, samples + cuts[i], cuts[i + 1] - cuts[i]),
        CLR_SUCCESS);
  }
  float *a = get_rgb(one, 1.0f), *b = get_rgb(split, 1.0f);
  assert_rgb_close(b, a, 50 * 40 * 3, 1e-5);
  sums x = get_sums(split), y = get_sums(split_ref);
  assert_sums_identical(&x, &y);
  assert_int_equal(film_sample_count(split), n);
  free_sums(&x);
  free_sums(&y);
  free(a);
  free(b);
  free(samples);
  film_release(one);
  film_release(split);
  film_release(split_ref);
}

static void test_box_pixel_centres_reproduce_image(void **state) {
  (void)state;
  film_setup s = basic(37, 29, CLR_FILTER_TYPE_BOX, 0.5f);
  float crop[4] = {0.1f, 0.8f, 0.0f, 0.9f};
  memcpy(s.crop, crop, sizeof crop);
  s.tile = 4;
  clr_film film = make_film(&s);
  clr_bounds2i b = film_pixel_bounds(film);
  int w = b.x1 - b.x0, h = b.y1 - b.y0;
  clr_film_sample *samples = malloc((size_t)w * h * sizeof *samples);
  float *image = malloc((size_t)w * h * 3 * sizeof *image);
  assert_true(samples && image);
  rng_state = 77u;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t i = (size_t)y * w + x;
      for (int c = 0; c < 3; ++c) image[3 * i + c] = rnd() * 10.0f;
      clr_film_sample smp = {(float)(b.x0 + x) + 0.5f, (float)(b.y0 + y) + 0.5f, image[3 * i],
                             image[3 * i + 1],         image[3 * i + 2],         1.0f};
      samples[i] = smp;
    }
  assert_int_equal(film_add_samples(film, samples, (size_t)w * h), CLR_SUCCESS);
  float *rgb = get_rgb(film, 1.0f);
  assert_memory_equal(rgb, image, (size_t)w * h * 3 * sizeof *rgb);
  free(rgb);
  free(samples);
  free(image);
  film_release(film);
}

static void test_constant_radiance_triangle(void **state) {
  (void)state;
  film_setup s = basic(40, 30, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  clr_film film = make_film(&s);
  size_t n = 0;
  clr_film_sample *samples = constant_jittered_samples(film, 9u, &n);
  assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
  float *rgb = get_rgb(film, 1.0f);
  const float expect[3] = {0.25f, 0.5f, 2.0f};
  for (int i = 0; i < 40 * 30; ++i)
    for (int c = 0; c < 3; ++c) assert_float_equal(rgb[3 * i + c], expect[c], 1e-5 * expect[c]);
  free(rgb);
  free(samples);
  film_release(film);
}

/* pbrt's formula in double: sum_i L_i w_i f(p - d_i) / sum_i f(p - d_i), triangle exact. */
static void test_brute_force_double(void **state) {
  (void)state;
  film_setup s = basic(24, 18, CLR_FILTER_TYPE_TRIANGLE, 1.7f);
  s.ry = 2.3f;
  s.use_table = 0;
  clr_film film = make_film(&s);
  size_t n = 4000;
  clr_film_sample *samples = random_samples(film, n, 0.0f, 11u);
  assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
  float *rgb = get_rgb(film, 1.0f);
  float *expect = malloc(24 * 18 * 3 * sizeof *expect);
  assert_non_null(expect);
  for (int py = 0; py < 18; ++py)
    for (int px = 0; px < 24; ++px) {
      double acc[3] = {0, 0, 0}, wsum = 0;
      for (size_t i = 0; i < n; ++i) {
        double dx = (double)px - ((double)samples[i].x - 0.5);
        double dy = (double)py - ((double)samples[i].y - 0.5);
        double f = fmax(0.0, (double)s.rx - fabs(dx)) * fmax(0.0, (double)s.ry - fabs(dy));
        acc[0] += samples[i].r * samples[i].weight * f;
        acc[1] += samples[i].g * samples[i].weight * f;
        acc[2] += samples[i].b * samples[i].weight * f;
        wsum += f;
      }
      for (int c = 0; c < 3; ++c) expect[(py * 24 + px) * 3 + c] = (float)(acc[c] / wsum);
    }
  /* Float sums of ~100 terms per pixel: a few float ulps. */
  assert_rgb_close(rgb, expect, 24 * 18 * 3, 2e-6);
  free(expect);
  free(rgb);
  free(samples);
  film_release(film);
}

static void test_bad_samples_dropped(void **state) {
  (void)state;
  film_setup s = basic(16, 16, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  clr_film film = make_film(&s), clean = make_film(&s);
  clr_bounds2i sb = film_sample_bounds(film);
  const clr_film_sample good[] = {{3.2f, 4.7f, 1, 2, 3, 1},
                                  {8.0f, 8.0f, 0.5f, 0.25f, 0.125f, 2},
                                  {5.5f, 9.1f, -1e-5f, 0, 0, 1}, /* luminance -2e-6: kept */
                                  {12.9f, 0.4f, 4, 0, 1, 0.5f}};
  const clr_film_sample bad[] = {{NAN, 3, 1, 1, 1, 1},     {3, 3, INFINITY, 1, 1, 1},
                                 {3, 3, 1, 1, 1, NAN},     {3, 3, -1, 0, 0, 1},
                                 {3, 3, 0, -2e-5f, 0, 1},  {3, 3, 1, 1, 1, -INFINITY},
                                 {3, INFINITY, 1, 1, 1, 1}};
  const clr_film_sample outside[] = {
      {-5, 3, 1, 1, 1, 1}, {3, (float)sb.y1, 1, 1, 1, 1}, {(float)sb.x0 - 0.001f, 3, 1, 1, 1, 1}};
  clr_film_sample all[14];
  size_t n = 0;
  all[n++] = bad[0];
  all[n++] = good[0];
  all[n++] = outside[0];
  all[n++] = bad[1];
  all[n++] = bad[2];
  all[n++] = good[1];
  all[n++] = bad[3];
  all[n++] = outside[1];
  all[n++] = bad[4];
  all[n++] = good[2];
  all[n++] = bad[5];
  all[n++] = bad[6];
  all[n++] = outside[2];
  all[n++] = good[3];
  assert_int_equal(film_add_samples(film, all, n), CLR_SUCCESS);
  assert_int_equal(film_sample_count(film), 4);
  assert_int_equal(film_dropped_samples(film), 7);
  assert_int_equal(film_outside_samples(film), 3);
  assert_int_equal(film_add_samples(clean, good, 4), CLR_SUCCESS);
  sums a = get_sums(film), b = get_sums(clean);
  assert_sums_identical(&a, &b);
  double total = 0;
  for (size_t i = 0; i < a.n; ++i) total += a.w[i];
  assert_true(total > 0);
  /* Only bad samples: nothing added, every one counted. */
  assert_int_equal(film_add_samples(clean, bad, 7), CLR_SUCCESS);
  assert_int_equal(film_dropped_samples(clean), 7);
  sums c = get_sums(clean);
  assert_sums_identical(&c, &b);
  /* L * w overflowing float is dropped too (its sums would be inf, and inf * 0 NaN). */
  const clr_film_sample overflow[] = {{3, 3, 1e30f, 1, 1, 1e30f}, {3, 3, 1, 1, 1e20f, 1e20f}};
  assert_int_equal(film_add_samples(clean, overflow, 2), CLR_SUCCESS);
  assert_int_equal(film_dropped_samples(clean), 9);
  assert_int_equal(film_sample_count(clean), 4);
  free_sums(&c);
  c = get_sums(clean);
  assert_sums_identical(&c, &b);
  free_sums(&a);
  free_sums(&b);
  free_sums(&c);
  film_release(film);
  film_release(clean);
}

static void test_max_luminance_clamp(void **state) {
  (void)state;
  film_setup s = basic(4, 4, CLR_FILTER_TYPE_BOX, 0.5f);
  s.max_lum = 2.0f;
  clr_film film = make_film(&s);
  const clr_film_sample samples[] = {{1.5f, 1.5f, 10, 10, 10, 1}, {2.5f, 1.5f, 1, 0.5f, 2, 1}};
  assert_int_equal(film_add_samples(film, samples, 2), CLR_SUCCESS);
  float *rgb = get_rgb(film, 1.0f);
  volatile float lum = 0.212671f * 10.0f + 0.715160f * 10.0f + 0.072169f * 10.0f;
  volatile float k = 2.0f / lum;
  float clamped = 10.0f * k;
  for (int c = 0; c < 3; ++c) assert_true(rgb[(1 * 4 + 1) * 3 + c] == clamped);
  assert_true(fabsf(clamped - 2.0f) < 1e-5f);
  assert_true(rgb[(1 * 4 + 2) * 3 + 0] == 1.0f && rgb[(1 * 4 + 2) * 3 + 1] == 0.5f &&
              rgb[(1 * 4 + 2) * 3 + 2] == 2.0f);
  assert_true(rgb[0] == 0.0f);
  free(rgb);
  film_release(film);
}

/* Splits the sample bounds into 16x16 regions, renders each into a tile, merges in `order`. */
static void render_tiles(clr_film film, const clr_film_sample *samples, const size_t *starts,
                         const clr_bounds2i *regions, const int *order, int count) {
  clr_film_tile tiles[64];
  for (int i = 0; i < count; ++i) {
    assert_int_equal(film_get_tile(film, regions[i], &tiles[i]), CLR_SUCCESS);
    assert_int_equal(
        film_tile_add_samples(tiles[i], samples + starts[i], starts[i + 1] - starts[i]),
        CLR_SUCCESS);
  }
  for (int i = 0; i < count; ++i)
    assert_int_equal(film_merge_tile(film, tiles[order[i]]), CLR_SUCCESS);
  for (int i = 0; i < count; ++i) film_tile_release(tiles[i]);
}

static void test_tiles_merge(void **state) {
  (void)state;
  film_setup s = basic(48, 40, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  clr_film a = make_film(&s), b = make_film(&s), c = make_film(&s), d = make_film(&s);
  clr_bounds2i sb = film_sample_bounds(a);
  clr_bounds2i regions[64];
  size_t starts[65];
  int count = 0;
  size_t per = 600, n = 0;
  clr_film_sample *samples = malloc(64 * per * sizeof *samples);
  assert_non_null(samples);
  rng_state = 21u;
  for (int y = sb.y0; y < sb.y1; y += 16)
    for (int x = sb.x0; x < sb.x1; x += 16) {
      clr_bounds2i r = {x, y, x + 16 < sb.x1 ? x + 16 : sb.x1, y + 16 < sb.y1 ? y + 16 : sb.y1};
      regions[count] = r;
      starts[count++] = n;
      for (size_t k = 0; k < per; ++k) {
        clr_film_sample smp = {(float)r.x0 + rnd() * (float)(r.x1 - r.x0),
                               (float)r.y0 + rnd() * (float)(r.y1 - r.y0),
                               rnd(),
                               rnd() * 2,
                               rnd(),
                               1.0f};
        samples[n++] = smp;
      }
    }
  starts[count] = n;
  assert_true(count <= 64);
  /* pbrt GetFilmTile bounds of the first region [-2,14)^2: [ceil(-4.5), floor(15.5) + 1) = [-4,16)
   * clipped to the pixel bounds. */
  assert_true(regions[0].x0 == -2 && regions[0].y0 == -2);
  clr_film_tile t0 = NULL;
  assert_int_equal(film_get_tile(a, regions[0], &t0), CLR_SUCCESS);
  clr_bounds2i tb = film_tile_pixel_bounds(t0);
  assert_true(tb.x0 == 0 && tb.y0 == 0 && tb.x1 == 16 && tb.y1 == 16);
  assert_int_equal(film_merge_tile(b, t0), CLR_ERROR_INVALID_TILE);
  film_tile_release(t0);

  int forward[64], backward[64];
  for (int i = 0; i < count; ++i) forward[i] = i, backward[i] = count - 1 - i;
  render_tiles(a, samples, starts, regions, forward, count);
  render_tiles(b, samples, starts, regions, forward, count);
  render_tiles(c, samples, starts, regions, backward, count);
  assert_int_equal(film_add_samples(d, samples, n), CLR_SUCCESS);
  assert_int_equal(film_sample_count(a), n);
  sums sa = get_sums(a), sbs = get_sums(b);
  assert_sums_identical(&sa, &sbs);
  float *ra = get_rgb(a, 1.0f), *rc = get_rgb(c, 1.0f), *rd = get_rgb(d, 1.0f);
  assert_rgb_close(rc, ra, 48 * 40 * 3, 1e-5);
  assert_rgb_close(rd, ra, 48 * 40 * 3, 1e-5);

  clr_film_tile twice = NULL;
  assert_int_equal(film_get_tile(a, regions[1], &twice), CLR_SUCCESS);
  assert_int_equal(film_merge_tile(a, twice), CLR_SUCCESS);
  assert_int_equal(film_merge_tile(a, twice), CLR_ERROR_INVALID_TILE);
  film_tile_release(twice);
  free_sums(&sa);
  free_sums(&sbs);
  free(ra);
  free(rc);
  free(rd);
  free(samples);
  film_release(a);
  film_release(b);
  film_release(c);
  film_release(d);
}

static void test_splats_and_scale(void **state) {
  (void)state;
  film_setup s = basic(8, 6, CLR_FILTER_TYPE_BOX, 0.5f);
  s.scale = 2.0f;
  clr_film film = make_film(&s);
  assert_int_equal(film_add_splat(film, 3.7f, 2.2f, 1, 2, 3), CLR_SUCCESS);
  assert_int_equal(film_add_splat(film, 3.1f, 2.9f, 1, 2, 3), CLR_SUCCESS);
  assert_int_equal(film_add_splat(film, 3.5f, 2.5f, NAN, 0, 0), CLR_SUCCESS);
  assert_int_equal(film_add_splat(film, 3.5f, 2.5f, -1, 0, 0), CLR_SUCCESS);
  assert_int_equal(film_add_splat(film, 3.5f, 2.5f, INFINITY, 0, 0), CLR_SUCCESS);
  assert_int_equal(film_add_splat(film, -0.5f, 2.5f, 1, 1, 1), CLR_SUCCESS); /* floor: pixel -1 */
  assert_int_equal(film_add_splat(film, 8.0f, 2.5f, 1, 1, 1), CLR_SUCCESS);
  assert_int_equal(film_dropped_samples(film), 3);
  const clr_film_sample smp = {3.5f, 2.5f, 4, 4, 4, 1};
  assert_int_equal(film_add_samples(film, &smp, 1), CLR_SUCCESS);
  float *rgb = get_rgb(film, 0.5f);
  /* (4 + 0.5 * 2 * (1,2,3)) * 2 */
  size_t i = (2 * 8 + 3) * 3;
  assert_true(rgb[i] == 10.0f && rgb[i + 1] == 12.0f && rgb[i + 2] == 14.0f);
  for (size_t k = 0; k < 8 * 6 * 3; ++k)
    if (k < i || k > i + 2) assert_true(rgb[k] == 0.0f);
  free(rgb);
  film_release(film);
}

static void test_sums_roundtrip(void **state) {
  (void)state;
  film_setup s = basic(30, 20, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  clr_film a = make_film(&s), b = make_film(&s), c = make_film(&s);
  clr_film_sample *samples = random_samples(a, 5000, 0.0f, 31u);
  assert_int_equal(film_add_samples(a, samples, 5000), CLR_SUCCESS);
  assert_int_equal(film_add_splat(a, 5.5f, 6.5f, 1, 1, 1), CLR_SUCCESS);
  sums sa = get_sums(a);
  clr_bounds2i all = film_pixel_bounds(a);
  assert_int_equal(film_merge_sums(b, all, sa.rgb, sa.w, sa.splat), CLR_SUCCESS);
  sums sb = get_sums(b);
  assert_sums_identical(&sa, &sb);
  float *ra = get_rgb(a, 1.0f), *rb = get_rgb(b, 1.0f);
  assert_memory_equal(ra, rb, 30 * 20 * 3 * sizeof *ra);
  /* Sub-region: the weight of pixel (10, 5) only. */
  clr_bounds2i one = {10, 5, 11, 6};
  double w = 2.5;
  assert_int_equal(film_merge_sums(c, one, NULL, &w, NULL), CLR_SUCCESS);
  sums sc = get_sums(c);
  for (size_t i = 0; i < sc.n; ++i) assert_true(sc.w[i] == (i == 5 * 30 + 10 ? 2.5 : 0.0));
  free_sums(&sa);
  free_sums(&sb);
  free_sums(&sc);
  free(ra);
  free(rb);
  free(samples);
  film_release(a);
  film_release(b);
  film_release(c);
}

/* The film holds 4 double sums per pixel (32 bytes) until something splats; merging sums whose
 * splats are all zero keeps it so, and the resolve and the sums read zero splats meanwhile. */
static void test_film_memory_until_splat(void **state) {
  (void)state;
  film_setup s = basic(30, 20, CLR_FILTER_TYPE_TRIANGLE, 2.0f);
  clr_film a = make_film(&s), b = make_film(&s);
  const size_t table = CLR_FILTER_TABLE_SIZE * CLR_FILTER_TABLE_SIZE * sizeof(float);
  clr_film_sample *samples = random_samples(a, 2000, 0.0f, 7u);
  assert_int_equal(film_add_samples(a, samples, 2000), CLR_SUCCESS);
  assert_int_equal(clr_film_sums_bytes(a), 30 * 20 * 32 + table);
  sums sa = get_sums(a);
  for (size_t i = 0; i < 3 * sa.n; ++i) assert_true(sa.splat[i] == 0.0);
  clr_bounds2i all = film_pixel_bounds(a);
  assert_int_equal(film_merge_sums(b, all, sa.rgb, sa.w, sa.splat), CLR_SUCCESS);
  assert_int_equal(clr_film_sums_bytes(b), 30 * 20 * 32 + table);
  sa.splat[3 * 45 + 1] = 0.25; /* a nonzero splat sum allocates the splats */
  assert_int_equal(film_merge_sums(b, all, NULL, NULL, sa.splat), CLR_SUCCESS);
  assert_int_equal(clr_film_sums_bytes(b), 30 * 20 * 56 + table);
  sums sb = get_sums(b);
  for (size_t i = 0; i < 3 * sb.n; ++i) assert_true(sb.splat[i] == (i == 3 * 45 + 1 ? 0.25 : 0.0));
  assert_int_equal(film_add_splat(a, 5.5f, 6.5f, 1, 2, 3), CLR_SUCCESS);
  assert_int_equal(clr_film_sums_bytes(a), 30 * 20 * 56 + table);
  free_sums(&sa);
  free_sums(&sb);
  free(samples);
  film_release(a);
  film_release(b);
}

/* Samples exactly at a pixel centre along x, y or both reach 5 pixels per axis at radius 2, the
 * outer two factors 0 for the filters that vanish at their radius (exact mitchell, triangle,
 * gaussian, catmullrom: the chunk's reach counts 4, and the 8-lane weigh takes its one-vector
 * path), not for box or table mode (reach 5). Either way every pixel's sums equal the host
 * reference's bit for bit, from host samples and from a device buffer. */
static void test_samples_at_the_radius(void **state) {
  (void)state;
  static const int types[] = {CLR_FILTER_TYPE_MITCHELL, CLR_FILTER_TYPE_TRIANGLE,
                              CLR_FILTER_TYPE_GAUSSIAN, CLR_FILTER_TYPE_CATMULLROM,
                              CLR_FILTER_TYPE_BOX};
  const size_t n = 6000;
  for (size_t t = 0; t < sizeof types / sizeof types[0]; ++t)
    for (int table = 0; table < 2; ++table) {
      film_setup s = basic(37, 29, types[t], 2.0f);
      s.use_table = table;
      clr_film ref = make_film(&s);
      clr_film_sample *samples = random_samples(ref, n, 1.0f, 90u + (uint32_t)t);
      for (size_t i = 0; i < n; ++i) {
        if (i % 3 == 0) samples[i].x = floorf(samples[i].x) + 0.5f;
        if (i % 5 < 2) samples[i].y = floorf(samples[i].y) + 0.5f;
      }
      assert_int_equal(film_add_samples_reference(ref, samples, n), CLR_SUCCESS);
      sums expect = get_sums(ref);
      for (int from_buffer = 0; from_buffer < 2; ++from_buffer) {
        clr_film film = make_film(&s);
        if (from_buffer)
          add_samples_from_buffer(film, samples, n);
        else
          assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
        sums got = get_sums(film);
        assert_sums_identical(&got, &expect);
        assert_int_equal(film_sample_count(film), film_sample_count(ref));
        free_sums(&got);
        film_release(film);
      }
      free_sums(&expect);
      free(samples);
      film_release(ref);
    }
}

/* Every filter, exact and table mode, default radius: tile-size, group-size, device-buffer and
 * host-reference invariance (bit-identical sums). */
static void test_every_filter_invariance(void **state) {
  (void)state;
  for (int type = 0; type < CLR_FILTER_TYPE_COUNT; ++type)
    for (int table = 0; table < 2; ++table) {
      clr_filter_desc fd;
      clr_filter_desc_init(&fd, (clr_filter_type)type);
      film_setup s = basic(40, 30, type, fd.radius[0]);
      s.use_table = table;
      check_invariance(s, 3000, 20u + (uint32_t)type);
    }
}

/* A constant radiance field reconstructs to the constant with every filter, including the
 * negative-lobed mitchell, sinc and catmullrom, away from the image edges. */
static void test_constant_radiance_every_filter(void **state) {
  (void)state;
  for (int type = 0; type < CLR_FILTER_TYPE_COUNT; ++type)
    for (int table = 0; table < 2; ++table) {
      clr_filter_desc fd;
      clr_filter_desc_init(&fd, (clr_filter_type)type);
      film_setup s = basic(24, 20, type, fd.radius[0]);
      s.use_table = table;
      clr_film film = make_film(&s);
      size_t n = 0;
      clr_film_sample *samples = constant_jittered_samples(film, 5u + (uint32_t)type, &n);
      assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
      float *rgb = get_rgb(film, 1.0f);
      const float expect[3] = {0.25f, 0.5f, 2.0f};
      for (int i = 0; i < 24 * 20; ++i)
        for (int c = 0; c < 3; ++c) assert_float_equal(rgb[3 * i + c], expect[c], 2e-5 * expect[c]);
      free(rgb);
      free(samples);
      film_release(film);
    }
}

/* pbrt-v3's 1D filter factors in double (libm), for the brute-force reference. */
static double pbrt_filter_1d(int type, double x, double r, const clr_filter_desc *fd) {
  double ax = fabs(x);
  if (ax > r) return 0.0;
  switch (type) {
    case CLR_FILTER_TYPE_GAUSSIAN:
      return fmax(0.0, exp(-(double)fd->alpha * x * x) - exp(-(double)fd->alpha * r * r));
    case CLR_FILTER_TYPE_MITCHELL: {
      double B = fd->b, C = fd->c, t = fabs(2.0 * x / r);
      if (t > 1.0)
        return ((-B - 6 * C) * t * t * t + (6 * B + 30 * C) * t * t + (-12 * B - 48 * C) * t +
                (8 * B + 24 * C)) /
               6.0;
      return ((12 - 9 * B - 6 * C) * t * t * t + (-18 + 12 * B + 6 * C) * t * t + (6 - 2 * B)) /
             6.0;
    }
    case CLR_FILTER_TYPE_SINC: {
      double tau = fd->tau;
      double s1 = ax < 1e-5 ? 1.0 : sin(3.14159265358979323846 * x) / (3.14159265358979323846 * x);
      double xt = x / tau;
      double s2 =
          fabs(xt) < 1e-5 ? 1.0 : sin(3.14159265358979323846 * xt) / (3.14159265358979323846 * xt);
      return s1 * s2;
    }
    default:
      return 0.0;
  }
}

/* Every pixel equals pbrt-v3's formula sum L w f / sum f evaluated in double with libm filters,
 * for gaussian, mitchell and sinc in exact mode: within 2e-5 relative to max(pixel, mean). */
static void test_brute_force_double_every_filter(void **state) {
  (void)state;
  const int types[] = {CLR_FILTER_TYPE_GAUSSIAN, CLR_FILTER_TYPE_MITCHELL, CLR_FILTER_TYPE_SINC};
  for (int t = 0; t < 3; ++t) {
    clr_filter_desc fd;
    clr_filter_desc_init(&fd, (clr_filter_type)types[t]);
    film_setup s = basic(16, 12, types[t], fd.radius[0]);
    s.use_table = 0;
    clr_film film = make_film(&s);
    size_t n = 6000;
    clr_film_sample *samples = random_samples(film, n, 0.0f, 31u + (uint32_t)t);
    for (size_t i = 0; i < n; ++i)
      samples[i].r = samples[i].g = samples[i].b = 0.5f + (float)(i % 7) * 0.25f;
    assert_int_equal(film_add_samples(film, samples, n), CLR_SUCCESS);
    float *rgb = get_rgb(film, 1.0f);
    float *expect = malloc(16 * 12 * 3 * sizeof *expect);
    assert_non_null(expect);
    for (int py = 0; py < 12; ++py)
      for (int px = 0; px < 16; ++px) {
        double acc = 0, wsum = 0;
        for (size_t i = 0; i < n; ++i) {
          double dx = (double)px - ((double)samples[i].x - 0.5);
          double dy = (double)py - ((double)samples[i].y - 0.5);
          double f = pbrt_filter_1d(types[t], dx, fd.radius[0], &fd) *
                     pbrt_filter_1d(types[t], dy, fd.radius[1], &fd);
          acc += samples[i].r * samples[i].weight * f;
          wsum += f;
        }
        for (int c = 0; c < 3; ++c) expect[(py * 16 + px) * 3 + c] = (float)fmax(0.0, acc / wsum);
      }
    assert_rgb_close(rgb, expect, 16 * 12 * 3, 2e-5);
    free(expect);
    free(rgb);
    free(samples);
    film_release(film);
  }
}

/* The canonical order (film.h): a pixel adds its samples by bin p0 = ceil(d - r) (row, then
 * column), batch order only inside a bin. In batch order (1 + 1e8) - 1e8 rounds to 0; in bin order
 * (-1e8 + 1e8) + 1 = 1. */
static void test_canonical_order(void **state) {
  (void)state;
  film_setup s = basic(12, 12, CLR_FILTER_TYPE_BOX, 2.0f);
  /* Bins p0.x: 4, 3, 2 (dx = 5.5, 4.5, 3.5); every sample reaches pixel (5, 5). */
  const clr_film_sample samples[] = {{6.0f, 5.5f, 1.0f, 0, 0, 1},
                                     {5.0f, 5.5f, 1e8f, 0, 0, 1},
                                     {4.0f, 5.5f, 1e8f, 0, 0, -1}}; /* weight -1: adds -1e8 */
  for (int tile = 4; tile <= 8; tile += 4) {
    s.tile = tile;
    clr_film film = make_film(&s), ref = make_film(&s);
    assert_int_equal(film_add_samples(film, samples, 3), CLR_SUCCESS);
    assert_int_equal(film_add_samples_reference(ref, samples, 3), CLR_SUCCESS);
    sums a = get_sums(film), b = get_sums(ref);
    assert_sums_identical(&a, &b);
    assert_true(a.rgb[3 * (5 * 12 + 5)] == 1.0);
    assert_true(a.w[5 * 12 + 5] == 3.0);
    /* Pixel (3, 5) is reached by the second and third samples only: 1e8 - 1e8. */
    assert_true(a.rgb[3 * (5 * 12 + 3)] == 0.0 && a.w[5 * 12 + 3] == 2.0);
    free_sums(&a);
    free_sums(&b);
    film_release(film);
    film_release(ref);
  }
}

/* film_create(NULL, ...): a host film gives the device film's bits for samples and tiles and
 * refuses device buffers. */
static void test_host_film(void **state) {
  (void)state;
  film_setup s = basic(37, 23, CLR_FILTER_TYPE_MITCHELL, 2.0f);
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = s.xres;
  d.y_resolution = s.yres;
  clr_filter_desc_init(&d.filter, CLR_FILTER_TYPE_MITCHELL);
  d.filter.radius[0] = d.filter.radius[1] = 2.0f;
  clr_film host = NULL, dev = NULL;
  assert_int_equal(film_create(NULL, &d, &host), CLR_SUCCESS);
  assert_int_equal(film_create(ctx, &d, &dev), CLR_SUCCESS);
  clr_film_sample *samples = random_samples(host, 20000, 1.5f, 77);
  assert_int_equal(film_add_samples(host, samples, 20000), CLR_SUCCESS);
  assert_int_equal(film_add_samples(dev, samples, 20000), CLR_SUCCESS);
  clr_bounds2i region = {3, 2, 19, 14};
  clr_film_tile th = NULL, td = NULL;
  assert_int_equal(film_get_tile(host, region, &th), CLR_SUCCESS);
  assert_int_equal(film_get_tile(dev, region, &td), CLR_SUCCESS);
  assert_int_equal(film_tile_add_samples(th, samples, 5000), CLR_SUCCESS);
  assert_int_equal(film_tile_add_samples(td, samples, 5000), CLR_SUCCESS);
  assert_int_equal(film_merge_tile(host, th), CLR_SUCCESS);
  assert_int_equal(film_merge_tile(dev, td), CLR_SUCCESS);
  sums a = get_sums(host), b = get_sums(dev);
  assert_sums_identical(&a, &b);
  assert_int_equal(film_dropped_samples(host), film_dropped_samples(dev));
  cl_int err = CL_SUCCESS;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_WRITE,
                              16 * sizeof(clr_film_sample), NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  assert_int_equal(film_add_samples_buffer(host, buf, 16), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "no OpenCL context"));
  clReleaseMemObject(buf);
  free_sums(&a);
  free_sums(&b);
  free(samples);
  film_tile_release(th);
  film_tile_release(td);
  film_release(host);
  film_release(dev);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_host_film),
      cmocka_unit_test(test_every_filter_invariance),
      cmocka_unit_test(test_samples_at_the_radius),
      cmocka_unit_test(test_film_memory_until_splat),
      cmocka_unit_test(test_constant_radiance_every_filter),
      cmocka_unit_test(test_brute_force_double_every_filter),
      cmocka_unit_test(test_bounds_match_pbrt),
      cmocka_unit_test(test_bad_inputs),
      cmocka_unit_test(test_older_desc_gets_defaults),
      cmocka_unit_test(test_tile_size_invariance_box),
      cmocka_unit_test(test_tile_size_invariance_triangle),
      cmocka_unit_test(test_split_calls),
      cmocka_unit_test(test_canonical_order),
      cmocka_unit_test(test_box_pixel_centres_reproduce_image),
      cmocka_unit_test(test_constant_radiance_triangle),
      cmocka_unit_test(test_brute_force_double),
      cmocka_unit_test(test_bad_samples_dropped),
      cmocka_unit_test(test_max_luminance_clamp),
      cmocka_unit_test(test_tiles_merge),
      cmocka_unit_test(test_splats_and_scale),
      cmocka_unit_test(test_sums_roundtrip),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
