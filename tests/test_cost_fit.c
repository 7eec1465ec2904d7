/* The lazy-sample chooser's generated-value cost (host/render/cost_fit.h): the slope of a
 * least-squares line through (values, seconds) observations, so that a fixed cost per call is
 * not counted as the values' cost; the average where the slope cannot be trusted. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include "cost_fit.h"

/* |a - b| <= tol, printing both when not. */
static void near(double a, double b, double tol) {
  if (!(fabs(a - b) <= tol)) print_error("%.17g is not %.17g within %g\n", a, b, tol);
  assert_true(fabs(a - b) <= tol);
}

/* Bands of 0.9 M and 0.6 M values at 3 ns each after a fixed 0.7 ms per call. */
static void test_slope_without_fixed_cost(void **state) {
  (void)state;
  clr_cost_fit f = {0};
  const double units[6] = {933888, 933888, 622592, 221184, 933888, 622592};
  for (int i = 0; i < 6; ++i) clr_cost_fit_add(&f, units[i], 0.7e-3 + 3e-9 * units[i]);
  near(clr_cost_fit_per_unit(&f), 3e-9, 1e-15);
  /* the average counts the fixed cost: about 4 ns here */
  assert_true(f.seconds / f.units > 3.9e-9);
}

/* Noisy observations around a line: the slope is recovered within the noise. */
static void test_slope_with_noise(void **state) {
  (void)state;
  clr_cost_fit f = {0};
  uint32_t s = 12345u;
  for (int i = 0; i < 400; ++i) {
    s = s * 1664525u + 1013904223u;
    double units = 2e5 + (double)(s >> 12) / 1048576.0 * 8e5; /* 0.2 M .. 1 M */
    s = s * 1664525u + 1013904223u;
    double noise = ((double)(s >> 8) / 16777216.0 - 0.5) * 1e-3; /* +-0.5 ms */
    clr_cost_fit_add(&f, units, 0.5e-3 + 5e-9 * units + noise);
  }
  near(clr_cost_fit_per_unit(&f), 5e-9, 0.3e-9);
}

/* Without spread in the units (every band the same size) the slope is unknown: the average. */
static void test_same_units_give_the_average(void **state) {
  (void)state;
  clr_cost_fit f = {0};
  for (int i = 0; i < 5; ++i) clr_cost_fit_add(&f, 1e6, 2e-3 + 1e-4 * i);
  near(clr_cost_fit_per_unit(&f), 2.2e-3 / 1e6, 1e-18);
  clr_cost_fit g = {0}; /* a spread of 0.5 %, whose slope (1 ns, half the average) is not used */
  for (int i = 0; i < 4; ++i) {
    double units = 1e6 * (1.0 + 0.005 * (i & 1));
    clr_cost_fit_add(&g, units, 1e-3 + 1e-9 * units);
  }
  near(clr_cost_fit_per_unit(&g), g.seconds / g.units, 1e-18);
}

/* Fewer than 3 observations: the average; none: 0. */
static void test_few_observations(void **state) {
  (void)state;
  clr_cost_fit f = {0};
  assert_true(clr_cost_fit_per_unit(&f) == 0.0);
  clr_cost_fit_add(&f, 1e5, 1e-3);
  clr_cost_fit_add(&f, 9e5, 2e-3);
  near(clr_cost_fit_per_unit(&f), 3e-3 / 1e6, 1e-18);
}

/* A slope below a tenth of the average (negative here: the larger band took less time) is
 * raised to that tenth; a slope above the average (a negative fixed cost) is the average. */
static void test_slope_bounds(void **state) {
  (void)state;
  clr_cost_fit f = {0};
  clr_cost_fit_add(&f, 1e5, 3e-3);
  clr_cost_fit_add(&f, 5e5, 2e-3);
  clr_cost_fit_add(&f, 9e5, 1e-3);
  near(clr_cost_fit_per_unit(&f), 0.1 * 6e-3 / 1.5e6, 1e-18);
  clr_cost_fit h = {0}; /* a positive slope, 0.5 ns, below a tenth of the 5.5 ns average */
  for (int i = 1; i <= 3; ++i) clr_cost_fit_add(&h, 1e5 * i, 1e-3 + 0.5e-9 * 1e5 * i);
  near(clr_cost_fit_per_unit(&h), 0.1 * h.seconds / h.units, 1e-18);
  clr_cost_fit g = {0};
  for (int i = 1; i <= 3; ++i) clr_cost_fit_add(&g, 1e5 * i, -1e-4 + 2e-9 * 1e5 * i);
  near(clr_cost_fit_per_unit(&g), g.seconds / g.units, 1e-18);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_slope_without_fixed_cost),
      cmocka_unit_test(test_slope_with_noise),
      cmocka_unit_test(test_same_units_give_the_average),
      cmocka_unit_test(test_few_observations),
      cmocka_unit_test(test_slope_bounds),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
