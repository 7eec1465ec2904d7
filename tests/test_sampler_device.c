/* Sampler kernels on the OpenCL device against the host reference built from the same headers:
 * bit-identical values, order independence, stratification of device output, bad input. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"

#include "context_fixture.h"
#include "sample_batch_test_util.h"

/* Camera (2,1,2) then an integrator's 1D, 2D, 2D: 10 values. */
static const clr_sample_request camera10[] = {{2, 0}, {1, 0}, {2, 0}, {1, 0}, {2, 0}, {2, 0}};
/* With arrays, and singles past stratified's 4 dimensions. */
static const clr_sample_request with_arrays[] = {{2, 0}, {1, 0}, {2, 0}, {1, 5}, {2, 0},
                                                 {2, 7}, {1, 0}, {1, 0}, {1, 0}, {2, 0},
                                                 {2, 0}, {2, 3}, {1, 0}};

static clr_sampler make_sampler(clr_sampler_type type, clr_seeding seeding, int res) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.seeding = seeding;
  d.pixel_samples = 16; /* random's default is 4; the issue asks 16 spp for every sampler */
  d.film.x_resolution = d.film.y_resolution = res;
  d.film.filter_radius[0] = d.film.filter_radius[1] = 1.5f;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
  return s;
}

typedef struct generated {
  float *values;
  uint64_t *indices;
  size_t count, items;
  int32_t per_sample;
} generated;

static generated generate(clr_sampler s, clr_bounds2i px, int first, int count,
                          const clr_sample_request *req, int nreq, int device) {
  generated g;
  clr_sample_batch b = sample_batch(px, first, count, req, nreq);
  assert_int_equal(clr_sample_layout_values(req, nreq, &g.per_sample), CLR_SUCCESS);
  int spp = count ? count : clr_sampler_spp(s);
  g.items = (size_t)(px.x1 - px.x0) * (px.y1 - px.y0) * spp;
  g.count = g.items * g.per_sample;
  g.values = malloc(g.count * sizeof(float));
  g.indices = malloc(g.items * sizeof(uint64_t));
  assert_non_null(g.values);
  assert_non_null(g.indices);
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = g.values;
  out.host_indices = g.indices;
  clr_result r =
      device ? clr_sampler_generate(s, &b, &out) : clr_sampler_generate_reference(s, &b, &out);
  if (r != CLR_SUCCESS) fprintf(stderr, "%s\n", clr_last_error_message());
  assert_int_equal(r, CLR_SUCCESS);
  return g;
}

static void free_generated(generated *g) {
  free(g->values);
  free(g->indices);
}

/* Every value of dev and ref bit for bit (the first three differences printed after `what`). */
static void assert_same_values(const generated *dev, const generated *ref, const char *what) {
  assert_int_equal(dev->count, ref->count);
  size_t bad = 0;
  for (size_t i = 0; i < dev->count; ++i)
    if (memcmp(&dev->values[i], &ref->values[i], 4) != 0 && bad++ < 3)
      fprintf(stderr, "%s: value %zu device %.9g reference %.9g\n", what, i, (double)dev->values[i],
              (double)ref->values[i]);
  assert_int_equal(bad, 0);
}

/* s's device values against the reference's on pixels px, with the camera layout and the layout
 * with arrays: every sample, and (when s has at least first + 2) samples first .. spp - 2, a
 * range that starts and ends inside each pixel. `what` names the case in messages. */
static void assert_batches_match_reference(clr_sampler s, clr_bounds2i px, int first,
                                           const char *what) {
  int spp = clr_sampler_spp(s), n = (int)(sizeof with_arrays / sizeof with_arrays[0]);
  for (int range = 0; range < (spp >= first + 2 ? 2 : 1); ++range) {
    int from = range ? first : 0, count = range ? spp - first - 1 : 0;
    for (int layout = 0; layout < 2; ++layout) {
      const clr_sample_request *req = layout ? with_arrays : camera10;
      generated dev = generate(s, px, from, count, req, layout ? n : 6, 1);
      generated ref = generate(s, px, from, count, req, layout ? n : 6, 0);
      char label[160];
      snprintf(label, sizeof label, "%s first %d layout %d", what, from, layout);
      assert_same_values(&dev, &ref, label);
      free_generated(&dev);
      free_generated(&ref);
    }
  }
}

static void assert_bit_identical(clr_sampler_type type, clr_seeding seeding,
                                 const clr_sample_request *req, int nreq) {
  clr_sampler s = make_sampler(type, seeding, 64);
  clr_bounds2i px = {0, 0, 64, 64};
  generated dev = generate(s, px, 0, 0, req, nreq, 1);
  generated ref = generate(s, px, 0, 0, req, nreq, 0);
  size_t mismatches = 0;
  for (size_t i = 0; i < dev.count; ++i) {
    if (memcmp(&dev.values[i], &ref.values[i], 4) != 0 && mismatches++ < 5)
      fprintf(stderr, "%s: value %zu device %.9g reference %.9g\n", clr_sampler_type_name(type), i,
              (double)dev.values[i], (double)ref.values[i]);
    assert_true(dev.values[i] >= 0.0f && dev.values[i] < 1.0f);
  }
  assert_int_equal(mismatches, 0);
  assert_memory_equal(dev.indices, ref.indices, dev.items * sizeof(uint64_t));
  free_generated(&dev);
  free_generated(&ref);
  clr_sampler_release(s);
}

