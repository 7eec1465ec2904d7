/* Reconstruction filters: support, symmetry, integrals, pbrt-v3's table, portable math, device
 * bits. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "clrender/filter.h"
#include "filter_funcs.h"
#include "filter_internal.h"

#define ALL_TYPES CLR_FILTER_TYPE_COUNT
#define PI 3.14159265358979323846
#define BH_EDGE (0.35875 - 0.48829 + 0.14128 - 0.01168)

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double uniform(void) { /* xorshift64*, [0,1) */
  rng_state ^= rng_state >> 12;
  rng_state ^= rng_state << 25;
  rng_state ^= rng_state >> 27;
  return (double)((rng_state * 0x2545f4914f6cdd1dull) >> 11) * 0x1p-53;
}

static clr_filter_params make_params(clr_filter_type type, float rx, float ry, int use_table) {
  clr_filter_desc d;
  clr_filter_desc_init(&d, type);
  if (rx > 0) d.radius[0] = rx;
  if (ry > 0) d.radius[1] = ry;
  d.use_table = use_table;
  clr_filter_params p;
  assert_int_equal(clr_filter_params_make(&d, &p), CLR_SUCCESS);
  return p;
}

/* ---- double-precision references written from the published formulas ---- */

static double ref_sinc(double x) {
  x = fabs(x);
  return x < 1e-5 ? 1.0 : sin(PI * x) / (PI * x);
}

static double ref_mitchell(double x, double b, double c) { /* pbrt-v3 Mitchell1D, x in [-1,1] */
  double t = fabs(2 * x);
  if (t > 1)
    return ((-b - 6 * c) * t * t * t + (6 * b + 30 * c) * t * t + (-12 * b - 48 * c) * t +
            (8 * b + 24 * c)) /
           6;
  return ((12 - 9 * b - 6 * c) * t * t * t + (-18 + 12 * b + 6 * c) * t * t + (6 - 2 * b)) / 6;
}

static double ref_blackman_harris(double u) { /* LuxCore's BlackmanHarris1D, u = x / width */
  if (u < -1 || u > 1) return 0;
  double v = (u + 1) * 0.5 * PI;
  return 0.35875 - 0.48829 * cos(2 * v) + 0.14128 * cos(4 * v) - 0.01168 * cos(6 * v);
}

static double ref_1d(const clr_filter_params *p, double x, double r) {
  double a = fabs(x);
  if (a > r) return 0;
  switch (p->type) {
    case CLR_FILTER_TYPE_BOX:
      return 1;
    case CLR_FILTER_TYPE_TRIANGLE:
      return fmax(0, r - a);
    case CLR_FILTER_TYPE_GAUSSIAN:
      return fmax(0, exp(-(double)p->alpha * a * a) - exp(-(double)p->alpha * r * r));
    case CLR_FILTER_TYPE_MITCHELL:
      return ref_mitchell(a / r, p->b, p->c);
    case CLR_FILTER_TYPE_SINC:
      return ref_sinc(a) * ref_sinc(a / p->tau);
    case CLR_FILTER_TYPE_BLACKMANHARRIS:
      return ref_blackman_harris(a / r);
    case CLR_FILTER_TYPE_CATMULLROM:
      return ref_mitchell(a / r, 0.0, 0.5);
    default:
      return NAN;
  }
}

static double ref_2d(const clr_filter_params *p, double x, double y) {
  return ref_1d(p, x, p->radius_x) * ref_1d(p, y, p->radius_y);
}

/* Closed-form integral over [-r, r] of one factor, NAN where there is none (sinc). */
static double closed_form_1d(const clr_filter_params *p, double r) {
  switch (p->type) {
    case CLR_FILTER_TYPE_BOX:
      return 2 * r;
    case CLR_FILTER_TYPE_TRIANGLE:
      return r * r;
    case CLR_FILTER_TYPE_GAUSSIAN: {
      double al = p->alpha;
      return sqrt(PI / al) * erf(r * sqrt(al)) - 2 * r * exp(-al * r * r);
    }
    case CLR_FILTER_TYPE_MITCHELL:
    case CLR_FILTER_TYPE_CATMULLROM:
      return r / 2; /* the Mitchell kernel integrates to 1 over t */
    case CLR_FILTER_TYPE_BLACKMANHARRIS:
      return 2 * r * 0.35875;
    default:
      return NAN;
  }
}

/* ---- Gauss-Legendre integration over [-r, r] in 32 panels (panel ends at multiples of r/16) ----
 */

static const double gl_node[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                  0.9061798459386640};
static const double gl_weight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                    0.4786286704993665, 0.2369268850561891};
#define GL_PANELS 32
#define GL_POINTS (GL_PANELS * 5)

static void gl_rule(double r, double *x, double *w) {
  double h = 2 * r / GL_PANELS;
  for (int i = 0; i < GL_PANELS; ++i)
    for (int k = 0; k < 5; ++k) {
      x[i * 5 + k] = -r + h * (i + 0.5) + 0.5 * h * gl_node[k];
      w[i * 5 + k] = 0.5 * h * gl_weight[k];
    }
}

static double integral_float_2d(const clr_filter_params *p) {
  static double xs[GL_POINTS], wx[GL_POINTS], ys[GL_POINTS], wy[GL_POINTS];
  gl_rule(p->radius_x, xs, wx);
  gl_rule(p->radius_y, ys, wy);
  double sum = 0;
  for (int j = 0; j < GL_POINTS; ++j)
    for (int i = 0; i < GL_POINTS; ++i)
      sum += wx[i] * wy[j] * clr_filter_eval_exact(p, (float)xs[i], (float)ys[j]);
  return sum;
}

