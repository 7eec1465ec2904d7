/* End-to-end renders of small scenes with known answers, determinism across threads, tiles and
 * crops, and CLI failures on bad scene files. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>
#include "clrender.h"
#include "renderer.h"
#include "scene_parser.h"
#include "integrator.h"
#include "render_scene.h"
#include "cornell_test_scene.h"
#include "scene_test_util.h"

#define PI_F 3.14159265358979323846

static clr_render_image render_text(const char *text, const clr_render_options *opts) {
  return stu_render_image(text, "test.pbrt", opts, NULL);
}

/* pbrt-v3 AO: each unoccluded cosine-weighted direction adds Dot(wi,n)/(pdf nSamples) = pi/n, so
 * an open plane is exactly pi everywhere. */
static void test_ao_open_plane(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [2]\n"
      "Integrator \"ambientocclusion\" \"integer nsamples\" [8]\n"
      "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n";
  clr_render_image im = render_text(scene, NULL);
  assert_int_equal(im.width, 16);
  for (int i = 0; i < im.width * im.height * 3; ++i) assert_float_equal(im.rgb[i], PI_F, 1e-4);
  free(im.rgb);
}

/* Scene files with pbrt-v3's (0,2)-sequence sampler under both of its names and maxmindist
 * (pixelsamples 3 is rounded up to 4 with a warning, as pbrt-v3 does): the open plane is still pi
 * everywhere. */
static void test_ao_open_plane_02sequence(void **state) {
  (void)state;
  static const char *names[] = {"02sequence", "lowdiscrepancy", "maxmindist"};
  for (int n = 0; n < 3; ++n) {
    char scene[1024];
    snprintf(scene, sizeof scene,
             "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\"\n"
             "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
             "Sampler \"%s\" \"integer pixelsamples\" [3] \"integer dimensions\" [2]\n"
             "Integrator \"ambientocclusion\" \"integer nsamples\" [%d]\n"
             "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
             "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
             names[n], n == 1 ? 3 : 8); /* 3: rounded up to 4 as pbrt-v3's RoundCount */
    clr_render_image im = render_text(scene, NULL);
    assert_int_equal(im.width, 16);
    for (int i = 0; i < im.width * im.height * 3; ++i) assert_float_equal(im.rgb[i], PI_F, 1e-4);
    free(im.rgb);
  }
}

static void count_warning(void *user, const char *message) {
  if (strstr(message, "Taking 4 samples, not 3 as specified")) ++*(int *)user;
}

/* pbrt-v3's integrators round their array sizes with the sampler's RoundCount. */
static void test_integrator_round_count(void **state) {
  (void)state;
  const char *text =
      "Film \"image\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
      "Integrator \"ambientocclusion\" \"integer nsamples\" [3]\n"
      "WorldBegin\nShape \"sphere\"\nWorldEnd\n";
  clr_scene_desc *desc = NULL;
  clr_render_scene *scene = stu_build(text, "test.pbrt", &desc);
  static const struct {
    clr_sampler_type type;
    int want;
  } cases[] = {{CLR_SAMPLER_HALTON, 3}, {CLR_SAMPLER_ZEROTWO, 4}, {CLR_SAMPLER_MAXMINDIST, 4}};
  for (int c = 0; c < 3; ++c) {
    clr_integrator it;
    int warnings = 0;
    assert_int_equal(
        clr_integrator_create_for(desc, scene, cases[c].type, count_warning, &warnings, &it),
        CLR_SUCCESS);
    assert_int_equal(it.ao_samples, cases[c].want);
    assert_int_equal(it.requests[it.request_count - 1].array_size, cases[c].want);
    assert_int_equal(warnings, cases[c].want == 4);
    clr_integrator_free(&it);
  }
  clr_render_scene_free(scene);
  clr_scene_desc_free(desc);
}

/* Lambertian plane under a point light, pixel-centre samples and a box filter: every pixel is
 * Kd/pi * I cos(theta) / r^2 at the point it sees. */
