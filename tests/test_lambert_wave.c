/* The structure-of-arrays Lambertian sampling (integrators/lambert_wave.c) against the scalar
 * steps the integrators ran before it (lambertian.h): the same wi, pdf and f |cos| bits for
 * every entry of waves of random and edge-case surfaces, directions and sample values (the disk's
 * centre and diagonals, u0 = 1, dpdu along ns or zero, ns against the shape's normal, wo on
 * either side), of lengths the vector loops split into full vectors and a remainder. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "hemisphere_wave.h"
#include "lambert_wave.h"

#define WAVE_TEST_SEED 0x853c49e6748fea9bULL
#include "wave_test_random.h"

/* Surface k of a wave: a random frame, every 7th with dpdu along ns, every 11th with dpdu 0,
 * every 3rd with ns on the other side of the shape's normal; ng a perturbed ns. */
static void make_surface(int k, clr_surface *s) {
  memset(s, 0, sizeof *s);
  random_unit(s->ns);
  for (int a = 0; a < 3; ++a) s->ng[a] = s->ns[a] + 0.3f * (2.0f * uniform() - 1.0f);
  rs_normalize(s->ng);
  if (rs_dot(s->ng, s->ns) < 0.0f)
    for (int a = 0; a < 3; ++a) s->ng[a] = -s->ng[a];
  for (int a = 0; a < 3; ++a) s->n_geom[a] = k % 3 == 0 ? -s->ng[a] : s->ng[a];
  for (int a = 0; a < 3; ++a) s->dpdu[a] = 5.0f * (2.0f * uniform() - 1.0f);
  if (k % 7 == 0)
    for (int a = 0; a < 3; ++a) s->dpdu[a] = 2.5f * s->ns[a];
  if (k % 11 == 0) memset(s->dpdu, 0, sizeof s->dpdu);
  s->on_a = 1.0f;
  s->kd[0] = s->kd[1] = s->kd[2] = 0.5f;
  s->has_material = 1;
}

/* Sample values of entry k: random, with the disk's centre, its diagonals, its edges and u0 = 1
 * among them. */
static void make_u(int k, float u[2]) {
  static const float edge[][2] = {{0.5f, 0.5f},   {0.0f, 0.0f},        {1.0f, 0.25f},
                                  {0.75f, 0.75f}, {0.25f, 0.75f},      {0.5f, 0.0f},
                                  {0.0f, 0.5f},   {0.99999994f, 0.5f}, {0.5f, 0.99999994f}};
  int ne = (int)(sizeof edge / sizeof edge[0]);
  if (k % 5 == 0) {
    u[0] = edge[(k / 5) % ne][0];
    u[1] = edge[(k / 5) % ne][1];
  } else {
    u[0] = uniform();
    u[1] = uniform();
  }
}

static void check_wave(int n) {
  clr_lambert_wave w;
  memset(&w, 0, sizeof w);
  assert_int_equal(clr_lambert_wave_reserve(&w, n), CLR_SUCCESS);
  clr_surface *surfaces = calloc((size_t)n, sizeof *surfaces);
  float(*wo)[3] = calloc((size_t)n, sizeof *wo), (*u)[2] = calloc((size_t)n, sizeof *u);
  assert_non_null(surfaces);
  assert_non_null(wo);
  assert_non_null(u);
  for (int k = 0; k < n; ++k) {
    make_surface(k, &surfaces[k]);
    random_unit(wo[k]);
    make_u(k, u[k]);
    assert_int_equal(clr_lambert_wave_push(&w, &surfaces[k], wo[k], u[k], 1000 + k), k);
  }
  assert_int_equal(w.n, n);
  clr_lambert_wave_sample(&w);
  int reflected = 0;
  for (int k = 0; k < n; ++k) {
    float wi[3], pdf;
    clr_lambert_sample_dir(&surfaces[k], wo[k], u[k], wi, &pdf);
    float fcos = clr_lambert_cos_plain(&surfaces[k], wo[k], wi);
    float got[3] = {w.wi[0][k], w.wi[1][k], w.wi[2][k]};
    if (memcmp(got, wi, sizeof wi) || memcmp(&w.pdf[k], &pdf, sizeof pdf) ||
        memcmp(&w.fcos[k], &fcos, sizeof fcos))
      fail_msg("entry %d of %d: wave wi (%a %a %a) pdf %a fcos %a, scalar (%a %a %a) %a %a", k, n,
               got[0], got[1], got[2], w.pdf[k], w.fcos[k], wi[0], wi[1], wi[2], pdf, fcos);
    assert_int_equal(w.owner[k], 1000 + k);
    /* and what the bits mean: a unit direction, pdf |cos(wi, n)| / pi (dpdu along ns leaves a
     * rounding residue as the tangent, not orthogonal to ns: no frame to check there) */
    if (k % 7) {
      assert_true(fabsf(rs_dot(wi, wi) - 1.0f) < 1e-5f);
      assert_true(fabsf(pdf - fabsf(rs_dot(wi, surfaces[k].ns)) * RS_INV_PI) < 1e-5f);
    }
    reflected += fcos > 0.0f;
  }
  if (n >= 100) assert_true(reflected > n / 4 && reflected < n); /* both cases exercised */
  clr_lambert_wave_free(&w);
  free(surfaces);
  free(wo);
  free(u);
}

