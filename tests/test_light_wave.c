/* The structure-of-arrays triangle-light samples (integrators/light_wave.c) against the scalar
 * code the integrators run for other lights: the light sample (clr_render_scene_sample_light:
 * wi, Li, pdf, shadow ray) and the Lambertian value and pdf (lambertian.h), combined as
 * EstimateDirect does (power heuristic, f Li w / pdf; weight 1 for a point light). Same bits for
 * every entry: one-sided, two-sided and reversed triangle lights and a point light, surface
 * points above and below them, a point on a light's vertex or position (no sample), sample
 * values on the triangle's corners and edges. The shape wave's tests of MIS rays against
 * triangle lights (integrators/shape_wave.c) against clr_render_scene_light_may_hit: rays aimed
 * at the triangles' insides, vertices and edges, past them, in their planes, short of them. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "light_wave.h"
#include "shape_wave.h"
#include "render_scene.h"
#include "scene_parser.h"
#include "scene_test_util.h"

/* A one-sided square (two triangles) facing down at y = 4, a two-sided triangle, a reversed
 * one-sided triangle, a point light, a sphere light and a spot light (neither in a wave) and a
 * floor. */
static const char *const LIGHTS =
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [7.3 5.1 3.3] \"point from\" [0.5 2 1]\n"
    "LightSource \"spot\" \"rgb I\" [5 5 5] \"point from\" [0 5 0] \"point to\" [0 0 0]\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4.3 3.1 2.7]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
    "\"point P\" [-1 4 -1  1 4 -1  1 4 1  -1 4 1]\nAttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1.3 2.2 3.7] \"bool twosided\" true\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [3 0.5 -2  5 0.5 -2  4 3 -1]\n"
    "AttributeEnd\n"
    "AttributeBegin\nReverseOrientation\nAreaLightSource \"diffuse\" \"rgb L\" [2.9 2.1 1.7]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [-4 1 2  -2 1 2  -3 3 3]\n"
    "AttributeEnd\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nTranslate 0 6 6\n"
    "Shape \"sphere\" \"float radius\" [0.5]\nAttributeEnd\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
    "\"point P\" [-10 0 -10  10 0 -10  10 0 10  -10 0 10]\n"
    "WorldEnd\n";

#define WAVE_TEST_SEED 0x2545f4914f6cdd1dULL
#include "wave_test_random.h"

/* Surface k: a point in the box around the lights (every 50th on the square's corner, every 50th
 * on the point light),
 * a random geometric normal and a shading normal near it, a colour with a zero channel. */
static void make_surface(int k, clr_surface *s) {
  memset(s, 0, sizeof *s);
  for (int a = 0; a < 3; ++a) s->p[a] = 12.0f * uniform() - 6.0f;
  if (k % 50 == 7) {
    s->p[0] = -1.0f;
    s->p[1] = 4.0f;
    s->p[2] = -1.0f;
  }
  if (k % 50 == 8) {
    s->p[0] = 0.5f;
    s->p[1] = 2.0f;
    s->p[2] = 1.0f;
  }
  random_unit(s->ng);
  for (int a = 0; a < 3; ++a) s->ns[a] = s->ng[a] + 0.2f * (2.0f * uniform() - 1.0f);
  rs_normalize(s->ns);
  memcpy(s->n_geom, s->ng, sizeof s->ng);
  s->kd[0] = 0.7f;
  s->kd[1] = k % 9 == 0 ? 0.0f : 0.4f;
  s->kd[2] = 0.1f;
  s->on_a = 1.0f;
  s->has_material = 1;
}

static void make_u(int k, float u[2]) {
  static const float edge[][2] = {{0.0f, 0.0f},        {0.0f, 0.7f},
                                  {0.99999994f, 0.0f}, {0.99999994f, 0.99999994f},
                                  {0.25f, 1.0f},       {0.5f, 0.5f}};
  if (k % 4 == 0) {
    memcpy(u, edge[(k / 4) % 6], sizeof edge[0]);
  } else {
    u[0] = uniform();
    u[1] = uniform();
  }
}

static int same(const float *a, const float *b, size_t n) { return !memcmp(a, b, n * 4); }

/* Entry e's BSDF sample (u) at surface sf seen from wo against the scalar code: the Lambertian
 * direction, pdf and f |cos| / Kd (lambertian.h), the spawned ray's origin and the light's
 * shape test (clr_render_scene_light_may_hit); returns the test's answer. */
