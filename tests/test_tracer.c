/* Embree tracer: triangle/quad/sphere hits at analytic t, instances, packets, occlusion, threads. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>
#include "mesh.h"
#include "tracer.h"
#include "animated_transform.h"

#define PI 3.14159265358979323846

/* ---- helpers ---- */

static clr_ray make_ray(float ox, float oy, float oz, float dx, float dy, float dz, float tnear,
                        float tfar) {
  clr_ray r = {ox, oy, oz, tnear, dx, dy, dz, tfar, 0.0f};
  return r;
}

static clr_ray ray_inf(float ox, float oy, float oz, float dx, float dy, float dz) {
  return make_ray(ox, oy, oz, dx, dy, dz, 0.0f, INFINITY);
}

static void identity(float m[16]) {
  memset(m, 0, 16 * sizeof(float));
  m[0] = m[5] = m[10] = m[15] = 1.0f;
}

static void translate(float m[16], float x, float y, float z) {
  identity(m);
  m[3] = x, m[7] = y, m[11] = z;
}

/* c = a * b for row-major 4x4 matrices (c may not alias). */
static void mul(const float a[16], const float b[16], float c[16]) {
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) {
      double s = 0.0;
      for (int j = 0; j < 4; ++j) s += (double)a[4 * r + j] * b[4 * j + k];
      c[4 * r + k] = (float)s;
    }
}

static void apply_linear(const float m[16], const double v[3], double out[3]) {
  for (int r = 0; r < 3; ++r) out[r] = m[4 * r] * v[0] + m[4 * r + 1] * v[1] + m[4 * r + 2] * v[2];
}

static double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Cosine of the angle between a float and a double vector. */
static double cos_angle(const float a[3], const double b[3]) {
  double ad[3] = {a[0], a[1], a[2]};
  return dot3(ad, b) / sqrt(dot3(ad, ad) * dot3(b, b));
}

static void assert_rel(double got, double expected, double rel) {
  if (fabs(got - expected) > rel * fabs(expected))
    fail_msg("got %.9g, expected %.9g (relative tolerance %g)", got, expected, rel);
}

/* Embree's triangle test multiplies by a refined reciprocal, so exact answers come back within
 * a few float ulps, not bit-exact. */
static void assert_tuv(const clr_hit *h, double t, double u, double v) {
  if (fabs(h->t - t) > 5e-7 * t || fabs(h->u - u) > 1e-6 || fabs(h->v - v) > 1e-6)
    fail_msg("hit (t %.9g, u %.9g, v %.9g), expected (%.9g, %.9g, %.9g)", (double)h->t,
             (double)h->u, (double)h->v, t, u, v);
}

static void assert_vec_near(const float *got, const double *expected, int n, double tol) {
  for (int i = 0; i < n; ++i)
    if (fabs(got[i] - expected[i]) > tol)
      fail_msg("component %d: got %.9g, expected %.9g (tolerance %g)", i, (double)got[i],
               expected[i], tol);
}

static void assert_miss(const clr_hit *h) {
  assert_int_equal(h->geom_id, CLR_TRACER_INVALID_ID);
  assert_int_equal(h->inst_id, CLR_TRACER_INVALID_ID);
  assert_int_equal(h->user_id, CLR_TRACER_INVALID_ID);
  assert_true(isinf(h->t) && h->t > 0);
}

static void assert_error(clr_result got, clr_result expected, const char *needle) {
  assert_int_equal(got, expected);
  if (needle && !strstr(clr_last_error_message(), needle))
    fail_msg("\"%s\" not in error message \"%s\"", needle, clr_last_error_message());
}

static clr_mesh mesh_of(const int32_t *idx, size_t ni, const float *P, size_t np, const float *N,
                        const float *uv) {
  clr_mesh m;
  assert_int_equal(
      clr_mesh_from_arrays("test", idx, ni, P, np, N, N ? np : 0, uv, uv ? np / 3 * 2 : 0, &m),
      CLR_SUCCESS);
  return m;
}

/* The unit triangle (0,0,0), (1,0,0), (0,1,0). */
static clr_mesh unit_triangle(void) {
  static const float P[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  return mesh_of(NULL, 0, P, 9, NULL, NULL);
}

static clr_hit trace1(clr_tracer t, clr_ray r) {
  clr_hit h;
  assert_int_equal(clr_tracer_intersect(t, &r, &h, 1), CLR_SUCCESS);
  return h;
}

static uint64_t rng_state = 0x853c49e6748fea9bULL;
static double rnd(void) { /* 53-bit uniform in [0,1) from a 64-bit LCG */
  rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static int hits_equal(const clr_hit *a, const clr_hit *b) {
  return a->t == b->t && a->u == b->u && a->v == b->v && a->ng[0] == b->ng[0] &&
         a->ng[1] == b->ng[1] && a->ng[2] == b->ng[2] && a->prim_id == b->prim_id &&
         a->geom_id == b->geom_id && a->inst_id == b->inst_id && a->user_id == b->user_id;
}

/* ---- triangles ---- */

static void test_triangle_and_quad(void **state) {
  (void)state;
  clr_tracer t;
  assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
  clr_mesh tri = unit_triangle();
  static const float QP[] = {2, 0, -3, 4, 0, -3, 4, 2, -3, 2, 2, -3};
  static const float QN[] = {0, 0, 1, 1, 0, 1, 0, 0, 2, 0, 1, 1};
  static const float QUV[] = {0, 0, 1, 0, 1, 1, 0, 1};
  static const int32_t QI[] = {0, 1, 2, 0, 2, 3};
  clr_mesh quad = mesh_of(QI, 6, QP, 12, QN, QUV);
  uint32_t id_tri = 99, id_quad = 99;
  assert_int_equal(clr_tracer_add_mesh(t, 0, &tri, 11, &id_tri), CLR_SUCCESS);
  assert_int_equal(clr_tracer_add_mesh(t, 0, &quad, 12, &id_quad), CLR_SUCCESS);
  clr_mesh_free(&tri); /* the tracer keeps its own copy */
  clr_mesh_free(&quad);
  assert_int_equal(id_tri, 0);
  assert_int_equal(id_quad, 1);
  assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);

  clr_hit h = trace1(t, ray_inf(0.25f, 0.5f, 5.0f, 0, 0, -1));
  assert_tuv(&h, 5.0, 0.25, 0.5);
  assert_int_equal(h.geom_id, 0);
  assert_int_equal(h.prim_id, 0);
  assert_int_equal(h.user_id, 11);
  assert_int_equal(h.inst_id, CLR_TRACER_INVALID_ID);
  assert_true(h.ng[0] == 0.0f && h.ng[1] == 0.0f && h.ng[2] > 0.0f); /* (p1-p0) x (p2-p0) = +z */
  float p[3], n[3], uv[2];
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_SUCCESS);
  assert_vec_near(p, (double[]){0.25, 0.5, 0.0}, 3, 1e-6);
  assert_true(n[0] == 0.0f && n[1] == 0.0f && n[2] == 1.0f); /* geometric: no vertex normals */
  assert_vec_near(uv, (double[]){0.75, 0.5}, 2, 2e-6);       /* pbrt's default uvs: (u+v, v) */

  /* the same triangle seen from below: the geometric normal does not flip */
  h = trace1(t, ray_inf(0.25f, 0.5f, -1.0f, 0, 0, 2));
  assert_tuv(&h, 0.5, 0.25, 0.5);
  assert_true(h.ng[2] > 0.0f && h.geom_id == 0);

  /* quad: first triangle (0,1,2) at (3.5, 0.5), second (0,2,3) at (2.5, 1.5) */
  h = trace1(t, ray_inf(3.5f, 0.5f, 5.0f, 0, 0, -1));
  assert_tuv(&h, 8.0, 0.5, 0.25);
  assert_int_equal(h.prim_id, 0);
  assert_int_equal(h.geom_id, 1);
  assert_int_equal(h.user_id, 12);
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_SUCCESS);
  assert_vec_near(p, (double[]){3.5, 0.5, -3.0}, 3, 4e-6);
  assert_vec_near(uv, (double[]){0.75, 0.25}, 2, 2e-6);
  double n_expected[3] = {0.25 * 0 + 0.5 * 1 + 0.25 * 0, 0, 0.25 * 1 + 0.5 * 1 + 0.25 * 2};
  assert_true(cos_angle(n, n_expected) > 1.0 - 1e-12);
  assert_true(fabs(sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]) - 1.0) <
              1e-6);
  h = trace1(t, ray_inf(2.5f, 1.5f, 5.0f, 0, 0, -1));
  assert_tuv(&h, 8.0, 0.25, 0.5);
  assert_int_equal(h.prim_id, 1);
  assert_int_equal(h.user_id, 12);

  /* misses: outside the triangle (u + v > 1), beyond tfar, before tnear, pointing away */
  h = trace1(t, ray_inf(0.6f, 0.6f, 5.0f, 0, 0, -1));
  assert_miss(&h);
  h = trace1(t, make_ray(0.25f, 0.5f, 5.0f, 0, 0, -1, 0.0f, 4.99f));
  assert_miss(&h);
  h = trace1(t, make_ray(0.25f, 0.5f, 5.0f, 0, 0, -1, 5.01f, INFINITY));
  assert_miss(&h);
  h = trace1(t, ray_inf(0.25f, 0.5f, 5.0f, 0, 0, 1));
  assert_miss(&h);
  h = trace1(t, ray_inf(4.01f, 1.0f, 5.0f, 0, 0, -1));
  assert_miss(&h);
  assert_error(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_ERROR_INVALID_ARGUMENT,
               "clr_tracer_mesh_interpolate");
  clr_tracer_release(t);
}

