/* Skipped requests (CLR_SAMPLE_REQUEST_SKIPPED): for every sampler and seeding, on the host
 * reference and on the device, a layout with skipped requests gives each request that is not
 * skipped the same bits as the full layout (dimensions and RNG draws unchanged), its values packed
 * without the skipped ones; clr_sampler_generate_at agrees; bad flags are refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"

#define SKIP CLR_SAMPLE_REQUEST_SKIPPED
#define NREQ 13

#include "context_fixture.h"
#include "sample_batch_test_util.h"

/* Camera (film, time, lens), arrays of both kinds, singles past stratified's 4 dimensions (RNG
 * fallbacks of the pixel samplers): 40 values. */
static const clr_sample_request full[NREQ] = {{2, 0}, {1, 0}, {2, 0}, {1, 5}, {2, 0},
                                              {2, 7}, {1, 0}, {1, 0}, {1, 0}, {2, 0},
                                              {2, 0}, {2, 3}, {1, 0}};

/* Which requests each case skips (bit i: request i): a pinhole camera's time and lens; the
 * arrays; two single-value streams of stratified, a fallback single between others and the last
 * request (a fallback too); everything but the film offset. */
static const unsigned skip_masks[] = {0x6u, 0x828u, 0x1540u, 0x1ffeu};

static void skipped_layout(unsigned mask, clr_sample_request *out) {
  for (int i = 0; i < NREQ; ++i) {
    out[i] = full[i];
    if (mask >> i & 1u) out[i].dims |= SKIP;
  }
}

static int request_values(const clr_sample_request *r) {
  return r->dims * (r->array_size ? r->array_size : 1);
}

/* values of `mask`'s layout, per sample, with map[k] = the full layout's index of value k */
static int packed_map(unsigned mask, int *map) {
  int at = 0, n = 0;
  for (int i = 0; i < NREQ; ++i) {
    int v = request_values(&full[i]);
    for (int k = 0; k < v && !(mask >> i & 1u); ++k) map[n++] = at + k;
    at += v;
  }
  return n;
}

static float *generate(clr_sampler s, const clr_sample_request *req, clr_bounds2i px, int first,
                       int count, int device, int32_t *per_sample) {
  assert_int_equal(clr_sample_layout_values(req, NREQ, per_sample), CLR_SUCCESS);
  size_t items = (size_t)(px.x1 - px.x0) * (size_t)(px.y1 - px.y0) * (size_t)count;
  float *v = malloc(items * (size_t)*per_sample * sizeof(float));
  assert_non_null(v);
  memset(v, 0xa5, items * (size_t)*per_sample * sizeof(float));
  clr_sample_batch b = sample_batch(px, first, count, req, NREQ);
  clr_sample_output o;
  clr_sample_output_init(&o);
  o.host_values = v;
  clr_result r =
      device ? clr_sampler_generate(s, &b, &o) : clr_sampler_generate_reference(s, &b, &o);
  if (r != CLR_SUCCESS) fprintf(stderr, "%s\n", clr_last_error_message());
  assert_int_equal(r, CLR_SUCCESS);
  return v;
}

static clr_sampler make(clr_sampler_type type, clr_seeding seeding) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.seeding = seeding;
  d.pixel_samples = 8;
  if (type == CLR_SAMPLER_STRATIFIED) d.x_samples = 4, d.y_samples = 2;
  d.film.x_resolution = 37;
  d.film.y_resolution = 21;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
  return s;
}

/* pbrt-v4's own samplers run pbrt-v4's algorithm under any seeding (once); 02sequence and
 * maxmindist have no pbrt-v4 version. */
static int applies(int type, int seeding) {
  if (type >= CLR_SAMPLER_INDEPENDENT) return seeding == CLR_SEEDING_PBRT_V4;
  return seeding != CLR_SEEDING_PBRT_V4 ||
         (type != CLR_SAMPLER_ZEROTWO && type != CLR_SAMPLER_MAXMINDIST);
}

