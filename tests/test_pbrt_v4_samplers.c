/* pbrt-v4's samplers (kernels/pbrt_v4_sampler_funcs.h) on the host reference: values pinned from
 * pbrt-v4's own samplers.h (built outside the repository), (0,k,2)-nets of the (0,2) samplers'
 * 2D values per pixel, scrambling that changes values and keeps the nets, stratified's strata,
 * the correctly rounded division, and parameter validation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "pbrt_v4_hash_funcs.h"
#include "pbrt_v4_sampler_funcs.h"

/* GetPixel2D, Get1D, Get2D, Get1D: the layout pinned below. */
static const clr_sample_request layout[] = {{2, 0}, {1, 0}, {2, 0}, {1, 0}};
#define LAYOUT_VALUES 6

typedef struct pinned {
  clr_sampler_type type;
  clr_randomization randomization;
  uint32_t seed;
  int spp, x_samples, y_samples, res_x, res_y;
  int px, py, sample;
  float values[LAYOUT_VALUES];
} pinned;

/* From pbrt-v4 (commit of /work/peers/pbrt-v4 at the time of writing), its samplers.h through a
 * standalone harness: StartPixelSample(p, sample), GetPixel2D, Get1D, Get2D, Get1D. */
static const pinned pins[] = {
    {CLR_SAMPLER_SOBOL,
     CLR_RANDOMIZATION_FASTOWEN,
     0,
     16,
     0,
     0,
     64,
     64,
     0,
     0,
     0,
     {0x0p+0f, 0x0p+0f, 0x1.1492fep-2f, 0x1.0430ccp-2f, 0x1.3ed824p-2f, 0x1.4b6404p-4f}},
    {CLR_SAMPLER_SOBOL,
     CLR_RANDOMIZATION_FASTOWEN,
     0,
     16,
     0,
     0,
     64,
     64,
     3,
     5,
     7,
     {0x1.cep-2f, 0x1.aep-2f, 0x1.1745b2p-1f, 0x1.063b08p-1f, 0x1.4bf6a6p-1f, 0x1.ba5556p-2f}},
    {CLR_SAMPLER_SOBOL,
     CLR_RANDOMIZATION_OWEN,
     7,
     16,
     0,
     0,
     1280,
     720,
     100,
     200,
     3,
     {0x1.006p-2f, 0x1.0aap-2f, 0x1.ff6e8cp-1f, 0x1.4a9eaap-1f, 0x1.459408p-1f, 0x1.2cfb12p-1f}},
    {CLR_SAMPLER_SOBOL,
     CLR_RANDOMIZATION_PERMUTEDIGITS,
     0,
     16,
     0,
     0,
     64,
     64,
     3,
     5,
     7,
     {0x1.cep-2f, 0x1.aep-2f, 0x1.9dd848p-1f, 0x1.84a344p-1f, 0x1.df05dp-1f, 0x1.13f68ap-3f}},
    {CLR_SAMPLER_HALTON,
     CLR_RANDOMIZATION_PERMUTEDIGITS,
     0,
     16,
     0,
     0,
     64,
     64,
     3,
     5,
     7,
     {0x1.0c8p-1f, 0x1.1b0a34p-1f, 0x1.87783cp-2f, 0x1.5cde3p-3f, 0x1.bb65eap-2f, 0x1.f062f8p-2f}},
    {CLR_SAMPLER_HALTON,
     CLR_RANDOMIZATION_OWEN,
     7,
     16,
     0,
     0,
     1280,
     720,
     100,
     200,
     3,
     {0x1.07p-2f, 0x1.b2be5cp-1f, 0x1.6cd83ap-1f, 0x1.2228ccp-2f, 0x1.9eb4f6p-3f, 0x1.98d0bap-1f}},
    {CLR_SAMPLER_HALTON,
     CLR_RANDOMIZATION_NONE,
     0,
     16,
     0,
     0,
     64,
     64,
     3,
     5,
     7,
     {0x1.0c8p-1f, 0x1.1b0a34p-1f, 0x1.ed9096p-1f, 0x1.d3806cp-1f, 0x1.5c6162p-1f, 0x1.d4ba0ep-1f}},
    {CLR_SAMPLER_ZSOBOL,
     CLR_RANDOMIZATION_FASTOWEN,
     0,
     16,
     0,
     0,
     64,
     64,
     3,
     5,
     7,
     {0x1.6d533ap-2f, 0x1.f1ee4cp-4f, 0x1.f24574p-3f, 0x1.c35e96p-2f, 0x1.afdafcp-3f,
      0x1.38f602p-1f}},
    {CLR_SAMPLER_ZSOBOL,
     CLR_RANDOMIZATION_NONE,
     7,
     8,
     0,
     0,
     1280,
     720,
     100,
     200,
     3,
     {0x1.f7208p-2f, 0x1.0f228p-2f, 0x1.20c4d4p-1f, 0x1.7dc64p-1f, 0x1.5dadp-3f, 0x1.b6454p-6f}},
    {CLR_SAMPLER_PADDEDSOBOL,
     CLR_RANDOMIZATION_FASTOWEN,
     0,
     16,
     0,
     0,
     64,
     64,
     3,
     5,
     7,
     {0x1.d8e0a6p-1f, 0x1.110796p-1f, 0x1.295cf4p-3f, 0x1.d8c0d8p-1f, 0x1.0478e2p-2f,
      0x1.dfd01cp-1f}},
    {CLR_SAMPLER_PADDEDSOBOL,
     CLR_RANDOMIZATION_PERMUTEDIGITS,
     7,
     12,
     0,
     0,
     64,
     64,
     3,
     5,
     7,
     {0x1.8fb8fcp-3f, 0x1.f036cep-3f, 0x1.8d4082p-2f, 0x1.2fb1d2p-1f, 0x1.887194p-3f,
      0x1.9e2e3cp-3f}},
    {CLR_SAMPLER_INDEPENDENT,
     CLR_RANDOMIZATION_DEFAULT,
     0,
     4,
     0,
     0,
     64,
     64,
     3,
     5,
     2,
     {0x1.ec8704p-1f, 0x1.bfd4b6p-8f, 0x1.e7a8f2p-2f, 0x1.81d0cp-1f, 0x1.525492p-1f, 0x1.0c71p-1f}},
    {CLR_SAMPLER_RANDOM,
     CLR_RANDOMIZATION_DEFAULT,
     0,
     4,
     0,
     0,
     64,
     64,
     3,
     5,
     2,
     {0x1.ec8704p-1f, 0x1.bfd4b6p-8f, 0x1.e7a8f2p-2f, 0x1.81d0cp-1f, 0x1.525492p-1f, 0x1.0c71p-1f}},
    {CLR_SAMPLER_STRATIFIED,
     CLR_RANDOMIZATION_DEFAULT,
     7,
     12,
     4,
     3,
     64,
     64,
     3,
     5,
     7,
     {0x1.6645dp-2f, 0x1.2c6f8ep-4f, 0x1.ec0456p-2f, 0x1.70e1d8p-1f, 0x1.885e2p-2f,
      0x1.4e1762p-2f}},
};

