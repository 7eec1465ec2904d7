/* Host film tiles' separable path (film_tile_add.c): the same bits as the per-pixel path
 * (clr_film_accumulate per pixel) for every filter in both modes, on random samples and on
 * edge cases (pixel borders, exactly at and one ulp around the radius, outside the tile, sums
 * holding -0), and film_tile_add_samples' sums and counters through the public API. */
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
#include "film_tile_add.h"
#include "xorshift_test_random.h"

#define XRES 24
#define YRES 20

static clr_film make_film(clr_filter_type type, float rx, float ry, int use_table) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = XRES;
  d.y_resolution = YRES;
  clr_filter_desc_init(&d.filter, type);
  d.filter.radius[0] = rx;
  d.filter.radius[1] = ry;
  d.filter.use_table = use_table;
  clr_film film = NULL;
  assert_int_equal(film_create(NULL, &d, &film), CLR_SUCCESS);
  return film;
}

/* Positions along one axis: pixel borders and centres, exactly at the radius from a centre and
 * one ulp either side, and random ones, from 3 pixels before to 3 past the film. */
static size_t axis_positions(float radius, int res, float *out) {
  size_t n = 0;
  for (int p = -3; p < res + 3; ++p) {
    float c = (float)p + 0.5f;
    float edge[] = {(float)p, c, c + radius, c - radius};
    for (int k = 0; k < 4; ++k) {
      out[n++] = edge[k];
      if (k >= 2) {
        out[n++] = nextafterf(edge[k], INFINITY);
        out[n++] = nextafterf(edge[k], -INFINITY);
      }
    }
    out[n++] = (float)p + rnd();
  }
  return n;
}

/* Sums of a tile-sized block: random values, some +0 and -0. */
static void fill_sums(float *sums, size_t floats) {
  for (size_t i = 0; i < floats; ++i) {
    float u = rnd();
    sums[i] = u < 0.2f ? 0.0f : u < 0.4f ? -0.0f : rnd() * 8.0f;
  }
}

/* Every (x, y) of the position lists as a sample, some of them bad, through both paths into
 * sums over `bounds` that start equal; compares sums and counts. */
static void check_filter(clr_filter_type type, float rx, float ry, int use_table) {
  clr_film film = make_film(type, rx, ry, use_table);
  clr_tile_adder a;
  clr_tile_adder_init(&a, &film->params, &film->filter, film->factors);
  assert_int_equal(a.box, type == CLR_FILTER_TYPE_BOX);
  const clr_bounds2i bounds = {3, 2, 14, 12};
  const size_t floats = (size_t)(11 * 10) * CLR_FILM_SUM_FLOATS;
  float xs[(XRES + 6) * 9], ys[(YRES + 6) * 9];
  size_t nx = axis_positions(rx, XRES, xs), ny = axis_positions(ry, YRES, ys);
  float *fast = malloc(floats * sizeof(float)), *general = malloc(floats * sizeof(float));
  clr_film_sample *samples = malloc(nx * ny * sizeof *samples);
  assert_non_null(fast);
  assert_non_null(general);
  assert_non_null(samples);
  for (size_t j = 0; j < ny; ++j)
    for (size_t i = 0; i < nx; ++i) {
      /* Some negative components (positive luminance): their zero-weight products are -0. */
      clr_film_sample smp = {xs[i], ys[j], rnd() - 0.3f, rnd() + 0.5f, rnd() * 3.0f, 0.25f + rnd()};
      float u = rnd();
      if (u < 0.01f)
        smp.g = NAN;
      else if (u < 0.02f)
        smp.g = -4.0f; /* negative luminance */
      else if (u < 0.03f)
        smp.weight = INFINITY;
      samples[j * nx + i] = smp;
    }
  fill_sums(fast, floats);
  memcpy(general, fast, floats * sizeof(float));
  clr_tile_counts cf = {1, 2, 3}, cg = {1, 2, 3};
  clr_tile_add_samples(&a, samples, nx * ny, bounds, fast, &cf);
  clr_tile_add_samples_per_pixel(&a, samples, nx * ny, bounds, general, &cg);
  assert_memory_equal(fast, general, floats * sizeof(float));
  assert_int_equal(cf.accepted, cg.accepted);
  assert_int_equal(cf.dropped, cg.dropped);
  assert_int_equal(cf.outside, cg.outside);
  assert_true(cg.accepted > nx * ny / 4 && cg.dropped > 2 && cg.outside > nx);
  free(samples);
  free(fast);
  free(general);
  film_release(film);
}

static const clr_filter_type all_types[] = {
    CLR_FILTER_TYPE_BOX,       CLR_FILTER_TYPE_TRIANGLE, CLR_FILTER_TYPE_GAUSSIAN,
    CLR_FILTER_TYPE_MITCHELL,  CLR_FILTER_TYPE_SINC,     CLR_FILTER_TYPE_BLACKMANHARRIS,
    CLR_FILTER_TYPE_CATMULLROM};