/* CLRENDER_EMBREE_ISA caps Embree's ISA: every accepted value traces the triangle and quad
 * exactly as above (Embree runs at most what the CPU has); anything else is refused by name. */
static void test_embree_isa_cap(void **state) {
  static const char *const isas[] = {"sse2", "sse4.2", "avx", "avx2", "avx512"};
  for (size_t i = 0; i < sizeof isas / sizeof *isas; ++i) {
    setenv("CLRENDER_EMBREE_ISA", isas[i], 1);
    test_triangle_and_quad(state);
  }
  setenv("CLRENDER_EMBREE_ISA", "avx9", 1);
  clr_tracer t = (clr_tracer)(uintptr_t)1; /* must come back NULL */
  assert_error(clr_tracer_create(&t), CLR_ERROR_INVALID_ARGUMENT, "CLRENDER_EMBREE_ISA=avx9");
  assert_null(t);
  unsetenv("CLRENDER_EMBREE_ISA");
}

/* ---- spheres ---- */

/* pbrt-v3 sphere uv of an object-space point. */
static void sphere_uv(const double p[3], double *u, double *v) {
  double phi = atan2(p[1], p[0]);
  if (phi < 0) phi += 2 * PI;
  double r = sqrt(dot3(p, p));
  *u = phi / (2 * PI);
  *v = (acos(p[2] / r) - PI) / (0 - PI);
}

static void test_sphere(void **state) {
  (void)state;
  clr_tracer t;
  assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
  float m[16];
  translate(m, 1, 2, 3);
  uint32_t id = 99;
  assert_int_equal(clr_tracer_add_sphere(t, 0, m, 2.0f, 7, &id), CLR_SUCCESS);
  assert_int_equal(id, 0);
  assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);

  /* from outside, through object point (1, 1, -sqrt 2): t = 13 - sqrt 2, phi = pi/4, theta = 3pi/4 */
  clr_hit h = trace1(t, ray_inf(2, 3, -10, 0, 0, 1));
  assert_int_equal(h.geom_id, 0);
  assert_int_equal(h.user_id, 7);
  assert_int_equal(h.prim_id, 0);
  assert_int_equal(h.inst_id, CLR_TRACER_INVALID_ID);
  assert_rel(h.t, 13 - sqrt(2.0), 1e-6);
  assert_rel(h.u, 0.125, 1e-6);
  assert_rel(h.v, 0.25, 1e-6);
  double n_out[3] = {1, 1, -sqrt(2.0)};
  assert_true(cos_angle(h.ng, n_out) > 1 - 1e-10);
  float p[3], n[3], uv[2];
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_SUCCESS);
  assert_rel(p[0], 2, 1e-6);
  assert_rel(p[1], 3, 1e-6);
  assert_rel(p[2], 3 - sqrt(2.0), 1e-6);
  assert_true(cos_angle(n, n_out) > 1 - 1e-10);
  assert_true(uv[0] == h.u && uv[1] == h.v);

  /* tnear past the entry point: the exit point at 13 + sqrt 2, normal still outwards */
  h = trace1(t, make_ray(2, 3, -10, 0, 0, 1, 12.0f, INFINITY));
  assert_rel(h.t, 13 + sqrt(2.0), 1e-6);
  double n_exit[3] = {1, 1, sqrt(2.0)};
  assert_true(cos_angle(h.ng, n_exit) > 1 - 1e-10);

  /* from the centre with an unnormalised direction (1,2,2): t = radius / |d| = 2/3 */
  h = trace1(t, ray_inf(1, 2, 3, 1, 2, 2));
  assert_rel(h.t, 2.0 / 3.0, 1e-6);
  double n_in[3] = {1, 2, 2};
  assert_true(cos_angle(h.ng, n_in) > 1 - 1e-10);
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_SUCCESS);
  assert_rel(p[0], 1 + 2.0 / 3.0, 1e-6);
  assert_rel(p[1], 2 + 4.0 / 3.0, 1e-6);
  assert_rel(p[2], 3 + 4.0 / 3.0, 1e-6);

  /* misses: tangent-free pass beside the sphere, pointing away, tfar short of the surface */
  h = trace1(t, ray_inf(3.01f, 2, -10, 0, 0, 1));
  assert_miss(&h);
  h = trace1(t, ray_inf(2, 3, -10, 0, 0, -1));
  assert_miss(&h);
  h = trace1(t, make_ray(2, 3, -10, 0, 0, 1, 0.0f, 11.5f));
  assert_miss(&h);
  clr_tracer_release(t);
}