static void test_device_matches_reference(void **state) {
  (void)state;
  for (int t = 0; t <= CLR_SAMPLER_MAXMINDIST; ++t) {
    assert_bit_identical((clr_sampler_type)t, CLR_SEEDING_PIXEL, camera10, 6);
    assert_bit_identical((clr_sampler_type)t, CLR_SEEDING_PBRT_V3, camera10, 6);
  }
}

static void test_device_matches_reference_with_arrays(void **state) {
  (void)state;
  int n = (int)(sizeof with_arrays / sizeof with_arrays[0]);
  for (int t = 0; t <= CLR_SAMPLER_MAXMINDIST; ++t) {
    assert_bit_identical((clr_sampler_type)t, CLR_SEEDING_PIXEL, with_arrays, n);
    assert_bit_identical((clr_sampler_type)t, CLR_SEEDING_PBRT_V3, with_arrays, n);
  }
}

/* The same (pixel, sample, value) gives the same bits whatever batch, sample range or visiting
 * order produced it. */
static void test_order_independence(void **state) {
  (void)state;
  int n = (int)(sizeof with_arrays / sizeof with_arrays[0]);
  for (int t = 0; t <= CLR_SAMPLER_MAXMINDIST; ++t) {
    for (int seeding = 0; seeding < 2; ++seeding) {
      clr_sampler s = make_sampler((clr_sampler_type)t, (clr_seeding)seeding, 40);
      clr_bounds2i all = clr_sampler_sample_bounds(s);
      int spp = clr_sampler_spp(s);
      generated full = generate(s, all, 0, 0, with_arrays, n, 1);
      int w = all.x1 - all.x0;
      /* Visit a few pixels backwards, one sample at a time, on the device and the host. */
      for (int k = 7; k >= 0; --k) {
        int x = all.x0 + (k * 13) % w, y = all.y0 + (k * 7) % (all.y1 - all.y0);
        clr_bounds2i one = {x, y, x + 1, y + 1};
        for (int sample = spp - 1; sample >= 0; sample -= 3) {
          generated part = generate(s, one, sample, 1, with_arrays, n, k & 1);
          size_t item = ((size_t)(y - all.y0) * w + (x - all.x0)) * spp + sample;
          assert_memory_equal(part.values, full.values + item * full.per_sample,
                              full.per_sample * sizeof(float));
          assert_int_equal(part.indices[0], full.indices[item]);
          free_generated(&part);
        }
      }
      free_generated(&full);
      clr_sampler_release(s);
    }
  }
}

/* Device output of the stratified sampler: film offsets hit each of the 4x4 strata once per
 * pixel, the time dimension each of 16 strata once, 2D arrays are Latin hypercubes. */
static void test_stratified_device_strata(void **state) {
  (void)state;
  clr_sampler s = make_sampler(CLR_SAMPLER_STRATIFIED, CLR_SEEDING_PIXEL, 16);
  clr_bounds2i px = {0, 0, 16, 16};
  int n = (int)(sizeof with_arrays / sizeof with_arrays[0]);
  generated g = generate(s, px, 0, 0, with_arrays, n, 1);
  for (int p = 0; p < 256; ++p) {
    int cells[16] = {0}, strata[16] = {0};
    for (int i = 0; i < 16; ++i) {
      const float *v = g.values + ((size_t)p * 16 + i) * g.per_sample;
      cells[(int)(v[0] * 4) + 4 * (int)(v[1] * 4)]++;
      strata[(int)(v[2] * 16)]++;
      /* 2D array of 7 (request 5) starts after 2+1+2+5+2 values. */
      int rows[7] = {0}, cols[7] = {0};
      for (int j = 0; j < 7; ++j) {
        cols[(int)(v[12 + 2 * j] * 7)]++;
        rows[(int)(v[12 + 2 * j + 1] * 7)]++;
      }
      for (int j = 0; j < 7; ++j) {
        assert_int_equal(rows[j], 1);
        assert_int_equal(cols[j], 1);
      }
    }
    for (int c = 0; c < 16; ++c) {
      assert_int_equal(cells[c], 1);
      assert_int_equal(strata[c], 1);
    }
  }
  free_generated(&g);
  clr_sampler_release(s);
}

/* Stratified's SIMD kernel shuffles up to 16 strata as a permutation in registers and more in
 * scratch: strata counts on both sides of 16, with and without jitter, whole pixels and a sample
 * range (read through the permutation), bit-identical to the host reference. */
