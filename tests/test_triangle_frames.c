/* Mesh surfaces read each triangle's unit normal and dpdu from a table built with the scene
 * (render_scene.c build_triangle_frames): the surface's n_geom and dpdu at hits on triangles
 * without uvs, with uvs and with degenerate uvs (the axis-made tangent), one of them reversed,
 * are bit for bit pbrt-v3 Triangle::Intersect's, computed here from the vertices. */
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

/* Four triangles above z = 0 facing +z (tilted): plain, with uvs, with all-equal uvs, and
 * reversed; the shapes' indices 0 .. 3 in this order. */
static const float VERTS[4][9] = {{-3.1f, -1.2f, 0.3f, -1.05f, -0.9f, 0.1f, -2.2f, 1.3f, 0.45f},
                                  {-0.8f, -1.1f, 0.2f, 0.9f, -1.3f, 0.35f, 0.1f, 1.2f, 0.05f},
                                  {1.2f, -1.0f, 0.1f, 2.9f, -1.1f, 0.2f, 2.1f, 1.4f, 0.3f},
                                  {3.3f, -1.0f, 0.25f, 5.1f, -0.8f, 0.1f, 4.2f, 1.1f, 0.4f}};
static const float UVS[6] = {0.13f, 0.27f, 0.91f, 0.35f, 0.52f, 0.88f};
static const float SAME_UVS[6] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};

static void append(char *text, size_t cap, const char *fmt, ...) {
  size_t len = strlen(text);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text + len, cap - len, fmt, ap);
  va_end(ap);
}

static void mesh_text(char *text, size_t cap, int k) {
  const float *v = VERTS[k];
  append(text, cap, "AttributeBegin\n%sShape \"trianglemesh\" \"integer indices\" [0 1 2] ",
         k == 3 ? "ReverseOrientation\n" : "");
  append(text, cap, "\"point P\" [%a %a %a %a %a %a %a %a %a]", v[0], v[1], v[2], v[3], v[4], v[5],
         v[6], v[7], v[8]);
  const float *uv = k == 1 ? UVS : k == 2 ? SAME_UVS : NULL;
  if (uv)
    append(text, cap, " \"float uv\" [%a %a %a %a %a %a]", uv[0], uv[1], uv[2], uv[3], uv[4],
           uv[5]);
  append(text, cap, "\nAttributeEnd\n");
}

/* pbrt-v3 Triangle::Intersect's normal (flipped for a reversed shape) and dpdu. */
static void expected_frame(int k, float n[3], float dpdu[3]) {
  const float *p0 = VERTS[k], *p1 = VERTS[k] + 3, *p2 = VERTS[k] + 6;
  const float *uv = k == 1 ? UVS : k == 2 ? SAME_UVS : (const float[6]){0, 0, 1, 0, 1, 1};
  float dp02[3], dp12[3];
  for (int i = 0; i < 3; ++i) {
    dp02[i] = p0[i] - p2[i];
    dp12[i] = p1[i] - p2[i];
  }
  n[0] = dp02[1] * dp12[2] - dp02[2] * dp12[1];
  n[1] = dp02[2] * dp12[0] - dp02[0] * dp12[2];
  n[2] = dp02[0] * dp12[1] - dp02[1] * dp12[0];
  float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int i = 0; i < 3; ++i) n[i] /= len;
  float du02 = uv[0] - uv[4], dv02 = uv[1] - uv[5], du12 = uv[2] - uv[4], dv12 = uv[3] - uv[5];
  float det = du02 * dv12 - dv02 * du12;
  if (fabsf(det) < 1e-8f) { /* pbrt-v3 CoordinateSystem on the normal */
    int wide = fabsf(n[0]) > fabsf(n[1]);
    dpdu[0] = wide ? -n[2] : 0.0f;
    dpdu[1] = wide ? 0.0f : n[2];
    dpdu[2] = wide ? n[0] : -n[1];
  } else {
    float inv = 1.0f / det;
    for (int i = 0; i < 3; ++i) dpdu[i] = (dv12 * dp02[i] - dv02 * dp12[i]) * inv;
  }
  if (k == 3)
    for (int i = 0; i < 3; ++i) n[i] = -n[i];
}

static void test_surface_frames(void **state) {
  (void)state;
  static char text[4096];
  text[0] = 0;
  append(text, sizeof text, "WorldBegin\n");
  for (int k = 0; k < 4; ++k) mesh_text(text, sizeof text, k);
  append(text, sizeof text, "WorldEnd\n");
  clr_scene_desc *d = stu_parse(text, CLR_BINARY_DIR "/triframes.pbrt");
  clr_render_scene *rs = NULL;
  assert_int_equal(clr_render_scene_build(d, NULL, NULL, &rs), CLR_SUCCESS);
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < 3; ++j) { /* three points inside triangle k, hit from above */
      const float *v = VERTS[k];
      float b1 = 0.2f + 0.2f * (float)j, b2 = 0.25f, b0 = 1.0f - b1 - b2;
      clr_ray ray = {.ox = b0 * v[0] + b1 * v[3] + b2 * v[6],
                     .oy = b0 * v[1] + b1 * v[4] + b2 * v[7],
                     .oz = 5.0f,
                     .dz = -1.0f,
                     .tfar = INFINITY};
      clr_hit hit;
      assert_int_equal(clr_tracer_intersect(clr_render_scene_tracer(rs), &ray, &hit, 1),
                       CLR_SUCCESS);
      assert_int_equal(hit.user_id, k);
      clr_surface sf;
      clr_render_scene_surface(rs, &ray, &hit, &sf);
      float n[3], dpdu[3];
      expected_frame(k, n, dpdu);
      if (memcmp(sf.n_geom, n, sizeof n) || memcmp(sf.dpdu, dpdu, sizeof dpdu))
        fail_msg("triangle %d: n (%a %a %a) dpdu (%a %a %a), expected (%a %a %a) (%a %a %a)", k,
                 sf.n_geom[0], sf.n_geom[1], sf.n_geom[2], sf.dpdu[0], sf.dpdu[1], sf.dpdu[2], n[0],
                 n[1], n[2], dpdu[0], dpdu[1], dpdu[2]);
      assert_true(n[2] * (k == 3 ? -1.0f : 1.0f) > 0.9f); /* faces +z (reversed: -z) */
    }
  }
  clr_render_scene_free(rs);
  clr_scene_desc_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_surface_frames),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