/* A sphere under a non-uniform scale, a rotation and a translation: hits at analytic points. */
static void test_transformed_sphere(void **state) {
  (void)state;
  const double radius = 1.5;
  float s[16], r[16], tr[16], rs[16], m[16];
  identity(s);
  s[0] = 1.0f, s[5] = 2.0f, s[10] = 0.5f;
  identity(r); /* 30 degrees about z, then nothing else */
  double c = cos(PI / 6), sn = sin(PI / 6);
  r[0] = (float)c, r[1] = (float)-sn, r[4] = (float)sn, r[5] = (float)c;
  translate(tr, -3, 4, 1);
  mul(r, s, rs);
  mul(tr, rs, m);
  clr_tracer t;
  assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
  assert_int_equal(clr_tracer_add_sphere(t, 0, m, (float)radius, 5, NULL), CLR_SUCCESS);
  assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
  /* inverse transpose of the linear part, for normals: R * S^-1 (R orthonormal) */
  float s_inv[16], nm[16];
  identity(s_inv);
  s_inv[0] = 1.0f, s_inv[5] = 0.5f, s_inv[10] = 2.0f;
  mul(r, s_inv, nm);
  for (int k = 0; k < 20; ++k) {
    double z = 2 * rnd() - 1, phi = 2 * PI * rnd(), q = sqrt(1 - z * z);
    double obj[3] = {radius * q * cos(phi), radius * q * sin(phi), radius * z};
    /* an entering object-space direction: inward plus a tangential part */
    double tangent[3] = {-obj[1], obj[0], 0.0};
    double d_obj[3] = {-obj[0] + 0.7 * tangent[0], -obj[1] + 0.7 * tangent[1], -obj[2]};
    double wp[3], d[3], t_true = 3.0 + 4.0 * rnd();
    apply_linear(m, obj, wp);
    for (int i = 0; i < 3; ++i) wp[i] += m[4 * i + 3];
    apply_linear(m, d_obj, d);
    clr_ray ray = ray_inf((float)(wp[0] - t_true * d[0]), (float)(wp[1] - t_true * d[1]),
                          (float)(wp[2] - t_true * d[2]), (float)d[0], (float)d[1], (float)d[2]);
    clr_hit h = trace1(t, ray);
    assert_int_equal(h.user_id, 5);
    assert_rel(h.t, t_true, 1e-5);
    double n_world[3];
    apply_linear(nm, obj, n_world);
    assert_true(cos_angle(h.ng, n_world) > 1 - 1e-9);
    double u, v;
    sphere_uv(obj, &u, &v);
    assert_true(fabs(h.u - u) < 1e-5 || fabs(fabs(h.u - u) - 1) < 1e-5); /* phi wraps at 0 */
    assert_true(fabs(h.v - v) < 1e-5);
    float p[3];
    assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, NULL, NULL), CLR_SUCCESS);
    for (int i = 0; i < 3; ++i) assert_true(fabs(p[i] - wp[i]) < 1e-4);
  }
  clr_tracer_release(t);
}

/* ---- instances ---- */

/* World: a triangle (user 1); group 1: the unit triangle (user 21) and, with_sphere, a sphere of
 * radius 1 at (5,0,0) (user 22); instance A = translate(0,0,10) scale 2 (user 31), instance B =
 * translate(0,-10,0) rotX(90) scale(1,3,1) (user 32). World ids: 0 triangle, 1 A, 2 B. */
static clr_tracer build_scene(int with_sphere) {
  clr_tracer t;
  assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
  static const float WP[] = {-5, -5, -20, 5, -5, -20, 0, 5, -20};
  clr_mesh world = mesh_of(NULL, 0, WP, 9, NULL, NULL);
  assert_int_equal(clr_tracer_add_mesh(t, 0, &world, 1, NULL), CLR_SUCCESS);
  clr_mesh_free(&world);
  int32_t g = -1;
  assert_int_equal(clr_tracer_new_group(t, &g), CLR_SUCCESS);
  assert_int_equal(g, 1);
  clr_mesh tri = unit_triangle();
  uint32_t id = 99;
  assert_int_equal(clr_tracer_add_mesh(t, g, &tri, 21, &id), CLR_SUCCESS);
  assert_int_equal(id, 0);
  clr_mesh_free(&tri);
  float m[16];
  translate(m, 5, 0, 0);
  if (with_sphere) {
    assert_int_equal(clr_tracer_add_sphere(t, g, m, 1.0f, 22, &id), CLR_SUCCESS);
    assert_int_equal(id, 1);
  }
  float a[16];
  identity(a);
  a[0] = a[5] = a[10] = 2.0f;
  a[11] = 10.0f;
  assert_int_equal(clr_tracer_add_instance(t, g, a, 31), CLR_SUCCESS);
  const float b[16] = {1, 0, 0, 0, 0, 0, -1, -10, 0, 3, 0, 0, 0, 0, 0, 1};
  assert_int_equal(clr_tracer_add_instance(t, g, b, 32), CLR_SUCCESS);
  assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
  return t;
}

static clr_tracer build_instanced_scene(void) { return build_scene(1); }

static void test_instances(void **state) {
  (void)state;
  clr_tracer t = build_instanced_scene();
  int32_t group;
  uint32_t user;
  assert_int_equal(clr_tracer_instance_info(t, 1, &group, &user), CLR_SUCCESS);
  assert_true(group == 1 && user == 31);
  assert_int_equal(clr_tracer_instance_info(t, 2, &group, &user), CLR_SUCCESS);
  assert_true(group == 1 && user == 32);
  assert_error(clr_tracer_instance_info(t, 0, &group, &user), CLR_ERROR_INVALID_ARGUMENT,
               "instance");
  assert_error(clr_tracer_instance_info(t, 3, &group, &user), CLR_ERROR_INVALID_ARGUMENT,
               "instance");

  /* instance A's triangle: world (0,0,10), (2,0,10), (0,2,10) */
  clr_hit h = trace1(t, ray_inf(0.5f, 1.0f, 20.0f, 0, 0, -1));
  assert_tuv(&h, 10.0, 0.25, 0.5);
  assert_int_equal(h.inst_id, 1);
  assert_int_equal(h.geom_id, 0);
  assert_int_equal(h.user_id, 21);
  double up[3] = {0, 0, 1};
  assert_true(cos_angle(h.ng, up) > 1 - 1e-12);
  float p[3], n[3], uv[2];
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_SUCCESS);
  assert_vec_near(p, (double[]){0.5, 1.0, 10.0}, 3, 4e-6);
  assert_true(n[0] == 0.0f && n[1] == 0.0f && n[2] == 1.0f);
  assert_vec_near(uv, (double[]){0.75, 0.5}, 2, 2e-6);

  /* instance B's triangle: world (0,-10,0), (1,-10,0), (0,-10,3); world normal is -y */
  h = trace1(t, ray_inf(0.25f, 0.0f, 1.5f, 0, -1, 0));
  assert_tuv(&h, 10.0, 0.25, 0.5);
  assert_int_equal(h.inst_id, 2);
  assert_int_equal(h.user_id, 21);
  double minus_y[3] = {0, -1, 0};
  assert_true(cos_angle(h.ng, minus_y) > 1 - 1e-12);
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_SUCCESS);
  assert_true(fabsf(p[0] - 0.25f) < 1e-6f && fabsf(p[1] + 10.0f) < 1e-6f &&
              fabsf(p[2] - 1.5f) < 1e-6f);
  assert_true(cos_angle(n, minus_y) > 1 - 1e-12);

  /* instance A's sphere: centre (10,0,10), radius 2; object point (0.6, 0, -0.8) at world z 8.4 */
  h = trace1(t, ray_inf(11.2f, 0.0f, 0.0f, 0, 0, 1));
  assert_rel(h.t, 8.4, 1e-6);
  assert_int_equal(h.inst_id, 1);
  assert_int_equal(h.geom_id, 1);
  assert_int_equal(h.user_id, 22);
  double n_sphere[3] = {0.6, 0, -0.8};
  assert_true(cos_angle(h.ng, n_sphere) > 1 - 1e-10);
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, n, uv), CLR_SUCCESS);
  assert_true(fabsf(p[0] - 11.2f) < 1e-5f && fabsf(p[1]) < 1e-5f && fabsf(p[2] - 8.4f) < 1e-5f);

  /* instance B's sphere: object (5,0,0) + unit sphere -> world centre (5,-10,0), ellipsoid
   * semi-axes x 1, y (object z) 1, z (object y) 3: from +z, hits at z = 3 */
  h = trace1(t, ray_inf(5.0f, -10.0f, 10.0f, 0, 0, -1));
  assert_rel(h.t, 7.0, 1e-6);
  assert_int_equal(h.inst_id, 2);
  assert_int_equal(h.user_id, 22);
  assert_true(cos_angle(h.ng, up) > 1 - 1e-10);

  /* the world triangle, not instanced */
  h = trace1(t, ray_inf(0.0f, 0.0f, 0.0f, 0, 0, -1));
  assert_rel(h.t, 20.0, 5e-7);
  assert_int_equal(h.inst_id, CLR_TRACER_INVALID_ID);
  assert_int_equal(h.geom_id, 0);
  assert_int_equal(h.user_id, 1);
  clr_tracer_release(t);
}