static void test_stratified_strata_counts_match_reference(void **state) {
  (void)state;
  static const int strata[][3] = {{3, 3, 1}, {4, 4, 0}, {1, 7, 1}, {5, 5, 1}, {2, 9, 0}};
  for (size_t t = 0; t < sizeof strata / sizeof strata[0]; ++t) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, CLR_SAMPLER_STRATIFIED);
    d.x_samples = strata[t][0];
    d.y_samples = strata[t][1];
    d.jitter = strata[t][2];
    d.film.x_resolution = 13;
    d.film.y_resolution = 11;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
    char what[64];
    snprintf(what, sizeof what, "%dx%d jitter %d", strata[t][0], strata[t][1], strata[t][2]);
    assert_batches_match_reference(s, (clr_bounds2i){0, 0, 13, 11}, 2, what);
    clr_sampler_release(s);
  }
}

/* 02sequence and maxmindist in the SIMD kernel shuffle up to 16 samples' points as a permutation
 * in registers and more in scratch: 1 to 64 samples per pixel (maxmindist's first 2D stream is
 * its (0,m,2)-net's), whole pixels and a sample range, streams and arrays, bit-identical to the
 * host reference. */
static void test_zerotwo_spp_match_reference(void **state) {
  (void)state;
  static const int spps[] = {1, 2, 8, 32, 64};
  for (int t = CLR_SAMPLER_ZEROTWO; t <= CLR_SAMPLER_MAXMINDIST; ++t)
    for (size_t k = 0; k < sizeof spps / sizeof spps[0]; ++k) {
      clr_sampler_desc d;
      clr_sampler_desc_init(&d, (clr_sampler_type)t);
      d.pixel_samples = spps[k];
      d.film.x_resolution = 13;
      d.film.y_resolution = 11;
      clr_sampler s = NULL;
      assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
      assert_int_equal(clr_sampler_spp(s), spps[k]);
      char what[64];
      snprintf(what, sizeof what, "%s %d spp", clr_sampler_type_name((clr_sampler_type)t), spps[k]);
      assert_batches_match_reference(s, (clr_bounds2i){0, 0, 13, 11}, 2, what);
      clr_sampler_release(s);
    }
}

/* zsobol and paddedsobol in the SIMD kernel (8 pixels per work-item), pbrt-v4's sobol, halton
 * and independent (8 items per work-item): 1 to 64 samples per pixel (zsobol: odd and even powers
 * of two, the last binary digit's flip; paddedsobol: any count, the permutation's cycle walks;
 * halton: lanes across pixels), every randomizer, two seeds, whole pixels and a sample range,
 * streams and arrays, a batch away from the origin whose width is no multiple of 8,
 * bit-identical to the host reference. */