static double integral_ref_1d(const clr_filter_params *p, double r) {
  double xs[GL_POINTS], w[GL_POINTS], sum = 0;
  gl_rule(r, xs, w);
  for (int i = 0; i < GL_POINTS; ++i) sum += w[i] * ref_1d(p, xs[i], r);
  return sum;
}

/* ---- tests ---- */

static void test_defaults_and_names(void **state) {
  (void)state;
  static const float radius[ALL_TYPES] = {0.5f, 2, 2, 2, 4, 2, 2};
  static const char *names[ALL_TYPES] = {"box",  "triangle",       "gaussian",  "mitchell",
                                         "sinc", "blackmanharris", "catmullrom"};
  for (int t = 0; t < ALL_TYPES; ++t) {
    clr_filter_desc d;
    clr_filter_desc_init(&d, (clr_filter_type)t);
    assert_int_equal(d.struct_size, sizeof d);
    assert_true(d.radius[0] == radius[t] && d.radius[1] == radius[t]);
    assert_true(d.alpha == 2.0f && d.tau == 3.0f);
    assert_int_equal(d.use_table, 0);
    assert_string_equal(clr_filter_type_name((clr_filter_type)t), names[t]);
    clr_filter_type parsed = CLR_FILTER_BOX;
    assert_int_equal(clr_filter_type_from_name(names[t], &parsed), CLR_SUCCESS);
    assert_int_equal(parsed, t);
  }
  clr_filter_desc d;
  clr_filter_desc_init(&d, CLR_FILTER_MITCHELL);
  assert_true(d.b == 1.0f / 3.0f && d.c == 1.0f / 3.0f);
  clr_filter_params p = make_params(CLR_FILTER_CATMULLROM, 0, 0, 0);
  assert_true(p.b == 0.0f && p.c == 0.5f);
  p = make_params(CLR_FILTER_GAUSSIAN, 0, 0, 0);
  assert_true(fabs(p.exp_x - exp(-8.0)) < 2.4e-7 * exp(-8.0) && p.exp_x == p.exp_y);
  assert_string_equal(clr_filter_type_name((clr_filter_type)99), "unknown");
  clr_filter_type parsed;
  assert_int_equal(clr_filter_type_from_name("lanczos", &parsed), CLR_ERROR_INVALID_FILTER);
  assert_non_null(strstr(clr_last_error_message(), "\"lanczos\""));
  assert_int_equal(clr_filter_type_from_name("Box", &parsed), CLR_ERROR_INVALID_FILTER);
  assert_int_equal(clr_filter_type_from_name(NULL, &parsed), CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_filter_type_from_name("box", NULL), CLR_ERROR_NULL_POINTER);
  assert_int_equal(sizeof(clr_filter_params) % 16, 0);
}

/* One factor's value at |x| = r by its formula: box 1, Blackman-Harris LuxCore's 6e-5, the others
 * 0 (the sinc at integer radii). */
static double edge_1d(const clr_filter_params *p) {
  switch (p->type) {
    case CLR_FILTER_TYPE_BOX:
      return 1;
    case CLR_FILTER_TYPE_BLACKMANHARRIS:
      return BH_EDGE;
    default:
      return 0;
  }
}

static void check_support(const clr_filter_params *p, const float *table) {
  float rx = p->radius_x, ry = p->radius_y;
  float out_x = nextafterf(rx, INFINITY), out_y = nextafterf(ry, INFINITY);
  float probes[][2] = {{out_x, 0},         {-out_x, 0},          {0, out_y},  {0, -out_y},
                       {out_x, out_y},     {-out_x, -out_y},     {2 * rx, 0}, {0, 3 * ry},
                       {2 * rx, 2 * ry},   {-4 * rx, 0.1f * ry}, {1e30f, 0},  {0, -1e30f},
                       {INFINITY, 0},      {0, -INFINITY},       {NAN, 0},    {0, NAN},
                       {rx * 0.5f, out_y}, {out_x, ry * 0.25f}};
  for (size_t i = 0; i < sizeof probes / sizeof probes[0]; ++i) {
    float v = clr_filter_params_evaluate(p, table, probes[i][0], probes[i][1]);
    if (v != 0.0f || signbit(v))
      fail_msg("%s (table %d): f(%g, %g) = %g, expected +0", clr_filter_type_name(p->type),
               p->use_table, probes[i][0], probes[i][1], v);
  }
  if (!p->use_table) { /* the support is closed; the value on its edge is the formula's */
    double expect_x = edge_1d(p) * ref_1d(p, 0, ry), expect_y = edge_1d(p) * ref_1d(p, 0, rx);
    float vx = clr_filter_params_evaluate(p, NULL, rx, 0),
          vy = clr_filter_params_evaluate(p, NULL, 0, ry);
    if (fabs(vx - expect_x) > 1e-7 || (expect_x == 0 && vx != 0))
      fail_msg("%s: f(r, 0) = %g, expected %g", clr_filter_type_name(p->type), vx, expect_x);
    if (fabs(vy - expect_y) > 1e-7 || (expect_y == 0 && vy != 0))
      fail_msg("%s: f(0, r) = %g, expected %g", clr_filter_type_name(p->type), vy, expect_y);
    assert_true(clr_filter_params_evaluate(p, NULL, -rx, 0) == vx);
    assert_true(clr_filter_params_evaluate(p, NULL, 0, -ry) == vy);
  }
}