static void test_separable_equals_per_pixel(void **state) {
  (void)state;
  const float radii[][2] = {{0.5f, 0.5f}, {1.0f, 1.0f}, {0.25f, 0.4f}, {1.5f, 0.75f},
                            {2.0f, 2.0f}, {0.3f, 3.0f}, {32.0f, 0.5f}};
  rng_state = 7u;
  for (size_t t = 0; t < sizeof all_types / sizeof all_types[0]; ++t)
    for (size_t k = 0; k < sizeof radii / sizeof radii[0]; ++k)
      for (int table = 0; table < 2; ++table)
        check_filter(all_types[t], radii[k][0], radii[k][1], table);
}

/* The box path's factors are clr_film_filter_factor's, at the radius and one ulp around it. */
static void test_box_factors(void **state) {
  (void)state;
  const float radii[] = {0.5f, 0.25f, 1.0f, 1.5f, 0.7f};
  for (size_t k = 0; k < sizeof radii / sizeof radii[0]; ++k)
    for (int table = 0; table < 2; ++table) {
      clr_film film = make_film(CLR_FILTER_TYPE_BOX, radii[k], radii[k], table);
      clr_tile_adder a;
      clr_tile_adder_init(&a, &film->params, &film->filter, film->factors);
      assert_true(a.box);
      const clr_bounds2i bounds = {0, 0, XRES, YRES};
      for (int p = 0; p < 6; ++p) {
        float c = (float)p + 0.5f;
        float xs[] = {
            c + radii[k], nextafterf(c + radii[k], INFINITY), nextafterf(c + radii[k], 0.0f),
            c - radii[k], nextafterf(c - radii[k], INFINITY), nextafterf(c - radii[k], 0.0f)};
        for (size_t i = 0; i < sizeof xs / sizeof xs[0]; ++i) {
          clr_film_prepared s;
          if (clr_film_prepare(&a.params, &a.filter, xs[i], 3.5f, 1, 1, 1, 1, &s) !=
              CLR_FILM_SAMPLE_OK)
            continue;
          float sums[XRES * YRES * CLR_FILM_SUM_FLOATS] = {0};
          clr_film_sample smp = {xs[i], 3.5f, 1, 1, 1, 1};
          clr_tile_counts n = {0, 0, 0};
          clr_tile_add_samples(&a, &smp, 1, bounds, sums, &n);
          assert_int_equal(n.accepted, 1);
          for (int x = 0; x < XRES; ++x) {
            float want = x >= s.x0 && x <= s.x1
                             ? clr_film_filter_factor(&a.filter, a.factors, 0, s.dx, x)
                             : 0.0f;
            assert_true(sums[(3 * XRES + x) * CLR_FILM_SUM_FLOATS + 3] == want);
          }
        }
      }
      film_release(film);
    }
}

/* Positions a few ulps around the radius whose footprint (ceil(d - r), floor(d + r)) holds a
 * pixel the filter does not reach (|p - d| rounds past r): a zero weight whose +0 products turn
 * a -0 sum into +0, through both paths, for box and triangle filters in both modes. */
static void test_zero_factor_pixels(void **state) {
  (void)state;
  const float radii[] = {0.3f, 0.7f, 1.3f, 0.5f, 0.1f};
  const clr_filter_type types[] = {CLR_FILTER_TYPE_BOX, CLR_FILTER_TYPE_TRIANGLE};
  size_t zero_cases = 0;
  for (size_t t = 0; t < 2; ++t)
    for (size_t k = 0; k < sizeof radii / sizeof radii[0]; ++k)
      for (int table = 0; table < 2; ++table) {
        clr_film film = make_film(types[t], radii[k], 0.5f, table);
        clr_tile_adder a;
        clr_tile_adder_init(&a, &film->params, &film->filter, film->factors);
        clr_film_sample samples[XRES * 2 * 17];
        size_t n = 0;
        for (int p = 0; p < XRES; ++p)
          for (int side = -1; side <= 1; side += 2) {
            float x = (float)p + 0.5f + (float)side * radii[k];
            for (int u = 0; u < 8; ++u) x = nextafterf(x, -INFINITY);
            for (int u = 0; u < 17; ++u, x = nextafterf(x, INFINITY)) {
              clr_film_sample smp = {x, 10.5f, -1.0f, 2.0f, 1.0f, 1.0f};
              clr_film_prepared s;
              if (clr_film_prepare(&a.params, &a.filter, x, 10.5f, -1, 2, 1, 1, &s) ==
                  CLR_FILM_SAMPLE_OK)
                for (int q = s.x0; q <= s.x1; ++q)
                  zero_cases += clr_film_filter_factor(&a.filter, a.factors, 0, s.dx, q) == 0.0f;
              samples[n++] = smp;
            }
          }
        const clr_bounds2i bounds = {0, 0, XRES, YRES};
        float *fast = malloc(XRES * YRES * CLR_FILM_SUM_FLOATS * sizeof(float));
        float *general = malloc(XRES * YRES * CLR_FILM_SUM_FLOATS * sizeof(float));
        assert_non_null(fast);
        assert_non_null(general);
        for (size_t i = 0; i < n; ++i) { /* one sample at a time: a later one would hide it */
          for (int k = 0; k < XRES * YRES * CLR_FILM_SUM_FLOATS; ++k) fast[k] = general[k] = -0.0f;
          clr_tile_counts cf = {0, 0, 0}, cg = {0, 0, 0};
          clr_tile_add_samples(&a, &samples[i], 1, bounds, fast, &cf);
          clr_tile_add_samples_per_pixel(&a, &samples[i], 1, bounds, general, &cg);
          assert_memory_equal(fast, general, XRES * YRES * CLR_FILM_SUM_FLOATS * sizeof(float));
          assert_int_equal(cf.accepted, cg.accepted);
        }
        free(fast);
        free(general);
        film_release(film);
      }
  assert_true(zero_cases > 0);
}