static void test_v4_lanes_match_reference(void **state) {
  (void)state;
  static const struct {
    clr_sampler_type type;
    int spp;
  } cases[] = {
      {CLR_SAMPLER_ZSOBOL, 1},       {CLR_SAMPLER_ZSOBOL, 2},       {CLR_SAMPLER_ZSOBOL, 4},
      {CLR_SAMPLER_ZSOBOL, 8},       {CLR_SAMPLER_ZSOBOL, 16},      {CLR_SAMPLER_ZSOBOL, 32},
      {CLR_SAMPLER_ZSOBOL, 64},      {CLR_SAMPLER_PADDEDSOBOL, 1},  {CLR_SAMPLER_PADDEDSOBOL, 3},
      {CLR_SAMPLER_PADDEDSOBOL, 5},  {CLR_SAMPLER_PADDEDSOBOL, 12}, {CLR_SAMPLER_PADDEDSOBOL, 16},
      {CLR_SAMPLER_PADDEDSOBOL, 33}, {CLR_SAMPLER_SOBOL, 1},        {CLR_SAMPLER_SOBOL, 12},
      {CLR_SAMPLER_SOBOL, 16},       {CLR_SAMPLER_SOBOL, 64},       {CLR_SAMPLER_INDEPENDENT, 1},
      {CLR_SAMPLER_INDEPENDENT, 7},  {CLR_SAMPLER_INDEPENDENT, 16}, {CLR_SAMPLER_PMJ02BN, 1},
      {CLR_SAMPLER_PMJ02BN, 3},      {CLR_SAMPLER_PMJ02BN, 16},     {CLR_SAMPLER_PMJ02BN, 48},
      {CLR_SAMPLER_HALTON, 1},       {CLR_SAMPLER_HALTON, 7},       {CLR_SAMPLER_HALTON, 16},
      {CLR_SAMPLER_HALTON, 64}};
  int n = (int)(sizeof with_arrays / sizeof with_arrays[0]);
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k)
    for (int r = 0; r <= CLR_RANDOMIZATION_OWEN; ++r) {
      if ((cases[k].type == CLR_SAMPLER_INDEPENDENT || cases[k].type == CLR_SAMPLER_PMJ02BN) &&
          r != CLR_RANDOMIZATION_DEFAULT)
        continue;
      if (cases[k].type == CLR_SAMPLER_HALTON && r == CLR_RANDOMIZATION_FASTOWEN) continue;
      int spp = cases[k].spp;
      clr_sampler_desc d;
      clr_sampler_desc_init(&d, cases[k].type);
      d.seeding = CLR_SEEDING_PBRT_V4;
      d.randomization = (clr_randomization)r;
      d.seed = (uint32_t)(k & 1u) * 7u;
      d.pixel_samples = spp;
      d.film.x_resolution = 45;
      d.film.y_resolution = 21;
      clr_sampler s = NULL;
      assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
      assert_int_equal(clr_sampler_spp(s), spp);
      char what[96];
      snprintf(what, sizeof what, "%s %d spp %s", clr_sampler_type_name(cases[k].type), spp,
               clr_randomization_name((clr_randomization)r));
      assert_batches_match_reference(s, (clr_bounds2i){3, 2, 42, 9}, 1, what);
      clr_sampler_release(s);
    }
  /* Pixels far from the origin at 256 spp: zsobol's Morton and sobol's indices of 36 bits (the
   * Sobol' matrices' upper 32 columns); sobol past its 1024 dimensions (wrapping to 2) in a 1D
   * array of 1030 values and a 2D array of 520 points. */
  static const clr_sample_request many[] = {{2, 0}, {1, 1030}, {2, 520}};
  for (int t = 0; t < 2; ++t) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, t ? CLR_SAMPLER_SOBOL : CLR_SAMPLER_ZSOBOL);
    d.seeding = CLR_SEEDING_PBRT_V4;
    d.pixel_samples = 256;
    d.film.x_resolution = d.film.y_resolution = 16384;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
    clr_bounds2i far = {16370, 16001, 16381, 16003};
    for (int layout = 0; layout < 2; ++layout) {
      generated dev = generate(s, far, 250, 6, layout ? many : with_arrays, layout ? 3 : n, 1);
      generated ref = generate(s, far, 250, 6, layout ? many : with_arrays, layout ? 3 : n, 0);
      assert_memory_equal(dev.values, ref.values, dev.count * sizeof(float));
      free_generated(&dev);
      free_generated(&ref);
    }
    clr_sampler_release(s);
  }
}

/* pbrt-v4's halton with permuted digits reads DigitPermutation tables built on the host for the
 * layout's dimensions: several seeds (a new table each), a layout that grows on the same sampler
 * (the tables grow), 1300 dimensions (past the 1000 primes pbrt-v4 wraps at), halton indices past
 * 2^32 (64-bit digit division), and every value against the reference's per-digit hashes. */
static void test_v4_halton_digit_tables_match_reference(void **state) {
  (void)state;
  static clr_sample_request many[650];
  for (int i = 0; i < 650; ++i) many[i] = (clr_sample_request){2, 0};
  int n = (int)(sizeof with_arrays / sizeof with_arrays[0]);
  static const struct {
    uint32_t seed;
    int spp, res;
    clr_bounds2i px;
    int first, count;
  } cases[] = {{0, 16, 64, {3, 5, 14, 7}, 0, 0},
               {5, 64, 64, {60, 0, 64, 3}, 7, 20},
               {12345, 1, 64, {0, 0, 9, 2}, 0, 0},
               {7, 4096, 4096, {4000, 4090, 4003, 4091}, 4090, 6}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, CLR_SAMPLER_HALTON);
    d.seeding = CLR_SEEDING_PBRT_V4;
    d.randomization = CLR_RANDOMIZATION_PERMUTEDIGITS;
    d.seed = cases[c].seed;
    d.pixel_samples = cases[c].spp;
    d.film.x_resolution = d.film.y_resolution = cases[c].res;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
    for (int layout = 0; layout < 3; ++layout) {
      const clr_sample_request *req = layout == 0 ? camera10 : layout == 1 ? with_arrays : many;
      int nreq = layout == 0 ? 6 : layout == 1 ? n : 650;
      generated dev = generate(s, cases[c].px, cases[c].first, cases[c].count, req, nreq, 1);
      generated ref = generate(s, cases[c].px, cases[c].first, cases[c].count, req, nreq, 0);
      char what[64];
      snprintf(what, sizeof what, "halton seed %u layout %d", cases[c].seed, layout);
      assert_same_values(&dev, &ref, what);
      free_generated(&dev);
      free_generated(&ref);
    }
    clr_sampler_release(s);
  }
}

/* pbrt-v4's stratified (8 items per work-item on SIMD contexts) and pmj02bn divide by the strata
 * and sample counts correctly rounded: in double on devices with fp64, in integers on the host;
 * strata counts that are no powers of two (3x5, 7x1, 13x2, 4x4), with and without jitter, and
 * pmj02bn's 1D values at 3, 12 and 48 spp; whole pixels and a sample range, bit-identical. */