static clr_sampler make_v4(clr_sampler_type type, clr_randomization r, uint32_t seed, int spp,
                           int res_x, int res_y) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.seeding = CLR_SEEDING_PBRT_V4;
  d.randomization = r;
  d.seed = seed;
  d.pixel_samples = spp;
  d.film.x_resolution = res_x;
  d.film.y_resolution = res_y;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  return s;
}

/* values[s * count + k] for the samples of pixel (px, py) in `requests`. */
static float *pixel_values(clr_sampler s, int px, int py, const clr_sample_request *requests,
                           int count, int *values_per_sample) {
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = (clr_bounds2i){px, py, px + 1, py + 1};
  b.requests = requests;
  b.request_count = count;
  *values_per_sample = 0; /* (pbrt-v4 layouts may start with 1D requests: no strict check) */
  for (int i = 0; i < count; ++i)
    *values_per_sample += requests[i].dims * (requests[i].array_size ? requests[i].array_size : 1);
  float *v = malloc(sizeof(float) * (size_t)clr_sampler_spp(s) * (size_t)*values_per_sample);
  assert_non_null(v);
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = v;
  assert_int_equal(clr_sampler_generate_reference(s, &b, &out), CLR_SUCCESS);
  return v;
}

static void test_pinned_pbrt_v4_values(void **state) {
  (void)state;
  for (size_t i = 0; i < sizeof pins / sizeof pins[0]; ++i) {
    const pinned *p = &pins[i];
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, p->type);
    d.seeding = CLR_SEEDING_PBRT_V4;
    d.randomization = p->randomization;
    d.seed = p->seed;
    d.pixel_samples = p->spp;
    if (p->x_samples) {
      d.x_samples = p->x_samples;
      d.y_samples = p->y_samples;
    }
    d.film.x_resolution = p->res_x;
    d.film.y_resolution = p->res_y;
    clr_sampler s = NULL;
    assert_int_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
    int n = 0;
    float *v = pixel_values(s, p->px, p->py, layout, 4, &n);
    assert_int_equal(n, LAYOUT_VALUES);
    for (int k = 0; k < LAYOUT_VALUES; ++k)
      if (v[p->sample * n + k] != p->values[k])
        fail_msg("pin %zu (%s %s seed %u) value %d: %a, pbrt-v4 %a", i,
                 clr_sampler_type_name(p->type), clr_randomization_name(p->randomization), p->seed,
                 k, v[p->sample * n + k], p->values[k]);
    free(v);
    clr_sampler_release(s);
  }
}

