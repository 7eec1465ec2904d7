/* pbrt-v3 scene parser: transforms, every directive and parameter type, graphics state,
 * Include, instancing, warnings, syntax errors, and pbrt-v3's killeroo-simple scene. */
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
#include "scene_parser.h"

#define SCENES CLR_SOURCE_DIR "/tests/data/scenes/"

/* ---- warning capture --------------------------------------------------------------------- */

typedef struct warnings {
  int count;
  char messages[64][512];
} warnings;

static void capture_warning(void *user, const char *message) {
  warnings *w = user;
  if (w->count < 64) snprintf(w->messages[w->count], sizeof w->messages[0], "%s", message);
  ++w->count;
}

static int warnings_containing(const warnings *w, const char *a, const char *b) {
  int n = 0;
  for (int i = 0; i < w->count && i < 64; ++i)
    if (strstr(w->messages[i], a) && (!b || strstr(w->messages[i], b))) ++n;
  return n;
}

static clr_parse_options capture_options(warnings *w) {
  clr_parse_options opts;
  clr_parse_options_init(&opts);
  memset(w, 0, sizeof *w);
  opts.warn = capture_warning;
  opts.warn_user = w;
  return opts;
}

static clr_scene_desc *parse_ok(const char *text, warnings *w) {
  clr_parse_options opts = capture_options(w);
  clr_scene_desc *desc = NULL;
  clr_result r = clr_scene_parse_string(text, "scenes/test.pbrt", &opts, &desc);
  if (r != CLR_SUCCESS) fail_msg("parse failed: %s", clr_last_error_message());
  assert_non_null(desc);
  return desc;
}

/* ---- matrix helpers ---------------------------------------------------------------------- */

static void assert_matrix_near(const float a[4][4], const float b[4][4], float tolerance) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!(fabsf(a[i][j] - b[i][j]) <= tolerance))
        fail_msg("m[%d][%d] = %.9g, expected %.9g", i, j, a[i][j], b[i][j]);
}

static void assert_inverse_pair(const clr_transform *t, float tolerance) {
  float product[4][4];
  clr_transform id = clr_transform_identity();
  clr_matrix_multiply(t->m, t->m_inv, product);
  assert_matrix_near(product, id.m, tolerance);
}

static void assert_point_near(const float p[3], float x, float y, float z, float tolerance) {
  if (!(fabsf(p[0] - x) <= tolerance && fabsf(p[1] - y) <= tolerance &&
        fabsf(p[2] - z) <= tolerance))
    fail_msg("point (%.7g %.7g %.7g), expected (%.7g %.7g %.7g)", p[0], p[1], p[2], x, y, z);
}

/* Camera-to-world of pbrt-v3's LookAt, computed independently in double. */
static void look_at_camera_to_world(const double e[3], const double l[3], const double u[3],
                                    float out[4][4]) {
  double dir[3] = {l[0] - e[0], l[1] - e[1], l[2] - e[2]};
  double n = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  for (int i = 0; i < 3; ++i) dir[i] /= n;
  double un = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  double up[3] = {u[0] / un, u[1] / un, u[2] / un};
  double right[3] = {up[1] * dir[2] - up[2] * dir[1], up[2] * dir[0] - up[0] * dir[2],
                     up[0] * dir[1] - up[1] * dir[0]};
  double rn = sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
  for (int i = 0; i < 3; ++i) right[i] /= rn;
  double new_up[3] = {dir[1] * right[2] - dir[2] * right[1], dir[2] * right[0] - dir[0] * right[2],
                      dir[0] * right[1] - dir[1] * right[0]};
  memset(out, 0, 16 * sizeof(float));
  for (int i = 0; i < 3; ++i) {
    out[i][0] = (float)right[i];
    out[i][1] = (float)new_up[i];
    out[i][2] = (float)dir[i];
    out[i][3] = (float)e[i];
  }
  out[3][3] = 1.0f;
}

/* ---- transforms -------------------------------------------------------------------------- */