static void test_v4_divisions_match_reference(void **state) {
  (void)state;
  static const int strata[][2] = {{3, 5}, {7, 1}, {13, 2}, {4, 4}};
  static const int pmj_spps[] = {3, 12, 48};
  for (int c = 0; c < 11; ++c) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, c < 8 ? CLR_SAMPLER_STRATIFIED : CLR_SAMPLER_PMJ02BN);
    d.seeding = CLR_SEEDING_PBRT_V4;
    if (c < 8) {
      d.x_samples = strata[c % 4][0];
      d.y_samples = strata[c % 4][1];
      d.jitter = c < 4;
    } else {
      d.pixel_samples = pmj_spps[c - 8];
    }
    d.film.x_resolution = 29;
    d.film.y_resolution = 17;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
    char what[64];
    snprintf(what, sizeof what, "%s case %d", clr_sampler_type_name(d.type), c);
    assert_batches_match_reference(s, (clr_bounds2i){1, 2, 28, 6}, 1, what);
    clr_sampler_release(s);
  }
}

/* Past Sobol's 1024 dimensions and Halton's 1000 primes values fall back to a hash: in range,
 * and not constant. */
static void test_past_available_dimensions(void **state) {
  (void)state;
  static clr_sample_request req[601];
  req[0] = (clr_sample_request){2, 0};
  for (int i = 1; i < 601; ++i) req[i] = (clr_sample_request){2, 0}; /* dims up to 1201 */
  for (int t = CLR_SAMPLER_HALTON; t <= CLR_SAMPLER_SOBOL; ++t) {
    clr_sampler s = make_sampler((clr_sampler_type)t, CLR_SEEDING_PIXEL, 8);
    clr_bounds2i px = {0, 0, 2, 2};
    generated dev = generate(s, px, 0, 0, req, 601, 1);
    generated ref = generate(s, px, 0, 0, req, 601, 0);
    assert_true(dev.per_sample == 1202);
    assert_memory_equal(dev.values, ref.values, dev.count * sizeof(float));
    double sum = 0;
    for (size_t i = 0; i < dev.count; ++i) {
      assert_true(dev.values[i] >= 0.0f && dev.values[i] < 1.0f);
      sum += dev.values[i];
    }
    assert_true(sum / dev.count > 0.4 && sum / dev.count < 0.6);
    free_generated(&dev);
    free_generated(&ref);
    clr_sampler_release(s);
  }
}

/* Large global indices take the device's other paths: halton indices past 2^32 and sobol indices
 * of more than 32 bits (lane-by-lane scalar code), and halton digits whose reversal exceeds 2^32
 * (64-bit accumulation). Each must still match the reference bit for bit. */
static void test_large_indices_match_reference(void **state) {
  (void)state;
  static clr_sample_request req[201];
  for (int i = 0; i < 201; ++i) req[i] = (clr_sample_request){2, 0}; /* dims up to 401 */
  static const clr_sample_request arrays[] = {{2, 0}, {1, 0}, {2, 3}, {1, 2}};
  struct {
    clr_sampler_type type;
    int spp, first, count;
    const clr_sample_request *req;
    int nreq;
  } cases[] = {
      {CLR_SAMPLER_HALTON, 1 << 18, (1 << 18) - 4, 4, camera10, 6}, /* stride 31104 << 18 */
      {CLR_SAMPLER_HALTON, 4096, 4090, 6, req, 201}, /* indices past 7919^2: 3 digits */
      {CLR_SAMPLER_HALTON, 4096, 200, 8, arrays, 4},
      {CLR_SAMPLER_SOBOL, 1 << 16, (1 << 16) - 5, 5, camera10, 6}, /* 20 + 16 index bits */
      {CLR_SAMPLER_SOBOL, 1 << 16, 100, 3, arrays, 4},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, cases[c].type);
    d.pixel_samples = cases[c].spp;
    d.film.x_resolution = d.film.y_resolution = 512;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
    clr_bounds2i px = {300, 301, 303, 303};
    generated dev = generate(s, px, cases[c].first, cases[c].count, cases[c].req, cases[c].nreq, 1);
    generated ref = generate(s, px, cases[c].first, cases[c].count, cases[c].req, cases[c].nreq, 0);
    assert_memory_equal(dev.values, ref.values, dev.count * sizeof(float));
    assert_memory_equal(dev.indices, ref.indices, dev.items * sizeof(uint64_t));
    if (c == 0) assert_true(dev.indices[0] > UINT32_MAX);
    free_generated(&dev);
    free_generated(&ref);
    clr_sampler_release(s);
  }
}

/* Sobol's log2 resolution m and frame bits are launch arguments of one program: every m from 0
 * to 15 (2m pixel bits), with sample numbers of 0 to 20 bits up to 32 index bits in all (the SIMD
 * kernel's limit: columns and 3-bit lookups four at a time, a partial last step) and one past it
 * (the lane-by-lane path), on a film whose width is not a power of two. Device == reference. */
