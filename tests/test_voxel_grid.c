/* The spatial light distribution's voxel index (integrators/light_distribution.h): the
 * branch-free index (SSE2 lanes) and its scalar form give the voxel the per-axis division and
 * clamp of pbrt-v3's SpatialLightDistribution give, for random points, the exact voxel
 * boundaries and their float neighbours, the grid's faces, points outside, NaN, infinities and
 * signed zeros, on grids with flat axes, one voxel, odd counts and far offsets; and on the grid
 * of a parsed scene. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>
#include "clrender.h"
#include "light_distribution.h"
#include "render_scene.h"
#include "scene_parser.h"

/* The index as the light distribution computed it before the grid constants: a division by the
 * extent where hi > lo, then a branch per clamp. */
static size_t division_voxel(const float lo[3], const float hi[3], const int n[3],
                             const float p[3]) {
  int v[3];
  for (int i = 0; i < 3; ++i) {
    float o = p[i] - lo[i];
    if (hi[i] > lo[i]) o /= hi[i] - lo[i];
    float f = o * (float)n[i];
    v[i] = !(f > 0.0f) ? 0 : f >= (float)(n[i] - 1) ? n[i] - 1 : (int)f;
  }
  return ((size_t)v[2] * (size_t)n[1] + (size_t)v[1]) * (size_t)n[0] + (size_t)v[0];
}

static uint32_t next(uint32_t *s) {
  *s = *s * 1664525u + 1013904223u;
  return *s;
}

/* Values along one axis worth testing: the faces, every voxel boundary lo + k (hi - lo) / n as
 * float and its neighbours up to 3 floats away, points outside, and the special values. */
static int axis_values(float lo, float hi, int n, float *out) {
  int m = 0;
  float ext = hi - lo;
  for (int k = 0; k <= n; ++k) {
    float b[2] = {lo + (float)k * ext / (float)n, lo + ext * ((float)k / (float)n)};
    for (int j = 0; j < 2; ++j) {
      float x = b[j];
      for (int s = 0; s < 3; ++s) x = nextafterf(x, -INFINITY);
      for (int s = 0; s < 7; ++s, x = nextafterf(x, INFINITY)) out[m++] = x;
    }
  }
  const float special[] = {lo,
                           hi,
                           nextafterf(lo, -INFINITY),
                           nextafterf(hi, INFINITY),
                           lo - ext,
                           hi + ext,
                           0.0f,
                           -0.0f,
                           NAN,
                           -NAN,
                           INFINITY,
                           -INFINITY,
                           FLT_MAX,
                           -FLT_MAX,
                           FLT_MIN,
                           -FLT_MIN,
                           1e-45f,
                           1e30f,
                           -1e30f};
  for (size_t i = 0; i < sizeof special / sizeof *special; ++i) out[m++] = special[i];
  return m;
}

#define MAX_AXIS_VALUES (65 * 14 + 19)

/* Every combination of two axes' test values (the third random inside), and random points in and
 * around the grid: both indices equal the division's. */
static void check_grid(const float lo[3], const float hi[3], const int n[3], uint32_t seed) {
  clr_voxel_grid g;
  clr_voxel_grid_init(&g, lo, hi, n);
  static float values[3][MAX_AXIS_VALUES];
  int count[3];
  for (int i = 0; i < 3; ++i) count[i] = axis_values(lo[i], hi[i], n[i], values[i]);
  uint32_t s = seed;
  size_t checked = 0;
  for (int a = 0; a < 3; ++a)
    for (int ia = 0; ia < count[a]; ++ia)
      for (int ib = 0; ib < count[(a + 1) % 3]; ib += 3) {
        float p[3];
        int c = (a + 2) % 3;
        p[a] = values[a][ia];
        p[(a + 1) % 3] = values[(a + 1) % 3][ib];
        p[c] = lo[c] + (hi[c] - lo[c]) * (float)(next(&s) >> 8) / 16777216.0f;
        size_t want = division_voxel(lo, hi, n, p);
        if (clr_voxel_grid_index(&g, p) != want || clr_voxel_grid_index_scalar(&g, p) != want)
          fail_msg("p (%a %a %a): %zu and %zu, division %zu", p[0], p[1], p[2],
                   clr_voxel_grid_index(&g, p), clr_voxel_grid_index_scalar(&g, p), want);
        ++checked;
      }
  for (int k = 0; k < 200000; ++k) {
    float p[3];
    for (int i = 0; i < 3; ++i) {
      float u = (float)(next(&s) >> 8) / 16777216.0f * 1.2f - 0.1f;
      p[i] = lo[i] + (hi[i] - lo[i]) * u;
    }
    size_t want = division_voxel(lo, hi, n, p);
    assert_int_equal(clr_voxel_grid_index(&g, p), want);
    assert_int_equal(clr_voxel_grid_index_scalar(&g, p), want);
  }
  assert_true(checked > 1000);
}