/* ---- packets, occlusion, threads ---- */

/* Random rays from a box around the instanced scene towards random points near its objects. */
static void random_rays(clr_ray *rays, int n) {
  static const double centres[5][3] = {
      {0.6, 0.6, 10}, {10, 0, 10}, {0.3, -10, 1}, {5, -10, 0}, {0, 0, -20}};
  for (int i = 0; i < n; ++i) {
    double o[3] = {24 * rnd() - 12, 24 * rnd() - 12, 30 * rnd() - 10}, target[3];
    const double *c = centres[(int)(5 * rnd())];
    for (int k = 0; k < 3; ++k) target[k] = c[k] + 3 * rnd() - 1.5;
    rays[i] = make_ray((float)o[0], (float)o[1], (float)o[2], (float)(target[0] - o[0]),
                       (float)(target[1] - o[1]), (float)(target[2] - o[2]), 0.0f,
                       rnd() < 0.2 ? (float)(2 * rnd()) : INFINITY);
  }
}

/* Packets (more rays than one loaded batch too) give the single-ray hits and occlusion, at the
 * device's packet width and at 16 (Embree's split of a 16-wide packet under SSE4.2); without the
 * sphere, occlusion past one loaded batch goes through Embree's ray stream. */
static void packets_equal_single(int expected_width, int with_sphere) {
  clr_tracer t = build_scene(with_sphere);
  int width = clr_tracer_packet_width(t);
  if (expected_width)
    assert_int_equal(width, expected_width);
  else
    assert_true(width == 8 || width == 16);
  enum { N = 600 };
  static clr_ray rays[N];
  static clr_hit packet[N], single[N];
  random_rays(rays, N);
  assert_int_equal(clr_tracer_intersect_single(t, rays, single, N), CLR_SUCCESS);
  int hit_count = 0, inst_count = 0;
  for (int i = 0; i < N; ++i)
    hit_count += single[i].geom_id != CLR_TRACER_INVALID_ID,
        inst_count += single[i].inst_id != CLR_TRACER_INVALID_ID;
  /* hits and misses both, through instances too (random_rays aims at objects) */
  if (hit_count < (with_sphere ? 180 : 100) || inst_count < (with_sphere ? 90 : 20) ||
      hit_count >= N)
    fail_msg("sphere %d: %d hits, %d in instances", with_sphere, hit_count, inst_count);
  static const int counts[] = {1, 7, 8, 9, 15, 16, 17, 100, 512, 513, 599};
  for (size_t c = 0; c < sizeof counts / sizeof counts[0]; ++c) {
    for (int i = 0; i < N; ++i) packet[i].t = -1.0f; /* detect writes past count */
    assert_int_equal(clr_tracer_intersect(t, rays, packet, counts[c]), CLR_SUCCESS);
    for (int i = 0; i < counts[c]; ++i)
      if (!hits_equal(&packet[i], &single[i]))
        fail_msg("width %d count %d ray %d: packet t %g geom %u, single t %g geom %u", width,
                 counts[c], i, (double)packet[i].t, packet[i].geom_id, (double)single[i].t,
                 single[i].geom_id);
    for (int i = counts[c]; i < N; ++i) assert_true(packet[i].t == -1.0f);
  }
  assert_int_equal(clr_tracer_intersect(t, rays, packet, 0), CLR_SUCCESS);

  /* occlusion agrees with the closest hits: occluded exactly when a hit exists */
  static uint8_t occ[N];
  static const int occ_counts[] = {1, 9, 17, 100, 513, 599, N};
  for (size_t c = 0; c < sizeof occ_counts / sizeof occ_counts[0]; ++c) {
    memset(occ, 7, sizeof occ);
    assert_int_equal(clr_tracer_occluded(t, rays, occ, occ_counts[c]), CLR_SUCCESS);
    for (int i = 0; i < occ_counts[c]; ++i)
      assert_int_equal(occ[i], single[i].geom_id != CLR_TRACER_INVALID_ID);
    for (int i = occ_counts[c]; i < N; ++i) assert_int_equal(occ[i], 7);
  }
  clr_tracer_release(t);
}

static void test_packets_equal_single(void **state) {
  (void)state;
  packets_equal_single(0, 1);
  packets_equal_single(0, 0);
  setenv("CLRENDER_EMBREE_ISA", "sse4.2", 1); /* no native 8-wide packets */
  packets_equal_single(16, 1);
  packets_equal_single(16, 0);
  unsetenv("CLRENDER_EMBREE_ISA");
}

static void test_occlusion_tfar(void **state) {
  (void)state;
  clr_tracer t = build_instanced_scene();
  clr_ray rays[] = {
      make_ray(0.5f, 1.0f, 20.0f, 0, 0, -1, 0.0f, 9.99f),  /* triangle at 10 beyond tfar */
      make_ray(0.5f, 1.0f, 20.0f, 0, 0, -1, 0.0f, 10.01f), /* within */
      make_ray(0.5f, 1.0f, 20.0f, 0, 0, -1, 0.0f, INFINITY),
      make_ray(0.5f, 1.0f, 20.0f, 0, 0, -1, 10.01f, 39.99f), /* tnear past it; world tri at 40 */
      make_ray(0.5f, 1.0f, 20.0f, 0, 0, -1, 10.01f, 40.01f),
      make_ray(11.2f, 0.0f, 0.0f, 0, 0, 1, 0.0f, 8.39f), /* sphere at 8.4 */
      make_ray(11.2f, 0.0f, 0.0f, 0, 0, 1, 0.0f, 8.41f),
      make_ray(11.2f, 0.0f, 0.0f, 0, 0, 1, 8.41f, 11.59f), /* between entry and exit (11.6) */
      make_ray(11.2f, 0.0f, 0.0f, 0, 0, 1, 8.41f, 11.61f),
      make_ray(30.0f, 30.0f, 0.0f, 0, 0, 1, 0.0f, INFINITY), /* nothing there */
  };
  static const uint8_t expected[] = {0, 1, 1, 0, 1, 0, 1, 0, 1, 0};
  enum { N = sizeof rays / sizeof rays[0] };
  uint8_t occ[N];
  assert_int_equal(clr_tracer_occluded(t, rays, occ, N), CLR_SUCCESS);
  for (int i = 0; i < N; ++i)
    if (occ[i] != expected[i]) fail_msg("ray %d: occluded %d, expected %d", i, occ[i], expected[i]);
  clr_tracer_release(t);
}

/* The occlusion and uv tests' sphere transform: scale (1.5, 0.75, 1), then translate (0.5, -1, 2). */
static void ellipsoid_to_world(float m[16]) {
  float s[16], tr[16];
  identity(s);
  s[0] = 1.5f, s[5] = 0.75f, s[10] = 1.0f;
  translate(tr, 0.5f, -1.0f, 2.0f);
  mul(tr, s, m);
}

/* Geometry 0: a sphere of radius 2 under `m`, whole or cut (z in [-1.2, 1.5], phi up to 250). */
static void add_whole_or_partial_sphere(clr_tracer t, const float m[16], int partial) {
  if (partial)
    assert_int_equal(clr_tracer_add_partial_sphere(t, 0, m, 2.0f, -1.2f, 1.5f, 250.0f, 3, NULL),
                     CLR_SUCCESS);
  else
    assert_int_equal(clr_tracer_add_sphere(t, 0, m, 2.0f, 3, NULL), CLR_SUCCESS);
}