static void test_sobol_every_index_width_matches_reference(void **state) {
  (void)state;
  for (int m = 0; m <= 15; ++m) {
    int room = 32 - 2 * m < 20 ? 32 - 2 * m : 20; /* frame bits that keep 32-bit indices */
    int frame_bits[] = {0, 1, room / 2, room - 1, room, room + 1};
    for (size_t k = 0; k < sizeof frame_bits / sizeof frame_bits[0]; ++k) {
      if (frame_bits[k] < 0 || frame_bits[k] > 20) continue; /* pixelsamples <= 2^20 */
      int spp = 1 << frame_bits[k], side = m < 2 ? 1 << m : (1 << m) - 1;
      clr_sampler_desc d;
      clr_sampler_desc_init(&d, CLR_SAMPLER_SOBOL);
      d.pixel_samples = spp;
      d.film.x_resolution = side;
      d.film.y_resolution = m < 2 ? side : 3;
      clr_sampler s = NULL;
      if (clr_sampler_create(ctx, &d, &s) != CLR_SUCCESS)
        fail_msg("sobol m = %d, %d spp: %s", m, spp, clr_last_error_message());
      int x0 = side > 9 ? side - 9 : 0, y0 = d.film.y_resolution > 2 ? d.film.y_resolution - 2 : 0;
      clr_bounds2i px = {x0, y0, side, d.film.y_resolution};
      int count = spp < 3 ? spp : 3;
      generated dev = generate(s, px, spp - count, count, camera10, 6, 1);
      generated ref = generate(s, px, spp - count, count, camera10, 6, 0);
      if (memcmp(dev.values, ref.values, dev.count * sizeof(float)) != 0 ||
          memcmp(dev.indices, ref.indices, dev.items * sizeof(uint64_t)) != 0)
        fail_msg("sobol m = %d, %d spp: device differs from the reference", m, spp);
      free_generated(&dev);
      free_generated(&ref);
      clr_sampler_release(s);
    }
  }
}

/* Halton's pair tables (two lookups per value where every argument of a launch is below 2^28 and
 * fits the table limits): 512^2 film, so indices below 31104 * spp; tables of one to four digits
 * per part, with 64 spp larger ones, with 500 values past the tables' budget (the rest keep the
 * chunk loop, as do the bases of test_large_indices_match_reference). Pixel (0, 0) has arguments
 * below B (a zero top part). Work-items whose 8 lanes are consecutive samples of one pixel read
 * lo from the lane rows (whole pixels, and samples 8-23 of 24); samples 3-15 put other
 * work-items across two pixels (lane by lane). At 16 spp dimensions 31-53 (bases 131-251, two-digit
 * top parts) have tables whose digit counts the kernel derives; the 42-value cases end there like
 * the path tracer's layout (dimension 40). Device == reference bit for bit. */
static void test_halton_pair_tables_match_reference(void **state) {
  (void)state;
  static clr_sample_request req[250];
  for (int i = 0; i < 250; ++i) req[i] = (clr_sample_request){2, 0}; /* dims up to 499 */
  struct {
    int spp, nreq;
    clr_bounds2i px;
    int first, count;
  } cases[] = {{16, 30, {0, 0, 64, 2}, 0, 0},       {16, 30, {448, 509, 512, 512}, 0, 0},
               {64, 30, {100, 7, 132, 8}, 0, 0},    {16, 250, {5, 5, 7, 6}, 0, 0},
               {24, 30, {200, 60, 203, 62}, 8, 16}, {16, 30, {0, 0, 9, 2}, 3, 13},
               {16, 21, {0, 0, 16, 2}, 0, 0},       {16, 21, {250, 3, 253, 5}, 3, 13}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, CLR_SAMPLER_HALTON);
    d.pixel_samples = cases[c].spp;
    d.film.x_resolution = d.film.y_resolution = 512;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
    generated dev = generate(s, cases[c].px, cases[c].first, cases[c].count, req, cases[c].nreq, 1);
    generated ref = generate(s, cases[c].px, cases[c].first, cases[c].count, req, cases[c].nreq, 0);
    assert_memory_equal(dev.values, ref.values, dev.count * sizeof(float));
    assert_memory_equal(dev.indices, ref.indices, dev.items * sizeof(uint64_t));
    free_generated(&dev);
    free_generated(&ref);
    clr_sampler_release(s);
  }
}

/* Halton's one-pixel index on the device (work-items of 8 samples of one pixel) divides by
 * scale[1] = 3^e1 with a reciprocal per e1: films whose heights give e1 = 0..5 (1, 2, 9, 27, 81,
 * 300 rows; widths give e0 from 0 to 7), whole films or a corner, 8 and 16 spp. Device ==
 * reference. */
