/* Four-sample checks of host film tiles (film_screen.h): a group of plain samples passes with
 * clr_film_prepare's prepared forms bit for bit; one bad sample (NaN or Inf in any component,
 * negative luminance, L*w overflow, luminance to clamp, outside the sample bounds) at
 * any lane sends the group to clr_film_prepare; a sample exactly at the radius past the last pixel
 * passes; and clr_tile_add_samples on batches of 1..13 samples with a bad one at every position
 * gives the sums and accepted/dropped/outside counts of the one-by-one reference. */
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
#include "film_screen.h"
#include "film_tile_add.h"
#define XORSHIFT_TEST_SEED 11u
#include "xorshift_test_random.h"

#define XRES 20
#define YRES 12
#define MAX_LUMINANCE 40.0f

/* clamp: a finite max_sample_luminance. */
static clr_film make_film(clr_filter_type type, float radius, int clamp) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = XRES;
  d.y_resolution = YRES;
  clr_filter_desc_init(&d.filter, type);
  d.filter.radius[0] = radius;
  d.filter.radius[1] = radius;
  if (clamp) d.max_sample_luminance = MAX_LUMINANCE;
  clr_film film = NULL;
  assert_int_equal(film_create(NULL, &d, &film), CLR_SUCCESS);
  return film;
}

/* A plain sample: inside the film, positive luminance below the clamp, some negative components. */
static clr_film_sample plain_sample(void) {
  clr_film_sample s = {rnd() * XRES,        rnd() * YRES,        rnd() * 2.0f - 0.3f,
                       rnd() * 3.0f + 0.5f, rnd() * 4.0f - 1.0f, rnd() + 0.1f};
  return s;
}

/* Bad kinds: what clr_film_prepare returns for them, and how to make one from a plain sample. */
enum {
  BAD_NAN,
  BAD_INF,
  BAD_NEG_INF,
  BAD_NEG_LUMINANCE,
  BAD_HUGE,
  BAD_LW_OVERFLOW,
  BAD_CLAMP,
  BAD_LEFT,
  BAD_RIGHT,
  BAD_BELOW,
  BAD_ABOVE,
  BAD_KINDS
};

/* Kind k applied to s; field: the component for NaN/Inf kinds (0..5 = x y r g b weight), the
 * one whose L*w overflows for LW_OVERFLOW (0..2 = r g b). HUGE:
 * clamped on a film with a clamp, else L*w overflows; RIGHT and ABOVE: one ulp past the edge
 * sample (exactly at the radius past the last pixel centre). */
/* Variants of kind k (its fields). */
static int kind_fields(int k) {
  return k >= 0 && k <= BAD_NEG_INF ? 6 : k == BAD_LW_OVERFLOW ? 3 : 1;
}

static clr_film_sample make_bad(clr_film_sample s, int k, int field, float radius) {
  float *f = &s.x;
  if (k == BAD_NAN) f[field] = NAN;
  if (k == BAD_INF) f[field] = INFINITY;
  if (k == BAD_NEG_INF) f[field] = -INFINITY;
  if (k == BAD_NEG_LUMINANCE) s.r = s.b = 0.1f, s.g = -1.0f;
  if (k == BAD_HUGE) s.r = s.g = s.b = 3e38f, s.weight = 2.0f;
  if (k == BAD_LW_OVERFLOW) s.r = s.g = s.b = 0.25f, f[2 + field] = 2.0f, s.weight = 3e38f;
  if (k == BAD_CLAMP) s.g = 4.0f * MAX_LUMINANCE;
  if (k == BAD_LEFT) s.x = nextafterf(0.0f, -INFINITY);
  if (k == BAD_RIGHT) s.x = nextafterf((float)XRES - 0.5f + radius, INFINITY);
  if (k == BAD_BELOW) s.y = -0.25f;
  if (k == BAD_ABOVE) s.y = nextafterf((float)YRES - 0.5f + radius, INFINITY);
  return s;
}

static void expect_same_prepared(const clr_film_prepared *got, const clr_film_prepared *want) {
  assert_memory_equal(got, want, sizeof *got);
}

/* Plain groups pass, with clr_film_prepare's output; the edge sample is plain. */
static void test_plain_groups_pass(void **state) {
  (void)state;
  const float radii[] = {0.5f, 1.0f, 2.0f, 0.3f};
  for (size_t r = 0; r < sizeof radii / sizeof radii[0]; ++r)
    for (int clamp = 0; clamp < 2; ++clamp) {
      clr_film film = make_film(CLR_FILTER_BOX, radii[r], clamp);
      clr_film_screen sc;
      clr_film_screen_init(&sc, &film->params, &film->filter);
      for (int t = 0; t < 200; ++t) {
        clr_film_sample s[4];
        for (int k = 0; k < 4; ++k) s[k] = plain_sample();
        if (t < 8) { /* exactly at the radius past the last pixel centre, on x or y */
          s[t % 4].x = (float)XRES - 0.5f + radii[r];
          s[(t + 1) % 4].y = (float)YRES - 0.5f + radii[r];
        }
        clr_film_prepared got[4], want;
        assert_int_equal(clr_film_screen4(&sc, s, got), 1);
        for (int k = 0; k < 4; ++k) {
          assert_int_equal(clr_film_prepare(&film->params, &film->filter, s[k].x, s[k].y, s[k].r,
                                            s[k].g, s[k].b, s[k].weight, &want),
                           CLR_FILM_SAMPLE_OK);
          expect_same_prepared(&got[k], &want);
        }
      }
      film_release(film);
    }
}