/* Occlusion of whole and partial spheres (transformed) agrees with intersection, ray by ray:
 * occluded exactly when the closest hit lies within [tnear, tfar]. Rays start outside, inside
 * and on the far side, with tfar before, between and past the roots. */
static void test_sphere_occlusion_matches_hits(void **state) {
  (void)state;
  float m[16];
  ellipsoid_to_world(m);
  for (int partial = 0; partial < 2; ++partial) {
    clr_tracer t;
    assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
    add_whole_or_partial_sphere(t, m, partial);
    assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
    enum { N = 4000 };
    clr_ray *rays = calloc(N, sizeof *rays);
    clr_hit *hits = calloc(N, sizeof *hits);
    uint8_t *occ = calloc(N, 1);
    assert_true(rays && hits && occ);
    for (int i = 0; i < N; ++i) {
      double o[3] = {0.5 + 8 * rnd() - 4, -1.0 + 8 * rnd() - 4, 2.0 + 8 * rnd() - 4};
      double target[3] = {0.5 + 3 * rnd() - 1.5, -1.0 + 3 * rnd() - 1.5, 2.0 + 3 * rnd() - 1.5};
      float d[3] = {(float)(target[0] - o[0]), (float)(target[1] - o[1]),
                    (float)(target[2] - o[2])};
      float tnear = i % 3 == 0 ? (float)(0.5 * rnd()) : 0.0f;
      float tfar = i % 4 == 0 ? INFINITY : (float)(tnear + 2.0 * rnd());
      rays[i] = make_ray((float)o[0], (float)o[1], (float)o[2], d[0], d[1], d[2], tnear, tfar);
    }
    assert_int_equal(clr_tracer_intersect(t, rays, hits, N), CLR_SUCCESS);
    assert_int_equal(clr_tracer_occluded(t, rays, occ, N), CLR_SUCCESS);
    int hit_count = 0;
    for (int i = 0; i < N; ++i) {
      int hit = hits[i].geom_id != CLR_TRACER_INVALID_ID;
      hit_count += hit;
      if (occ[i] != hit)
        fail_msg("%s sphere, ray %d: occluded %d, closest hit %d (t %g, tfar %g)",
                 partial ? "partial" : "whole", i, occ[i], hit, (double)hits[i].t,
                 (double)rays[i].tfar);
    }
    assert_true(hit_count > N / 10 && hit_count < N - N / 10); /* both answers are exercised */
    free(rays);
    free(hits);
    free(occ);
    clr_tracer_release(t);
  }
}

/* Packets (the whole sphere's two-lane path) equal single rays at the edges of the range: rays
 * whose tfar or tnear is exactly a first hit's float distance, or one float short of it. The
 * range test compares the root rounded to float, so tfar = t still hits. */
static void test_sphere_packets_at_root_bounds(void **state) {
  (void)state;
  float m[16];
  ellipsoid_to_world(m);
  enum { N = 2000 };
  clr_ray *rays = calloc(N, sizeof *rays), *edge = calloc(N, sizeof *edge);
  clr_hit *first = calloc(N, sizeof *first), *single = calloc(N, sizeof *single),
          *packet = calloc(N, sizeof *packet);
  uint8_t *occ = calloc(N, 1);
  assert_true(rays && edge && first && single && packet && occ);
  for (int i = 0; i < N; ++i) {
    double o[3] = {0.5 + 8 * rnd() - 4, -1.0 + 8 * rnd() - 4, 2.0 + 8 * rnd() - 4};
    double target[3] = {0.5 + 3 * rnd() - 1.5, -1.0 + 3 * rnd() - 1.5, 2.0 + 3 * rnd() - 1.5};
    rays[i] = make_ray((float)o[0], (float)o[1], (float)o[2], (float)(target[0] - o[0]),
                       (float)(target[1] - o[1]), (float)(target[2] - o[2]), 0.0f, INFINITY);
  }
  for (int partial = 0; partial < 2; ++partial) {
    clr_tracer t;
    assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
    add_whole_or_partial_sphere(t, m, partial);
    assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
    assert_int_equal(clr_tracer_intersect_single(t, rays, first, N), CLR_SUCCESS);
    for (int bound = 0; bound < 3; ++bound) { /* tfar = t, tfar one float short, tnear = t */
      int hits_at_tfar = 0, hit_rays = 0;
      for (int i = 0; i < N; ++i) {
        edge[i] = rays[i];
        if (first[i].geom_id == CLR_TRACER_INVALID_ID) continue;
        ++hit_rays;
        if (bound == 0) edge[i].tfar = first[i].t;
        if (bound == 1) edge[i].tfar = nextafterf(first[i].t, 0.0f);
        if (bound == 2) edge[i].tnear = first[i].t;
      }
      assert_int_equal(clr_tracer_intersect_single(t, edge, single, N), CLR_SUCCESS);
      assert_int_equal(clr_tracer_intersect(t, edge, packet, N), CLR_SUCCESS);
      assert_int_equal(clr_tracer_occluded(t, edge, occ, N), CLR_SUCCESS);
      for (int i = 0; i < N; ++i) {
        int hit = single[i].geom_id != CLR_TRACER_INVALID_ID;
        hits_at_tfar += bound == 0 && hit && single[i].t == first[i].t;
        if (!hits_equal(&packet[i], &single[i]) || occ[i] != hit)
          fail_msg(
              "%s sphere, bound %d, ray %d: packet t %a geom %u, single t %a geom %u, "
              "occluded %d",
              partial ? "partial" : "whole", bound, i, (double)packet[i].t, packet[i].geom_id,
              (double)single[i].t, single[i].geom_id, occ[i]);
      }
      assert_true(hit_rays > N / 10);
      if (bound == 0) assert_int_equal(hits_at_tfar, hit_rays);
    }
    clr_tracer_release(t);
  }
  free(rays);
  free(edge);
  free(first);
  free(single);
  free(packet);
  free(occ);
}

/* Rays that start just off the surface (offsets from 1e-2 down to 1e-7 of the radius), as AO
 * and shadow rays do, in every direction: packets (whose two-lane path skips the roots of rays
 * leaving the sphere) give the single-ray hits and occlusion. Leaving rays miss, entering hit. */
static void test_sphere_rays_leaving_surface(void **state) {
  (void)state;
  float m[16];
  ellipsoid_to_world(m);
  clr_tracer t;
  assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
  add_whole_or_partial_sphere(t, m, 0);
  assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
  enum { N = 3000 };
  clr_ray *rays = calloc(N, sizeof *rays);
  clr_hit *single = calloc(N, sizeof *single), *packet = calloc(N, sizeof *packet);
  uint8_t *occ = calloc(N, 1);
  int *leaving = calloc(N, sizeof *leaving);
  assert_true(rays && single && packet && occ && leaving);
  for (int i = 0; i < N; ++i) {
    double n[3], d[3], len = 0.0, along = 0.0; /* object space: a unit normal and a direction */
    for (int k = 0; k < 3; ++k) n[k] = 2 * rnd() - 1, d[k] = 2 * rnd() - 1;
    for (int k = 0; k < 3; ++k) len += n[k] * n[k];
    for (int k = 0; k < 3; ++k) n[k] /= sqrt(len), along += n[k] * d[k];
    double offset = pow(10.0, -2.0 - 5.0 * rnd()), r = 2.0 * (1.0 + offset); /* radius 2 */
    leaving[i] = along > 0.05 && offset > 1e-5; /* below, float origins may fall inside */
    double o[3] = {r * n[0], r * n[1], r * n[2]}, w[3], v[3]; /* ellipsoid_to_world's map */
    w[0] = 1.5 * o[0] + 0.5, w[1] = 0.75 * o[1] - 1.0, w[2] = o[2] + 2.0;
    v[0] = 1.5 * d[0], v[1] = 0.75 * d[1], v[2] = d[2];
    rays[i] = make_ray((float)w[0], (float)w[1], (float)w[2], (float)v[0], (float)v[1], (float)v[2],
                       0.0f, i % 5 == 0 ? 3.0f : INFINITY);
  }
  assert_int_equal(clr_tracer_intersect_single(t, rays, single, N), CLR_SUCCESS);
  assert_int_equal(clr_tracer_intersect(t, rays, packet, N), CLR_SUCCESS);
  assert_int_equal(clr_tracer_occluded(t, rays, occ, N), CLR_SUCCESS);
  int left = 0, entered = 0;
  for (int i = 0; i < N; ++i) {
    int hit = single[i].geom_id != CLR_TRACER_INVALID_ID;
    if (!hits_equal(&packet[i], &single[i]) || occ[i] != hit)
      fail_msg("ray %d (leaving %d): packet t %a geom %u, single t %a geom %u, occluded %d", i,
               leaving[i], (double)packet[i].t, packet[i].geom_id, (double)single[i].t,
               single[i].geom_id, occ[i]);
    if (leaving[i]) {
      assert_false(hit);
      ++left;
    } else if (hit) {
      ++entered;
    }
  }
  if (left < N / 5 || entered < N / 5) fail_msg("%d rays left, %d entered", left, entered);
  clr_tracer_release(t);
  free(rays);
  free(single);
  free(packet);
  free(occ);
  free(leaving);
}