static void test_zero_outside_support(void **state) {
  (void)state;
  float table[CLR_FILTER_TABLE_ENTRIES];
  for (int t = 0; t < ALL_TYPES; ++t)
    for (int use_table = 0; use_table < 2; ++use_table) {
      clr_filter_params p = make_params((clr_filter_type)t, 0, 0, use_table);
      assert_int_equal(clr_filter_params_table(&p, table), CLR_SUCCESS);
      check_support(&p, use_table ? table : NULL);
      if (use_table) check_support(&p, NULL); /* entries computed on the fly */
      /* Integer radii other than the defaults keep the sinc's edge zero. */
      clr_filter_params q = make_params((clr_filter_type)t, 3.0f, 3.0f, use_table);
      assert_int_equal(clr_filter_params_table(&q, table), CLR_SUCCESS);
      check_support(&q, table);
    }
}

static void test_symmetry(void **state) {
  (void)state;
  float table[CLR_FILTER_TABLE_ENTRIES];
  for (int t = 0; t < ALL_TYPES; ++t)
    for (int use_table = 0; use_table < 2; ++use_table) {
      clr_filter_params p = make_params((clr_filter_type)t, 1.5f, 2.5f, use_table);
      assert_int_equal(clr_filter_params_table(&p, table), CLR_SUCCESS);
      for (int i = 0; i < 4000; ++i) {
        float x = (float)((uniform() * 2 - 1) * 1.1 * p.radius_x);
        float y = (float)((uniform() * 2 - 1) * 1.1 * p.radius_y);
        float v = clr_filter_params_evaluate(&p, table, x, y);
        assert_true(clr_filter_params_evaluate(&p, table, -x, y) == v);
        assert_true(clr_filter_params_evaluate(&p, table, x, -y) == v);
        assert_true(clr_filter_params_evaluate(&p, table, -x, -y) == v);
      }
    }
}

/* The float implementation follows the published formulas at every point of the support. */
static void test_exact_matches_formulas(void **state) {
  (void)state;
  float radii[][2] = {{0, 0}, {1.5f, 2.5f}, {0.75f, 3.0f}};
  for (int t = 0; t < ALL_TYPES; ++t)
    for (size_t k = 0; k < sizeof radii / sizeof radii[0]; ++k) {
      clr_filter_params p = make_params((clr_filter_type)t, radii[k][0], radii[k][1], 0);
      double peak = ref_2d(&p, 0, 0);
      double scale = t == CLR_FILTER_TYPE_TRIANGLE ? peak : fmax(1.0, peak);
      double worst = 0;
      for (int i = 0; i < 20000; ++i) {
        float x = (float)((uniform() * 2 - 1) * p.radius_x);
        float y = (float)((uniform() * 2 - 1) * p.radius_y);
        double err = fabs(clr_filter_eval_exact(&p, x, y) - ref_2d(&p, x, y)) / scale;
        if (err > worst) worst = err;
      }
      if (worst > 1e-6)
        fail_msg("%s radius %g x %g: max error %g", clr_filter_type_name(p.type), p.radius_x,
                 p.radius_y, worst);
    }
}

static void test_integrals(void **state) {
  (void)state;
  float radii[][2] = {{0, 0}, {1.5f, 2.5f}};
  for (int t = 0; t < ALL_TYPES; ++t)
    for (size_t k = 0; k < 2; ++k) {
      clr_filter_params p = make_params((clr_filter_type)t, radii[k][0], radii[k][1], 0);
      double ix = integral_ref_1d(&p, p.radius_x), iy = integral_ref_1d(&p, p.radius_y);
      double cx = closed_form_1d(&p, p.radius_x), cy = closed_form_1d(&p, p.radius_y);
      if (!isnan(cx)) { /* the numeric reference agrees with the closed form */
        assert_true(fabs(ix - cx) <= 1e-9 * fabs(cx));
        assert_true(fabs(iy - cy) <= 1e-9 * fabs(cy));
      }
      double got = integral_float_2d(&p), expect = ix * iy;
      if (fabs(got - expect) > 1e-4 * fabs(expect))
        fail_msg("%s radius %g x %g: integral %.9g, expected %.9g", clr_filter_type_name(p.type),
                 p.radius_x, p.radius_y, got, expect);
    }
  /* Known values: box (2r)^2, triangle r^4, mitchell r/2 per axis (1 at pbrt's radius 2). */
  clr_filter_params box = make_params(CLR_FILTER_BOX, 0, 0, 0);
  assert_true(fabs(integral_float_2d(&box) - 1.0) < 1e-6);
  clr_filter_params tri = make_params(CLR_FILTER_TRIANGLE, 0, 0, 0);
  assert_true(fabs(integral_float_2d(&tri) - 16.0) < 16e-6);
  clr_filter_params mit = make_params(CLR_FILTER_MITCHELL, 0, 0, 0);
  assert_true(fabs(integral_float_2d(&mit) - 1.0) < 1e-5);
}

static void test_mitchell_continuity(void **state) {
  (void)state;
  float bc[][2] = {{1.0f / 3, 1.0f / 3}, {0, 0.5f}, {1, 0}, {0.5f, 0.25f}, {-2, 3}};
  for (size_t k = 0; k < sizeof bc / sizeof bc[0]; ++k) {
    clr_filter_desc d;
    clr_filter_desc_init(&d, CLR_FILTER_MITCHELL);
    d.b = bc[k][0];
    d.c = bc[k][1];
    d.radius[0] = 2.0f;
    d.radius[1] = 1.0f;
    clr_filter_params p;
    assert_int_equal(clr_filter_params_make(&d, &p), CLR_SUCCESS);
    for (int axis = 0; axis < 2; ++axis) {
      float r = axis ? p.radius_y : p.radius_x;
      float half = 0.5f * r, below = nextafterf(half, 0), above = nextafterf(half, INFINITY);
      float vb = axis ? clr_filter_eval_exact(&p, 0, below) : clr_filter_eval_exact(&p, below, 0);
      float va = axis ? clr_filter_eval_exact(&p, 0, above) : clr_filter_eval_exact(&p, above, 0);
      double g0 = ref_mitchell(0, d.b, d.c);
      double at_one = d.b / 6 * g0; /* both cubics give B/6 at t = 1 */
      assert_true(fabs(vb - at_one) < 1e-5 && fabs(va - at_one) < 1e-5);
      float edge = axis ? clr_filter_eval_exact(&p, 0, r) : clr_filter_eval_exact(&p, r, 0);
      assert_true(edge == 0.0f); /* t = 2: exactly 0 */
      float near = nextafterf(r, 0);
      float vn = axis ? clr_filter_eval_exact(&p, 0, near) : clr_filter_eval_exact(&p, near, 0);
      assert_true(fabs(vn) < 1e-9);
    }
  }
}

