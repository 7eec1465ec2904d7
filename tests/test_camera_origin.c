/* A pinhole camera's rays start at its world origin, mapped once by rs_camera_set_film
 * (camera.c fixed_origin): the same bits as mapping the camera-space origin per ray, at the
 * LookAt eye; a lens or a moving camera keeps mapping per ray. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include "camera.h"
#include "scene_parser.h"
#include "scene_test_util.h"

static void build_camera(const char *text, rs_camera *cam) {
  clr_scene_desc *d = stu_parse(text, CLR_BINARY_DIR "/camera_origin.pbrt");
  assert_int_equal(rs_camera_build(cam, d, NULL, NULL), CLR_SUCCESS);
  assert_int_equal(rs_camera_set_film(cam, 48, 32), CLR_SUCCESS);
  clr_scene_desc_free(d);
}

/* Rays over the raster (pixel corners and centres, lens and time samples varied) with the
 * origin mapped once and mapped per ray are equal field by field, bit for bit. */
static void assert_same_rays(const rs_camera *fixed) {
  rs_camera general = *fixed;
  general.fixed_origin = 0;
  for (int y = 0; y <= 32; y += 4)
    for (int x = 0; x <= 48; x += 3) {
      float fx = (float)x + (x % 2 ? 0.5f : 0.0f), fy = (float)y + 0.25f;
      float u = (float)((x * 7 + y) % 10) / 10.0f, v = (float)((y * 3 + x) % 10) / 10.0f;
      clr_ray a, b;
      rs_camera_ray(fixed, fx, fy, u, u, v, &a, NULL);
      rs_camera_ray(&general, fx, fy, u, u, v, &b, NULL);
      assert_memory_equal(&a, &b, sizeof a);
    }
}

static void test_pinhole_origin_is_the_eye(void **state) {
  (void)state;
  rs_camera cam;
  build_camera(
      "LookAt 0.25 1.5 -3  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" [45]\n"
      "WorldBegin\nWorldEnd\n",
      &cam);
  assert_int_equal(cam.fixed_origin, 1);
  const float eye[3] = {0.25f, 1.5f, -3.0f};
  for (int i = 0; i < 3; ++i) assert_true(fabsf(cam.origin_world[i] - eye[i]) < 1e-6f);
  clr_ray r;
  rs_camera_ray(&cam, 24.0f, 16.0f, 0.5f, 0.5f, 0.5f, &r, NULL);
  assert_true(fabsf(r.ox - eye[0]) < 1e-6f && fabsf(r.oy - eye[1]) < 1e-6f &&
              fabsf(r.oz - eye[2]) < 1e-6f);
  /* the centre ray looks at the LookAt target: (-0.25, -1, 3) normalised */
  double len = sqrt(0.25 * 0.25 + 1.0 + 9.0);
  assert_true(fabs(r.dx + 0.25 / len) < 1e-5 && fabs(r.dy + 1.0 / len) < 1e-5 &&
              fabs(r.dz - 3.0 / len) < 1e-5);
  assert_same_rays(&cam);
}

static void test_lens_and_motion_map_per_ray(void **state) {
  (void)state;
  rs_camera lens, moving;
  build_camera(
      "LookAt 0 1 -3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [45] "
      "\"float lensradius\" [0.2] \"float focaldistance\" [3]\nWorldBegin\nWorldEnd\n",
      &lens);
  assert_int_equal(lens.fixed_origin, 0);
  assert_same_rays(&lens);
  clr_ray a, b; /* different lens samples, different origins */
  rs_camera_ray(&lens, 24.0f, 16.0f, 0.5f, 0.1f, 0.1f, &a, NULL);
  rs_camera_ray(&lens, 24.0f, 16.0f, 0.5f, 0.9f, 0.9f, &b, NULL);
  assert_true(fabsf(a.ox - b.ox) > 1e-3f || fabsf(a.oy - b.oy) > 1e-3f);
  build_camera(
      "ActiveTransform StartTime\nLookAt 0 1 -3  0 0 0  0 1 0\n"
      "ActiveTransform EndTime\nLookAt 1 1 -3  1 0 0  0 1 0\nActiveTransform All\n"
      "Camera \"perspective\" \"float fov\" [45]\nWorldBegin\nWorldEnd\n",
      &moving);
  assert_int_equal(moving.fixed_origin, 0);
  rs_camera_ray(&moving, 24.0f, 16.0f, 0.0f, 0.5f, 0.5f, &a, NULL);
  rs_camera_ray(&moving, 24.0f, 16.0f, 1.0f, 0.5f, 0.5f, &b, NULL);
  assert_true(fabsf(a.ox - 0.0f) < 1e-5f && fabsf(b.ox - 1.0f) < 1e-5f);
  assert_same_rays(&moving);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pinhole_origin_is_the_eye),
      cmocka_unit_test(test_lens_and_motion_map_per_ray),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