/* pbrt-v4's camera order with its wavelength sample: Get1D, GetPixel2D, Get1D, Get2D (seed 5,
 * 16 spp, 64x64, pixel (3, 5), sample 1), from pbrt-v4. */
static void test_pinned_wavelength_first(void **state) {
  (void)state;
  static const clr_sample_request order[] = {{1, 0}, {2, 0}, {1, 0}, {2, 0}};
  static const struct {
    clr_sampler_type type;
    float values[6];
  } want[] = {
      {CLR_SAMPLER_ZSOBOL,
       {0x1.9f4136p-2f, 0x1.872b46p-1f, 0x1.619128p-1f, 0x1.a00504p-2f, 0x1.6aec3ap-2f,
        0x1.ab9fdap-1f}},
      {CLR_SAMPLER_SOBOL,
       {0x1.04529ap-2f, 0x1.4cp-1f, 0x1.7cp-1f, 0x1.3077d8p-1f, 0x1.9f4412p-1f, 0x1.6f84aep-2f}},
      {CLR_SAMPLER_STRATIFIED,
       {0x1.2d98dep-2f, 0x1.b16fccp-1f, 0x1.9fa3ccp-2f, 0x1.a55dp-1f, 0x1.8866fp-2f,
        0x1.e3f32ap-1f}},
  };
  for (int i = 0; i < 3; ++i) {
    clr_sampler s = make_v4(want[i].type, CLR_RANDOMIZATION_DEFAULT, 5, 16, 64, 64);
    int n = 0;
    float *v = pixel_values(s, 3, 5, order, 4, &n);
    assert_int_equal(n, 6);
    for (int k = 0; k < 6; ++k)
      if (v[n + k] != want[i].values[k])
        fail_msg("%s value %d: %a, pbrt-v4 %a", clr_sampler_type_name(want[i].type), k, v[n + k],
                 want[i].values[k]);
    free(v);
    clr_sampler_release(s);
  }
  /* the strict layout check still wants the film offset first */
  int32_t values = 0;
  assert_int_not_equal(clr_sample_layout_values(order, 4, &values), CLR_SUCCESS);
}