static int check_bsdf_sample(const clr_render_scene *scene, const clr_light_wave *w, int32_t e,
                             int light, const clr_surface *sf, const float wo[3],
                             const float u[2]) {
  float wi[3], pdf;
  clr_lambert_sample_dir(sf, wo, u, wi, &pdf);
  float fcos = clr_lambert_cos_plain(sf, wo, wi);
  const clr_lambert_wave *b = &w->bsdf;
  float got_wi[3] = {b->wi[0][e], b->wi[1][e], b->wi[2][e]};
  if (!same(got_wi, wi, 3) || !same(&b->pdf[e], &pdf, 1) || !same(&b->fcos[e], &fcos, 1))
    fail_msg("entry %d: wave wi (%a %a %a) pdf %a fcos %a, scalar (%a %a %a) %a %a", (int)e,
             got_wi[0], got_wi[1], got_wi[2], b->pdf[e], b->fcos[e], wi[0], wi[1], wi[2], pdf,
             fcos);
  clr_ray r;
  clr_render_scene_spawn_ray(sf, wi, &r);
  float o[3] = {r.ox, r.oy, r.oz},
        got_o[3] = {w->mis_origin[0][e], w->mis_origin[1][e], w->mis_origin[2][e]};
  if (!same(got_o, o, 3))
    fail_msg("entry %d: wave origin (%a %a %a), scalar (%a %a %a)", (int)e, got_o[0], got_o[1],
             got_o[2], o[0], o[1], o[2]);
  int may = clr_render_scene_light_may_hit(scene, light, &r);
  if ((w->mis_hit[e] != 0.0) != may)
    fail_msg("entry %d: wave shape test %g, scalar %d", (int)e, w->mis_hit[e], may);
  return may;
}

/* Entry e's next direction (values u) against the scalar Lambertian sample and spawned ray. */
static void check_next_sample(const clr_light_wave *w, int32_t e, const clr_surface *sf,
                              const float wo[3], const float u[2]) {
  float wi[3], pdf;
  clr_lambert_sample_dir(sf, wo, u, wi, &pdf);
  float fcos = clr_lambert_cos_plain(sf, wo, wi);
  clr_ray r;
  clr_render_scene_spawn_ray(sf, wi, &r);
  float o[3] = {r.ox, r.oy, r.oz};
  float got_wi[3] = {w->next_wi[0][e], w->next_wi[1][e], w->next_wi[2][e]};
  float got_o[3] = {w->next_origin[0][e], w->next_origin[1][e], w->next_origin[2][e]};
  if (!same(got_wi, wi, 3) || !same(&w->next_pdf[e], &pdf, 1) ||
      !same(&w->next_fcos[e], &fcos, 1) || !same(got_o, o, 3))
    fail_msg(
        "entry %d: wave next wi (%a %a %a) pdf %a fcos %a origin (%a %a %a), scalar "
        "(%a %a %a) %a %a (%a %a %a)",
        (int)e, got_wi[0], got_wi[1], got_wi[2], w->next_pdf[e], w->next_fcos[e], got_o[0],
        got_o[1], got_o[2], wi[0], wi[1], wi[2], pdf, fcos, o[0], o[1], o[2]);
}