static double ulp_of(double v) {
  float f = fabsf((float)v);
  if (f < CLR_FLT_MIN_NORMAL) return 0x1p-149;
  return (double)nextafterf(f, INFINITY) - (double)f;
}

static double max_ulp_error(float (*fn)(float), double (*ref)(double), float lo, float hi, int n,
                            float *worst_x) {
  double worst = 0;
  for (int i = 0; i <= n + 2000; ++i) {
    float x = i <= n ? lo + (hi - lo) * (float)i / (float)n : (float)(lo + (hi - lo) * uniform());
    double r = ref(x);
    double err = fabs((double)fn(x) - r) / ulp_of(r);
    if (err > worst) {
      worst = err;
      *worst_x = x;
    }
  }
  return worst;
}

/* sin(pi x) in double with exact reduction x = k/2 + f (libm's sin(PI * x) is not 0 at integers).
 */
static double ref_sinpi_shifted(double x, int quarter_turns) {
  double k = nearbyint(2 * x), f = x - k / 2;
  int quadrant = (int)(((long long)k + quarter_turns) & 3);
  double v = (quadrant & 1) ? cos(PI * f) : sin(PI * f);
  return (quadrant & 2) ? -v : v;
}
static double ref_sinpi(double x) { return ref_sinpi_shifted(x, 0); }
static double ref_cospi(double x) { return ref_sinpi_shifted(x, 1); }
static double ref_rcp(double x) { return 1.0 / x; }

static void expect_ulp(const char *name, float (*fn)(float), double (*ref)(double), float lo,
                       float hi, int n, double limit) {
  float wx = 0;
  double e = max_ulp_error(fn, ref, lo, hi, n, &wx);
  if (e > limit) fail_msg("%s: %.3f ulp at x = %a in [%g, %g]", name, e, wx, lo, hi);
}

static void test_portable_math(void **state) {
  (void)state;
  expect_ulp("exp", clr_exp_portable, exp, -87.0f, 88.0f, 1 << 21, 2.0);
  expect_ulp("exp", clr_exp_portable, exp, -1.0f, 1.0f, 1 << 20, 2.0);
  expect_ulp("exp", clr_exp_portable, exp, -1e-6f, 1e-6f, 1 << 16, 2.0);
  assert_true(clr_exp_portable(0.0f) == 1.0f);
  assert_true(clr_exp_portable(-87.5f) == 0.0f && clr_exp_portable(-INFINITY) == 0.0f);
  assert_true(clr_exp_portable(NAN) == 0.0f && isinf(clr_exp_portable(100.0f)));
  assert_true(clr_exp_portable(-87.0f) >= CLR_FLT_MIN_NORMAL);

  expect_ulp("sinpi", clr_sinpi_portable, ref_sinpi, -64.0f, 64.0f, 1 << 22, 2.0);
  expect_ulp("sinpi", clr_sinpi_portable, ref_sinpi, -0.5f, 0.5f, 1 << 20, 2.0);
  expect_ulp("sinpi", clr_sinpi_portable, ref_sinpi, 0.999f, 1.001f, 1 << 18, 2.0);
  expect_ulp("sinpi", clr_sinpi_portable, ref_sinpi, 4095.0f, 4097.0f, 1 << 16, 2.0);
  expect_ulp("cospi", clr_cospi_portable, ref_cospi, -4.0f, 4.0f, 1 << 21, 2.0);
  expect_ulp("cospi", clr_cospi_portable, ref_cospi, 0.499f, 0.501f, 1 << 18, 2.0);
  expect_ulp("rcp", clr_rcp_portable, ref_rcp, 0.5f, 8192.0f, 1 << 20, 2.0);
  for (int k = -300; k <= 300; ++k) { /* exact zeros at integers, exact +-1 at half-integers */
    assert_true(clr_sinpi_portable((float)k) == 0.0f);
    float h = clr_sinpi_portable((float)k + 0.5f);
    assert_true(h == ((k & 1) ? -1.0f : 1.0f));
  }
  assert_true(clr_sinpi_portable(0x1p-140f) > 0.0f);
  assert_true(clr_sinpi_portable(1e30f) == 0.0f && clr_sinpi_portable(NAN) == 0.0f);
  assert_true(clr_sinpi_portable(0x1.000002p22f) == 1.0f); /* 2^22 + 0.5: sin(pi/2) */
}

