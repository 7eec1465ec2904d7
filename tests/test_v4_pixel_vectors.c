/* The per-pixel walk of zsobol, paddedsobol and pmj02bn (clr_v4_pixel_vectors, the device's
 * clr_v4_generate_pixels) gives the per-item reference's values bit for bit (clr_v4_sample_vector)
 * for power-of-two and other spp, odd log2 spp, batches starting past sample 0, arrays and 1D
 * values before the film offset; and pmj02bn's point-set table holds clr_pmj02_point. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "pbrt_v4_sampler_funcs.h"
#include "pmj02_tables.h"
#include "sobol_tables.h"

#define MAX_SLOTS 8

/* A layout: dims and array size per request; film: the GetPixel2D request. */
typedef struct layout {
  int count, film;
  int dims[MAX_SLOTS], arrays[MAX_SLOTS];
} layout;

static const layout layouts[] = {
    {6, 0, {2, 1, 2, 1, 2, 2}, {0, 0, 0, 0, 0, 0}},            /* the bench's camera-like layout */
    {4, 1, {1, 2, 1, 2}, {0, 0, 0, 0}},                        /* pbrt-v4's wavelength first */
    {5, 0, {2, 1, 2, 1, 2}, {0, 3, 0, 0, 5}},                  /* arrays */
    {8, 0, {2, 2, 2, 2, 2, 2, 2, 1}, {0, 0, 0, 0, 0, 0, 0, 9}} /* past pmj02bn's 5 point sets */
};

static int fill_slots(const layout *l, clr_request_slot *slots) {
  int at = 0;
  for (int r = 0; r < l->count; ++r) {
    memset(&slots[r], 0, sizeof slots[r]);
    slots[r].dims = l->dims[r];
    slots[r].array_size = l->arrays[r];
    slots[r].first_value = at;
    at += l->dims[r] * (l->arrays[r] ? l->arrays[r] : 1);
  }
  return at;
}

static int log2_int(int v) {
  int l = 0;
  while ((v >> (l + 1)) > 0) ++l;
  return l;
}

/* Compares every value of a w x h batch at (x0, y0), samples [first, first + count). */
static void compare(clr_sampler_params *p, const clr_v4_tables *t, const layout *l) {
  clr_request_slot slots[MAX_SLOTS];
  p->values_per_sample = fill_slots(l, slots);
  p->request_count = l->count;
  p->film_request = l->film;
  size_t items = (size_t)p->batch_width * (size_t)p->batch_height * (size_t)p->sample_count;
  size_t values = items * (size_t)p->values_per_sample;
  float *want = malloc(values * sizeof(float)), *got = malloc(values * sizeof(float));
  assert_non_null(want);
  assert_non_null(got);
  for (size_t i = 0; i < items; ++i)
    clr_v4_sample_vector(p, slots, t, (clr_i32)i, want + i * (size_t)p->values_per_sample);
  size_t per_pixel = (size_t)p->sample_count * (size_t)p->values_per_sample;
  for (int pixel = 0; pixel < p->batch_width * p->batch_height; ++pixel)
    clr_v4_pixel_vectors(p, slots, t, pixel, got + (size_t)pixel * per_pixel);
  for (size_t i = 0; i < values; ++i)
    if (memcmp(&want[i], &got[i], sizeof(float)) != 0)
      fail_msg("sampler %d spp %d randomization %d first %d: value %zu is %a, reference %a",
               p->v4_sampler, p->spp, p->randomization, p->first_sample, i, (double)got[i],
               (double)want[i]);
  free(want);
  free(got);
}

static void batch(clr_sampler_params *p, int x0, int y0, int first, int count) {
  p->batch_x0 = x0;
  p->batch_y0 = y0;
  p->batch_width = 5;
  p->batch_height = 3;
  p->first_sample = first;
  p->sample_count = count;
}