/* The wave's entries of the lights of one kind against the scalar light sample. */
static void check_kind(const clr_render_scene *scene, clr_wave_light_kind kind) {
  int nl = clr_render_scene_light_count(scene), lights[8], nk = 0;
  static clr_light_triangle tris[8];
  static clr_light_point points[8];
  for (int j = 0; j < nl; ++j) {
    int tri = clr_render_scene_light_triangle(scene, j, &tris[j]);
    int point = clr_render_scene_light_point(scene, j, &points[j]);
    assert_false(tri && point);
    if (kind == CLR_WAVE_LIGHT_TRIANGLE ? tri : point) lights[nk++] = j;
  }
  assert_int_equal(nk, kind == CLR_WAVE_LIGHT_TRIANGLE ? 4 : 1);
  enum { N = 1003 };
  clr_light_wave w;
  memset(&w, 0, sizeof w);
  assert_int_equal(clr_light_wave_reserve(&w, N), CLR_SUCCESS);
  static clr_surface surfaces[N];
  static float wo[N][3], u[N][2], ub[N][2], un[N][2];
  static int light[N];
  static int32_t entry[N];
  /* sample k of light k % nk; triangle lights' grouped by light: group g holds samples g,
   * g + nk, ... */
  int32_t first[8], next = 0;
  for (int g = 0; g < nk && kind == CLR_WAVE_LIGHT_TRIANGLE; ++g) {
    int32_t count = (N - g + nk - 1) / nk;
    first[g] = clr_light_wave_group(&w, count, &tris[lights[g]]);
    assert_int_equal(first[g], next);
    next += count;
  }
  for (int k = 0; k < N; ++k) {
    make_surface(k, &surfaces[k]);
    random_unit(wo[k]);
    make_u(k, u[k]);
    make_u(k + 1, ub[k]);
    make_u(k + 2, un[k]);
    if (k % 10 == 7) un[k][0] = 1.0f;
    if (k % 10 == 3) ub[k][0] = 1.0f; /* clamped below 1 */
    if (k % 3) {                      /* a tangent (else none: the frame's axis fallback) */
      surfaces[k].dpdu[0] = surfaces[k].p[1];
      surfaces[k].dpdu[1] = -surfaces[k].p[0];
      surfaces[k].dpdu[2] = 0.3f;
    }
    light[k] = lights[k % nk];
    if (kind == CLR_WAVE_LIGHT_TRIANGLE) {
      entry[k] = first[k % nk] + k / nk;
      clr_light_wave_put(&w, entry[k], &surfaces[k], wo[k], u[k], ub[k], k % 5 == 1 ? NULL : un[k]);
    } else {
      entry[k] = clr_light_wave_push_point(&w, &surfaces[k], wo[k], &points[light[k]]);
      assert_int_equal(entry[k], k);
    }
  }
  assert_int_equal(w.n, N);
  if (kind == CLR_WAVE_LIGHT_TRIANGLE)
    clr_light_wave_sample(&w);
  else
    clr_light_wave_sample_points(&w);
  int used = 0, unlit = 0, may_hit = 0;
  for (int k = 0; k < N; ++k) {
    const clr_surface *sf = &surfaces[k];
    if (kind == CLR_WAVE_LIGHT_TRIANGLE) { /* the BSDF sample, its ray and its shape test */
      may_hit += check_bsdf_sample(scene, &w, entry[k], light[k], sf, wo[k], ub[k]);
      if (k % 5 != 1) check_next_sample(&w, entry[k], sf, wo[k], un[k]);
    }
    clr_light_sample ls;
    clr_render_scene_sample_light(scene, light[k], sf->p, sf->ng, u[k], &ls);
    assert_int_equal(ls.is_delta, kind == CLR_WAVE_LIGHT_POINT);
    int use = 0;
    float contrib[3] = {0, 0, 0};
    if (ls.pdf > 0.0f && !(ls.li[0] == 0.0f && ls.li[1] == 0.0f && ls.li[2] == 0.0f)) {
      float fc = clr_lambert_cos_plain(sf, wo[k], ls.wi), f[3];
      for (int a = 0; a < 3; ++a) f[a] = sf->kd[a] * fc;
      if (fc > 0.0f && !(f[0] == 0.0f && f[1] == 0.0f && f[2] == 0.0f)) {
        float bp = clr_lambert_pdf(sf, wo[k], ls.wi), l2 = ls.pdf * ls.pdf, b2 = bp * bp;
        float mis = (l2 + b2) > 0.0f ? l2 / (l2 + b2) : 0.0f; /* pbrt PowerHeuristic(1, ., 1, .) */
        if (ls.is_delta) mis = 1.0f;
        for (int a = 0; a < 3; ++a) contrib[a] = f[a] * ls.li[a] * mis / ls.pdf;
        use = 1;
      }
    }
    if (w.use[entry[k]] != use)
      fail_msg("entry %d (light %d): wave use %d, scalar %d", k, light[k], w.use[entry[k]], use);
    used += use;
    unlit += !(ls.pdf > 0.0f);
    if (!use) continue;
    float got_c[3] = {w.contrib[0][entry[k]], w.contrib[1][entry[k]], w.contrib[2][entry[k]]};
    float got_o[3] = {w.origin[0][entry[k]], w.origin[1][entry[k]], w.origin[2][entry[k]]};
    float got_d[3] = {w.dir[0][entry[k]], w.dir[1][entry[k]], w.dir[2][entry[k]]};
    float o[3] = {ls.shadow.ox, ls.shadow.oy, ls.shadow.oz};
    float d[3] = {ls.shadow.dx, ls.shadow.dy, ls.shadow.dz};
    if (!same(got_c, contrib, 3) || !same(got_o, o, 3) || !same(got_d, d, 3) ||
        !same(&w.tfar[entry[k]], &ls.shadow.tfar, 1))
      fail_msg("entry %d (light %d): wave contrib (%a %a %a) tfar %a, scalar (%a %a %a) %a", k,
               light[k], got_c[0], got_c[1], got_c[2], w.tfar[entry[k]], contrib[0], contrib[1],
               contrib[2], ls.shadow.tfar);
    assert_true(ls.shadow.tnear == 0.0f);
  }
  assert_true(used > N / 10 && used < N); /* both outcomes exercised */
  assert_true(unlit > 0);                 /* the points on the light */
  if (kind == CLR_WAVE_LIGHT_TRIANGLE) assert_true(may_hit > 0 && may_hit < N / 2);
  clr_light_wave_free(&w);
}