/* With clr_tracer_set_sphere_uv(0) a whole and a partial sphere's hits keep their t, normal and
 * ids bit for bit (the partial sphere's clipping still reads phi), and carry u = v = 0. */
static void test_sphere_uv_off_keeps_hits(void **state) {
  (void)state;
  float m[16];
  ellipsoid_to_world(m);
  enum { N = 4000 };
  clr_ray *rays = calloc(N, sizeof *rays);
  clr_hit *hits[2] = {calloc(N, sizeof(clr_hit)), calloc(N, sizeof(clr_hit))};
  assert_true(rays && hits[0] && hits[1]);
  for (int i = 0; i < N; ++i) {
    double o[3] = {0.5 + 8 * rnd() - 4, -1.0 + 8 * rnd() - 4, 2.0 + 8 * rnd() - 4};
    double target[3] = {0.5 + 3 * rnd() - 1.5, -1.0 + 3 * rnd() - 1.5, 2.0 + 3 * rnd() - 1.5};
    rays[i] = make_ray((float)o[0], (float)o[1], (float)o[2], (float)(target[0] - o[0]),
                       (float)(target[1] - o[1]), (float)(target[2] - o[2]), 0.0f, INFINITY);
  }
  for (int partial = 0; partial < 2; ++partial) {
    int hit_count = 0;
    for (int with_uv = 0; with_uv < 2; ++with_uv) {
      clr_tracer t;
      assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
      assert_int_equal(clr_tracer_set_sphere_uv(t, with_uv), CLR_SUCCESS);
      add_whole_or_partial_sphere(t, m, partial);
      assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
      assert_int_equal(clr_tracer_intersect(t, rays, hits[with_uv], N), CLR_SUCCESS);
      clr_tracer_release(t);
    }
    for (int i = 0; i < N; ++i) {
      clr_hit *a = &hits[0][i], *b = &hits[1][i];
      assert_int_equal(a->geom_id, b->geom_id);
      if (a->geom_id == CLR_TRACER_INVALID_ID) continue;
      ++hit_count;
      assert_true(a->u == 0.0f && a->v == 0.0f);
      assert_true(b->u >= 0.0f && b->u <= 1.0f && b->v >= 0.0f && b->v <= 1.0f);
      if (memcmp(&a->t, &b->t, sizeof a->t) || memcmp(a->ng, b->ng, sizeof a->ng) ||
          a->user_id != b->user_id || a->prim_id != b->prim_id)
        fail_msg("%s sphere, ray %d: t %a / %a", partial ? "partial" : "whole", i, (double)a->t,
                 (double)b->t);
    }
    assert_true(hit_count > N / 10);
  }
  assert_int_equal(clr_tracer_set_sphere_uv(NULL, 0), CLR_ERROR_NULL_POINTER);
  free(rays);
  free(hits[0]);
  free(hits[1]);
}

typedef struct thread_job {
  clr_tracer tracer;
  const clr_ray *rays;
  clr_hit *hits;
  uint8_t *occluded;
  int count, repeats;
  clr_result result;
} thread_job;

static void *run_job(void *arg) {
  thread_job *job = arg;
  job->result = CLR_SUCCESS;
  for (int r = 0; r < job->repeats && job->result == CLR_SUCCESS; ++r) {
    job->result = clr_tracer_intersect(job->tracer, job->rays, job->hits, job->count);
    if (job->result == CLR_SUCCESS)
      job->result = clr_tracer_occluded(job->tracer, job->rays, job->occluded, job->count);
  }
  return NULL;
}

static void test_threads(void **state) {
  (void)state;
  clr_tracer t = build_instanced_scene();
  enum { N = 20000 };
  clr_ray *rays = malloc(N * sizeof *rays);
  clr_hit *reference = malloc(N * sizeof *reference), *hits[2];
  uint8_t *occ_reference = malloc(N), *occ[2];
  assert_non_null(rays);
  assert_non_null(reference);
  assert_non_null(occ_reference);
  random_rays(rays, N);
  assert_int_equal(clr_tracer_intersect(t, rays, reference, N), CLR_SUCCESS);
  assert_int_equal(clr_tracer_occluded(t, rays, occ_reference, N), CLR_SUCCESS);
  pthread_t threads[2];
  thread_job jobs[2];
  for (int k = 0; k < 2; ++k) {
    hits[k] = malloc(N * sizeof *hits[k]);
    occ[k] = malloc(N);
    assert_non_null(hits[k]);
    assert_non_null(occ[k]);
    jobs[k] = (thread_job){t, rays, hits[k], occ[k], N, 3, CLR_ERROR_INTERNAL};
    assert_int_equal(pthread_create(&threads[k], NULL, run_job, &jobs[k]), 0);
  }
  for (int k = 0; k < 2; ++k) {
    assert_int_equal(pthread_join(threads[k], NULL), 0);
    assert_int_equal(jobs[k].result, CLR_SUCCESS);
    for (int i = 0; i < N; ++i) assert_true(hits_equal(&hits[k][i], &reference[i]));
    assert_memory_equal(occ[k], occ_reference, N);
    free(hits[k]);
    free(occ[k]);
  }
  free(rays);
  free(reference);
  free(occ_reference);
  clr_tracer_release(t);
}

/* ---- bad input ---- */

/* A moving instance (a unit triangle translated by 4 along x, turned 60 degrees about y and
 * scaled by 2 over the ray time [0, 1]) is placed, at every time, as pbrt-v3's AnimatedTransform
 * interpolates (translation lerp, rotation slerp, scale lerp) within 1e-5; a ray at time 0.5
 * hits the triangle where that transform puts it (point within 1e-4, normal within 1e-5 in
 * cosine), misses it at time 0, and bad decompositions are errors. */