/* pbrt-v3's table: entry (x, y) = f((x + .5) rx / 16, (y + .5) ry / 16). */
static void test_table_matches_pbrt(void **state) {
  (void)state;
  float table[CLR_FILTER_TABLE_ENTRIES];
  float radii[][2] = {{0, 0}, {1.5f, 2.5f}, {0.3f, 5.0f}};
  for (int t = 0; t < ALL_TYPES; ++t)
    for (size_t k = 0; k < sizeof radii / sizeof radii[0]; ++k) {
      clr_filter_params p = make_params((clr_filter_type)t, radii[k][0], radii[k][1], 1);
      assert_int_equal(clr_filter_params_table(&p, table), CLR_SUCCESS);
      for (int iy = 0; iy < 16; ++iy)
        for (int ix = 0; ix < 16; ++ix) {
          double x = (ix + 0.5) * p.radius_x / 16, y = (iy + 0.5) * p.radius_y / 16;
          double expect = ref_2d(&p, x, y);
          float got = table[iy * 16 + ix];
          double tol = 1e-6 * (t == CLR_FILTER_TYPE_TRIANGLE ? p.radius_x * p.radius_y : 1.0);
          if (fabs(got - expect) > tol)
            fail_msg("%s table[%d][%d] = %.9g, pbrt-v3 gives %.9g", clr_filter_type_name(t), iy, ix,
                     got, expect);
        }
      /* Table-mode evaluation returns the entry of the cell holding (|x|, |y|). */
      for (int i = 0; i < 20000; ++i) {
        double x = (uniform() * 2 - 1) * p.radius_x, y = (uniform() * 2 - 1) * p.radius_y;
        double cx = fabs(x) * 16 / p.radius_x, cy = fabs(y) * 16 / p.radius_y;
        if (fabs(cx - nearbyint(cx)) < 1e-4 || fabs(cy - nearbyint(cy)) < 1e-4) continue;
        int ix = (int)cx < 15 ? (int)cx : 15, iy = (int)cy < 15 ? (int)cy : 15;
        assert_true(clr_filter_params_evaluate(&p, table, (float)x, (float)y) ==
                    table[iy * 16 + ix]);
        assert_true(clr_filter_params_evaluate(&p, NULL, (float)x, (float)y) ==
                    table[iy * 16 + ix]);
      }
    }
}

static int pbrt_index(float d, float inv_radius) { /* FilmTile::AddSample, written out */
  volatile float scaled = d * inv_radius;
  volatile float times16 = scaled * 16;
  int i = (int)floorf(fabsf(times16));
  return i < 15 ? i : 15;
}

static void test_table_index_edges(void **state) {
  (void)state;
  float exact_radii[] = {0.5f, 1.0f, 2.0f, 4.0f, 64.0f, 0.125f};
  for (size_t k = 0; k < sizeof exact_radii / sizeof exact_radii[0]; ++k) {
    float r = exact_radii[k], inv = 1.0f / r;
    for (int cell = 0; cell <= 16; ++cell) {
      float d = r * (float)cell / 16.0f; /* exactly on the boundary between cells */
      int expect = cell < 15 ? cell : 15;
      assert_int_equal(clr_filter_table_index(d, inv), expect);
      assert_int_equal(clr_filter_table_index(-d, inv), expect);
      if (cell > 0) { /* just below the boundary: the previous cell */
        float below = nextafterf(d, 0);
        assert_int_equal(clr_filter_table_index(below, inv), cell - 1 < 15 ? cell - 1 : 15);
      }
      float above = nextafterf(d, INFINITY);
      assert_int_equal(clr_filter_table_index(above, inv), expect);
    }
  }
  float radii[] = {1.5f, 2.5f, 0.3f, 0.7f, 3.3f, 17.1f};
  for (size_t k = 0; k < sizeof radii / sizeof radii[0]; ++k) {
    clr_filter_params p = make_params(CLR_FILTER_GAUSSIAN, radii[k], radii[k], 1);
    for (int cell = 0; cell <= 16; ++cell) {
      float d = p.radius_x * (float)cell / 16.0f;
      float probes[3] = {d, nextafterf(d, 0), nextafterf(d, INFINITY)};
      for (int j = 0; j < 3; ++j)
        assert_int_equal(clr_filter_table_index(probes[j], p.inv_radius_x),
                         pbrt_index(probes[j], p.inv_radius_x));
    }
  }
  assert_int_equal(clr_filter_table_index(1e30f, 1.0f), 15);
  assert_int_equal(clr_filter_table_index(INFINITY, 1.0f), 15);
  assert_int_equal(clr_filter_table_index(NAN, 1.0f), 15);
}

/* Separability as the film uses it: the 2D filter equals the flushed product of the 1D factors
 * bit for bit, every filter, exact and table mode, inside and outside the support, and the
 * 16x16 table equals the products of the 16-entry factors. */
static void test_separable_product(void **state) {
  (void)state;
  const float radii[][2] = {{0.5f, 0.5f}, {2.0f, 2.0f}, {1.5f, 3.0f}, {4.0f, 0.75f}};
  for (int type = 0; type < ALL_TYPES; ++type)
    for (size_t r = 0; r < sizeof radii / sizeof radii[0]; ++r)
      for (int use_table = 0; use_table < 2; ++use_table) {
        clr_filter_params p =
            make_params((clr_filter_type)type, radii[r][0], radii[r][1], use_table);
        float table[CLR_FILTER_TABLE_ENTRIES], factors[2 * CLR_FILTER_TABLE_SIZE];
        assert_int_equal(clr_filter_params_table(&p, table), CLR_SUCCESS);
        for (int axis = 0; axis < 2; ++axis)
          for (int i = 0; i < CLR_FILTER_TABLE_SIZE; ++i)
            factors[axis * CLR_FILTER_TABLE_SIZE + i] = clr_filter_table_factor(&p, axis, i);
        for (int iy = 0; iy < CLR_FILTER_TABLE_SIZE; ++iy)
          for (int ix = 0; ix < CLR_FILTER_TABLE_SIZE; ++ix) {
            float prod = clr_flush_subnormal(factors[ix] * factors[CLR_FILTER_TABLE_SIZE + iy]);
            assert_int_equal(clr_as_uint(table[iy * CLR_FILTER_TABLE_SIZE + ix]),
                             clr_as_uint(prod));
          }
        int nonzero = 0;
        for (int i = 0; i < 4000; ++i) {
          float x = (float)((uniform() * 2.4 - 1.2) * p.radius_x);
          float y = (float)((uniform() * 2.4 - 1.2) * p.radius_y);
          if (i == 0) x = p.radius_x, y = -p.radius_y; /* closed support edges */
          if (i == 1) x = 0.0f, y = 0x1p-140f;         /* subnormal offset */
          float f2 = clr_filter_eval(&p, x, y, table);
          float f1 = clr_flush_subnormal(clr_filter_eval_1d(&p, 0, x, factors) *
                                         clr_filter_eval_1d(&p, 1, y, factors));
          assert_int_equal(clr_as_uint(f2), clr_as_uint(f1));
          nonzero += f2 != 0.0f;
        }
        assert_true(nonzero > 1000);
        if (type == CLR_FILTER_TYPE_BOX)
          assert_true(clr_filter_eval_1d(&p, 1, p.radius_y * 1.0001f, factors) == 0.0f);
      }
}