static void test_transform_primitives(void **state) {
  (void)state;
  clr_transform t = clr_transform_translate(1, -2, 3);
  const float translate[4][4] = {{1, 0, 0, 1}, {0, 1, 0, -2}, {0, 0, 1, 3}, {0, 0, 0, 1}};
  const float translate_inv[4][4] = {{1, 0, 0, -1}, {0, 1, 0, 2}, {0, 0, 1, -3}, {0, 0, 0, 1}};
  assert_matrix_near(t.m, translate, 0);
  assert_matrix_near(t.m_inv, translate_inv, 0);

  clr_transform s = clr_transform_scale(2, 4, -0.5f);
  const float scale_inv[4][4] = {{0.5f, 0, 0, 0}, {0, 0.25f, 0, 0}, {0, 0, -2, 0}, {0, 0, 0, 1}};
  assert_matrix_near(s.m_inv, scale_inv, 0);
  assert_true(clr_transform_swaps_handedness(&s));
  assert_false(clr_transform_swaps_handedness(&t));

  /* Rotate 90 degrees about z: x -> y, y -> -x. Axis is normalized first. */
  clr_transform r = clr_transform_rotate(90, 0, 0, 7);
  const float rot_z[4][4] = {{0, -1, 0, 0}, {1, 0, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  assert_matrix_near(r.m, rot_z, 1e-7f);
  assert_inverse_pair(&r, 1e-6f);
  /* Rotate 120 degrees about (1,1,1) cycles the axes x -> y -> z. */
  clr_transform cyc = clr_transform_rotate(120, 1, 1, 1);
  const float cycle[4][4] = {{0, 0, 1, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 1}};
  assert_matrix_near(cyc.m, cycle, 1e-6f);

  /* Compose applies the right operand first: T * S maps p to S p + t. */
  clr_transform ts = clr_transform_compose(&t, &s);
  float p[3] = {1, 1, 2}, q[3];
  clr_transform_point(&ts, p, q);
  assert_point_near(q, 3, 2, 2, 0);
  assert_inverse_pair(&ts, 1e-6f);
  clr_transform inv = clr_transform_inverse(&ts);
  assert_matrix_near(inv.m, ts.m_inv, 0);

  /* Normals transform by the inverse transpose: a plane's normal stays perpendicular. */
  float n[3], nn[3] = {0, 0, 1};
  clr_transform_normal(&s, nn, n);
  assert_point_near(n, 0, 0, -2, 0);
  float v[3];
  clr_transform_vector(&t, (float[3]){1, 0, 0}, v);
  assert_point_near(v, 1, 0, 0, 0);
}

static void test_matrix_inverse(void **state) {
  (void)state;
  const float m[4][4] = {{2, 0, 1, 3}, {1, 3, 0, -1}, {0, 1, 4, 2}, {0, 0, 0, 1}};
  float inv[4][4], product[4][4];
  assert_true(clr_matrix_inverse(m, inv));
  clr_matrix_multiply(m, inv, product);
  clr_transform id = clr_transform_identity();
  assert_matrix_near(product, id.m, 1e-6f);
  /* Hand-computed: det of the 3x3 block is 2*(12-0) - 0 + 1*(1-0) = 25. */
  assert_true(fabsf(inv[0][0] - 12.0f / 25.0f) < 1e-6f);
  assert_true(fabsf(inv[0][2] - (-3.0f / 25.0f)) < 1e-6f);
  const float singular[4][4] = {{1, 2, 3, 0}, {2, 4, 6, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  assert_false(clr_matrix_inverse(singular, inv));
  assert_true(inv[0][0] == 0 && inv[3][3] == 0);
}

static void test_look_at(void **state) {
  (void)state;
  /* Axis-aligned case by hand: camera at (1,2,3) looking down +z with y up is a translation. */
  clr_transform t;
  assert_true(
      clr_transform_look_at((float[3]){1, 2, 3}, (float[3]){1, 2, 9}, (float[3]){0, 1, 0}, &t));
  clr_transform expect = clr_transform_translate(-1, -2, -3);
  assert_matrix_near(t.m, expect.m, 0);
  assert_matrix_near(t.m_inv, expect.m_inv, 0);

  /* General case against the pbrt-v3 formula (killeroo-simple's camera). */
  const double e[3] = {400, 20, 30}, l[3] = {0, 63, -110}, u[3] = {0, 0, 1};
  float c2w[4][4];
  look_at_camera_to_world(e, l, u, c2w);
  assert_true(clr_transform_look_at((float[3]){400, 20, 30}, (float[3]){0, 63, -110},
                                    (float[3]){0, 0, 1}, &t));
  assert_matrix_near(t.m_inv, c2w, 2e-5f);
  assert_inverse_pair(&t, 1e-4f);
  float eye_cam[3];
  clr_transform_point(&t, (float[3]){400, 20, 30}, eye_cam);
  assert_point_near(eye_cam, 0, 0, 0, 1e-3f);
  float look_cam[3];
  clr_transform_point(&t, (float[3]){0, 63, -110}, look_cam);
  double dist = sqrt(400.0 * 400 + 43.0 * 43 + 140.0 * 140);
  assert_point_near(look_cam, 0, 0, (float)dist, 1e-3f);

  /* Up parallel to the view direction: identity and false, as pbrt-v3. */
  assert_false(
      clr_transform_look_at((float[3]){0, 0, 0}, (float[3]){0, 0, 1}, (float[3]){0, 0, 2}, &t));
  assert_true(clr_transform_is_identity(&t));
}

/* ---- directives and parameter types ------------------------------------------------------ */

static const char *full_scene =
    "# every directive of the subset\n"
    "LookAt 0 0 5  0 0 0  0 1 0\n"
    "Camera \"perspective\" \"float fov\" [45] \"float screenwindow\" [-1 1 -0.5 0.5]\n"
    "Sampler \"stratified\" \"integer xsamples\" 4 \"bool jitter\" \"false\" \"bool extra\" [true "
    "false]\n"
    "PixelFilter \"gaussian\" \"float xwidth\" 2.5\n"
    "Film \"image\" \"integer xresolution\" [64] \"integer yresolution\" [32]\n"
    "  \"string filename\" \"out \\\"q\\\".exr\"\n"
    "Integrator \"directlighting\" \"integer maxdepth\" [3]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [1 2 3] \"point from\" [0 5 0]\n"
    "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" [4] \"color tex1\" [1 0 0]\n"
    "Texture \"bump\" \"float\" \"fbm\" \"vector2 v2\" [1 2] \"point3 p3\" [1 2 3]\n"
    "MakeNamedMaterial \"red\" \"string type\" \"matte\" \"texture Kd\" \"checks\"\n"
    "  \"texture bumpmap\" \"bump\"\n"
    "AttributeBegin\n"
    "  Translate 1 2 3\n"
    "  Material \"plastic\" \"color Kd\" [.4 .2 .2] \"float roughness\" .1\n"
    "  AreaLightSource \"diffuse\" \"rgb L\" [5 6 7]\n"
    "  ReverseOrientation\n"
    "  Shape \"sphere\" \"float radius\" 2\n"
    "AttributeEnd\n"
    "NamedMaterial \"red\"\n"
    "Shape \"trianglemesh\" \"point P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n"
    "  \"normal N\" [0 0 1 0 0 1 0 0 1] \"point2 uv\" [0 0 1 0 0 1] \"vector3 S\" [1 0 0 1 0 0 1 0 "
    "0]\n"
    "  \"normal3 N2\" [0 1 0] \"vector V\" [0 0 -1] \"point3 P3\" [4 5 6]\n"
    "TransformBegin\n"
    "  Scale 2 3 4\n"
    "  Shape \"disk\"\n"
    "TransformEnd\n"
    "ObjectBegin \"tree\"\n"
    "  Shape \"cylinder\"\n"
    "  Shape \"cone\"\n"
    "ObjectEnd\n"
    "Translate 10 0 0\n"
    "ObjectInstance \"tree\"\n"
    "Rotate 90 0 0 1\n"
    "ObjectInstance \"tree\"\n"
    "Transform [1 0 0 0  0 1 0 0  0 0 1 0  7 8 9 1]\n"
    "ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]\n"
    "Shape \"sphere\"\n"
    "Identity\n"
    "CoordinateSystem \"mine\"\n"
    "CoordSysTransform \"camera\"\n"
    "LightSource \"spot\"\n"
    "Translate 1 1 1\n"
    "CoordSysTransform \"mine\"\n"
    "LightSource \"distant\"\n"
    "WorldEnd\n";

static void test_options_and_parameter_types(void **state) {
  (void)state;
  warnings w;
  clr_scene_desc *d = parse_ok(full_scene, &w);
  assert_int_equal(w.count, 0);

  assert_true(d->camera.given);
  assert_string_equal(d->camera.type, "perspective");
  assert_true(clr_params_find_float(&d->camera.params, "fov", 90) == 45.0f);
  int n = 0;
  const float *sw = clr_params_find_floats(&d->camera.params, "screenwindow", &n);
  assert_int_equal(n, 4);
  assert_true(sw[0] == -1.0f && sw[3] == 0.5f);
  /* LookAt from (0,0,5) to the origin: camera at (0,0,5) looking down -z. */
  float eye[3];
  clr_transform_point(&d->camera.camera_to_world, (float[3]){0, 0, 0}, eye);
  assert_point_near(eye, 0, 0, 5, 1e-6f);
  float fwd[3];
  clr_transform_vector(&d->camera.camera_to_world, (float[3]){0, 0, 1}, fwd);
  assert_point_near(fwd, 0, 0, -1, 1e-6f);

  assert_string_equal(d->sampler.type, "stratified");
  assert_int_equal(clr_params_find_int(&d->sampler.params, "xsamples", 1), 4);
  assert_false(clr_params_find_bool(&d->sampler.params, "jitter", true));
  /* Two values: a single-value lookup gives the default, the array has both. */
  assert_true(clr_params_find_bool(&d->sampler.params, "extra", true));
  const clr_param *extra = clr_params_find(&d->sampler.params, "extra", CLR_PARAM_BOOL);
  assert_non_null(extra);
  assert_int_equal(extra->count, 2);
  assert_true(extra->ints[0] == 1 && extra->ints[1] == 0);
  /* Type-checked: "xsamples" is an integer, not a float. */
  assert_true(clr_params_find_float(&d->sampler.params, "xsamples", -1) == -1.0f);

  assert_string_equal(d->filter.type, "gaussian");
  assert_true(clr_params_find_float(&d->filter.params, "xwidth", 0) == 2.5f);
  assert_string_equal(d->film.type, "image");
  assert_int_equal(clr_params_find_int(&d->film.params, "xresolution", 0), 64);
  assert_int_equal(clr_params_find_int(&d->film.params, "yresolution", 0), 32);
  assert_string_equal(clr_params_find_string(&d->film.params, "filename", ""), "out \"q\".exr");
  assert_string_equal(d->integrator.type, "directlighting");
  assert_int_equal(clr_params_find_int(&d->integrator.params, "maxdepth", 5), 3);

  /* Lights: point in world space; spot in camera space; distant in "mine" (identity). */
  assert_int_equal(d->light_count, 3);
  assert_string_equal(d->lights[0].type, "point");
  float rgb[3];
  clr_params_find_rgb(&d->lights[0].params, "I", (float[3]){0, 0, 0}, rgb);
  assert_point_near(rgb, 1, 2, 3, 0);
  float from[3];
  clr_params_find_point3(&d->lights[0].params, "from", (float[3]){0, 0, 0}, from);
  assert_point_near(from, 0, 5, 0, 0);
  assert_true(clr_transform_is_identity(&d->lights[0].light_to_world));
  assert_string_equal(d->lights[1].type, "spot");
  assert_matrix_near(d->lights[1].light_to_world.m, d->camera.camera_to_world.m, 0);
  assert_string_equal(d->lights[2].type, "distant");
  assert_true(clr_transform_is_identity(&d->lights[2].light_to_world));

  /* Textures and their resolution from material parameters. */
  assert_int_equal(d->texture_count, 2);
  assert_string_equal(d->textures[0].name, "checks");
  assert_int_equal(d->textures[0].kind, CLR_TEXTURE_SPECTRUM);
  assert_string_equal(d->textures[0].type, "checkerboard");
  clr_params_find_rgb(&d->textures[0].params, "tex1", (float[3]){0, 0, 0}, rgb);
  assert_point_near(rgb, 1, 0, 0, 0);
  assert_int_equal(d->textures[1].kind, CLR_TEXTURE_FLOAT);
  const float *v2 = clr_params_find_point2s(&d->textures[1].params, "v2", &n);
  assert_null(v2); /* declared vector2, not point2 */
  const clr_param *v2p = clr_params_find(&d->textures[1].params, "v2", CLR_PARAM_VECTOR2);
  assert_non_null(v2p);
  assert_int_equal(v2p->count, 2);
  clr_params_find_point3(&d->textures[1].params, "p3", (float[3]){0, 0, 0}, from);
  assert_point_near(from, 1, 2, 3, 0);

  int red = clr_scene_desc_find_named_material(d, "red");
  assert_true(red > 0);
  assert_string_equal(d->materials[red].type, "matte");
  assert_string_equal(clr_params_find_texture(&d->materials[red].params, "Kd", ""), "checks");
  assert_int_equal(
      clr_params_find_texture_index(&d->materials[red].params, "Kd", CLR_TEXTURE_SPECTRUM), 0);
  assert_int_equal(
      clr_params_find_texture_index(&d->materials[red].params, "Kd", CLR_TEXTURE_FLOAT), -1);
  assert_int_equal(
      clr_params_find_texture_index(&d->materials[red].params, "bumpmap", CLR_TEXTURE_FLOAT), 1);

  /* Shapes: sphere (plastic, area light, reversed, translated), mesh (named "red"), disk
   * (scaled), cylinder and cone in object "tree", sphere with Transform * ConcatTransform. */
  assert_int_equal(d->shape_count, 6);
  const clr_shape_desc *sphere = &d->shapes[0];
  assert_string_equal(sphere->type, "sphere");
  assert_true(clr_params_find_float(&sphere->params, "radius", 1) == 2.0f);
  assert_true(sphere->reverse_orientation);
  assert_int_equal(sphere->object, -1);
  const float t123[4][4] = {{1, 0, 0, 1}, {0, 1, 0, 2}, {0, 0, 1, 3}, {0, 0, 0, 1}};
  assert_matrix_near(sphere->object_to_world.m, t123, 0);
  const clr_material_desc *plastic = &d->materials[sphere->material];
  assert_null(plastic->name);
  assert_string_equal(plastic->type, "plastic");
  clr_params_find_rgb(&plastic->params, "Kd", (float[3]){0, 0, 0}, rgb);
  assert_point_near(rgb, .4f, .2f, .2f, 0);
  assert_true(clr_params_find_float(&plastic->params, "roughness", 0) == .1f);
  assert_int_equal(sphere->area_light, 0);
  assert_string_equal(d->area_lights[0].type, "diffuse");
  clr_params_find_rgb(&d->area_lights[0].params, "L", (float[3]){0, 0, 0}, rgb);
  assert_point_near(rgb, 5, 6, 7, 0);

  const clr_shape_desc *mesh = &d->shapes[1];
  assert_string_equal(mesh->type, "trianglemesh");
  assert_int_equal(mesh->material, red);
  assert_int_equal(mesh->area_light, -1); /* restored by AttributeEnd */
  assert_false(mesh->reverse_orientation);
  assert_true(clr_transform_is_identity(&mesh->object_to_world));
  const float *P = clr_params_find_point3s(&mesh->params, "P", &n);
  assert_int_equal(n, 3);
  assert_true(P[3] == 1.0f && P[7] == 1.0f);
  const int *idx = clr_params_find_ints(&mesh->params, "indices", &n);
  assert_int_equal(n, 3);
  assert_int_equal(idx[2], 2);
  assert_non_null(clr_params_find_normals(&mesh->params, "N", &n));
  assert_int_equal(n, 3);
  assert_non_null(clr_params_find_point2s(&mesh->params, "uv", &n));
  assert_int_equal(n, 3);
  assert_non_null(clr_params_find_vector3s(&mesh->params, "S", &n));
  assert_int_equal(n, 3);
  assert_non_null(clr_params_find_normals(&mesh->params, "N2", &n));
  assert_non_null(clr_params_find_vector3s(&mesh->params, "V", &n));
  assert_non_null(clr_params_find_point3s(&mesh->params, "P3", &n));

  const clr_shape_desc *disk = &d->shapes[2];
  const float s234[4][4] = {{2, 0, 0, 0}, {0, 3, 0, 0}, {0, 0, 4, 0}, {0, 0, 0, 1}};
  assert_matrix_near(disk->object_to_world.m, s234, 0);
  assert_int_equal(disk->material, red); /* TransformEnd restores only the CTM */

  assert_int_equal(d->object_count, 1);
  assert_string_equal(d->objects[0].name, "tree");
  assert_int_equal(d->objects[0].shape_count, 2);
  assert_string_equal(d->shapes[d->objects[0].shapes[0]].type, "cylinder");
  assert_string_equal(d->shapes[d->objects[0].shapes[1]].type, "cone");
  assert_int_equal(d->shapes[3].object, 0);
  assert_int_equal(d->instance_count, 2);
  assert_int_equal(d->instances[0].object, 0);
  const float t10[4][4] = {{1, 0, 0, 10}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  assert_matrix_near(d->instances[0].instance_to_world.m, t10, 0);
  const float t10r[4][4] = {{0, -1, 0, 10}, {1, 0, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  assert_matrix_near(d->instances[1].instance_to_world.m, t10r, 1e-6f);

  /* Transform lists the matrix column by column: translation (7,8,9), then scale 2. */
  const float ts[4][4] = {{2, 0, 0, 7}, {0, 2, 0, 8}, {0, 0, 2, 9}, {0, 0, 0, 1}};
  assert_matrix_near(d->shapes[5].object_to_world.m, ts, 0);
  assert_inverse_pair(&d->shapes[5].object_to_world, 1e-6f);

  /* Lookups marked everything above as used except these. */
  warnings u;
  memset(&u, 0, sizeof u);
  clr_params_report_unused(&d->textures[0].params, capture_warning, &u);
  if (u.count != 1) fail_msg("%d unused: %s", u.count, u.messages[0]);
  if (!strstr(u.messages[0],
              "scenes/test.pbrt:11: unused parameter 'uscale' in Texture 'checkerboard'"))
    fail_msg("%s", u.messages[0]);
  clr_scene_desc_free(d);
}

static void test_defaults(void **state) {
  (void)state;
  warnings w;
  clr_scene_desc *d = parse_ok("WorldBegin\nShape \"sphere\"\n", &w); /* no WorldEnd: fine */
  assert_int_equal(w.count, 0);
  assert_false(d->camera.given);
  assert_string_equal(d->camera.type, "perspective");
  assert_true(clr_transform_is_identity(&d->camera.camera_to_world));
  assert_string_equal(d->sampler.type, "halton");
  assert_string_equal(d->filter.type, "box");
  assert_string_equal(d->film.type, "image");
  assert_string_equal(d->integrator.type, "path");
  assert_false(d->sampler.given || d->filter.given || d->film.given || d->integrator.given);
  assert_int_equal(d->material_count, 1);
  assert_string_equal(d->materials[0].type, "matte");
  assert_int_equal(d->shapes[0].material, 0);
  assert_int_equal(d->shapes[0].area_light, -1);
  clr_scene_desc_free(d);
}

static void test_attribute_stack(void **state) {
  (void)state;
  warnings w;
  clr_scene_desc *d = parse_ok(
      "WorldBegin\n"
      "Material \"matte\" \"rgb Kd\" [.1 .1 .1]\n"
      "Texture \"t\" \"float\" \"constant\" \"float value\" 1\n"
      "Translate 1 0 0\n"
      "AttributeBegin\n"
      "  Material \"metal\"\n"
      "  MakeNamedMaterial \"inner\" \"string type\" \"glass\"\n"
      "  Texture \"t\" \"float\" \"constant\" \"float value\" 2\n"
      "  NamedMaterial \"inner\"\n"
      "  Rotate 90 0 1 0\n"
      "  AreaLightSource \"diffuse\"\n"
      "  ReverseOrientation\n"
      "  Shape \"sphere\" \"texture alpha\" \"t\"\n"
      "AttributeEnd\n"
      "Shape \"disk\" \"texture alpha\" \"t\"\n"
      "NamedMaterial \"inner\"\n"
      "Shape \"cone\"\n",
      &w);
  assert_int_equal(d->shape_count, 3);
  const clr_shape_desc *in = &d->shapes[0], *out = &d->shapes[1], *cone = &d->shapes[2];
  assert_string_equal(d->materials[in->material].type, "glass");
  assert_true(in->reverse_orientation);
  assert_int_equal(in->area_light, 0);
  assert_int_equal(clr_params_find_texture_index(&in->params, "alpha", CLR_TEXTURE_FLOAT), 1);
  /* After AttributeEnd: material, CTM, orientation, area light and the texture binding are
   * back to the outer ones. */
  assert_string_equal(d->materials[out->material].type, "matte");
  assert_false(out->reverse_orientation);
  assert_int_equal(out->area_light, -1);
  const float t100[4][4] = {{1, 0, 0, 1}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  assert_matrix_near(out->object_to_world.m, t100, 0);
  assert_int_equal(clr_params_find_texture_index(&out->params, "alpha", CLR_TEXTURE_FLOAT), 0);
  /* "inner" was scoped to the attribute block (pbrt-v3 keeps named materials in the graphics
   * state): warning, and the current Material is used. */
  assert_string_equal(d->materials[cone->material].type, "matte");
  assert_int_equal(
      warnings_containing(&w, "scenes/test.pbrt:17", "undefined named material 'inner'"), 1);
  assert_int_equal(w.count, 1);
  clr_scene_desc_free(d);
}

static void test_include_relative_paths(void **state) {
  (void)state;
  warnings w;
  clr_parse_options opts = capture_options(&w);
  clr_scene_desc *d = NULL;
  assert_int_equal(clr_scene_parse_file(SCENES "include_main.pbrt", &opts, &d), CLR_SUCCESS);
  assert_int_equal(w.count, 0);
  assert_int_equal(d->shape_count, 4);
  for (int i = 0; i < 4; ++i)
    assert_true(clr_params_find_float(&d->shapes[i].params, "radius", 0) == (float)(i + 1));
  assert_non_null(strstr(d->shapes[1].params.file, "tests/data/scenes/sub/include_child.pbrt"));
  assert_non_null(strstr(d->shapes[2].params.file, "sub/include_grandchild.pbrt"));
  assert_int_equal(d->shapes[2].params.line, 2);
  assert_non_null(strstr(d->shapes[3].params.file, "include_main.pbrt"));
  assert_int_equal(d->shapes[3].params.line, 5);
  clr_scene_desc_free(d);
}

/* Moving shapes: a triangle mesh or a sphere given two transforms keeps its end transform
 * (rendered with motion blur), and so does a moving ObjectInstance; a moving disk with an area
 * light moves without emitting, as pbrt-v3 ignores the area light of an animated shape (one
 * warning); a moving shape inside ObjectBegin is an error naming file:line:column (below). */
static void test_moving_shapes(void **state) {
  (void)state;
  warnings w;
  clr_scene_desc *d = parse_ok(
      "TransformTimes 0 1\nWorldBegin\n"
      "ObjectBegin \"o\"\nShape \"sphere\"\nObjectEnd\n"
      "ActiveTransform EndTime\nTranslate 1 2 3\nActiveTransform All\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 0 1 0 0 0 1 0]\n"
      "Shape \"sphere\"\n"
      "ObjectInstance \"o\"\n"
      "AttributeBegin\nAreaLightSource \"diffuse\"\n"
      "Shape \"disk\"\n"
      "AttributeEnd\nWorldEnd\n",
      &w);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:14:",
                                       "moving Shape \"disk\" does not emit: the area light of a "
                                       "moving shape is ignored, as pbrt-v3 does"),
                   1);
  assert_int_equal(w.count, 1);
  assert_int_equal(d->shape_count, 4);
  assert_int_equal(d->shapes[3].area_light, -1);
  for (int k = 1; k < 3; ++k) {
    assert_true(clr_transform_is_identity(&d->shapes[k].object_to_world));
    assert_true(d->shapes[k].object_to_world_end.m[0][3] == 1.0f &&
                d->shapes[k].object_to_world_end.m[1][3] == 2.0f &&
                d->shapes[k].object_to_world_end.m[2][3] == 3.0f);
  }
  assert_true(clr_transform_is_identity(&d->shapes[3].object_to_world));
  assert_true(d->shapes[3].object_to_world_end.m[0][3] == 1.0f);
  assert_true(clr_transform_is_identity(&d->instances[0].instance_to_world));
  assert_true(d->instances[0].instance_to_world_end.m[1][3] == 2.0f);
  assert_int_equal(d->instances[0].line, 11);
  clr_scene_desc_free(d);
}

static void test_warnings(void **state) {
  (void)state;
  warnings w;
  clr_scene_desc *d = parse_ok(
      "Accelerator \"bvh\" \"integer maxnodeprims\" 4\n"
      "TransformTimes 0 1\n"
      "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n"
      "WorldBegin\n"
      "MediumInterface \"fog\" \"\"\n"
      "ActiveTransform EndTime\n"
      "Translate 5 5 5\n"
      "ActiveTransform All\n"
      "AreaLightSource \"diffuse\" \"blackbody L\" [6500 1] \"spectrum S\" \"file.spd\"\n"
      "Shape \"sphere\" \"float radius\" 1 \"float bogus\" 3 \"texture alpha\" \"nope\"\n"
      "Camera \"orthographic\"\n"
      "ObjectInstance \"ghost\"\n"
      "WorldEnd\n"
      "Shape \"after\"\n",
      &w);
  assert_int_equal(warnings_containing(&w, "Accelerator", NULL), 0); /* silent, as pbrt-v3 */
  /* motion: TransformTimes and ActiveTransform are read (camera motion blur); a shape given two
   * transforms is warned about once */
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:2:", "TransformTimes"), 0);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:3:", "MakeNamedMedium"), 1);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:5:", "MediumInterface"), 1);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:6:", "ActiveTransform"), 0);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:8:", "ActiveTransform"), 0);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:10:", "does not emit"), 1);
  /* blackbody is converted to RGB (pbrt-v3's normalized form), not warned about */
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:9:", "'blackbody'"), 0);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:9:", "'spectrum'"), 1);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:10:", "undefined texture 'nope'"), 1);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:11:", "Camera is not allowed"), 1);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:12:", "undefined object 'ghost'"), 1);
  assert_int_equal(warnings_containing(&w, "scenes/test.pbrt:14:", "after WorldEnd"), 1);
  assert_int_equal(w.count, 8); /* Accelerator is silent */
  /* Translate while only EndTime was active did not move the start transform. */
  assert_true(clr_transform_is_identity(&d->shapes[0].object_to_world));
  assert_string_equal(d->camera.type, "perspective");
  assert_int_equal(d->shape_count, 1);
  /* Blackbody kept raw: (temperature, scale) pairs. */
  const clr_param *bb = clr_params_find(&d->area_lights[0].params, "L", CLR_PARAM_BLACKBODY);
  assert_non_null(bb);
  assert_true(bb->count == 2 && bb->floats[0] == 6500.0f);

  /* A renderer reads radius only: "bogus" and "alpha" are reported with file:line. */
  assert_true(clr_params_find_float(&d->shapes[0].params, "radius", 0) == 1.0f);
  warnings u;
  memset(&u, 0, sizeof u);
  int reported = clr_scene_desc_report_unused(d, capture_warning, &u);
  assert_int_equal(reported, 3); /* bogus, alpha, and the area light's S */
  assert_int_equal(warnings_containing(
                       &u, "scenes/test.pbrt:10: unused parameter 'bogus' in Shape 'sphere'", NULL),
                   1);
  assert_int_equal(warnings_containing(&u, "unused parameter 'alpha' in Shape 'sphere'", NULL), 1);
  assert_int_equal(
      warnings_containing(
          &u, "scenes/test.pbrt:9: unused parameter 'S' in AreaLightSource 'diffuse'", NULL),
      1);
  clr_scene_desc_free(d);
}