static void test_wave_equals_scalar(void **state) {
  (void)state;
  const int lengths[] = {1, 3, 4, 7, 16, 33, 256, 1001};
  for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; ++i) check_wave(lengths[i]);
}

/* The AO integrator's directions: the hemisphere wave alone, on values not clamped below 1. */
static void test_hemisphere_wave_equals_scalar(void **state) {
  (void)state;
  enum { N = 203 };
  float u0[N], u1[N], x[N], y[N], z[N];
  for (int k = 0; k < N; ++k) {
    float u[2];
    make_u(k, u);
    u0[k] = k % 13 == 0 ? 1.0f : u[0];
    u1[k] = k % 17 == 0 ? 1.0f : u[1];
  }
  clr_wave_cosine_hemisphere(N, u0, u1, x, y, z);
  for (int k = 0; k < N; ++k) {
    float u[2] = {u0[k], u1[k]}, w[3], got[3] = {x[k], y[k], z[k]};
    clr_cosine_hemisphere(u, w);
    if (memcmp(got, w, sizeof w))
      fail_msg("entry %d: wave (%a %a %a), scalar (%a %a %a)", k, got[0], got[1], got[2], w[0],
               w[1], w[2]);
  }
  clr_wave_cosine_hemisphere(0, u0, u1, x, y, z); /* an empty wave writes nothing */
}

/* The AO integrator's world directions and terms at one point (clr_wave_ao_directions) against
 * pbrt-v3's AOIntegrator, written out: wi = s x + t y + n z, Dot(wi, n) and Dot / (pdf count)
 * with pdf = |z| / pi, 0 where z = 0; for counts the vector loop splits in several ways. */
static void test_ao_directions_equal_pbrt(void **state) {
  (void)state;
  enum { MAX = 67 };
  const int counts[] = {1, 2, 5, 8, 16, 64, MAX};
  for (size_t c = 0; c < sizeof counts / sizeof counts[0]; ++c) {
    int n = counts[c];
    float frame[9], x[MAX], y[MAX], z[MAX], cos_n[MAX], term[MAX], w[MAX][3];
    random_unit(frame + 6);
    random_unit(frame);
    rs_cross(frame + 6, frame, frame + 3);
    for (int k = 0; k < n; ++k) {
      random_unit(w[k]);
      w[k][2] = k % 9 == 4 ? 0.0f : fabsf(w[k][2]); /* z = 0: a zero pdf */
      x[k] = w[k][0], y[k] = w[k][1], z[k] = w[k][2];
    }
    clr_wave_ao_directions(n, frame, (float)n, x, y, z, cos_n, term);
    for (int k = 0; k < n; ++k) {
      float wi[3];
      for (int a = 0; a < 3; ++a)
        wi[a] = frame[a] * w[k][0] + frame[3 + a] * w[k][1] + frame[6 + a] * w[k][2];
      float dot = wi[0] * frame[6] + wi[1] * frame[7] + wi[2] * frame[8];
      float pdf = fabsf(w[k][2]) * RS_INV_PI, expect = pdf > 0.0f ? dot / (pdf * (float)n) : 0.0f;
      float got[5] = {x[k], y[k], z[k], cos_n[k], term[k]},
            want[5] = {wi[0], wi[1], wi[2], dot, expect};
      if (memcmp(got, want, sizeof got))
        fail_msg("count %d, direction %d: wave (%a %a %a) %a %a, pbrt (%a %a %a) %a %a", n, k,
                 got[0], got[1], got[2], got[3], got[4], want[0], want[1], want[2], want[3],
                 want[4]);
    }
  }
}

/* Reserving again keeps the storage when it is large enough and restarts the wave. */
static void test_wave_reuse(void **state) {
  (void)state;
  clr_lambert_wave w;
  memset(&w, 0, sizeof w);
  assert_int_equal(clr_lambert_wave_reserve(&w, 10), CLR_SUCCESS);
  float *block = w.block;
  clr_surface s;
  make_surface(1, &s);
  float wo[3] = {0.0f, 0.0f, 1.0f}, u[2] = {0.3f, 0.6f};
  clr_lambert_wave_push(&w, &s, wo, u, 7);
  assert_int_equal(clr_lambert_wave_reserve(&w, 5), CLR_SUCCESS);
  assert_ptr_equal(w.block, block);
  assert_int_equal(w.n, 0);
  assert_int_equal(clr_lambert_wave_reserve(&w, 100), CLR_SUCCESS);
  assert_true(w.cap >= 100);
  assert_int_equal(w.cap % 32, 16); /* an odd number of cache lines */
  clr_lambert_wave_free(&w);
  assert_null(w.block);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_wave_equals_scalar),
      cmocka_unit_test(test_hemisphere_wave_equals_scalar),
      cmocka_unit_test(test_ao_directions_equal_pbrt),
      cmocka_unit_test(test_wave_reuse),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
