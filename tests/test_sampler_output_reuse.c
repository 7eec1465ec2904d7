/* A device sampler keeps its host-output value buffer between calls: batches that shrink, grow
 * and repeat on one sampler each equal the host reference bit for bit (halton, sobol and a pixel
 * sampler), and a larger batch after a smaller one is whole. */
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

static const clr_sample_request layout[] = {{2, 0}, {1, 0}, {2, 0}, {2, 0}}; /* 7 values */

static void check_batch(clr_sampler s, clr_bounds2i px, int first, int count) {
  clr_sample_batch b = sample_batch(px, first, count, layout, 4);
  size_t n = (size_t)(px.x1 - px.x0) * (size_t)(px.y1 - px.y0) * (size_t)count * 7;
  float *dev = malloc(n * sizeof *dev), *ref = malloc(n * sizeof *ref);
  assert_non_null(dev);
  assert_non_null(ref);
  for (size_t i = 0; i < n; ++i) dev[i] = -1.0f; /* every value must be overwritten */
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = dev;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_SUCCESS);
  out.host_values = ref;
  assert_int_equal(clr_sampler_generate_reference(s, &b, &out), CLR_SUCCESS);
  assert_memory_equal(dev, ref, n * sizeof *dev);
  for (size_t i = 0; i < n; ++i) assert_true(dev[i] >= 0.0f && dev[i] < 1.0f);
  free(dev);
  free(ref);
}

static void check_sampler(clr_sampler_type type) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.pixel_samples = 16;
  d.film.x_resolution = d.film.y_resolution = 48;
  d.film.filter_radius[0] = d.film.filter_radius[1] = 0.5f;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
  check_batch(s, (clr_bounds2i){0, 0, 16, 16}, 0, 16);  /* first: the buffer is made */
  check_batch(s, (clr_bounds2i){5, 7, 9, 10}, 3, 5);    /* smaller: reused */
  check_batch(s, (clr_bounds2i){16, 0, 32, 16}, 0, 16); /* the same size again */
  check_batch(s, (clr_bounds2i){0, 0, 48, 48}, 0, 16);  /* larger: grown */
  check_batch(s, (clr_bounds2i){40, 40, 41, 41}, 15, 1);
  clr_sampler_release(s);
}

static void test_reused_output_buffer(void **state) {
  (void)state;
  check_sampler(CLR_SAMPLER_HALTON);
  check_sampler(CLR_SAMPLER_SOBOL);
  check_sampler(CLR_SAMPLER_STRATIFIED);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_reused_output_buffer)};
  return cmocka_run_group_tests(tests, setup, teardown);
}