static void test_point_light_plane(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [32] \"integer yresolution\" [32]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
      "Integrator \"directlighting\"\n"
      "WorldBegin\nLightSource \"point\" \"point from\" [0.3 -0.2 2] \"rgb I\" [5 5 5]\n"
      "Material \"matte\" \"rgb Kd\" [0.5 0.25 0.125]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n";
  clr_render_image im = render_text(scene, NULL);
  double kd[3] = {0.5, 0.25, 0.125};
  for (int py = 0; py < 32; ++py)
    for (int px = 0; px < 32; ++px) {
      /* camera x is world -x (pbrt's left-handed LookAt), camera y world +y */
      double sx = -1.0 + 2.0 * (px + 0.5) / 32.0, sy = 1.0 - 2.0 * (py + 0.5) / 32.0;
      double wx = -sx, wy = sy;
      double dx = 0.3 - wx, dy = -0.2 - wy, dz = 2.0, r2 = dx * dx + dy * dy + dz * dz;
      double cos_t = dz / sqrt(r2);
      for (int c = 0; c < 3; ++c) {
        double expect = kd[c] / PI_F * 5.0 * cos_t / r2;
        double got = im.rgb[3 * (py * 32 + px) + c];
        assert_true(fabs(got - expect) <= 1e-4 * expect);
      }
    }
  free(im.rgb);
}

static double mean_channel(const clr_render_image *im, int x0, int x1, int y0, int y1, int c) {
  double s = 0.0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) s += im->rgb[3 * (y * im->width + x) + c];
  return s / ((x1 - x0) * (y1 - y0));
}

/* Closed emitting sphere around the camera with albedo a: L = Le / (1 - a). */
static void test_furnace(void **state) {
  (void)state;
  const char *scene =
      "Camera \"perspective\" \"float fov\" [60]\n"
      "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [64]\n"
      "Integrator \"path\" \"integer maxdepth\" [200] \"float rrthreshold\" [1]\n"
      "WorldBegin\nAttributeBegin\nReverseOrientation\n"
      "AreaLightSource \"diffuse\" \"rgb L\" [0.25 0.25 0.25]\n"
      "Material \"matte\" \"rgb Kd\" [0.75 0.75 0.75]\n"
      "Shape \"sphere\" \"float radius\" [2]\nAttributeEnd\nWorldEnd\n";
  clr_render_image im = render_text(scene, NULL);
  double m = mean_channel(&im, 0, 8, 0, 8, 0);
  assert_true(fabs(m - 1.0) < 0.03);
  free(im.rgb);
}

/* Unoccluded convex matte sphere under a constant infinite light: Lo = Kd * L. */
static void test_infinite_light_sphere(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-2 2 -2 2]\n"
      "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [64]\n"
      "Integrator \"directlighting\"\n"
      "WorldBegin\nLightSource \"infinite\" \"rgb L\" [2 1 0.5]\n"
      "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5]\nShape \"sphere\" \"float radius\" "
      "[1.5]\nWorldEnd\n";
  clr_render_image im = render_text(scene, NULL);
  double L[3] = {2, 1, 0.5};
  for (int c = 0; c < 3; ++c) {
    assert_true(fabs(mean_channel(&im, 6, 10, 6, 10, c) - 0.5 * L[c]) < 0.03 * 0.5 * L[c]);
    assert_float_equal(im.rgb[c], L[c], 1e-6); /* corner: background */
  }
  free(im.rgb);
}

static const char *small_box = CORNELL_CAMERA
    "Film \"image\" \"integer xresolution\" [40] \"integer yresolution\" [36]\n"
    "Sampler \"halton\" \"integer pixelsamples\" [4]\nPixelFilter \"triangle\"\n"
    "Integrator \"path\" \"integer maxdepth\" [3]\nWorldBegin\n" CORNELL_LIGHT_FLOOR_AND_BACK_WALL
    "Shape \"sphere\" \"float radius\" [100]\nWorldEnd\n";

static void test_threads_bit_identical(void **state) {
  (void)state;
  clr_render_options o;
  clr_render_options_init(&o);
  o.nthreads = 1;
  clr_render_image a = render_text(small_box, &o);
  o.nthreads = 2;
  clr_render_image b = render_text(small_box, &o);
  assert_memory_equal(a.rgb, b.rgb, (size_t)a.width * a.height * 3 * sizeof(float));
  free(a.rgb);
  free(b.rgb);
}

/* The progress callback sees the tile counts grow and stops the render when it returns 1. */
typedef struct progress_log {
  int calls, stop_after, last_done, total;
} progress_log;

static int count_progress(void *user, int32_t done, int32_t total) {
  progress_log *log = user;
  assert_true(done >= log->last_done && done <= total);
  log->calls++;
  log->last_done = done;
  log->total = total;
  return log->stop_after >= 0 && done >= log->stop_after;
}