/* Every elementary interval of area 1/n (n = 2^k points) holds exactly one point. */
static int is_02_net(const float *v, int stride, int offset, int n) {
  int k = 0;
  while ((1 << k) < n) ++k;
  for (int a = 0; a <= k; ++a) {
    int cells_x = 1 << a, cells_y = 1 << (k - a);
    int *count = calloc((size_t)n, sizeof(int));
    for (int i = 0; i < n; ++i) {
      int cx = (int)(v[i * stride + offset] * (float)cells_x);
      int cy = (int)(v[i * stride + offset + 1] * (float)cells_y);
      ++count[cy * cells_x + cx];
    }
    int ok = 1;
    for (int c = 0; c < n; ++c) ok &= count[c] == 1;
    free(count);
    if (!ok) return 0;
  }
  return 1;
}

static const clr_sample_request camera[] = {{2, 0}, {1, 0}, {2, 0}, {2, 0}};

static void test_02_nets_per_pixel(void **state) {
  (void)state;
  /* sobol: GetPixel2D; paddedsobol: every 2D value; zsobol: every 2D value (an aligned block of
   * the pixel's Sobol' indices). */
  const clr_sampler_type types[] = {CLR_SAMPLER_SOBOL, CLR_SAMPLER_PADDEDSOBOL, CLR_SAMPLER_ZSOBOL};
  const int pixels[][2] = {{0, 0}, {5, 9}, {37, 20}};
  for (int t = 0; t < 3; ++t)
    for (int r = CLR_RANDOMIZATION_NONE; r <= CLR_RANDOMIZATION_OWEN; ++r)
      for (int spp = 4; spp <= 64; spp *= 2)
        for (int p = 0; p < 3; ++p) {
          clr_sampler s = make_v4(types[t], (clr_randomization)r, 3, spp, 48, 40);
          int n = 0;
          float *v = pixel_values(s, pixels[p][0], pixels[p][1], camera, 4, &n);
          int last = types[t] == CLR_SAMPLER_SOBOL ? 0 : 5;
          for (int offset = 0; offset <= last; offset += offset == 0 ? 3 : 2)
            if (!is_02_net(v, n, offset, spp))
              fail_msg("%s %s spp %d pixel %d: values %d,%d are not a (0,k,2)-net",
                       clr_sampler_type_name(types[t]),
                       clr_randomization_name((clr_randomization)r), spp, p, offset, offset + 1);
          free(v);
          clr_sampler_release(s);
        }
}

static void test_scrambling_changes_values(void **state) {
  (void)state;
  const clr_sampler_type types[] = {CLR_SAMPLER_SOBOL, CLR_SAMPLER_PADDEDSOBOL, CLR_SAMPLER_ZSOBOL,
                                    CLR_SAMPLER_HALTON};
  for (int t = 0; t < 4; ++t) {
    int n = 0;
    clr_sampler plain = make_v4(types[t], CLR_RANDOMIZATION_NONE, 0, 16, 32, 32);
    float *a = pixel_values(plain, 4, 6, camera, 4, &n);
    for (int r = CLR_RANDOMIZATION_PERMUTEDIGITS; r <= CLR_RANDOMIZATION_OWEN; ++r) {
      if (types[t] == CLR_SAMPLER_HALTON && r == CLR_RANDOMIZATION_FASTOWEN) continue;
      clr_sampler s = make_v4(types[t], (clr_randomization)r, 0, 16, 32, 32);
      float *b = pixel_values(s, 4, 6, camera, 4, &n);
      int differ = 0; /* of the values past GetPixel2D */
      for (int i = 0; i < 16; ++i)
        for (int k = 2; k < n; ++k) differ += a[i * n + k] != b[i * n + k];
      if (differ < 16 * (n - 2) / 2)
        fail_msg("%s %s: only %d of %d values differ from unscrambled",
                 clr_sampler_type_name(types[t]), clr_randomization_name((clr_randomization)r),
                 differ, 16 * (n - 2));
      free(b);
      clr_sampler_release(s);
    }
    free(a);
    clr_sampler_release(plain);
  }
}