/* ---- errors ------------------------------------------------------------------------------ */

static void expect_parse_error(const char *text, clr_result code, const char *message_part) {
  warnings w;
  clr_parse_options opts = capture_options(&w);
  clr_scene_desc *d = (clr_scene_desc *)&w; /* must be reset to NULL */
  clr_result r = clr_scene_parse_string(text, "bad.pbrt", &opts, &d);
  if (r != code)
    fail_msg("got %s (%s), expected %s", clr_result_name(r), clr_last_error_message(),
             clr_result_name(code));
  assert_null(d);
  if (!strstr(clr_last_error_message(), message_part))
    fail_msg("message \"%s\" lacks \"%s\"", clr_last_error_message(), message_part);
}

static void test_syntax_errors(void **state) {
  (void)state;
  expect_parse_error(
      "TransformTimes 0 1\nWorldBegin\nObjectBegin \"o\"\nActiveTransform EndTime\n"
      "Translate 1 0 0\nActiveTransform All\nShape \"sphere\"\nObjectEnd\n",
      CLR_ERROR_PARSE,
      "bad.pbrt:7:1: moving Shape \"sphere\" (ActiveTransform) inside ObjectBegin "
      "'o' is not supported");
  expect_parse_error("WorldBegin\nShape \"sphere\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:7: expected '\"' closing the string, got end of line");
  expect_parse_error("WorldBegin\nShape \"sphere", CLR_ERROR_PARSE, "bad.pbrt:2:7: expected '\"'");
  expect_parse_error("WorldBegin\nShape \"sphere\" \"string s\" \"a\\qb\"", CLR_ERROR_PARSE,
                     "bad.pbrt:2:29: expected an escape");
  expect_parse_error("WorldBegin\nShape \"sphere\" \"float radius\" [ 1 \n", CLR_ERROR_PARSE,
                     "bad.pbrt:3:1: expected ']' closing the '[' at 2:31, got end of file");
  expect_parse_error("WorldBegin\nShape \"sphere\" \"float radius\" [ 1\nShape \"disk\"\n",
                     CLR_ERROR_PARSE,
                     "bad.pbrt:3:1: expected a number or ']' closing the '[' at 2:31, got 'Shape'");
  expect_parse_error("WorldBegin\n  Shpe \"sphere\"\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:3: expected a directive, got 'Shpe'");
  expect_parse_error("\"sphere\"\n", CLR_ERROR_PARSE,
                     "bad.pbrt:1:1: expected a directive, got string \"sphere\"");
  expect_parse_error("WorldBegin\nShape \"sphere\" \"floot radius\" 1\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:16: expected a parameter type");
  expect_parse_error("WorldBegin\nShape \"sphere\" \"float\" 1\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:16: expected \"float NAME\"");
  expect_parse_error(
      "WorldBegin\nShape \"trianglemesh\" \"point P\" [0 0 0 1]\n", CLR_ERROR_PARSE,
      "bad.pbrt:2:22: expected a multiple of 3 values for point3 parameter 'P', got 4");
  expect_parse_error("WorldBegin\nShape \"x\" \"point2 uv\" [0 0 1]\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:11: expected a multiple of 2 values for point2");
  expect_parse_error("WorldBegin\nShape \"x\" \"rgb Kd\" [1 2]\n", CLR_ERROR_PARSE,
                     "multiple of 3");
  expect_parse_error("WorldBegin\nShape \"x\" \"texture t\" [\"a\" \"b\"]\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:11: expected one texture name");
  expect_parse_error("Translate 1 two 3\n", CLR_ERROR_PARSE,
                     "bad.pbrt:1:13: expected a number, got 'two'");
  expect_parse_error("LookAt 0 0 0 0 0 1 0 1\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:1: expected a number, got end of file");
  expect_parse_error("WorldBegin\nShape \"x\" \"float r\" [1 \"a\"]\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:24: expected a number or ']'");
  expect_parse_error("WorldBegin\nShape \"x\" \"integer n\" [1.5]\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:24: expected an integer");
  expect_parse_error("WorldBegin\nShape \"x\" \"string s\" 3\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:22: expected a quoted string, got '3'");
  expect_parse_error("WorldBegin\nShape \"x\" \"bool b\" \"yes\"\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:20: expected true or false");
  expect_parse_error("WorldBegin\nShape \"x\" \"float r\" ]\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:21: expected a value or '['");
  expect_parse_error("WorldBegin\nShape sphere\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:7: expected a quoted type name after Shape, got 'sphere'");
  expect_parse_error("Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 1]\n", CLR_ERROR_PARSE,
                     "bad.pbrt:1:44: expected ']' after 16 numbers");
  expect_parse_error("WorldBegin\nAttributeBegin\nAttributeEnd\nAttributeEnd\n", CLR_ERROR_PARSE,
                     "bad.pbrt:4:1: expected a AttributeBegin before AttributeEnd, got none");
  expect_parse_error("WorldBegin\nAttributeBegin\nTransformEnd\n", CLR_ERROR_PARSE,
                     "bad.pbrt:3:1: expected AttributeEnd (for the AttributeBegin at bad.pbrt:2)");
  expect_parse_error("WorldBegin\nObjectEnd\n", CLR_ERROR_PARSE,
                     "bad.pbrt:2:1: expected a ObjectBegin");
  expect_parse_error("WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\"\n", CLR_ERROR_PARSE,
                     "bad.pbrt:3:1: expected ObjectEnd for object 'a'");
  expect_parse_error("ActiveTransform Sometimes\n", CLR_ERROR_PARSE, "bad.pbrt:1:17: expected All");
  /* An error after many successful directives leaves nothing behind (checked under valgrind). */
  char *long_bad = malloc(strlen(full_scene) + 32);
  assert_non_null(long_bad);
  strcpy(long_bad, full_scene);
  strcpy(strstr(long_bad, "WorldEnd\n"), "  Oops\nWorldEnd\n");
  expect_parse_error(long_bad, CLR_ERROR_PARSE, "bad.pbrt:48:3: expected a directive, got 'Oops'");
  free(long_bad);
}