static void test_progress_callback_cancels(void **state) {
  (void)state;
  clr_scene_desc *desc = NULL;
  clr_parse_options po;
  clr_parse_options_init(&po);
  assert_int_equal(clr_scene_parse_string(small_box, "test.pbrt", &po, &desc), CLR_SUCCESS);
  clr_render_options o;
  clr_render_options_init(&o);
  o.quiet = 1;
  o.tile_size = 8; /* 44 x 40 sample bounds (triangle radius 2): 6 x 5 tiles */
  o.progress_callback = count_progress;
  progress_log full = {0, -1, 0, 0}, stopped = {0, 0, 0, 0}; /* stopped: at the first call */
  clr_render_stats st;
  clr_render_stats_init(&st);
  o.progress_user = &full;
  assert_int_equal(clr_render_desc(desc, &o, &st, 0, NULL), CLR_SUCCESS);
  assert_int_equal(full.total, 30);
  assert_int_equal(st.tiles_total, 30);
  assert_int_equal(full.last_done, 29); /* called before each merge: the last sees 29 done */
  assert_int_equal(st.tiles_done, 30);
  assert_int_equal(st.partial, 0);
  clr_render_stats_init(&st);
  o.progress_user = &stopped;
  assert_int_equal(clr_render_desc(desc, &o, &st, 0, NULL), CLR_SUCCESS);
  assert_int_equal(st.partial, 1);
  assert_int_equal(st.tiles_done, 0);
  assert_int_equal(stopped.calls, 1);
  clr_scene_desc_free(desc);
}

static void assert_close(const float *a, const float *b, size_t n) {
  for (size_t i = 0; i < n; ++i)
    assert_true(fabsf(a[i] - b[i]) <= 1e-5f * fmaxf(1.0f, fabsf(a[i])));
}

static void test_tile_sizes_agree(void **state) {
  (void)state;
  clr_render_options o;
  clr_render_options_init(&o);
  o.tile_size = 8;
  clr_render_image a = render_text(small_box, &o);
  o.tile_size = 16;
  clr_render_image b = render_text(small_box, &o);
  assert_close(a.rgb, b.rgb, (size_t)a.width * a.height * 3);
  free(a.rgb);
  free(b.rgb);
}

static void test_crop_matches_full(void **state) {
  (void)state;
  clr_render_image full = render_text(small_box, NULL);
  clr_render_options o;
  clr_render_options_init(&o);
  o.crop_given = 1;
  float cw[4] = {0.25f, 0.6f, 0.5f, 1.0f};
  memcpy(o.crop_window, cw, sizeof cw);
  clr_render_image crop = render_text(small_box, &o);
  assert_int_equal(crop.pixel_bounds.x0, 10);
  assert_int_equal(crop.pixel_bounds.y0, 18);
  for (int y = 0; y < crop.height; ++y)
    assert_close(crop.rgb + 3 * y * crop.width,
                 full.rgb + 3 * ((y + crop.pixel_bounds.y0) * full.width + crop.pixel_bounds.x0),
                 (size_t)crop.width * 3);
  free(full.rgb);
  free(crop.rgb);
}

/* ---- CLI failures ---- */

static char tmpdir[256];

static void write_file(const char *name, const char *text, size_t n) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(text, 1, n, f), n);
  fclose(f);
}

/* Runs the CLI on tmpdir/name; expects exit 1, `expect` in the message and no output. */
static void expect_cli_failure(const char *name, const char *expect) {
  char cmd[1200], out[4096] = {0}, exr[512], png[512];
  snprintf(exr, sizeof exr, "%s/out.exr", tmpdir);
  snprintf(png, sizeof png, "%s/out.png", tmpdir);
  snprintf(cmd, sizeof cmd, "%s render %s/%s --outfile %s --quiet 2>&1", CLR_CLI_PATH, tmpdir, name,
           exr);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t n = fread(out, 1, sizeof out - 1, p);
  out[n] = 0;
  int status = pclose(p);
  if (!strstr(out, expect)) fprintf(stderr, "output: %s\n(expected \"%s\")\n", out, expect);
  assert_int_equal(WEXITSTATUS(status), 1);
  assert_non_null(strstr(out, expect));
  assert_int_equal(access(exr, F_OK), -1);
  assert_int_equal(access(png, F_OK), -1);
}

static const char *head =
    "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\nWorldBegin\n";

