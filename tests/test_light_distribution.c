/* pbrt-v3's SpatialLightDistribution (integrators/light_distribution.c): a voxel's cdf against
 * its definition evaluated here (128 Halton points per voxel, luminance of Li / pdf per light, a
 * floor of 0.001 times the average), a physical check of the shares (a square light overhead
 * against a distant point light), lookups by point and by voxel index agreeing, and the light
 * samples it uses (no shadow ray) equal to the integrators' for every light type. */
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
#include "light_distribution.h"
#include "render_scene.h"
#include "scene_parser.h"
#include "scene_test_util.h"
#include "lcg_test_random.h"

/* A one-sided square light (two triangles, facing down) 4 above a floor, a point light off to
 * the side. */
static const char *const SQUARE_AND_POINT =
    "WorldBegin\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4 4 4]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
    "\"point P\" [-1 4 -1  1 4 -1  1 4 1  -1 4 1]\nAttributeEnd\n"
    "LightSource \"point\" \"point from\" [8 1 8] \"rgb I\" [20 20 20]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
    "\"point P\" [-10 0 -10  10 0 -10  10 0 10  -10 0 10]\n"
    "WorldEnd\n";

static clr_render_scene *build(const char *text, clr_scene_desc **desc) {
  return stu_build(text, CLR_BINARY_DIR "/lightdist.pbrt", desc);
}

static double radical_inverse(unsigned base, unsigned i) {
  double r = 0.0, f = 1.0 / base;
  for (; i; i /= base, f /= base) r += (double)(i % base) * f;
  return r;
}

/* The cdf of the voxel holding p by pbrt-v3's ComputeDistribution, in double. */
static void reference_cdf(const clr_render_scene *scene, const float p[3], double *cdf) {
  int n = clr_render_scene_light_count(scene), res[3], v[3];
  float lo[3], hi[3], bmax = 0.0f;
  clr_render_scene_world_bounds(scene, lo, hi);
  for (int i = 0; i < 3; ++i) bmax = fmaxf(bmax, hi[i] - lo[i]);
  double v0[3], v1[3];
  for (int i = 0; i < 3; ++i) {
    res[i] = (int)lround((hi[i] - lo[i]) / bmax * 64.0);
    if (res[i] < 1) res[i] = 1;
    v[i] = (int)((p[i] - lo[i]) / (hi[i] - lo[i]) * res[i]);
    if (v[i] > res[i] - 1) v[i] = res[i] - 1;
    if (v[i] < 0) v[i] = 0;
    v0[i] = lo[i] + (hi[i] - lo[i]) * v[i] / res[i];
    v1[i] = lo[i] + (hi[i] - lo[i]) * (v[i] + 1) / res[i];
  }
  double *contrib = calloc((size_t)n, sizeof *contrib), sum = 0.0;
  assert_non_null(contrib);
  static const unsigned bases[5] = {2, 3, 5, 7, 11};
  for (unsigned s = 0; s < 128; ++s) {
    float po[3], u[2] = {(float)radical_inverse(bases[3], s), (float)radical_inverse(bases[4], s)};
    for (int i = 0; i < 3; ++i) {
      double t = radical_inverse(bases[i], s);
      po[i] = (float)((1.0 - t) * v0[i] + t * v1[i]);
    }
    const float zero[3] = {0.0f, 0.0f, 0.0f};
    for (int j = 0; j < n; ++j) {
      clr_light_sample ls;
      clr_render_scene_sample_light(scene, j, po, zero, u, &ls);
      if (ls.pdf > 0.0f)
        contrib[j] += (0.212671 * ls.li[0] + 0.715160 * ls.li[1] + 0.072169 * ls.li[2]) / ls.pdf;
    }
  }
  for (int j = 0; j < n; ++j) sum += contrib[j];
  double floor_c = sum > 0.0 ? 0.001 * sum / (128.0 * n) : 1.0, total = 0.0;
  for (int j = 0; j < n; ++j) total += contrib[j] = fmax(contrib[j], floor_c);
  cdf[0] = 0.0;
  for (int j = 0; j < n; ++j) cdf[j + 1] = cdf[j] + contrib[j] / total;
  free(contrib);
}