/* film_tile_add_samples: the per-pixel sums of the prepared samples, bad ones dropped and
 * counted (NaN, Inf, negative luminance), outside ones counted, in every tile of a 4x4 split (6x5 pixels each). */
static void test_tile_add_samples_api(void **state) {
  (void)state;
  rng_state = 11u;
  for (size_t t = 0; t < sizeof all_types / sizeof all_types[0]; ++t) {
    clr_film film = make_film(all_types[t], t % 2 ? 1.5f : 0.5f, 0.5f + 0.25f * (float)t, 1);
    clr_tile_adder a;
    clr_tile_adder_init(&a, &film->params, &film->filter, film->factors);
    uint64_t want_ok = 0, want_dropped = 0, want_outside = 0;
    for (int ty = 0; ty < YRES; ty += 5)
      for (int tx = 0; tx < XRES; tx += 6) {
        clr_bounds2i region = {tx, ty, tx + 6, ty + 5};
        clr_film_tile tile = NULL;
        assert_int_equal(film_get_tile(film, region, &tile), CLR_SUCCESS);
        clr_film_sample samples[400];
        for (int i = 0; i < 400; ++i) {
          clr_film_sample smp = {(float)tx - 1.0f + rnd() * 8.0f,
                                 (float)ty - 1.0f + rnd() * 7.0f,
                                 rnd(),
                                 rnd(),
                                 rnd(),
                                 1.0f};
          samples[i] = smp;
        }
        samples[3].r = NAN;
        samples[5].weight = INFINITY;
        samples[7].g = -5.0f;  /* negative luminance */
        samples[9].x = -40.0f; /* outside the sample bounds */
        samples[11].y = (float)YRES + 9.0f;
        samples[13].x = (float)tx; /* pixel borders */
        samples[13].y = (float)ty;
        assert_int_equal(film_tile_add_samples(tile, samples, 400), CLR_SUCCESS);
        clr_bounds2i b = film_tile_pixel_bounds(tile);
        size_t floats = (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0) * CLR_FILM_SUM_FLOATS;
        float *want = calloc(floats ? floats : 1, sizeof(float));
        assert_non_null(want);
        clr_tile_counts n = {0, 0, 0};
        clr_tile_add_samples_per_pixel(&a, samples, 400, b, want, &n);
        want_ok += n.accepted;
        want_dropped += n.dropped;
        want_outside += n.outside;
        size_t size = film_tile_serialized_size(tile);
        char *bytes = malloc(size);
        assert_non_null(bytes);
        assert_int_equal(film_tile_serialize(tile, bytes, size), CLR_SUCCESS);
        assert_memory_equal(bytes + size - floats * sizeof(float), want, floats * sizeof(float));
        assert_int_equal(film_merge_tile(film, tile), CLR_SUCCESS);
        film_tile_release(tile);
        free(bytes);
        free(want);
      }
    assert_true(want_dropped >= 3 * 16 && want_outside >= 2 * 16);
    assert_int_equal(film_sample_count(film), want_ok);
    assert_int_equal(film_dropped_samples(film), want_dropped);
    assert_int_equal(film_outside_samples(film), want_outside);
    film_release(film);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_separable_equals_per_pixel),
      cmocka_unit_test(test_box_factors),
      cmocka_unit_test(test_zero_factor_pixels),
      cmocka_unit_test(test_tile_add_samples_api),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