static void test_file_errors(void **state) {
  (void)state;
  warnings w;
  clr_parse_options opts = capture_options(&w);
  clr_scene_desc *d = NULL;
  assert_int_equal(clr_scene_parse_file(SCENES "include_missing.pbrt", &opts, &d), CLR_ERROR_IO);
  assert_null(d);
  const char *msg = clr_last_error_message();
  assert_non_null(strstr(msg, "include_missing.pbrt:3:1: Include"));
  assert_non_null(strstr(msg, "tests/data/scenes/does-not-exist.pbrt"));

  assert_int_equal(clr_scene_parse_file(SCENES "include_recursive.pbrt", &opts, &d),
                   CLR_ERROR_PARSE);
  assert_non_null(
      strstr(clr_last_error_message(),
             "include_recursive.pbrt:2:1: expected Include files nested at most 32 deep"));

  assert_int_equal(clr_scene_parse_file(SCENES "unterminated_bracket.pbrt", &opts, &d),
                   CLR_ERROR_PARSE);
  assert_non_null(strstr(clr_last_error_message(),
                         "unterminated_bracket.pbrt:3:3: expected a number or ']' closing the '[' "
                         "at 2:32, got string \"integer indices\""));

  assert_int_equal(clr_scene_parse_file(SCENES "no-such-scene.pbrt", &opts, &d), CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "no-such-scene.pbrt"));
  assert_int_equal(clr_scene_parse_file(NULL, &opts, &d), CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_scene_parse_string("", NULL, NULL, NULL), CLR_ERROR_NULL_POINTER);
}