static void expect_make_error(const clr_filter_desc *d, clr_result code, const char *needle) {
  clr_filter_params p;
  memset(&p, 0x5a, sizeof p);
  clr_result r = clr_filter_params_make(d, &p);
  if (r != code)
    fail_msg("expected %s, got %s (%s)", clr_result_name(code), clr_result_name(r),
             clr_last_error_message());
  if (needle && !strstr(clr_last_error_message(), needle))
    fail_msg("message \"%s\" lacks \"%s\"", clr_last_error_message(), needle);
  unsigned char untouched[sizeof p];
  memset(untouched, 0x5a, sizeof untouched);
  assert_memory_equal(&p, untouched, sizeof p);
}

static void test_bad_params(void **state) {
  (void)state;
  clr_filter_desc d;
  clr_filter_params p;
  clr_filter_desc_init(&d, CLR_FILTER_GAUSSIAN);
  assert_int_equal(clr_filter_params_make(NULL, &p), CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_filter_params_make(&d, NULL), CLR_ERROR_NULL_POINTER);
  d.struct_size = 3;
  expect_make_error(&d, CLR_ERROR_INVALID_ARGUMENT, "struct_size");
  clr_filter_desc_init(&d, (clr_filter_type)7);
  expect_make_error(&d, CLR_ERROR_INVALID_FILTER, "type 7");
  clr_filter_desc_init(&d, (clr_filter_type)-1);
  expect_make_error(&d, CLR_ERROR_INVALID_FILTER, "type -1");
  clr_filter_desc_init(&d, CLR_FILTER_BOX);
  d.use_table = 2;
  expect_make_error(&d, CLR_ERROR_INVALID_ARGUMENT, "use_table is 2");

  struct {
    int axis;
    float value;
    const char *text;
  } radii[] = {{0, 0.0f, "radius[0] (xwidth) is 0"},
               {1, -1.0f, "radius[1] (ywidth) is -1"},
               {0, NAN, "is nan"},
               {1, INFINITY, "is inf"},
               {0, -INFINITY, "is -inf"},
               {1, 65.0f, "is 65"},
               {0, 1e-4f, "is 0.0001"}};
  for (size_t i = 0; i < sizeof radii / sizeof radii[0]; ++i) {
    clr_filter_desc_init(&d, CLR_FILTER_MITCHELL);
    d.radius[radii[i].axis] = radii[i].value;
    expect_make_error(&d, CLR_ERROR_INVALID_RADIUS, radii[i].text);
  }
  clr_filter_desc_init(&d, CLR_FILTER_BOX);
  d.radius[0] = CLR_FILTER_MAX_RADIUS;
  d.radius[1] = CLR_FILTER_MIN_RADIUS;
  assert_int_equal(clr_filter_params_make(&d, &p), CLR_SUCCESS);

  float alphas[] = {0.0f, -1.0f, NAN, INFINITY, 1e-30f};
  for (size_t i = 0; i < sizeof alphas / sizeof alphas[0]; ++i) {
    clr_filter_desc_init(&d, CLR_FILTER_GAUSSIAN);
    d.alpha = alphas[i];
    expect_make_error(&d, CLR_ERROR_INVALID_FILTER, "alpha");
  }
  float taus[] = {0.0f, -3.0f, NAN, INFINITY, 1e-3f, 1e7f};
  for (size_t i = 0; i < sizeof taus / sizeof taus[0]; ++i) {
    clr_filter_desc_init(&d, CLR_FILTER_SINC);
    d.tau = taus[i];
    expect_make_error(&d, CLR_ERROR_INVALID_FILTER, "tau");
  }
  float bcs[] = {NAN, INFINITY, -INFINITY, 101.0f};
  for (size_t i = 0; i < sizeof bcs / sizeof bcs[0]; ++i) {
    clr_filter_desc_init(&d, CLR_FILTER_MITCHELL);
    d.b = bcs[i];
    expect_make_error(&d, CLR_ERROR_INVALID_FILTER, "mitchell B");
    clr_filter_desc_init(&d, CLR_FILTER_MITCHELL);
    d.c = bcs[i];
    expect_make_error(&d, CLR_ERROR_INVALID_FILTER, "mitchell C");
  }
  /* Parameters a filter does not use are ignored, as in pbrt-v3. */
  clr_filter_desc_init(&d, CLR_FILTER_BOX);
  d.alpha = NAN;
  d.tau = -1;
  d.b = INFINITY;
  assert_int_equal(clr_filter_params_make(&d, &p), CLR_SUCCESS);
  clr_filter_desc_init(&d, CLR_FILTER_CATMULLROM);
  d.b = NAN;
  assert_int_equal(clr_filter_params_make(&d, &p), CLR_SUCCESS);
  assert_true(p.b == 0.0f && p.c == 0.5f);

  float table[CLR_FILTER_TABLE_ENTRIES];
  assert_int_equal(clr_filter_params_table(NULL, table), CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_filter_params_table(&p, NULL), CLR_ERROR_NULL_POINTER);
  clr_filter_params bad = p;
  bad.type = 42;
  assert_int_equal(clr_filter_params_table(&bad, table), CLR_ERROR_INVALID_FILTER);
  bad = p;
  bad.radius_y = NAN;
  assert_int_equal(clr_filter_params_table(&bad, table), CLR_ERROR_INVALID_RADIUS);
  assert_true(clr_filter_params_evaluate(NULL, NULL, 0, 0) == 0.0f);
}