static void test_skipped_values_match_full_layout(void **state) {
  (void)state;
  /* pixels across a pbrt-v3 tile border, a width that is no multiple of 8 (SIMD lanes), samples
   * 2..6 of 8 */
  const clr_bounds2i px = {13, 14, 18, 18};
  const int first = 2, count = 5;
  const size_t items = (size_t)(px.x1 - px.x0) * (size_t)(px.y1 - px.y0) * (size_t)count;
  int compared = 0;
  for (int t = 0; t < CLR_SAMPLER_TYPE_COUNT; ++t)
    for (int seeding = 0; seeding < 3; ++seeding) {
      if (!applies(t, seeding)) continue;
      clr_sampler s = make((clr_sampler_type)t, (clr_seeding)seeding);
      int32_t full_per = 0;
      float *ref = generate(s, full, px, first, count, 0, &full_per);
      assert_int_equal(full_per, 40);
      for (size_t m = 0; m < sizeof skip_masks / sizeof skip_masks[0]; ++m) {
        clr_sample_request req[NREQ];
        skipped_layout(skip_masks[m], req);
        int map[64];
        int n = packed_map(skip_masks[m], map);
        for (int device = 0; device < 2; ++device) {
          int32_t per = 0;
          float *v = generate(s, req, px, first, count, device, &per);
          assert_int_equal(per, n);
          for (size_t i = 0; i < items; ++i)
            for (int k = 0; k < n; ++k) {
              float a = v[i * (size_t)per + (size_t)k], b = ref[i * (size_t)full_per + map[k]];
              if (memcmp(&a, &b, sizeof a) != 0)
                fprintf(stderr, "%s seeding %d mask 0x%x %s: item %zu value %d %a, full %a\n",
                        clr_sampler_type_name((clr_sampler_type)t), seeding, skip_masks[m],
                        device ? "device" : "host", i, k, (double)a, (double)b);
              assert_memory_equal(&a, &b, sizeof a);
            }
          free(v);
          ++compared;
        }
      }
      free(ref);
      clr_sampler_release(s);
    }
  /* 10 types: 6 pbrt-v3 ones x pbrt-v3 and pixel seeding, 4 of them with pbrt-v4's, 4 pbrt-v4 */
  assert_int_equal(compared, (12 + 4 + 4) * 4 * 2);
}

/* clr_sampler_generate_at over a skipped layout: the packed layout's values, any range. */
static void test_generate_at_skips(void **state) {
  (void)state;
  static const clr_sampler_type types[] = {CLR_SAMPLER_HALTON, CLR_SAMPLER_SOBOL};
  const clr_sample_point pts[3] = {{0, 0, 0}, {20, 9, 7}, {36, 20, 3}};
  for (int t = 0; t < 2; ++t) {
    clr_sampler s = make(types[t], CLR_SEEDING_PIXEL);
    clr_sample_request req[NREQ];
    skipped_layout(0x1546u, req); /* time, lens, the 2D array, fallbacks */
    int32_t per = 0;
    assert_int_equal(clr_sample_layout_values(req, NREQ, &per), CLR_SUCCESS);
    int map[64];
    assert_int_equal(packed_map(0x1546u, map), per);
    for (int p = 0; p < 3; ++p) {
      int32_t full_per = 0;
      float *ref = generate(s, full, (clr_bounds2i){pts[p].x, pts[p].y, pts[p].x + 1, pts[p].y + 1},
                            pts[p].sample, 1, 0, &full_per);
      for (int first = 0; first < per; first += 3) {
        int n = per - first < 5 ? per - first : 5;
        float got[5];
        assert_int_equal(clr_sampler_generate_at(s, req, NREQ, &pts[p], 1, first, n, got),
                         CLR_SUCCESS);
        for (int k = 0; k < n; ++k) assert_memory_equal(&got[k], &ref[map[first + k]], 4);
      }
      free(ref);
    }
    /* the range counts stored values only */
    float one;
    assert_int_equal(clr_sampler_generate_at(s, req, NREQ, pts, 1, per, 1, &one),
                     CLR_ERROR_INVALID_ARGUMENT);
    clr_sampler_release(s);
  }
}