/* ---- pbrt-v3's example scene ------------------------------------------------------------- */

static void test_killeroo_simple(void **state) {
  (void)state;
  warnings w;
  clr_parse_options opts = capture_options(&w);
  clr_scene_desc *d = NULL;
  clr_result r = clr_scene_parse_file(CLR_SOURCE_DIR "/scenes/killeroo-simple/killeroo-simple.pbrt",
                                      &opts, &d);
  if (r != CLR_SUCCESS) fail_msg("%s", clr_last_error_message());
  assert_int_equal(w.count, 0);

  assert_true(d->camera.given);
  assert_string_equal(d->camera.type, "perspective");
  assert_true(clr_params_find_float(&d->camera.params, "fov", 90) == 39.0f);
  /* CTM = LookAt * Rotate(-5, z): world points are rotated first, so world-from-camera puts
   * the camera at the LookAt eye rotated by +5 degrees about world z, looking along the
   * equally rotated direction to the target. */
  const double c = cos(5 * 3.14159265358979323846 / 180), s = sin(5 * 3.14159265358979323846 / 180);
  const double e[3] = {400, 20, 30}, view[3] = {-400, 43, -140};
  double len = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
  float eye[3], dir[3];
  clr_transform_point(&d->camera.camera_to_world, (float[3]){0, 0, 0}, eye);
  assert_point_near(eye, (float)(c * e[0] - s * e[1]), (float)(s * e[0] + c * e[1]), 30, 1e-3f);
  clr_transform_vector(&d->camera.camera_to_world, (float[3]){0, 0, 1}, dir);
  assert_point_near(dir, (float)((c * view[0] - s * view[1]) / len),
                    (float)((s * view[0] + c * view[1]) / len), (float)(view[2] / len), 1e-5f);
  assert_inverse_pair(&d->camera.camera_to_world, 1e-3f);

  assert_int_equal(clr_params_find_int(&d->film.params, "xresolution", 0), 700);
  assert_int_equal(clr_params_find_int(&d->film.params, "yresolution", 0), 700);
  assert_string_equal(clr_params_find_string(&d->film.params, "filename", ""),
                      "killeroo-simple.exr");
  assert_string_equal(d->sampler.type, "halton");
  assert_int_equal(clr_params_find_int(&d->sampler.params, "pixelsamples", 0), 8);
  assert_string_equal(d->integrator.type, "path");
  assert_true(d->integrator.given);
  assert_false(d->filter.given);

  assert_int_equal(d->shape_count, 5);
  assert_int_equal(d->light_count, 0);
  const clr_shape_desc *light = &d->shapes[0];
  assert_string_equal(light->type, "sphere");
  assert_true(clr_params_find_float(&light->params, "radius", 1) == 3.0f);
  const float t[4][4] = {{1, 0, 0, 150}, {0, 1, 0, 120}, {0, 0, 1, 20}, {0, 0, 0, 1}};
  assert_matrix_near(light->object_to_world.m, t, 0);
  assert_int_equal(light->area_light, 0);
  float L[3];
  clr_params_find_rgb(&d->area_lights[0].params, "L", (float[3]){0, 0, 0}, L);
  assert_point_near(L, 2000, 2000, 2000, 0);
  assert_int_equal(clr_params_find_int(&d->area_lights[0].params, "nsamples", 1), 8);

  for (int i = 1; i <= 2; ++i) {
    assert_string_equal(d->shapes[i].type, "trianglemesh");
    assert_int_equal(d->shapes[i].area_light, -1);
    int n = 0;
    assert_non_null(clr_params_find_point3s(&d->shapes[i].params, "P", &n));
    assert_int_equal(n, 4);
    assert_non_null(clr_params_find_floats(&d->shapes[i].params, "uv", &n));
    assert_int_equal(n, 8);
  }
  float p[3];
  clr_transform_point(&d->shapes[1].object_to_world, (float[3]){0, 0, 0}, p);
  assert_point_near(p, 0, 0, -140, 0);

  /* The two killeroos: loop subdivision surfaces from geometry/killeroo.pbrt. */
  for (int i = 3; i <= 4; ++i) {
    const clr_shape_desc *k = &d->shapes[i];
    assert_string_equal(k->type, "loopsubdiv");
    assert_non_null(strstr(k->params.file, "killeroo-simple/geometry/killeroo.pbrt"));
    assert_int_equal(clr_params_find_int(&k->params, "nlevels", 0), 1);
    int ni = 0, np = 0;
    const int *indices = clr_params_find_ints(&k->params, "indices", &ni);
    const float *points = clr_params_find_point3s(&k->params, "P", &np);
    assert_non_null(indices);
    assert_non_null(points);
    assert_true(ni > 0 && ni % 3 == 0 && np > 0);
    assert_int_equal(indices[0], 2298);
    for (int j = 0; j < ni; ++j) assert_true(indices[j] >= 0 && indices[j] < np);
    assert_string_equal(d->materials[k->material].type, "plastic");
  }
  assert_true(clr_params_find_float(&d->materials[d->shapes[3].material].params, "roughness", 0) ==
              .025f);
  assert_true(clr_params_find_float(&d->materials[d->shapes[4].material].params, "roughness", 0) ==
              .15f);
  /* Second killeroo = first one moved by Translate -200 0 0 in the scaled, rotated frame. */
  float a[3], b[3];
  clr_transform_point(&d->shapes[3].object_to_world, (float[3]){0, 0, 0}, a);
  clr_transform_point(&d->shapes[4].object_to_world, (float[3]){0, 0, 0}, b);
  float dx = b[0] - a[0], dy = b[1] - a[1];
  assert_true(fabsf(sqrtf(dx * dx + dy * dy) - 100.0f) < 1e-3f); /* 200 * scale 0.5 */
  clr_scene_desc_free(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_transform_primitives),
      cmocka_unit_test(test_matrix_inverse),
      cmocka_unit_test(test_look_at),
      cmocka_unit_test(test_options_and_parameter_types),
      cmocka_unit_test(test_defaults),
      cmocka_unit_test(test_attribute_stack),
      cmocka_unit_test(test_include_relative_paths),
      cmocka_unit_test(test_moving_shapes),
      cmocka_unit_test(test_warnings),
      cmocka_unit_test(test_syntax_errors),
      cmocka_unit_test(test_file_errors),
      cmocka_unit_test(test_killeroo_simple),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
