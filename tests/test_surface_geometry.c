/* The ambient-occlusion integrator's lean surface record (clr_render_scene_surface_geometry)
 * equals the full record bit for bit in every field AO reads (p, ng, n_geom, dpdu, has_material,
 * time) at random hits on whole, partial and reversed spheres, triangles with normals and uvs, an
 * instanced sphere and triangle, a disk, a cylinder, a material "none" sphere and (the record then
 * made in full) a bump-mapped one; a sphere's (u, v) are made only in scenes with textures (the
 * only readers), there pbrt-v3 Sphere's, and textured scenes keep their ray differentials. */
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
#include "render_scene.h"
#include "scene_parser.h"
#include "scene_test_util.h"
#include "tracer.h"

#define PI_F 3.14159265358979323846f

static const char SHAPES[] =
    "AttributeBegin\nTranslate 0.3 -0.2 0.1\nScale 1.2 0.8 1.0\n"
    "Shape \"sphere\" \"float radius\" [1]\nAttributeEnd\n"
    "AttributeBegin\nTranslate 3 0 0\nRotate 30 1 1 0\nShape \"sphere\" \"float radius\" [1] "
    "\"float zmin\" [-0.5] \"float zmax\" [0.8] \"float phimax\" [250]\nAttributeEnd\n"
    "AttributeBegin\nTranslate -3 0 0\nReverseOrientation\n"
    "Shape \"sphere\" \"float radius\" [0.9]\nAttributeEnd\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" [-6 -6 -2 6 -6 -2.5 6 6 "
    "-2 -6 6 -1.5] \"normal N\" [0.1 0 1 0 0.2 1 -0.1 0 1 0 0 1] \"float uv\" [0 0 1 0 1 1 0 1]\n"
    "ObjectBegin \"thing\"\nShape \"sphere\" \"float radius\" [0.5]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 0.6 1 0 0.6 0 1 0.9]\n"
    "ObjectEnd\n"
    "AttributeBegin\nTranslate 0 3 0\nRotate 45 0 0 1\nScale 1.5 1 1\nObjectInstance \"thing\"\n"
    "AttributeEnd\n"
    "AttributeBegin\nTranslate 0 -3 0\nShape \"disk\" \"float radius\" [1]\n"
    "Shape \"cylinder\" \"float radius\" [0.6] \"float zmin\" [-0.5] \"float zmax\" [0.5]\n"
    "AttributeEnd\n"
    "AttributeBegin\nMaterial \"none\"\nTranslate 0 0 2.5\nShape \"sphere\" \"float radius\" "
    "[0.7]\nAttributeEnd\n";

static const char BUMPED[] =
    "Texture \"fb\" \"float\" \"fbm\" \"integer octaves\" [2]\n"
    "AttributeBegin\nMaterial \"matte\" \"texture bumpmap\" \"fb\"\nTranslate 2.5 2.5 0\n"
    "Shape \"sphere\" \"float radius\" [0.8]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 1 1 0 1 0 1 1.2] "
    "\"normal N\" [0 0.1 1 0.1 0 1 0 0 1]\nAttributeEnd\n";

static uint64_t rng_state = 0x853c49e6748fea9bULL;

static float rnd(void) {
  rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (float)(rng_state >> 40) / 16777216.0f;
}

static clr_render_scene *build(const char *shapes, const char *extra) {
  static char text[8192];
  snprintf(text, sizeof text, "WorldBegin\n%s%sWorldEnd\n", shapes, extra);
  clr_scene_desc *d = stu_parse(text, CLR_BINARY_DIR "/surface_geometry.pbrt");
  clr_render_scene *rs = NULL;
  assert_int_equal(clr_render_scene_build(d, NULL, NULL, &rs), CLR_SUCCESS);
  clr_scene_desc_free(d);
  return rs;
}

/* A ray from a random point of [-7, 7]^3 toward a random point of [-4, 4]^3. */
static clr_ray random_ray(void) {
  float o[3], t[3];
  for (int k = 0; k < 3; ++k) {
    o[k] = 14.0f * rnd() - 7.0f;
    t[k] = 8.0f * rnd() - 4.0f;
  }
  clr_ray r = {.ox = o[0],
               .oy = o[1],
               .oz = o[2],
               .dx = t[0] - o[0],
               .dy = t[1] - o[1],
               .dz = t[2] - o[2],
               .tfar = INFINITY,
               .time = rnd()};
  return r;
}

/* Random hits of scene `extra`: the lean record's AO fields equal the full record's. Returns how
 * many hits, and each shape's (user id's) count in per_shape[0..32). */
static int compare_records(const char *extra, int per_shape[32]) {
  clr_render_scene *rs = build(SHAPES, extra);
  memset(per_shape, 0, 32 * sizeof *per_shape);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    clr_ray ray = random_ray();
    clr_hit hit;
    assert_int_equal(clr_tracer_intersect(clr_render_scene_tracer(rs), &ray, &hit, 1), CLR_SUCCESS);
    if (hit.geom_id == CLR_TRACER_INVALID_ID) continue;
    ++hits;
    if (hit.user_id < 32) per_shape[hit.user_id]++;
    clr_surface full, lean;
    memset(&lean, 0xab, sizeof lean); /* fields the lean record leaves are not compared */
    clr_render_scene_surface(rs, &ray, &hit, &full);
    clr_render_scene_surface_geometry(rs, &ray, &hit, &lean);
    if (memcmp(full.p, lean.p, sizeof full.p) || memcmp(full.ng, lean.ng, sizeof full.ng) ||
        memcmp(full.n_geom, lean.n_geom, sizeof full.n_geom) ||
        memcmp(full.dpdu, lean.dpdu, sizeof full.dpdu) || full.has_material != lean.has_material ||
        memcmp(&full.time, &lean.time, sizeof full.time))
      fail_msg(
          "ray %d (shape %u): lean p (%a %a %a) ng (%a %a %a) n (%a %a %a) dpdu (%a %a %a) "
          "mat %d, full p (%a %a %a) ng (%a %a %a) n (%a %a %a) dpdu (%a %a %a) mat %d",
          i, hit.user_id, lean.p[0], lean.p[1], lean.p[2], lean.ng[0], lean.ng[1], lean.ng[2],
          lean.n_geom[0], lean.n_geom[1], lean.n_geom[2], lean.dpdu[0], lean.dpdu[1], lean.dpdu[2],
          lean.has_material, full.p[0], full.p[1], full.p[2], full.ng[0], full.ng[1], full.ng[2],
          full.n_geom[0], full.n_geom[1], full.n_geom[2], full.dpdu[0], full.dpdu[1], full.dpdu[2],
          full.has_material);
    assert_true(full.time == ray.time);
    float wo[3] = {-ray.dx, -ray.dy, -ray.dz};
    assert_true(full.ng[0] * wo[0] + full.ng[1] * wo[1] + full.ng[2] * wo[2] >= 0.0f);
  }
  clr_render_scene_free(rs);
  return hits;
}