/* zsobol (v4 CLR_V4_ZSOBOL) or paddedsobol: every spp, randomization and layout. */
static void sobol_pixel_walk(int v4) {
  static const int spps[] = {1, 2, 4, 8, 16, 32};
  static const int randomizations[] = {CLR_RANDOMIZE_TYPE_NONE, CLR_RANDOMIZE_TYPE_PERMUTEDIGITS,
                                       CLR_RANDOMIZE_TYPE_FASTOWEN, CLR_RANDOMIZE_TYPE_OWEN};
  clr_v4_tables t = {clr_sobol_matrices32, NULL, NULL, NULL, NULL, NULL, NULL, NULL, 0, NULL};
  for (size_t s = 0; s < sizeof spps / sizeof spps[0]; ++s)
    for (size_t r = 0; r < sizeof randomizations / sizeof randomizations[0]; ++r)
      for (size_t l = 0; l < sizeof layouts / sizeof layouts[0]; ++l) {
        clr_sampler_params p;
        memset(&p, 0, sizeof p);
        p.v4_sampler = v4;
        p.spp = spps[s] + (v4 == CLR_V4_PADDEDSOBOL && spps[s] > 4 ? 3 : 0);
        p.seed = 7u * (uint32_t)r;
        p.randomization = randomizations[r];
        p.zsobol_log2_spp = log2_int(p.spp);
        p.zsobol_base4_digits = 9 + (p.zsobol_log2_spp + 1) / 2; /* 512 x 512 film */
        batch(&p, 61, 250, 0, p.spp);
        compare(&p, &t, &layouts[l]);
        if (p.spp > 2) {
          batch(&p, 500, 3, p.spp / 2 - 1, p.spp / 2);
          compare(&p, &t, &layouts[l]);
        }
      }
}

static void test_zsobol_pixel_walk(void **state) {
  (void)state;
  sobol_pixel_walk(CLR_V4_ZSOBOL);
}

static void test_paddedsobol_pixel_walk(void **state) {
  (void)state;
  sobol_pixel_walk(CLR_V4_PADDEDSOBOL);
}

static void test_pmj02bn_pixel_walk(void **state) {
  (void)state;
  static const int spps[] = {1, 5, 16, 64};
  for (size_t s = 0; s < sizeof spps / sizeof spps[0]; ++s) {
    clr_sampler_params p;
    memset(&p, 0, sizeof p);
    p.v4_sampler = CLR_V4_PMJ02BN;
    p.spp = spps[s];
    p.seed = 3u;
    p.pmj_tile = clr_pmj02_tile_size(p.spp);
    float *table = clr_pmj02_pixel_table(p.spp, p.pmj_tile);
    assert_non_null(table);
    clr_v4_tables t = {clr_sobol_matrices32,
                       NULL,
                       NULL,
                       NULL,
                       table,
                       table + clr_v4_pmj02_pixel_floats(&p),
                       NULL,
                       NULL,
                       0,
                       NULL};
    for (int set = 0; set < CLR_PMJ02_SETS; ++set)
      for (int i = 0; i < p.spp; ++i)
        for (int c = 0; c < 2; ++c)
          assert_true(clr_v4_pmj02_set_point(&p, &t, set, (uint32_t)i, c) ==
                      (float)clr_pmj02_point(set, (uint32_t)i, c, clr_sobol_matrices32) * 0x1p-32f);
    for (size_t l = 0; l < sizeof layouts / sizeof layouts[0]; ++l) {
      batch(&p, 126, 37, 0, p.spp);
      compare(&p, &t, &layouts[l]);
      if (p.spp > 2) {
        batch(&p, 3, 511, 1, p.spp - 2);
        compare(&p, &t, &layouts[l]);
      }
    }
    free(table);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_zsobol_pixel_walk),
      cmocka_unit_test(test_paddedsobol_pixel_walk),
      cmocka_unit_test(test_pmj02bn_pixel_walk),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