/* The OpenCL setup runs beside the scene build (device_setup.c): a scene error is reported
 * before a device error, as when the two ran one after the other, and a device error alone is
 * reported with its own message. */
static void test_scene_error_before_device_error(void **state) {
  (void)state;
  const char *bad_scene =
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
      "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
      "WorldBegin\nShape \"plymesh\" \"string filename\" \"missing-mesh.ply\"\nWorldEnd\n";
  const char *good_scene =
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
      "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
      "WorldBegin\nShape \"sphere\"\nWorldEnd\n";
  const char *scenes[2] = {bad_scene, good_scene};
  const char *expected[2] = {"missing-mesh.ply", "no-such-device-here"};
  for (int k = 0; k < 2; ++k) {
    clr_scene_desc *desc = NULL;
    clr_parse_options po;
    clr_parse_options_init(&po);
    assert_int_equal(clr_scene_parse_string(scenes[k], "test.pbrt", &po, &desc), CLR_SUCCESS);
    clr_render_options o;
    clr_render_options_init(&o);
    o.quiet = 1;
    o.device = "no-such-device-here";
    clr_render_image im;
    memset(&im, 0, sizeof im);
    assert_int_not_equal(clr_render_desc(desc, &o, NULL, 0, &im), CLR_SUCCESS);
    assert_non_null(strstr(clr_last_error_message(), expected[k]));
    assert_null(im.rgb);
    clr_scene_desc_free(desc);
  }
}

static void test_cli_bad_files(void **state) {
  (void)state;
  snprintf(tmpdir, sizeof tmpdir, "%s/test_render_tmp_XXXXXX", CLR_BINARY_DIR);
  assert_non_null(mkdtemp(tmpdir));
  char text[2048];
  snprintf(text, sizeof text,
           "%sShape \"sphere\" \"float radius\" [1]\nMaterial \"matte\" \"string x\" \"open", head);
  write_file("unterminated.pbrt", text, strlen(text));
  expect_cli_failure("unterminated.pbrt", "unterminated.pbrt:4");
  snprintf(text, sizeof text, "%s\nInclude \"no-such-file.pbrt\"\n", head);
  write_file("include.pbrt", text, strlen(text));
  expect_cli_failure("include.pbrt", "include.pbrt:4");
  snprintf(
      text, sizeof text,
      "%s\n\nShape \"trianglemesh\" \"integer indices\" [0 1 7] \"point P\" [0 0 0 1 0 0 0 1 0]\n",
      head);
  write_file("index.pbrt", text, strlen(text));
  expect_cli_failure("index.pbrt", "index.pbrt:5");
  const char ply[] =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n\0\0\0\0\0\0";
  write_file("trunc.ply", ply, sizeof ply - 1);
  snprintf(text, sizeof text, "%sShape \"plymesh\" \"string filename\" \"trunc.ply\"\n", head);
  write_file("ply.pbrt", text, strlen(text));
  expect_cli_failure("ply.pbrt", "ply.pbrt:3");
  /* a good scene through the CLI writes both files */
  snprintf(text, sizeof text, "%sShape \"sphere\"\nWorldEnd\n", head);
  write_file("good.pbrt", text, strlen(text));
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "%s render %s/good.pbrt --outfile %s/good.exr --quiet --spp 1",
           CLR_CLI_PATH, tmpdir, tmpdir);
  assert_int_equal(system(cmd), 0);
  snprintf(cmd, sizeof cmd, "%s/good.png", tmpdir);
  assert_int_equal(access(cmd, F_OK), 0);
  snprintf(cmd, sizeof cmd, "%s render --bogus 2>/dev/null", CLR_CLI_PATH);
  assert_int_equal(WEXITSTATUS(system(cmd)), 2);
  snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
  assert_int_equal(system(cmd), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ao_open_plane),
      cmocka_unit_test(test_ao_open_plane_02sequence),
      cmocka_unit_test(test_integrator_round_count),
      cmocka_unit_test(test_point_light_plane),
      cmocka_unit_test(test_furnace),
      cmocka_unit_test(test_infinite_light_sphere),
      cmocka_unit_test(test_threads_bit_identical),
      cmocka_unit_test(test_tile_sizes_agree),
      cmocka_unit_test(test_crop_matches_full),
      cmocka_unit_test(test_scene_error_before_device_error),
      cmocka_unit_test(test_cli_bad_files),
      cmocka_unit_test(test_progress_callback_cancels),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