static void test_seed_changes_values(void **state) {
  (void)state;
  for (int t = 0; t < CLR_SAMPLER_TYPE_COUNT; ++t) {
    if (t == CLR_SAMPLER_ZEROTWO || t == CLR_SAMPLER_MAXMINDIST) continue;
    int n = 0;
    clr_sampler s0 = make_v4((clr_sampler_type)t, CLR_RANDOMIZATION_DEFAULT, 0, 16, 32, 32);
    clr_sampler s1 = make_v4((clr_sampler_type)t, CLR_RANDOMIZATION_DEFAULT, 1, 16, 32, 32);
    float *a = pixel_values(s0, 4, 6, camera, 4, &n);
    float *b = pixel_values(s1, 4, 6, camera, 4, &n);
    int differ = 0;
    for (int i = 0; i < 16 * n; ++i) differ += a[i] != b[i];
    if (differ < 16)
      fail_msg("%s: seed 1 changes only %d values", clr_sampler_type_name((clr_sampler_type)t),
               differ);
    free(a);
    free(b);
    clr_sampler_release(s0);
    clr_sampler_release(s1);
  }
}

/* pmj02bn (pbrt-v4's structure, our point sets): each pixel's GetPixel2D values are a
 * (0,k,2)-net for spp = 4^j, and each Get1D dimension has one value per 1/spp stratum. */
static void test_pmj02bn_nets_and_strata(void **state) {
  (void)state;
  const int pixels[][2] = {{0, 0}, {9, 4}, {300, 257}};
  for (int spp = 1; spp <= 256; spp *= 4)
    for (int p = 0; p < 3; ++p) {
      clr_sampler s = make_v4(CLR_SAMPLER_PMJ02BN, CLR_RANDOMIZATION_DEFAULT, 2, spp, 400, 300);
      int n = 0;
      float *v = pixel_values(s, pixels[p][0], pixels[p][1], camera, 4, &n);
      if (!is_02_net(v, n, 0, spp)) fail_msg("pmj02bn spp %d pixel %d: not a net", spp, p);
      int *seen = calloc((size_t)spp, sizeof(int));
      for (int i = 0; i < spp; ++i) ++seen[(int)(v[i * n + 2] * (float)spp)];
      for (int i = 0; i < spp; ++i) assert_int_equal(seen[i], 1);
      free(seen);
      free(v);
      clr_sampler_release(s);
    }
}

/* pbrt-v4's BlueNoiseSample (lowdiscrepancy.h), which pmj02bn uses for its rotations: values from
 * pbrt-v4's own function. */
static void test_blue_noise_sample(void **state) {
  (void)state;
  assert_true(clr_v4_blue_noise_sample(1, 1, 2) == 0x1.8p-1f);
  assert_true(clr_v4_blue_noise_sample(1, 1, 3) == 0x1p-2f);
  assert_true(clr_v4_blue_noise_sample(200, 77, 9) == 0x1.363p-1f);
  assert_true(clr_v4_blue_noise_sample(5, 300, 1) == 0x1.29ap-1f);
}

/* pbrt-v4's StratifiedSampler: each 1D and 2D dimension has one sample per stratum. */
static void test_stratified_strata(void **state) {
  (void)state;
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, CLR_SAMPLER_STRATIFIED);
  d.seeding = CLR_SEEDING_PBRT_V4;
  d.x_samples = 5;
  d.y_samples = 3;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  int n = 0;
  float *v = pixel_values(s, 7, 2, camera, 4, &n);
  int seen2[3][15] = {{0}}, seen1[15] = {0};
  for (int i = 0; i < 15; ++i) {
    ++seen1[(int)(v[i * n + 2] * 15.0f)];
    for (int k = 0; k < 3; ++k) {
      int off = k == 0 ? 0 : 1 + 2 * k;
      ++seen2[k][(int)(v[i * n + off + 1] * 3.0f) * 5 + (int)(v[i * n + off] * 5.0f)];
    }
  }
  for (int c = 0; c < 15; ++c) {
    assert_int_equal(seen1[c], 1);
    for (int k = 0; k < 3; ++k) assert_int_equal(seen2[k][c], 1);
  }
  free(v);
  clr_sampler_release(s);
}