static void test_halton_film_scales_match_reference(void **state) {
  (void)state;
  struct {
    int width, height, spp;
  } cases[] = {{1, 1, 16}, {3, 2, 8}, {5, 9, 16}, {16, 27, 8}, {70, 81, 16}, {300, 300, 16}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, CLR_SAMPLER_HALTON);
    d.pixel_samples = cases[c].spp;
    d.film.x_resolution = cases[c].width;
    d.film.y_resolution = cases[c].height;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
    clr_bounds2i px = {0, 0, cases[c].width < 24 ? cases[c].width : 24,
                       cases[c].height < 20 ? cases[c].height : 20};
    generated dev = generate(s, px, 0, 0, camera10, 6, 1);
    generated ref = generate(s, px, 0, 0, camera10, 6, 0);
    assert_memory_equal(dev.values, ref.values, dev.count * sizeof(float));
    assert_memory_equal(dev.indices, ref.indices, dev.items * sizeof(uint64_t));
    free_generated(&dev);
    free_generated(&ref);
    clr_sampler_release(s);
  }
}

static void test_bad_input(void **state) {
  (void)state;
  clr_sampler_desc d;
  clr_sampler s = NULL;
  clr_sampler_desc_init(&d, CLR_SAMPLER_HALTON);
  d.pixel_samples = 0;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_SPP);
  assert_non_null(strstr(clr_last_error_message(), "pixelsamples 0"));
  d.pixel_samples = -4;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_SPP);
  clr_sampler_desc_init(&d, CLR_SAMPLER_STRATIFIED);
  d.x_samples = 0;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_SPP);
  clr_sampler_desc_init(&d, CLR_SAMPLER_STRATIFIED);
  d.dimensions = 0;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_DIMENSIONS);
  clr_sampler_desc_init(&d, CLR_SAMPLER_SOBOL);
  d.film.x_resolution = 0;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_RESOLUTION);
  assert_non_null(strstr(clr_last_error_message(), "0x720"));
  d.film.x_resolution = -5;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_RESOLUTION);
  clr_sampler_desc_init(&d, CLR_SAMPLER_SOBOL);
  d.film.filter_radius[0] = -1.0f;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_RADIUS);
  d.type = (clr_sampler_type)17;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_ERROR_INVALID_SAMPLER);
  assert_null(s);
  clr_sampler_type type;
  assert_int_equal(clr_sampler_type_from_name("zeroTwo", &type), CLR_ERROR_INVALID_SAMPLER);
  assert_non_null(strstr(clr_last_error_message(), "zeroTwo"));
  assert_int_equal(clr_sampler_type_from_name("sobol", &type), CLR_SUCCESS);
  assert_int_equal(type, CLR_SAMPLER_SOBOL);

  s = make_sampler(CLR_SAMPLER_SOBOL, CLR_SEEDING_PIXEL, 16);
  float buf[64];
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = buf;
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = (clr_bounds2i){0, 0, 1, 1};
  b.requests = camera10;
  b.request_count = 0;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_REQUESTS);
  clr_sample_request bad_dims[] = {{2, 0}, {3, 0}};
  b.requests = bad_dims;
  b.request_count = 2;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_REQUESTS);
  clr_sample_request no_film[] = {{1, 0}};
  b.requests = no_film;
  b.request_count = 1;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_REQUESTS);
  clr_sample_request huge[] = {{2, 0}, {2, 100000}};
  b.requests = huge;
  b.request_count = 2;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_REQUEST_TOO_LARGE);
  clr_sample_request many[] = {{2, 0}, {2, 2040}, {2, 10}};
  b.requests = many;
  b.request_count = 3;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_REQUEST_TOO_LARGE);
  b.requests = camera10;
  b.request_count = 6;
  b.pixels = (clr_bounds2i){-50, 0, 1, 1};
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_PIXEL_RANGE);
  b.pixels = (clr_bounds2i){3, 3, 3, 4};
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_PIXEL_RANGE);
  b.pixels = (clr_bounds2i){0, 0, 1, 1};
  b.first_sample = 10;
  b.sample_count = 7;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_SPP);
  b.first_sample = 0;
  b.sample_count = 0;
  assert_int_equal(clr_sampler_generate(s, NULL, &out), CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_sampler_generate(NULL, &b, &out), CLR_ERROR_NULL_POINTER);
  out.host_values = NULL;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_NULL_POINTER);
  clr_sampler_release(s);
}

/* Device-resident output: values land in the caller's buffer; too small a buffer is refused. */
static void test_device_buffer_output(void **state) {
  (void)state;
  clr_sampler s = make_sampler(CLR_SAMPLER_HALTON, CLR_SEEDING_PIXEL, 16);
  clr_bounds2i px = {0, 0, 4, 4};
  generated ref = generate(s, px, 0, 0, camera10, 6, 0);
  cl_int err;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_WRITE,
                              ref.count * sizeof(float), NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = px;
  b.requests = camera10;
  b.request_count = 6;
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.device_values = buf;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_SUCCESS);
  float *back = malloc(ref.count * sizeof(float));
  assert_int_equal(clEnqueueReadBuffer(clr_context_cl_queue(ctx), buf, CL_TRUE, 0,
                                       ref.count * sizeof(float), back, 0, NULL, NULL),
                   CL_SUCCESS);
  assert_memory_equal(back, ref.values, ref.count * sizeof(float));
  b.pixels = (clr_bounds2i){0, 0, 8, 8};
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_ARGUMENT);
  free(back);
  clReleaseMemObject(buf);
  free_generated(&ref);
  clr_sampler_release(s);
}