static void test_waves_equal_scalar(void **state) {
  (void)state;
  clr_scene_desc *desc = NULL;
  clr_render_scene *scene = stu_build(LIGHTS, CLR_BINARY_DIR "/lightwave.pbrt", &desc);
  assert_int_equal(clr_render_scene_light_count(scene), 7);
  check_kind(scene, CLR_WAVE_LIGHT_TRIANGLE);
  check_kind(scene, CLR_WAVE_LIGHT_POINT);
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

/* Ray k toward triangle t: aimed at a point of barycentrics on a vertex, an edge or inside it
 * (some just outside), from a random origin or one in the triangle's plane; tfar short of the
 * point for some, tnear beyond it for others; from the vertices with tnear -1 and 0. */
static void make_shape_ray(int k, const clr_light_triangle *t, clr_ray *r) {
  float b1 = uniform(), b2 = uniform();
  switch (k % 7) {
    case 0:
      b1 = 0.0f, b2 = 0.0f;
      break; /* vertex p0 */
    case 1:
      b1 = 1.0f, b2 = 0.0f;
      break; /* vertex p1 */
    case 2:
      b2 = 1.0f - b1;
      break; /* edge p1 p2 */
    case 3:
      b2 = 0.0f;
      break; /* edge p0 p1 */
    case 4:
      b1 = 1.1f * b1, b2 = 1.1f * b2 * (1.0f - b1);
      break; /* around the triangle */
    default:
      if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
  }
  float target[3], o[3], d[3];
  for (int a = 0; a < 3; ++a)
    target[a] = (1.0f - b1 - b2) * t->p0[a] + b1 * t->p1[a] + b2 * t->p2[a];
  if (k % 23 == 5) /* in the triangle's plane */
    for (int a = 0; a < 3; ++a) o[a] = t->p0[a] + 2.0f * (t->p0[a] - t->p1[a]);
  else
    for (int a = 0; a < 3; ++a) o[a] = 12.0f * uniform() - 6.0f;
  for (int a = 0; a < 3; ++a) d[a] = target[a] - o[a];
  float dist = sqrtf(rs_dot(d, d));
  rs_normalize(d);
  *r = (clr_ray){.ox = o[0], .oy = o[1], .oz = o[2], .dx = d[0], .dy = d[1], .dz = d[2]};
  r->tnear = k % 11 == 3 ? 1.01f * dist : 0.0f;
  r->tfar = k % 13 == 4 ? 0.99f * dist : k % 13 == 6 ? dist : INFINITY;
  if (k % 17 == 2) r->dx = -r->dx, r->dy = -r->dy, r->dz = -r->dz; /* away from it */
  if (k % 29 == 9 || k % 29 == 10) { /* from a vertex: u, v, t exactly 0 or u + v exactly 1 */
    const float *v = (k / 29) % 3 == 0 ? t->p0 : (k / 29) % 3 == 1 ? t->p1 : t->p2;
    *r = (clr_ray){.ox = v[0], .oy = v[1], .oz = v[2], .dx = 0.25f, .dy = -0.5f, .dz = 0.75f};
    r->tnear = k % 29 == 9 ? -1.0f : 0.0f;
    r->tfar = INFINITY;
  }
}

static void test_shape_wave_equals_scalar(void **state) {
  (void)state;
  clr_scene_desc *desc = NULL;
  clr_render_scene *scene = stu_build(LIGHTS, CLR_BINARY_DIR "/shapewave.pbrt", &desc);
  int nl = clr_render_scene_light_count(scene), lights[8], nt = 0;
  static clr_light_triangle tris[8];
  for (int j = 0; j < nl; ++j)
    if (clr_render_scene_light_triangle(scene, j, &tris[j])) lights[nt++] = j;
  assert_int_equal(nt, 4);
  enum { N = 2011 };
  clr_shape_wave w;
  memset(&w, 0, sizeof w);
  assert_int_equal(clr_shape_wave_reserve(&w, N), CLR_SUCCESS);
  static clr_ray rays[N];
  static int light[N];
  for (int k = 0; k < N; ++k) {
    light[k] = lights[(k / 7) % nt];
    make_shape_ray(k, &tris[light[k]], &rays[k]);
    assert_int_equal(clr_shape_wave_push(&w, &rays[k], &tris[light[k]]), k);
  }
  clr_shape_wave_test(&w);
  int hits = 0;
  for (int k = 0; k < N; ++k) {
    int scalar = clr_render_scene_light_may_hit(scene, light[k], &rays[k]);
    if ((w.hit[k] != 0.0) != scalar || (w.hit[k] != 0.0 && w.hit[k] != 1.0))
      fail_msg("ray %d (light %d): wave %g, scalar %d", k, light[k], w.hit[k], scalar);
    hits += scalar;
  }
  assert_true(hits > N / 4 && hits < 3 * N / 4); /* both outcomes exercised */
  clr_shape_wave_free(&w);
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_waves_equal_scalar),
      cmocka_unit_test(test_shape_wave_equals_scalar),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