static void test_voxel_cdf_values(void **state) {
  (void)state;
  clr_scene_desc *desc = NULL;
  clr_render_scene *scene = build(SQUARE_AND_POINT, &desc);
  assert_int_equal(clr_render_scene_light_count(scene), 3);
  clr_light_distribution *d = NULL;
  assert_int_equal(clr_light_distribution_create(scene, &d), CLR_SUCCESS);
  const float points[4][3] = {
      {0.05f, 0.0f, 0.05f}, {-7.3f, 0.0f, 6.1f}, {9.9f, 0.0f, -9.9f}, {2.5f, 3.0f, 0.4f}};
  for (int k = 0; k < 4; ++k) {
    double want[4];
    reference_cdf(scene, points[k], want);
    const float *cdf = clr_light_distribution_lookup(d, points[k]);
    assert_non_null(cdf);
    for (int j = 0; j <= 3; ++j) {
      if (fabs(cdf[j] - want[j]) > 1e-4)
        fail_msg("point %d cdf[%d] %.8f want %.8f", k, j, cdf[j], want[j]);
    }
  }
  /* below the square light's centre: the two triangles share its ~1 of Li/pdf about equally
   * (E = L A cos cos / d^2 ~ 4 * 4 / 16), the point light adds I / d^2 = 20 / 129 */
  int point_light = -1;
  for (int j = 0; j < 3; ++j) {
    clr_light_info info;
    clr_render_scene_light_info(scene, j, &info);
    if (info.is_delta) point_light = j;
  }
  assert_true(point_light >= 0);
  const float *cdf = clr_light_distribution_lookup(d, points[0]);
  float share = cdf[point_light + 1] - cdf[point_light];
  if (!(share > 0.10f && share < 0.17f)) fail_msg("point light share %g", share);
  for (int j = 0; j < 3; ++j)
    if (j != point_light && fabsf((cdf[j + 1] - cdf[j]) - 0.5f * (1.0f - share)) > 0.05f)
      fail_msg("triangle %d share %g", j, cdf[j + 1] - cdf[j]);
  clr_light_distribution_free(d);
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

/* A lookup by point and one by its voxel index give the same cdf, computed once. */
static void test_lookup_by_voxel(void **state) {
  (void)state;
  clr_scene_desc *desc = NULL;
  clr_render_scene *scene = build(SQUARE_AND_POINT, &desc);
  clr_light_distribution *d = NULL;
  assert_int_equal(clr_light_distribution_create(scene, &d), CLR_SUCCESS);
  uint32_t s = 7u;
  for (int k = 0; k < 2000; ++k) {
    float p[3];
    for (int i = 0; i < 3; ++i) p[i] = lcg_float(&s) * 26.0f - 13.0f; /* past the bounds too */
    size_t voxel = clr_light_distribution_voxel(d, p);
    clr_light_distribution_prefetch(d, voxel);
    const float *by_voxel = clr_light_distribution_lookup_voxel(d, voxel);
    const float *by_point = clr_light_distribution_lookup(d, p);
    assert_non_null(by_voxel);
    assert_ptr_equal(by_voxel, by_point);
    assert_true(by_voxel[0] == 0.0f && by_voxel[3] == 1.0f);
  }
  clr_light_distribution_free(d);
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

/* clr_render_scene_sample_light_li gives sample_light's wi, li, pdf and is_delta, and no shadow
 * ray, for every kind of light. */
static void test_sample_li_matches(void **state) {
  (void)state;
  clr_scene_desc *desc = NULL;
  clr_render_scene *scene = build(
      "WorldBegin\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [-1 4 -1  1 4 -1  1 4 1]\n"
      "AttributeEnd\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [2 2 2] \"bool twosided\" true\n"
      "Translate 3 2 0\nShape \"sphere\" \"float radius\" [0.5]\nAttributeEnd\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [3 1 1]\nTranslate -3 3 0\n"
      "Rotate 90 1 0 0\nShape \"disk\" \"float radius\" [0.7]\nAttributeEnd\n"
      "LightSource \"point\" \"point from\" [0 5 0] \"rgb I\" [5 5 5]\n"
      "LightSource \"spot\" \"point from\" [0 6 0] \"point to\" [0 0 0] \"float coneangle\" [40]\n"
      "LightSource \"distant\" \"point from\" [1 1 1] \"point to\" [0 0 0]\n"
      "LightSource \"infinite\" \"rgb L\" [0.2 0.3 0.4]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
      "\"point P\" [-10 0 -10  10 0 -10  10 0 10  -10 0 10]\n"
      "WorldEnd\n",
      &desc);
  int n = clr_render_scene_light_count(scene);
  assert_int_equal(n, 7);
  uint32_t s = 99u;
  for (int k = 0; k < 500; ++k) {
    float r[5];
    for (int i = 0; i < 5; ++i) r[i] = lcg_float(&s);
    float p[3] = {16.0f * r[0] - 8.0f, 3.0f * r[1], 16.0f * r[2] - 8.0f}, u[2] = {r[3], r[4]};
    const float ng[3] = {0.0f, 1.0f, 0.0f};
    for (int j = 0; j < n; ++j) {
      clr_light_sample full, li;
      clr_render_scene_sample_light(scene, j, p, ng, u, &full);
      clr_render_scene_sample_light_li(scene, j, p, u, &li);
      assert_memory_equal(full.wi, li.wi, sizeof full.wi);
      assert_memory_equal(full.li, li.li, sizeof full.li);
      assert_true(memcmp(&full.pdf, &li.pdf, sizeof full.pdf) == 0);
      assert_int_equal(full.is_delta, li.is_delta);
      assert_true(li.shadow.tfar == 0.0f && li.shadow.dx == 0.0f);
    }
  }
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

/* A voxel's cdf as the distribution computed it before it kept each area light's emitter
 * points (one Sample_Li per light and Halton point, in float and double as there). */
static void per_sample_cdf(const clr_render_scene *scene, size_t index, float *cdf) {
  int n = clr_render_scene_light_count(scene), res[3], v[3];
  float lo[3], hi[3], bmax = 0.0f;
  clr_render_scene_world_bounds(scene, lo, hi);
  for (int i = 0; i < 3; ++i) bmax = fmaxf(bmax, hi[i] - lo[i]);
  for (int i = 0; i < 3; ++i) {
    int r = (int)lroundf((hi[i] - lo[i]) / bmax * 64.0f);
    res[i] = r < 1 ? 1 : r;
  }
  v[0] = (int)(index % (size_t)res[0]);
  v[1] = (int)(index / (size_t)res[0] % (size_t)res[1]);
  v[2] = (int)(index / (size_t)res[0] / (size_t)res[1]);
  float p0[3], p1[3];
  for (int i = 0; i < 3; ++i) {
    float t0 = (float)v[i] / (float)res[i], t1 = (float)(v[i] + 1) / (float)res[i];
    p0[i] = (1.0f - t0) * lo[i] + t0 * hi[i];
    p1[i] = (1.0f - t1) * lo[i] + t1 * hi[i];
  }
  double contrib[16] = {0};
  assert_true(n <= 16);
  static const unsigned bases[5] = {2, 3, 5, 7, 11};
  for (unsigned s = 0; s < 128; ++s) {
    float h[5];
    for (int b = 0; b < 5; ++b) h[b] = (float)fmin(radical_inverse(bases[b], s), 0x1.fffffep-1);
    float po[3], u[2] = {h[3], h[4]};
    for (int i = 0; i < 3; ++i) po[i] = (1.0f - h[i]) * p0[i] + h[i] * p1[i];
    for (int j = 0; j < n; ++j) {
      clr_light_sample ls;
      clr_render_scene_sample_light_li(scene, j, po, u, &ls);
      if (ls.pdf > 0.0f)
        contrib[j] += (0.212671 * ls.li[0] + 0.715160 * ls.li[1] + 0.072169 * ls.li[2]) / ls.pdf;
    }
  }
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += contrib[j];
  double avg = sum / (128.0 * n), floor_c = avg > 0.0 ? 0.001 * avg : 1.0;
  sum = 0.0;
  for (int j = 0; j < n; ++j) {
    contrib[j] = fmax(contrib[j], floor_c);
    if (!isfinite(contrib[j])) contrib[j] = floor_c;
    sum += contrib[j];
  }
  double acc = 0.0;
  cdf[0] = 0.0f;
  for (int j = 0; j < n; ++j) {
    acc += contrib[j];
    cdf[j + 1] = (float)(acc / sum);
  }
  cdf[n] = 1.0f;
}

/* The cdfs from the kept emitter points (triangles one- and two-sided, a disk, a cylinder) are
 * the bits of one Sample_Li per point (a sphere and a point light sampled as before). */
static void test_kept_points_exact(void **state) {
  (void)state;
  clr_scene_desc *desc = NULL;
  clr_render_scene *scene = build(
      "WorldBegin\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 2 3]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [-1 4 -1  1 4 -1  1 4 1]\n"
      "AttributeEnd\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [2 1 2] \"bool twosided\" true\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [4 1 -1  4 1 1  4 3 0]\n"
      "AttributeEnd\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [2 2 2] \"bool twosided\" true\n"
      "Translate 3 2 0\nShape \"sphere\" \"float radius\" [0.5]\nAttributeEnd\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [3 1 1]\nTranslate -3 3 0\n"
      "Rotate 90 1 0 0\nShape \"disk\" \"float radius\" [0.7]\nAttributeEnd\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 3 1]\nTranslate 0 2 -4\n"
      "Shape \"cylinder\" \"float radius\" [0.3] \"float zmin\" [-0.5] \"float zmax\" [0.5]\n"
      "AttributeEnd\n"
      "LightSource \"point\" \"point from\" [0 5 0] \"rgb I\" [5 5 5]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
      "\"point P\" [-10 0 -10  10 0 -10  10 0 10  -10 0 10]\n"
      "WorldEnd\n",
      &desc);
  int n = clr_render_scene_light_count(scene);
  assert_int_equal(n, 6);
  clr_light_distribution *d = NULL;
  assert_int_equal(clr_light_distribution_create(scene, &d), CLR_SUCCESS);
  uint32_t s = 5u;
  for (int k = 0; k < 300; ++k) {
    float p[3];
    for (int i = 0; i < 3; ++i) p[i] = lcg_float(&s) * 24.0f - 12.0f;
    size_t voxel = clr_light_distribution_voxel(d, p);
    const float *cdf = clr_light_distribution_lookup_voxel(d, voxel);
    float want[7];
    per_sample_cdf(scene, voxel, want);
    assert_non_null(cdf);
    if (memcmp(cdf, want, (size_t)(n + 1) * sizeof *cdf) != 0)
      fail_msg("voxel %zu: cdf differs from the per-sample one", voxel);
  }
  clr_light_distribution_free(d);
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_voxel_cdf_values),
      cmocka_unit_test(test_lookup_by_voxel),
      cmocka_unit_test(test_sample_li_matches),
      cmocka_unit_test(test_kept_points_exact),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