static void test_motion_instance(void **state) {
  (void)state;
  clr_transform start = clr_transform_translate(0, 0, -10), tr = clr_transform_translate(4, 0, -10),
                rot = clr_transform_rotate(60, 0, 1, 0), sc = clr_transform_scale(2, 2, 2);
  clr_transform rs = clr_transform_compose(&rot, &sc);
  clr_transform end = clr_transform_compose(&tr, &rs);
  rs_animated_transform a;
  rs_animated_transform_init(&a, &start, &end, 0.0f, 1.0f);
  float scale[2][3];
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 3; ++i) scale[k][i] = a.s[k][i][i];
  clr_tracer t;
  assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
  int32_t g = -1;
  assert_int_equal(clr_tracer_new_group(t, &g), CLR_SUCCESS);
  clr_mesh tri = unit_triangle();
  assert_int_equal(clr_tracer_add_mesh(t, g, &tri, 7, NULL), CLR_SUCCESS);
  clr_mesh_free(&tri);
  float bad[2][3] = {{0, 0, NAN}, {0, 0, 0}};
  assert_error(clr_tracer_add_motion_instance(t, g, bad, a.q, scale, 5), CLR_ERROR_SCENE,
               "non-finite");
  assert_error(clr_tracer_add_motion_instance(t, 0, a.t, a.q, scale, 5), CLR_ERROR_INVALID_ARGUMENT,
               "out of range");
  assert_int_equal(clr_tracer_add_motion_instance(t, g, a.t, a.q, scale, 5), CLR_SUCCESS);
  assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
  const float times[] = {0.0f, 0.25f, 0.5f, 0.8f, 1.0f};
  for (size_t k = 0; k < sizeof times / sizeof times[0]; ++k) {
    float m[16];
    clr_transform want;
    rs_animated_transform_at(&a, times[k], &want);
    assert_int_equal(clr_tracer_instance_transform(t, 0, times[k], m), CLR_SUCCESS);
    for (int i = 0; i < 16; ++i) assert_true(fabsf(m[i] - want.m[i / 4][i % 4]) <= 1e-5f);
  }
  clr_transform mid;
  rs_animated_transform_at(&a, 0.5f, &mid);
  float c[3] = {1.0f / 3, 1.0f / 3, 0}, cw[3], nz[3] = {0, 0, 1}, nw[3];
  clr_transform_point(&mid, c, cw);
  clr_transform_normal(&mid, nz, nw);
  clr_ray r = make_ray(cw[0], cw[1], cw[2] + 5.0f, 0, 0, -1, 0.0f, INFINITY);
  r.time = 0.5f;
  clr_hit h = trace1(t, r);
  assert_int_equal(h.user_id, 7);
  assert_int_equal(h.inst_id, 0);
  assert_true(h.time == 0.5f);
  float p[3];
  assert_int_equal(clr_tracer_mesh_interpolate(t, &h, p, NULL, NULL), CLR_SUCCESS);
  for (int i = 0; i < 3; ++i) assert_true(fabsf(p[i] - cw[i]) <= 1e-4f);
  double n[3] = {nw[0], nw[1], nw[2]};
  assert_true(fabs(cos_angle(h.ng, n)) >= 1.0 - 1e-5);
  r.time = 0.0f; /* at the start the triangle spans x in [0, 1] only at z = -10 */
  h = trace1(t, r);
  assert_true(cw[0] > 1.0f);
  assert_int_equal(h.geom_id, CLR_TRACER_INVALID_ID);
  /* a packet's lanes at different times, each traced at its own (every lane of a full packet) */
  enum { LANES = 12 };
  clr_ray rays[LANES];
  clr_hit hits[LANES];
  for (int i = 0; i < LANES; ++i) {
    rays[i] = r;
    rays[i].time = i % 3 == 1 ? 0.0f : 0.5f;
  }
  assert_int_equal(clr_tracer_intersect(t, rays, hits, LANES), CLR_SUCCESS);
  for (int i = 0; i < LANES; ++i) {
    clr_hit one = trace1(t, rays[i]);
    assert_true(hits[i].time == rays[i].time);
    assert_int_equal(hits[i].geom_id, i % 3 == 1 ? CLR_TRACER_INVALID_ID : one.geom_id);
    assert_int_equal(one.user_id, i % 3 == 1 ? CLR_TRACER_INVALID_ID : 7u);
    assert_true(hits[i].t == one.t);
  }
  clr_tracer_release(t);
}