/* ---- the same header compiled as OpenCL C gives the same bits ---- */

static const char *device_source =
    "#include \"filter_funcs.h\"\n"
    "__kernel void eval_filter(__global const clr_filter_params *fp, __global const float *table,\n"
    "                          __global const float *xy, __global float *out) {\n"
    "  size_t i = get_global_id(0);\n"
    "  clr_filter_params f = *fp;\n"
    "  out[3 * i] = clr_filter_eval_exact(&f, xy[2 * i], xy[2 * i + 1]);\n"
    "  out[3 * i + 1] = clr_filter_eval(&f, xy[2 * i], xy[2 * i + 1], table);\n"
    "  out[3 * i + 2] = i < 256 ? clr_filter_table_entry(&f, (int)(i % 16), (int)(i / 16)) : "
    "0.0f;\n"
    "}\n"
    "__kernel void eval_math(__global const float *x, __global float *out) {\n"
    "  size_t i = get_global_id(0);\n"
    "  out[4 * i] = clr_exp_portable(x[i] * 88.0f);\n"
    "  out[4 * i + 1] = clr_sinpi_portable(x[i] * 64.0f);\n"
    "  out[4 * i + 2] = clr_cospi_portable(x[i] * 4.0f);\n"
    "  out[4 * i + 3] = clr_sinc_portable(fabs(x[i]) * 70.0f);\n"
    "}\n";

typedef struct device_run {
  clr_context ctx;
  cl_context cl;
  cl_command_queue queue;
  cl_program program;
} device_run;

static cl_mem buffer_from(device_run *d, size_t bytes, const void *data) {
  cl_int err = CL_SUCCESS;
  cl_mem m = clCreateBuffer(d->cl, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes,
                            (void *)data, &err);
  assert_int_equal(err, CL_SUCCESS);
  return m;
}

static void run_kernel(device_run *d, const char *name, cl_mem *args, int nargs, size_t n) {
  cl_int err = CL_SUCCESS;
  cl_kernel k = clCreateKernel(d->program, name, &err);
  assert_int_equal(err, CL_SUCCESS);
  for (int i = 0; i < nargs; ++i)
    assert_int_equal(clSetKernelArg(k, (cl_uint)i, sizeof(cl_mem), &args[i]), CL_SUCCESS);
  assert_int_equal(clEnqueueNDRangeKernel(d->queue, k, 1, NULL, &n, NULL, 0, NULL, NULL),
                   CL_SUCCESS);
  assert_int_equal(clFinish(d->queue), CL_SUCCESS);
  clReleaseKernel(k);
}

static void read_back(device_run *d, cl_mem m, size_t bytes, void *out) {
  assert_int_equal(clEnqueueReadBuffer(d->queue, m, CL_TRUE, 0, bytes, out, 0, NULL, NULL),
                   CL_SUCCESS);
}