static void expect_refused(const clr_sample_request *req, int n, clr_result code,
                           const char *message) {
  int32_t per = -7;
  assert_int_equal(clr_sample_layout_values(req, n, &per), code);
  assert_int_equal(per, -7);
  if (!strstr(clr_last_error_message(), message))
    fprintf(stderr, "message \"%s\" lacks \"%s\"\n", clr_last_error_message(), message);
  assert_non_null(strstr(clr_last_error_message(), message));
}

static void test_bad_skips_refused(void **state) {
  (void)state;
  const clr_sample_request unknown_bit[] = {{2, 0}, {1 | 0x200, 0}};
  expect_refused(unknown_bit, 2, CLR_ERROR_INVALID_REQUESTS, "request 1 has dims 513");
  const clr_sample_request bad_dims[] = {{2, 0}, {3 | SKIP, 0}};
  expect_refused(bad_dims, 2, CLR_ERROR_INVALID_REQUESTS, "request 1 has dims 259");
  const clr_sample_request zero_dims[] = {{2, 0}, {SKIP, 4}};
  expect_refused(zero_dims, 2, CLR_ERROR_INVALID_REQUESTS, "request 1 has dims 256");
  const clr_sample_request film[] = {{2 | SKIP, 0}, {1, 0}};
  expect_refused(film, 2, CLR_ERROR_INVALID_REQUESTS, "request 0, the film offset, cannot be");
  const clr_sample_request negative[] = {{2, 0}, {-1, 0}};
  expect_refused(negative, 2, CLR_ERROR_INVALID_REQUESTS, "request 1 has dims -1");
  /* the limits count skipped requests: 2 + 2 * 2047 stored values would fit, 4096 + 2 do not */
  const clr_sample_request big[] = {{2, 0}, {2 | SKIP, 1}, {2 | SKIP, 2047}};
  expect_refused(big, 3, CLR_ERROR_REQUEST_TOO_LARGE, "4098 values per sample exceed");
  const clr_sample_request big_array[] = {{2, 0}, {1 | SKIP, CLR_MAX_VALUES_PER_SAMPLE + 1}};
  expect_refused(big_array, 2, CLR_ERROR_REQUEST_TOO_LARGE, "request 1 has array size 4097");
  /* a pbrt-v4 sampler finds the film offset past skipped leading 1D requests; it may not be
   * skipped there either */
  clr_sampler s = make(CLR_SAMPLER_ZSOBOL, CLR_SEEDING_PBRT_V4);
  const clr_sample_request v4_film[] = {{1 | SKIP, 0}, {2 | SKIP, 0}, {1, 0}};
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = (clr_bounds2i){0, 0, 1, 1};
  b.requests = v4_film;
  b.request_count = 3;
  float v[64];
  clr_sample_output o;
  clr_sample_output_init(&o);
  o.host_values = v;
  assert_int_equal(clr_sampler_generate_reference(s, &b, &o), CLR_ERROR_INVALID_REQUESTS);
  assert_non_null(strstr(clr_last_error_message(), "request 1, the film offset, cannot be"));
  clr_sampler_release(s);
}

/* Counts: every request stored, some skipped, all but the film offset skipped. */
static void test_layout_value_counts(void **state) {
  (void)state;
  int32_t per = 0;
  const clr_sample_request pinhole[] = {{2, 0}, {1 | SKIP, 0}, {2 | SKIP, 0}, {2, 16}};
  assert_int_equal(clr_sample_layout_values(pinhole, 4, &per), CLR_SUCCESS);
  assert_int_equal(per, 2 + 32);
  clr_sample_request req[NREQ];
  skipped_layout(0x1ffeu, req);
  assert_int_equal(clr_sample_layout_values(req, NREQ, &per), CLR_SUCCESS);
  assert_int_equal(per, 2);
  skipped_layout(0u, req);
  assert_int_equal(clr_sample_layout_values(req, NREQ, &per), CLR_SUCCESS);
  assert_int_equal(per, 40);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_skipped_values_match_full_layout),
      cmocka_unit_test(test_generate_at_skips),
      cmocka_unit_test(test_bad_skips_refused),
      cmocka_unit_test(test_layout_value_counts),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
