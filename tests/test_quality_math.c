/* The bench's quality math (bench/quality_math.c): the integrands' exact integrals against a
 * fine midpoint rule, the log-log slope fit on synthetic data, and the periodogram of point sets
 * whose spectrum is known in closed form. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>
#include "quality_math.h"

/* Midpoint rule on an n x n grid over the unit square. */
static double midpoint(const qm_integrand *q, int n) {
  double sum = 0, h = 1.0 / n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) sum += q->f((i + 0.5) * h, (j + 0.5) * h);
  return sum * h * h;
}

static void integrands_match_midpoint_rule(void **state) {
  (void)state;
  assert_int_equal(qm_integrand_count(), 3);
  /* h = 1/3000; measured: disk 2.4e-6, gaussian 6.2e-9 (O(h^2)), bilinear step 3.5e-8 */
  const double tolerance[3] = {1e-5, 1e-8, 1e-6};
  for (int k = 0; k < qm_integrand_count(); ++k) {
    const qm_integrand *q = qm_integrand_get(k);
    assert_non_null(q);
    double m = midpoint(q, 3000);
    if (fabs(m - q->exact) > tolerance[k])
      fail_msg("%s: exact %.9f, midpoint rule %.9f", q->name, q->exact, m);
  }
  assert_null(qm_integrand_get(-1));
  assert_null(qm_integrand_get(3));
}

static void integrands_have_their_closed_forms(void **state) {
  (void)state;
  /* disk of radius 0.35: pi r^2; bilinear step: (a^2/2 + 2ab/3 + b^2/4) / 2 with a 0.2, b 0.7 */
  assert_true(fabs(qm_integrand_get(0)->exact - 3.14159265358979 * 0.35 * 0.35) < 1e-12);
  assert_true(fabs(qm_integrand_get(2)->exact - 0.5 * (0.02 + 0.28 / 3.0 + 0.1225)) < 1e-12);
  assert_true(qm_integrand_get(1)->exact > 0.2 && qm_integrand_get(1)->exact < 0.26);
}

static void slope_of_power_laws(void **state) {
  (void)state;
  double spp[13], rmse[13];
  for (int i = 0; i < 13; ++i) spp[i] = 1 << i, rmse[i] = 3.0 * pow(spp[i], -0.75);
  assert_true(fabs(qm_loglog_slope(spp, rmse, 13) + 0.75) < 1e-12);
  for (int i = 0; i < 13; ++i) rmse[i] = 0.2 * pow(spp[i], -0.5) * (i % 2 ? 1.1 : 1 / 1.1);
  /* alternating +-log 1.1 around a power law: the fit of a zigzag over an even count is tilted
   * by 12 * log(1.1) * (sum of centred x with sign) / (sum of squared centred x) */
  double s = qm_loglog_slope(spp, rmse, 12), x_mean = 5.5, num = 0, den = 0;
  for (int i = 0; i < 12; ++i)
    num += (i - x_mean) * (i % 2 ? 1 : -1), den += (i - x_mean) * (i - x_mean);
  double expected = -0.5 + log(1.1) / log(2.0) * num / den;
  assert_true(fabs(s - expected) < 1e-12);
}

static void slope_by_hand_and_degenerate_input(void **state) {
  (void)state;
  /* log points (0,0), (1,1), (2,3): slope (3*7 - 3*4) / (3*5 - 3^2) = 1.5 */
  double e = exp(1.0), spp[5] = {1, e, e * e, 0, 4}, rmse[5] = {1, e, e * e * e, 1, -1};
  assert_true(fabs(qm_loglog_slope(spp, rmse, 5) - 1.5) < 1e-12); /* the last two are skipped */
  assert_true(qm_loglog_slope(spp, rmse, 1) == 0.0);
  double same[2] = {4, 4}, r2[2] = {1, 2};
  assert_true(qm_loglog_slope(same, r2, 2) == 0.0); /* no spread in spp */
}

enum { K = 20, SIDE = 2 * K + 1 };

/* An n x n grid of cell centres: the sum of exp(-2 pi i k.x) is n^2 (in modulus) when both
 * components of k are multiples of n and 0 otherwise, so P(k) = n^2 there and 0 elsewhere. */
static void periodogram_of_a_grid(void **state) {
  (void)state;
  int n = 8, count = n * n;
  float xy[2 * 64];
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      xy[2 * (j * n + i)] = (i + 0.5f) / n, xy[2 * (j * n + i) + 1] = (j + 0.5f) / n;
  double *power = calloc(SIDE * SIDE, sizeof(double)), radial[K + 1];
  assert_non_null(power);
  assert_int_equal(qm_periodogram_add(xy, count, K, power), 1);
  for (int ky = -K; ky <= K; ++ky)
    for (int kx = -K; kx <= K; ++kx) {
      double p = power[(ky + K) * SIDE + (kx + K)];
      double want = kx % n == 0 && ky % n == 0 ? count : 0.0;
      if (fabs(p - want) > 1e-9 * count) fail_msg("k = (%d, %d): P %g, want %g", kx, ky, p, want);
    }
  qm_radial_average(power, K, radial);
  assert_true(radial[0] == 0.0);
  /* peaks at |k| = 8 (ring 8), 8 sqrt 2 = 11.3 (ring 11), 16 (ring 16), 17.9 (ring 18) */
  for (int r = 1; r <= K; ++r) {
    int peak = r == 8 || r == 11 || r == 16 || r == 18;
    if (peak ? !(radial[r] > 1) : !(fabs(radial[r]) < 1e-9))
      fail_msg("ring %d: mean power %g", r, radial[r]);
  }
  free(power);
}

/* One point: |exp(-2 pi i k.x)|^2 = 1 at every frequency; adding accumulates. */
static void periodogram_of_one_point_is_flat(void **state) {
  (void)state;
  float xy[2] = {0.3f, 0.71f};
  double *power = calloc(SIDE * SIDE, sizeof(double)), radial[K + 1];
  assert_non_null(power);
  assert_int_equal(qm_periodogram_add(xy, 1, K, power), 1);
  assert_int_equal(qm_periodogram_add(xy, 1, K, power), 1);
  for (int i = 0; i < SIDE * SIDE; ++i) assert_true(fabs(power[i] - 2.0) < 1e-12);
  qm_radial_average(power, K, radial);
  for (int r = 1; r <= K; ++r) assert_true(fabs(radial[r] - 2.0) < 1e-12);
  free(power);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(integrands_match_midpoint_rule),
      cmocka_unit_test(integrands_have_their_closed_forms),
      cmocka_unit_test(slope_of_power_laws),
      cmocka_unit_test(slope_by_hand_and_degenerate_input),
      cmocka_unit_test(periodogram_of_a_grid),
      cmocka_unit_test(periodogram_of_one_point_is_flat),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
