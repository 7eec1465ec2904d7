/* The renderer's inline fmaxf and fminf (host/render/float_minmax.h): the larger (smaller)
 * operand, the second when they compare equal (so -0 and +0 give the second), the other operand
 * when one is NaN; and on x86-64 glibc the bits of libm's fmaxf and fminf for every pair. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>
#include "float_minmax.h"

static uint32_t bits(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  return u;
}

/* Volatile, so that the compiler cannot fold libm's calls with its own rules. */
static volatile float values[] = {-INFINITY, -2.0f,    -0.0f, 0.0f, 1e-45f,  1.0f, 2.0f,
                                  3.0e38f,   INFINITY, NAN,   -NAN, -1e-45f, 0.5f, -3.0e38f};
enum { COUNT = sizeof values / sizeof values[0] };

static void test_rules(void **state) {
  (void)state;
  assert_true(rs_fmaxf(1.0f, 2.0f) == 2.0f && rs_fmaxf(2.0f, 1.0f) == 2.0f);
  assert_true(rs_fminf(1.0f, 2.0f) == 1.0f && rs_fminf(2.0f, 1.0f) == 1.0f);
  assert_int_equal(bits(rs_fmaxf(-0.0f, 0.0f)), bits(0.0f));
  assert_int_equal(bits(rs_fmaxf(0.0f, -0.0f)), bits(-0.0f));
  assert_int_equal(bits(rs_fminf(0.0f, -0.0f)), bits(-0.0f));
  assert_int_equal(bits(rs_fminf(-0.0f, 0.0f)), bits(0.0f));
  assert_true(rs_fmaxf(values[9], 3.0f) == 3.0f && rs_fmaxf(3.0f, values[9]) == 3.0f);
  assert_true(rs_fminf(values[9], -3.0f) == -3.0f && rs_fminf(-3.0f, values[9]) == -3.0f);
  assert_true(isnan(rs_fmaxf(values[9], values[10])) && isnan(rs_fminf(values[10], values[9])));
  assert_true(rs_fmaxf(-INFINITY, -3.0e38f) == -3.0e38f && rs_fminf(INFINITY, 3.0e38f) == 3.0e38f);
}

static void test_libm_bits(void **state) {
  (void)state;
#if defined(__x86_64__) && defined(__GLIBC__)
  for (int i = 0; i < COUNT; ++i)
    for (int j = 0; j < COUNT; ++j) {
      float x = values[i], y = values[j];
      if (bits(rs_fmaxf(x, y)) != bits(fmaxf(x, y)) || bits(rs_fminf(x, y)) != bits(fminf(x, y)))
        fail_msg("pair %d, %d: max %08x against libm %08x, min %08x against %08x", i, j,
                 bits(rs_fmaxf(x, y)), bits(fmaxf(x, y)), bits(rs_fminf(x, y)), bits(fminf(x, y)));
    }
#else
  skip(); /* the rules above still hold; libm's choice among equal zeros may differ */
#endif
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rules),
      cmocka_unit_test(test_libm_bits),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