static void build_device_program(device_run *d) {
  assert_int_equal(clr_context_create(NULL, &d->ctx), CLR_SUCCESS);
  d->cl = clr_context_cl_context(d->ctx);
  d->queue = clr_context_cl_queue(d->ctx);
  cl_device_id dev = clr_context_cl_device(d->ctx);
  cl_int err = CL_SUCCESS;
  d->program = clCreateProgramWithSource(d->cl, 1, &device_source, NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  const char *options = "-cl-std=CL1.2 -I " CLR_SOURCE_DIR "/kernels";
  if (clBuildProgram(d->program, 1, &dev, options, NULL, NULL) != CL_SUCCESS) {
    static char log[16384];
    clGetProgramBuildInfo(d->program, dev, CL_PROGRAM_BUILD_LOG, sizeof log, log, NULL);
    fail_msg("filter kernels failed to build:\n%s", log);
  }
}

static void check_bits(const char *what, const float *host, const float *device, size_t n,
                       const float *inputs, size_t stride) {
  for (size_t i = 0; i < n; ++i)
    if (memcmp(&host[i], &device[i], sizeof(float)) != 0)
      fail_msg("%s: element %zu (input %a) host %a, device %a", what, i, inputs[i / stride * 2],
               host[i], device[i]);
}

static void test_device_matches_host(void **state) {
  (void)state;
  device_run d;
  build_device_program(&d);
  printf("# device: %s\n", clr_context_device_name(d.ctx));
  enum { N = 8192 };
  static float xy[2 * N], host[3 * N], dev[3 * N], table[CLR_FILTER_TABLE_ENTRIES];
  for (int t = 0; t < ALL_TYPES; ++t) {
    clr_filter_params p = make_params((clr_filter_type)t, t == 1 ? 1.5f : 0, t == 1 ? 2.5f : 0, 1);
    assert_int_equal(clr_filter_params_table(&p, table), CLR_SUCCESS);
    for (int i = 0; i < N; ++i) {
      double spread = i < 64 ? 1.0 : 1.05; /* some points on the edge and just outside */
      xy[2 * i] = i < 16 ? p.radius_x * (float)i / 15.0f
                         : (float)((uniform() * 2 - 1) * spread * p.radius_x);
      xy[2 * i + 1] = (float)((uniform() * 2 - 1) * spread * p.radius_y);
    }
    for (int i = 0; i < N; ++i) {
      host[3 * i] = clr_filter_eval_exact(&p, xy[2 * i], xy[2 * i + 1]);
      host[3 * i + 1] = clr_filter_eval(&p, xy[2 * i], xy[2 * i + 1], table);
      host[3 * i + 2] = i < 256 ? table[i] : 0.0f;
    }
    cl_mem args[4] = {buffer_from(&d, sizeof p, &p), buffer_from(&d, sizeof table, table),
                      buffer_from(&d, sizeof xy, xy), buffer_from(&d, sizeof dev, NULL)};
    run_kernel(&d, "eval_filter", args, 4, N);
    read_back(&d, args[3], sizeof dev, dev);
    for (int i = 0; i < 4; ++i) clReleaseMemObject(args[i]);
    check_bits(clr_filter_type_name(t), host, dev, 3 * N, xy, 3);
  }
  enum { M = 1 << 18 };
  float *x = malloc(M * sizeof *x), *hm = malloc(4 * M * sizeof *hm),
        *dm = malloc(4 * M * sizeof *dm);
  assert_non_null(x);
  assert_non_null(hm);
  assert_non_null(dm);
  for (int i = 0; i < M; ++i) {
    x[i] = i < M / 2 ? -1.0f + 2.0f * (float)i / (float)(M / 2) : (float)(uniform() * 2 - 1);
    hm[4 * i] = clr_exp_portable(x[i] * 88.0f);
    hm[4 * i + 1] = clr_sinpi_portable(x[i] * 64.0f);
    hm[4 * i + 2] = clr_cospi_portable(x[i] * 4.0f);
    hm[4 * i + 3] = clr_sinc_portable(fabsf(x[i]) * 70.0f);
  }
  cl_mem margs[2] = {buffer_from(&d, M * sizeof *x, x), buffer_from(&d, 4 * M * sizeof *dm, NULL)};
  run_kernel(&d, "eval_math", margs, 2, M);
  read_back(&d, margs[1], 4 * M * sizeof *dm, dm);
  clReleaseMemObject(margs[0]);
  clReleaseMemObject(margs[1]);
  for (int i = 0; i < 4 * M; ++i)
    if (memcmp(&hm[i], &dm[i], sizeof(float)) != 0)
      fail_msg("math function %d at x = %a: host %a, device %a", i % 4, x[i / 4], hm[i], dm[i]);
  free(x);
  free(hm);
  free(dm);
  clReleaseProgram(d.program);
  clr_context_release(d.ctx);
}

/* The public desc-based calls give the internal parameter block's bits. */
static void test_public_desc_api(void **state) {
  (void)state;
  for (int type = 0; type < CLR_FILTER_TYPE_COUNT; ++type)
    for (int use_table = 0; use_table < 2; ++use_table) {
      clr_filter_desc d;
      clr_filter_desc_init(&d, (clr_filter_type)type);
      d.use_table = use_table;
      assert_int_equal(clr_filter_check(&d), CLR_SUCCESS);
      clr_filter_params p;
      assert_int_equal(clr_filter_params_make(&d, &p), CLR_SUCCESS);
      float table[CLR_FILTER_TABLE_ENTRIES], expected[CLR_FILTER_TABLE_ENTRIES];
      assert_int_equal(clr_filter_make_table(&d, table), CLR_SUCCESS);
      assert_int_equal(clr_filter_params_table(&p, expected), CLR_SUCCESS);
      assert_memory_equal(table, expected, sizeof table);
      for (int k = 0; k < 50; ++k) {
        float x = (k - 25) * 0.09f, y = (k % 7 - 3) * 0.31f, v = -1.0f;
        assert_int_equal(clr_filter_evaluate(&d, x, y, &v), CLR_SUCCESS);
        float want = clr_filter_params_evaluate(&p, NULL, x, y);
        assert_memory_equal(&v, &want, sizeof v);
      }
    }
  clr_filter_desc bad;
  clr_filter_desc_init(&bad, CLR_FILTER_GAUSSIAN);
  bad.alpha = -1.0f;
  float v = 0.0f, table[CLR_FILTER_TABLE_ENTRIES];
  assert_int_equal(clr_filter_evaluate(&bad, 0, 0, &v), CLR_ERROR_INVALID_FILTER);
  assert_non_null(strstr(clr_last_error_message(), "alpha"));
  assert_int_equal(clr_filter_make_table(&bad, table), CLR_ERROR_INVALID_FILTER);
  assert_int_equal(clr_filter_check(NULL), CLR_ERROR_NULL_POINTER);
  clr_filter_desc_init(&bad, CLR_FILTER_BOX);
  assert_int_equal(clr_filter_evaluate(&bad, 0, 0, NULL), CLR_ERROR_NULL_POINTER);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_defaults_and_names), cmocka_unit_test(test_zero_outside_support),
      cmocka_unit_test(test_symmetry),           cmocka_unit_test(test_exact_matches_formulas),
      cmocka_unit_test(test_integrals),          cmocka_unit_test(test_mitchell_continuity),
      cmocka_unit_test(test_portable_math),      cmocka_unit_test(test_table_matches_pbrt),
      cmocka_unit_test(test_table_index_edges),  cmocka_unit_test(test_separable_product),
      cmocka_unit_test(test_bad_params),         cmocka_unit_test(test_device_matches_host),
      cmocka_unit_test(test_public_desc_api),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