static void test_lean_record_matches_full(void **state) {
  (void)state;
  int per_shape[32];
  int hits = compare_records("", per_shape);
  assert_true(hits > 4000);
  for (int k = 0; k < 9; ++k) /* shapes 0 .. 8: three spheres, mesh, instanced pair, disk, ... */
    if (per_shape[k] < 20) fail_msg("shape %d hit %d times", k, per_shape[k]);
  hits = compare_records(BUMPED, per_shape);
  for (int k = 9; k < 11; ++k) /* the bumped sphere and triangle */
    if (per_shape[k] < 20) fail_msg("bumped shape %d hit %d times", k, per_shape[k]);
}

/* pbrt-v3 Sphere::Intersect's (u, v) of a whole sphere of radius r at object point po. */
static void sphere_uv(const float po[3], float r, float uv[2]) {
  float phi = atan2f(po[1], po[0]);
  if (phi < 0.0f) phi += 2.0f * PI_F;
  uv[0] = phi / (2.0f * PI_F);
  uv[1] = 1.0f - acosf(fminf(1.0f, fmaxf(-1.0f, po[2] / r))) / PI_F;
}

/* A sphere of radius 2 at the origin hit by 200 rays from outside: its (u, v) in a scene with a
 * texture are pbrt-v3's (to 2e-6: the test's own refinement), in one without they are not made. */