static void test_index_equals_division(void **state) {
  (void)state;
  const struct {
    float lo[3], hi[3];
    int n[3];
  } grids[] = {
      {{-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}, {64, 64, 64}},
      {{-278.0f, 0.0f, -280.0f}, {278.0f, 548.8f, 279.6f}, {64, 63, 64}},
      {{0.1f, 0.2f, 0.3f}, {0.7f, 0.2f, 0.9f}, {64, 1, 64}}, /* flat y */
      {{5.0f, 5.0f, 5.0f}, {5.0f, 5.0f, 5.0f}, {1, 1, 1}},   /* a point */
      {{1000.0f, -3e4f, 7.0f}, {1000.3f, 2e4f, 7.001f}, {1, 64, 3}},
      {{-13.7f, 2.25f, -0.001f}, {41.3f, 19.0f, 0.002f}, {37, 11, 5}},
  };
  for (size_t k = 0; k < sizeof grids / sizeof *grids; ++k)
    check_grid(grids[k].lo, grids[k].hi, grids[k].n, 17u + (uint32_t)k);
}

/* Known indices: the low corner is voxel 0, the high corner the last voxel, the centre of a
 * 4x2x8 grid over [0,4]x[0,2]x[0,8] voxel (2, 1, 4), NaN coordinates 0. */
static void test_known_indices(void **state) {
  (void)state;
  const float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {4.0f, 2.0f, 8.0f};
  const int n[3] = {4, 2, 8};
  clr_voxel_grid g;
  clr_voxel_grid_init(&g, lo, hi, n);
  const float corner[3] = {0.0f, 0.0f, 0.0f}, top[3] = {4.0f, 2.0f, 8.0f},
              centre[3] = {2.0f, 1.0f, 4.0f}, nan[3] = {NAN, 1.5f, NAN},
              below[3] = {3.999f, 0.999f, 7.999f};
  assert_int_equal(clr_voxel_grid_index(&g, corner), 0);
  assert_int_equal(clr_voxel_grid_index(&g, top), 4 * 2 * 8 - 1);
  assert_int_equal(clr_voxel_grid_index(&g, centre), (4 * 2 + 1) * 4 + 2);
  assert_int_equal(clr_voxel_grid_index(&g, nan), 4);
  assert_int_equal(clr_voxel_grid_index(&g, below), (7 * 2 + 0) * 4 + 3);
}

/* The grid of a parsed scene: the light distribution's index equals the division over its
 * bounds and counts. */
static void test_scene_grid(void **state) {
  (void)state;
  clr_parse_options po;
  clr_parse_options_init(&po);
  clr_scene_desc *desc = NULL;
  const char *text =
      "WorldBegin\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4 4 4]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
      "\"point P\" [-1 4 -1  1 4 -1  1 4 1  -1 4 1]\nAttributeEnd\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
      "\"point P\" [-10 0 -7.3  10 0 -7.3  10 0 10  -10 0 10]\n"
      "WorldEnd\n";
  assert_int_equal(clr_scene_parse_string(text, CLR_BINARY_DIR "/voxelgrid.pbrt", &po, &desc),
                   CLR_SUCCESS);
  clr_render_scene *scene = NULL;
  assert_int_equal(clr_render_scene_build(desc, NULL, NULL, &scene), CLR_SUCCESS);
  clr_light_distribution *d = NULL;
  assert_int_equal(clr_light_distribution_create(scene, &d), CLR_SUCCESS);
  float lo[3], hi[3];
  clr_render_scene_world_bounds(scene, lo, hi);
  const clr_voxel_grid *g = clr_light_distribution_grid(d);
  int n[3];
  for (int i = 0; i < 3; ++i) n[i] = (int)g->cells[i];
  assert_int_equal(n[0], 64);
  assert_int_equal(n[2], 55); /* 17.3 / 20 * 64 = 55.36 */
  uint32_t s = 99u;
  for (int k = 0; k < 100000; ++k) {
    float p[3];
    for (int i = 0; i < 3; ++i)
      p[i] = lo[i] + (hi[i] - lo[i]) * ((float)(next(&s) >> 8) / 16777216.0f * 1.1f - 0.05f);
    assert_int_equal(clr_light_distribution_voxel(d, p), division_voxel(lo, hi, n, p));
  }
  check_grid(lo, hi, n, 5u);
  clr_light_distribution_free(d);
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_index_equals_division),
      cmocka_unit_test(test_known_indices),
      cmocka_unit_test(test_scene_grid),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