/* clr_v4_div is IEEE division (the host's a / b) for the quotients the samplers form. */
static void test_correctly_rounded_division(void **state) {
  (void)state;
  uint32_t x = 12345u;
  for (int i = 0; i < 2000000; ++i) {
    x = x * 1664525u + 1013904223u;
    uint32_t b = 1u + (x >> 8) % 65536u;
    float a = (float)(x % 70000u) + (float)(x >> 9) * 0x1p-23f;
    float want = a / (float)b;
    float got = clr_v4_div(a, b);
    if (got != want) fail_msg("%a / %u: %a, IEEE %a", a, b, got, want);
  }
  assert_true(clr_v4_div(0.0f, 7u) == 0.0f);
  assert_true(clr_v4_div(1.0f, 3u) == 1.0f / 3.0f);
}

static void test_names_and_validation(void **state) {
  (void)state;
  for (int t = 0; t < CLR_SAMPLER_TYPE_COUNT; ++t) {
    clr_sampler_type back;
    assert_int_equal(clr_sampler_type_from_name(clr_sampler_type_name((clr_sampler_type)t), &back),
                     CLR_SUCCESS);
    assert_int_equal((int)back, t);
  }
  clr_randomization r;
  assert_int_equal(clr_randomization_from_name("owen", &r), CLR_SUCCESS);
  assert_int_equal(r, CLR_RANDOMIZATION_OWEN);
  assert_int_not_equal(clr_randomization_from_name("fast-owen", &r), CLR_SUCCESS);
  assert_non_null(strstr(clr_last_error_message(), "fast-owen"));
  clr_sampler_desc d;
  clr_sampler s = NULL;
  clr_sampler_desc_init(&d, CLR_SAMPLER_HALTON);
  d.seeding = CLR_SEEDING_PBRT_V4;
  d.randomization = CLR_RANDOMIZATION_FASTOWEN;
  assert_int_not_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  assert_non_null(strstr(clr_last_error_message(), "fastowen"));
  clr_sampler_desc_init(&d, CLR_SAMPLER_ZEROTWO);
  d.seeding = CLR_SEEDING_PBRT_V4;
  assert_int_not_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  assert_non_null(strstr(clr_last_error_message(), "not a pbrt-v4 sampler"));
  clr_sampler_desc_init(&d, CLR_SAMPLER_STRATIFIED);
  d.seeding = CLR_SEEDING_PBRT_V4;
  d.randomization = CLR_RANDOMIZATION_OWEN;
  assert_int_not_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  assert_non_null(strstr(clr_last_error_message(), "randomization"));
  clr_sampler_desc_init(&d, CLR_SAMPLER_ZSOBOL);
  d.pixel_samples = 1 << 20;
  d.film.x_resolution = d.film.y_resolution = 1 << 20;
  assert_int_not_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  assert_null(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pinned_pbrt_v4_values),
      cmocka_unit_test(test_pinned_wavelength_first),
      cmocka_unit_test(test_02_nets_per_pixel),
      cmocka_unit_test(test_scrambling_changes_values),
      cmocka_unit_test(test_seed_changes_values),
      cmocka_unit_test(test_stratified_strata),
      cmocka_unit_test(test_pmj02bn_nets_and_strata),
      cmocka_unit_test(test_blue_noise_sample),
      cmocka_unit_test(test_correctly_rounded_division),
      cmocka_unit_test(test_names_and_validation),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