/* The status clr_film_prepare gives bad kind k (k < 0: none) on a film with or without a clamp. */
static clr_i32 bad_status(int k, int clamp) {
  if (k < 0 || k == BAD_CLAMP || (k == BAD_HUGE && clamp)) return CLR_FILM_SAMPLE_OK;
  return k >= BAD_LEFT ? CLR_FILM_SAMPLE_OUTSIDE : CLR_FILM_SAMPLE_DROPPED;
}

/* One bad sample at each lane: the group is refused, and clr_film_prepare says what it is. */
static void test_bad_lane_refuses_group(void **state) {
  (void)state;
  clr_film film = make_film(CLR_FILTER_BOX, 0.5f, 1);
  clr_film_screen sc;
  clr_film_screen_init(&sc, &film->params, &film->filter);
  for (int k = 0; k < BAD_KINDS; ++k)
    for (int field = 0; field < kind_fields(k); ++field)
      for (int lane = 0; lane < 4; ++lane) {
        clr_film_sample s[4];
        for (int j = 0; j < 4; ++j) s[j] = plain_sample();
        s[lane] = make_bad(s[lane], k, field, 0.5f);
        clr_film_prepared got[4], one;
        clr_i32 st = clr_film_prepare(&film->params, &film->filter, s[lane].x, s[lane].y, s[lane].r,
                                      s[lane].g, s[lane].b, s[lane].weight, &one);
        if (st != bad_status(k, 1))
          fail_msg("kind %d field %d lane %d: status %d", k, field, lane, (int)st);
        if (clr_film_screen4(&sc, s, got) != 0)
          fail_msg("kind %d field %d lane %d: group passed", k, field, lane);
      }
  film_release(film);
}

/* Batches of 1..13 samples with bad kind k at every position (and none): the tile adder's sums
 * and counts equal the one-by-one reference's; the counts are the kind's. */
static void check_batches(clr_filter_type type, int clamp) {
  clr_film film = make_film(type, 0.5f, clamp);
  clr_tile_adder a;
  clr_tile_adder_init(&a, &film->params, &film->filter, film->factors);
  const clr_bounds2i bounds = {0, 0, XRES, YRES};
  const size_t floats = (size_t)XRES * YRES * CLR_FILM_SUM_FLOATS;
  float fast[XRES * YRES * CLR_FILM_SUM_FLOATS], ref[XRES * YRES * CLR_FILM_SUM_FLOATS];
  for (int k = -1; k < BAD_KINDS; ++k)
    for (int field = 0; field < kind_fields(k); ++field)
      for (size_t n = 1; n <= 13; ++n)
        for (size_t at = 0; at < (k < 0 ? 1 : n); ++at) {
          clr_film_sample s[13];
          for (size_t j = 0; j < n; ++j) s[j] = plain_sample();
          if (k >= 0) s[at] = make_bad(s[at], k, field, 0.5f);
          for (size_t i = 0; i < floats; ++i) fast[i] = ref[i] = rnd() < 0.3f ? -0.0f : rnd();
          clr_tile_counts cf = {0, 0, 0}, cr = {0, 0, 0};
          clr_tile_add_samples(&a, s, n, bounds, fast, &cf);
          clr_tile_add_samples_per_pixel(&a, s, n, bounds, ref, &cr);
          if (memcmp(fast, ref, sizeof fast) != 0)
            fail_msg("filter %d clamp %d kind %d field %d: %zu samples, bad at %zu: sums differ",
                     (int)type, clamp, k, field, n, at);
          clr_i32 status = bad_status(k, clamp);
          assert_int_equal(cf.accepted, cr.accepted);
          assert_int_equal(cf.dropped, cr.dropped);
          assert_int_equal(cf.outside, cr.outside);
          assert_int_equal(cf.accepted, n - (status != CLR_FILM_SAMPLE_OK));
          assert_int_equal(cf.dropped, status == CLR_FILM_SAMPLE_DROPPED);
          assert_int_equal(cf.outside, status == CLR_FILM_SAMPLE_OUTSIDE);
        }
  film_release(film);
}

static void test_batches_match_reference(void **state) {
  (void)state;
  for (int clamp = 0; clamp < 2; ++clamp) {
    check_batches(CLR_FILTER_BOX, clamp);
    check_batches(CLR_FILTER_MITCHELL, clamp);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_plain_groups_pass),
      cmocka_unit_test(test_bad_lane_refuses_group),
      cmocka_unit_test(test_batches_match_reference),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