static void test_sphere_uv_where_read(void **state) {
  (void)state;
  const char *sphere = "Shape \"sphere\" \"float radius\" [2]\n";
  const char *textured =
      "Texture \"ck\" \"spectrum\" \"checkerboard\"\n"
      "Material \"matte\" \"texture Kd\" \"ck\"\n";
  for (int with_texture = 0; with_texture < 2; ++with_texture) {
    clr_render_scene *rs = build(with_texture ? textured : "", sphere);
    int spread = 0;
    for (int i = 0; i < 200; ++i) {
      float z = 2.0f * rnd() - 1.0f, a = 2.0f * PI_F * rnd(), s = sqrtf(1.0f - z * z);
      float dir[3] = {s * cosf(a), s * sinf(a), z};
      clr_ray ray = {.ox = 6.0f * dir[0],
                     .oy = 6.0f * dir[1],
                     .oz = 6.0f * dir[2],
                     .dx = -dir[0] + 0.1f * rnd(),
                     .dy = -dir[1],
                     .dz = -dir[2],
                     .tfar = INFINITY};
      clr_hit hit;
      assert_int_equal(clr_tracer_intersect(clr_render_scene_tracer(rs), &ray, &hit, 1),
                       CLR_SUCCESS);
      assert_true(hit.geom_id != CLR_TRACER_INVALID_ID);
      assert_true(hit.u == 0.0f && hit.v == 0.0f); /* the renderer's tracer skips them */
      clr_surface sf;
      clr_render_scene_surface(rs, &ray, &hit, &sf);
      float uv[2];
      sphere_uv(sf.p, 2.0f, uv);
      if (!with_texture) {
        assert_true(sf.uv[0] == 0.0f && sf.uv[1] == 0.0f);
        continue;
      }
      if (fabsf(uv[0] - sf.uv[0]) > 2e-6f || fabsf(uv[1] - sf.uv[1]) > 2e-6f)
        fail_msg("hit %d: uv (%g %g), pbrt-v3's (%g %g)", i, (double)sf.uv[0], (double)sf.uv[1],
                 (double)uv[0], (double)uv[1]);
      spread += uv[1] > 0.25f && uv[1] < 0.75f;
    }
    if (with_texture) assert_true(spread > 40);
    clr_render_scene_free(rs);
  }
}

/* Textured scenes keep differentials: an imagemap's scene gives camera rays differentials, and a
 * mirror's hit of such a ray its screen-space dpdx, dpdy. */
static void test_textures_keep_differentials(void **state) {
  (void)state;
  static char text[2048];
  snprintf(text, sizeof text,
           "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [30]\n"
           "WorldBegin\nTexture \"im\" \"spectrum\" \"imagemap\" \"string filename\" "
           "\"%s/tests/data/scenes/v3_checker.png\"\nAttributeBegin\nMaterial \"matte\" "
           "\"texture Kd\" \"im\"\nTranslate 0 0 5\nShape \"sphere\" \"float radius\" "
           "[1]\nAttributeEnd\nAttributeBegin\nMaterial \"mirror\"\nShape \"sphere\" \"float "
           "radius\" [1]\nAttributeEnd\nWorldEnd\n",
           CLR_SOURCE_DIR);
  clr_scene_desc *d = stu_parse(text, CLR_BINARY_DIR "/surface_geometry_tex.pbrt");
  clr_render_scene *rs = NULL;
  assert_int_equal(clr_render_scene_build(d, NULL, NULL, &rs), CLR_SUCCESS);
  clr_scene_desc_free(d);
  assert_int_equal(clr_render_scene_uses_differentials(rs), 1);
  assert_int_equal(clr_render_scene_set_film(rs, 64, 64), CLR_SUCCESS);
  clr_render_scene_set_samples_per_pixel(rs, 1);
  clr_ray ray;
  clr_ray_differential rd;
  clr_render_scene_camera_ray(rs, 30.5f, 31.5f, 0.0f, 0.5f, 0.5f, &ray, &rd);
  assert_int_equal(rd.has, 1);
  clr_hit hit;
  assert_int_equal(clr_tracer_intersect(clr_render_scene_tracer(rs), &ray, &hit, 1), CLR_SUCCESS);
  assert_true(hit.geom_id != CLR_TRACER_INVALID_ID);
  clr_surface sf;
  clr_render_scene_surface_differential(rs, &ray, &rd, &hit, &sf);
  assert_true(sf.mirror && sf.has_differentials);
  float dx2 = sf.dpdx[0] * sf.dpdx[0] + sf.dpdx[1] * sf.dpdx[1] + sf.dpdx[2] * sf.dpdx[2];
  float dy2 = sf.dpdy[0] * sf.dpdy[0] + sf.dpdy[1] * sf.dpdy[1] + sf.dpdy[2] * sf.dpdy[2];
  /* one pixel of a 30-degree, 64-pixel film at distance ~4: about 4 tan(15 deg) / 32 = 0.033 */
  assert_true(dx2 > 1e-4f && dx2 < 1e-2f && dy2 > 1e-4f && dy2 < 1e-2f);
  clr_render_scene_free(rs);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_lean_record_matches_full),
      cmocka_unit_test(test_sphere_uv_where_read),
      cmocka_unit_test(test_textures_keep_differentials),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