static void test_bad_input(void **state) {
  (void)state;
  assert_error(clr_tracer_create(NULL), CLR_ERROR_NULL_POINTER, "clr_tracer_create");
  clr_tracer_release(NULL);
  clr_tracer t;
  assert_int_equal(clr_tracer_create(&t), CLR_SUCCESS);
  float m[16];
  identity(m);
  clr_mesh tri = unit_triangle();
  int32_t g;
  uint32_t id;
  assert_error(clr_tracer_new_group(NULL, &g), CLR_ERROR_NULL_POINTER, "clr_tracer_new_group");
  assert_error(clr_tracer_new_group(t, NULL), CLR_ERROR_NULL_POINTER, "group_id");
  assert_error(clr_tracer_add_mesh(NULL, 0, &tri, 0, &id), CLR_ERROR_NULL_POINTER, "tracer");
  assert_error(clr_tracer_add_mesh(t, 0, NULL, 0, &id), CLR_ERROR_NULL_POINTER, "mesh");
  assert_error(clr_tracer_add_mesh(t, 1, &tri, 0, &id), CLR_ERROR_INVALID_ARGUMENT, "group 1");
  assert_error(clr_tracer_add_mesh(t, -1, &tri, 0, &id), CLR_ERROR_INVALID_ARGUMENT, "group -1");
  tri.indices[2] = 3; /* out of range */
  assert_error(clr_tracer_add_mesh(t, 0, &tri, 0, &id), CLR_ERROR_SCENE, "vertex index 3");
  tri.indices[2] = 2;
  tri.p[4] = NAN;
  assert_error(clr_tracer_add_mesh(t, 0, &tri, 0, &id), CLR_ERROR_SCENE, "not finite");
  tri.p[4] = 0.0f;
  clr_mesh empty = {0};
  assert_error(clr_tracer_add_mesh(t, 0, &empty, 0, &id), CLR_ERROR_SCENE, "no triangles");
  assert_error(clr_tracer_add_sphere(t, 0, NULL, 1.0f, 0, &id), CLR_ERROR_NULL_POINTER,
               "object_to_group");
  const float bad_radii[] = {0.0f, -1.0f, NAN, INFINITY};
  for (int i = 0; i < 4; ++i)
    assert_error(clr_tracer_add_sphere(t, 0, m, bad_radii[i], 0, &id), CLR_ERROR_SCENE, "radius");
  float singular[16];
  identity(singular);
  singular[5] = 0.0f;
  assert_error(clr_tracer_add_sphere(t, 0, singular, 1.0f, 0, &id), CLR_ERROR_SCENE,
               "object_to_group");
  float projective[16];
  identity(projective);
  projective[14] = 1.0f;
  assert_error(clr_tracer_add_sphere(t, 0, projective, 1.0f, 0, &id), CLR_ERROR_SCENE, "affine");
  assert_error(clr_tracer_add_instance(t, 0, m, 0), CLR_ERROR_INVALID_ARGUMENT, "group 0");
  assert_int_equal(clr_tracer_new_group(t, &g), CLR_SUCCESS);
  assert_error(clr_tracer_add_instance(t, g + 1, m, 0), CLR_ERROR_INVALID_ARGUMENT, "out of range");
  assert_error(clr_tracer_add_instance(t, g, singular, 0), CLR_ERROR_SCENE, "instance_to_world");
  assert_error(clr_tracer_add_instance(t, g, NULL, 0), CLR_ERROR_NULL_POINTER, "instance_to_world");

  /* queries before commit */
  clr_ray ray = ray_inf(0.25f, 0.25f, 1.0f, 0, 0, -1);
  clr_hit hit;
  uint8_t occ;
  assert_error(clr_tracer_intersect(t, &ray, &hit, 1), CLR_ERROR_INVALID_ARGUMENT, "not committed");
  assert_error(clr_tracer_occluded(t, &ray, &occ, 1), CLR_ERROR_INVALID_ARGUMENT, "not committed");
  assert_error(clr_tracer_commit(NULL), CLR_ERROR_NULL_POINTER, "clr_tracer_commit");

  assert_int_equal(clr_tracer_add_mesh(t, g, &tri, 0, &id), CLR_SUCCESS);
  assert_int_equal(clr_tracer_add_instance(t, g, m, 0), CLR_SUCCESS); /* world id 0 */
  assert_int_equal(clr_tracer_commit(t), CLR_SUCCESS);
  assert_error(clr_tracer_commit(t), CLR_ERROR_INVALID_ARGUMENT, "already committed");
  assert_error(clr_tracer_add_mesh(t, 0, &tri, 0, &id), CLR_ERROR_INVALID_ARGUMENT,
               "already committed");
  assert_error(clr_tracer_add_sphere(t, 0, m, 1.0f, 0, &id), CLR_ERROR_INVALID_ARGUMENT,
               "already committed");
  assert_error(clr_tracer_add_instance(t, g, m, 0), CLR_ERROR_INVALID_ARGUMENT,
               "already committed");
  assert_error(clr_tracer_new_group(t, &g), CLR_ERROR_INVALID_ARGUMENT, "already committed");
  clr_mesh_free(&tri);

  assert_int_equal(clr_tracer_intersect(t, &ray, &hit, 1), CLR_SUCCESS);
  assert_tuv(&hit, 1.0, 0.25, 0.25);
  assert_int_equal(hit.inst_id, 0);
  assert_error(clr_tracer_intersect(NULL, &ray, &hit, 1), CLR_ERROR_NULL_POINTER, "tracer");
  assert_error(clr_tracer_intersect(t, NULL, &hit, 1), CLR_ERROR_NULL_POINTER, "rays");
  assert_error(clr_tracer_intersect(t, &ray, NULL, 1), CLR_ERROR_NULL_POINTER, "output");
  assert_error(clr_tracer_intersect_single(t, &ray, NULL, 1), CLR_ERROR_NULL_POINTER, "output");
  assert_error(clr_tracer_occluded(t, &ray, NULL, 1), CLR_ERROR_NULL_POINTER, "output");
  assert_error(clr_tracer_intersect(t, &ray, &hit, -1), CLR_ERROR_INVALID_ARGUMENT, "count -1");
  assert_error(clr_tracer_occluded(t, &ray, &occ, -3), CLR_ERROR_INVALID_ARGUMENT, "count -3");
  clr_ray bad[] = {
      make_ray(NAN, 0, 0, 0, 0, 1, 0, INFINITY),     make_ray(0, 0, INFINITY, 0, 0, 1, 0, INFINITY),
      make_ray(0, 0, 0, 0, 0, 0, 0, INFINITY),       make_ray(0, 0, 0, 0, NAN, 1, 0, INFINITY),
      make_ray(0, 0, 0, 0, 0, 1, -1, INFINITY),      make_ray(0, 0, 0, 0, 0, 1, 0, NAN),
      make_ray(0, 0, 0, 0, 0, 1, INFINITY, INFINITY)};
  clr_ray batch[20];
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    for (int k = 0; k < 20; ++k) batch[k] = ray;
    batch[17] = bad[i];
    clr_hit hits[20];
    uint8_t occs[20];
    assert_error(clr_tracer_intersect(t, batch, hits, 20), CLR_ERROR_INVALID_ARGUMENT, "ray 17");
    assert_error(clr_tracer_intersect_single(t, batch, hits, 20), CLR_ERROR_INVALID_ARGUMENT,
                 "ray 17");
    assert_error(clr_tracer_occluded(t, batch, occs, 20), CLR_ERROR_INVALID_ARGUMENT, "ray 17");
  }
  /* nothing traced, outputs untouched, and the first bad ray named: calls checked in their
   * packets (up to 512 rays) and calls checked ray by ray first */
  enum { MANY = 600 };
  static clr_ray many[MANY];
  static clr_hit many_hits[MANY];
  static uint8_t many_occ[MANY];
  /* from the fifth on: the only bad ray, in each lane of a group of four */
  const int32_t counts[] = {16, 33, 512, MANY, MANY, MANY, MANY, MANY};
  const int32_t bad_at[] = {15, 32, 511, 517, 516, 517, 518, 599};
  for (int c = 0; c < 8; ++c)
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
      for (int k = 0; k < MANY; ++k) many[k] = ray;
      many[bad_at[c]] = bad[i];
      if (c < 4) many[MANY - 1] = bad[(i + 1) % (sizeof bad / sizeof bad[0])]; /* not named */
      memset(many_hits, 0x5a, sizeof many_hits);
      memset(many_occ, 0x5a, sizeof many_occ);
      char want[16];
      snprintf(want, sizeof want, "ray %d ", (int)bad_at[c]);
      assert_error(clr_tracer_intersect(t, many, many_hits, counts[c]), CLR_ERROR_INVALID_ARGUMENT,
                   want);
      assert_error(clr_tracer_occluded(t, many, many_occ, counts[c]), CLR_ERROR_INVALID_ARGUMENT,
                   want);
      for (int k = 0; k < MANY; ++k) {
        const unsigned char *h = (const unsigned char *)&many_hits[k];
        for (size_t b = 0; b < sizeof many_hits[k]; ++b) assert_int_equal(h[b], 0x5a);
        assert_int_equal(many_occ[k], 0x5a);
      }
    }
  /* a tfar below tnear is a valid empty segment */
  ray.tfar = -1.0f;
  assert_int_equal(clr_tracer_intersect(t, &ray, &hit, 1), CLR_SUCCESS);
  assert_miss(&hit);

  /* interpolation of hits that are not this tracer's */
  float p[3];
  clr_hit fake = {.t = 1, .geom_id = 0, .inst_id = CLR_TRACER_INVALID_ID};
  assert_error(clr_tracer_mesh_interpolate(t, &fake, p, NULL, NULL), CLR_ERROR_INVALID_ARGUMENT,
               "geom_id 0");
  fake.inst_id = 5;
  assert_error(clr_tracer_mesh_interpolate(t, &fake, p, NULL, NULL), CLR_ERROR_INVALID_ARGUMENT,
               "inst_id 5");
  fake.inst_id = 0;
  fake.prim_id = 1;
  assert_error(clr_tracer_mesh_interpolate(t, &fake, p, NULL, NULL), CLR_ERROR_INVALID_ARGUMENT,
               "prim_id 1");
  fake.geom_id = 1;
  assert_error(clr_tracer_mesh_interpolate(t, &fake, p, NULL, NULL), CLR_ERROR_INVALID_ARGUMENT,
               "geom_id 1");
  assert_error(clr_tracer_mesh_interpolate(t, NULL, p, NULL, NULL), CLR_ERROR_NULL_POINTER, "hit");
  assert_error(clr_tracer_mesh_interpolate(NULL, &fake, p, NULL, NULL), CLR_ERROR_NULL_POINTER,
               "tracer");
  clr_tracer_release(t);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_triangle_and_quad),
      cmocka_unit_test(test_embree_isa_cap),
      cmocka_unit_test(test_sphere),
      cmocka_unit_test(test_transformed_sphere),
      cmocka_unit_test(test_instances),
      cmocka_unit_test(test_packets_equal_single),
      cmocka_unit_test(test_occlusion_tfar),
      cmocka_unit_test(test_sphere_occlusion_matches_hits),
      cmocka_unit_test(test_sphere_packets_at_root_bounds),
      cmocka_unit_test(test_sphere_rays_leaving_surface),
      cmocka_unit_test(test_sphere_uv_off_keeps_hits),
      cmocka_unit_test(test_threads),
      cmocka_unit_test(test_motion_instance),
      cmocka_unit_test(test_bad_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