/* Halton launches alternating between layouts (the whole one, prefixes of it, one with arrays,
 * another spp's pixels): each equals the reference, whether its pair tables are built or reused
 * from an earlier launch's. */
static void test_halton_alternating_layouts(void **state) {
  (void)state;
  clr_sampler s = make_sampler(CLR_SAMPLER_HALTON, CLR_SEEDING_PIXEL, 40);
  const struct {
    const clr_sample_request *req;
    int nreq, first, count;
  } launches[] = {{with_arrays, 13, 0, 0}, {with_arrays, 5, 0, 0}, {camera10, 6, 0, 0},
                  {with_arrays, 13, 0, 0}, {with_arrays, 9, 3, 5}, {with_arrays, 5, 0, 0},
                  {with_arrays, 13, 2, 9}, {camera10, 6, 0, 0}};
  for (size_t k = 0; k < sizeof launches / sizeof launches[0]; ++k) {
    clr_bounds2i px = {(int)k, 3, (int)k + 6, 7};
    generated dev =
        generate(s, px, launches[k].first, launches[k].count, launches[k].req, launches[k].nreq, 1);
    generated ref =
        generate(s, px, launches[k].first, launches[k].count, launches[k].req, launches[k].nreq, 0);
    if (memcmp(dev.values, ref.values, dev.count * sizeof(float)) != 0)
      fail_msg("launch %zu: values differ from the reference", k);
    free_generated(&dev);
    free_generated(&ref);
  }
  clr_sampler_release(s);
}

/* Host output (written in place on host-unified devices such as PoCL's): the reference's values
 * at addresses 4, 8 and 64 bytes past an aligned block, the floats around them untouched, and
 * twice into the same memory (a second batch overwrites the first's values in full). */
static void test_host_output_in_place(void **state) {
  (void)state;
  clr_sampler s = make_sampler(CLR_SAMPLER_SOBOL, CLR_SEEDING_PIXEL, 16);
  clr_bounds2i px = {1, 2, 6, 5}, other = {7, 3, 12, 6};
  generated ref = generate(s, px, 0, 0, camera10, 6, 0);
  generated ref_other = generate(s, other, 0, 0, camera10, 6, 0);
  const size_t offsets[] = {1, 2, 16};
  float *block = malloc((ref.count + 32) * sizeof(float));
  assert_non_null(block);
  for (size_t k = 0; k < sizeof offsets / sizeof offsets[0]; ++k) {
    for (size_t i = 0; i < ref.count + 32; ++i) block[i] = -1.0f;
    clr_sample_batch b;
    clr_sample_batch_init(&b);
    b.requests = camera10;
    b.request_count = 6;
    clr_sample_output out;
    clr_sample_output_init(&out);
    out.host_values = block + offsets[k];
    b.pixels = other;
    assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_SUCCESS);
    assert_memory_equal(block + offsets[k], ref_other.values, ref.count * sizeof(float));
    b.pixels = px;
    assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_SUCCESS);
    assert_memory_equal(block + offsets[k], ref.values, ref.count * sizeof(float));
    for (size_t i = 0; i < offsets[k]; ++i) assert_true(block[i] == -1.0f);
    for (size_t i = offsets[k] + ref.count; i < ref.count + 32; ++i) assert_true(block[i] == -1.0f);
  }
  free(block);
  free_generated(&ref);
  free_generated(&ref_other);
  clr_sampler_release(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_device_matches_reference),
      cmocka_unit_test(test_device_matches_reference_with_arrays),
      cmocka_unit_test(test_order_independence),
      cmocka_unit_test(test_stratified_device_strata),
      cmocka_unit_test(test_stratified_strata_counts_match_reference),
      cmocka_unit_test(test_zerotwo_spp_match_reference),
      cmocka_unit_test(test_v4_lanes_match_reference),
      cmocka_unit_test(test_v4_halton_digit_tables_match_reference),
      cmocka_unit_test(test_v4_divisions_match_reference),
      cmocka_unit_test(test_past_available_dimensions),
      cmocka_unit_test(test_large_indices_match_reference),
      cmocka_unit_test(test_sobol_every_index_width_matches_reference),
      cmocka_unit_test(test_halton_pair_tables_match_reference),
      cmocka_unit_test(test_halton_film_scales_match_reference),
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_device_buffer_output),
      cmocka_unit_test(test_host_output_in_place),
      cmocka_unit_test(test_halton_alternating_layouts),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
