#define _POSIX_C_SOURCE 200809L
/* Film output and merging: EXR round trip of values and metadata, PNG preview, quarter crops and
 * independent passes merged (API and `clrender merge`) against the single film, bad input. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>
#include "clrender.h"
#include "exr_io.h"
#include "pcg32.h"

static clr_context ctx;
static char dir[256]; /* under the build tree */

static int setup(void **state) {
  (void)state;
  if (snprintf(dir, sizeof dir, "%s/test_film_output_XXXXXX", CLR_BINARY_DIR) >= 200) {
    fprintf(stderr, "test_film_output: build folder path too long: %s\n", CLR_BINARY_DIR);
    return -1;
  }
  if (!mkdtemp(dir)) return -1;
  return clr_context_create(NULL, &ctx) == CLR_SUCCESS ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd) != 0) return -1;
  clr_context_release(ctx);
  return 0;
}

#define W 48
#define H 32

static clr_film_sample *random_samples(size_t n, uint64_t seq) {
  clr_film_sample *s = malloc(n * sizeof *s);
  clr_pcg32 rng = clr_pcg32_sequence(seq);
  for (size_t i = 0; i < n; ++i) {
    s[i].x = clr_pcg32_float(&rng) * W;
    s[i].y = clr_pcg32_float(&rng) * H;
    s[i].r = clr_pcg32_float(&rng) * 2.0f;
    s[i].g = clr_pcg32_float(&rng);
    s[i].b = clr_pcg32_float(&rng) * 0.5f;
    s[i].weight = 1.0f;
  }
  return s;
}

static clr_film make_film(clr_filter_type type, float x0, float x1, float y0, float y1) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = W;
  d.y_resolution = H;
  d.crop_window[0] = x0;
  d.crop_window[1] = x1;
  d.crop_window[2] = y0;
  d.crop_window[3] = y1;
  clr_filter_desc_init(&d.filter, type);
  clr_film f = NULL;
  assert_int_equal(film_create(ctx, &d, &f), CLR_SUCCESS);
  return f;
}

static void path_of(char *out, size_t n, const char *name) { snprintf(out, n, "%s/%s", dir, name); }

static void test_exr_round_trip(void **state) {
  (void)state;
  clr_film f = make_film(CLR_FILTER_MITCHELL, 0.25f, 0.75f, 0.0f, 0.5f);
  clr_film_sample *s = random_samples(20000, 1);
  assert_int_equal(film_add_samples(f, s, 20000), CLR_SUCCESS);
  char path[300];
  path_of(path, sizeof path, "round.exr");
  clr_film_write_options o;
  clr_film_write_options_init(&o);
  o.sampler = "sobol";
  o.spp = 16;
  o.render_time_s = 1.5;
  const char *keys[] = {"clrender.scene"}, *values[] = {"unit test"};
  o.metadata_keys = keys;
  o.metadata_values = values;
  o.metadata_count = 1;
  assert_int_equal(film_write(f, path, &o), CLR_SUCCESS);
  clr_exr_image *im = NULL;
  assert_int_equal(clr_exr_read(path, &im), CLR_SUCCESS);
  assert_int_equal(im->display_width, W);
  assert_int_equal(im->display_height, H);
  clr_bounds2i pb = film_pixel_bounds(f);
  assert_int_equal(im->data_window.x0, pb.x0);
  assert_int_equal(im->data_window.x1, pb.x1);
  assert_int_equal(im->data_window.y0, 0);
  assert_int_equal(im->data_window.y1, 16);
  size_t n = (size_t)(pb.x1 - pb.x0) * (pb.y1 - pb.y0);
  float *rgb = malloc(n * 3 * sizeof(float));
  assert_int_equal(film_get_rgb(f, rgb, 1.0f), CLR_SUCCESS);
  const char *names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    const float *plane = clr_exr_image_channel(im, names[c]);
    assert_non_null(plane);
    for (size_t i = 0; i < n; ++i) assert_memory_equal(&plane[i], &rgb[3 * i + c], 4);
  }
  assert_string_equal(clr_exr_image_string_attr(im, "clrender.sampler"), "sobol");
  assert_string_equal(clr_exr_image_string_attr(im, "clrender.filter"), "mitchell");
  assert_string_equal(clr_exr_image_string_attr(im, "clrender.scene"), "unit test");
  assert_non_null(strstr(clr_exr_image_string_attr(im, "software"), "clrender"));
  assert_string_equal(clr_exr_image_string_attr(im, "clrender.cropwindow"), "0.25 0.75 0 0.5");
  int32_t spp = 0, partial = 7;
  float radius = 0, t = 0, bc = 0;
  assert_true(clr_exr_image_int_attr(im, "clrender.spp", &spp));
  assert_int_equal(spp, 16);
  assert_true(clr_exr_image_int_attr(im, "clrender.partial", &partial));
  assert_int_equal(partial, 0);
  assert_true(clr_exr_image_float_attr(im, "clrender.filter.xwidth", &radius));
  assert_true(radius == 2.0f);
  assert_true(clr_exr_image_float_attr(im, "clrender.filter.B", &bc));
  assert_true(bc == 1.0f / 3.0f);
  assert_true(clr_exr_image_float_attr(im, "clrender.render_time_s", &t));
  assert_true(t == 1.5f);
  /* The raw sums: hi + lo reproduce the film's double sums. */
  double *w = malloc(n * sizeof(double));
  assert_int_equal(film_get_sums(f, NULL, w, NULL), CLR_SUCCESS);
  const float *hi = clr_exr_image_channel(im, "weight"),
              *lo = clr_exr_image_channel(im, "weight.lo");
  assert_non_null(hi);
  assert_non_null(lo);
  for (size_t i = 0; i < n; ++i)
    assert_true(fabs((double)hi[i] + (double)lo[i] - w[i]) <= 1e-12 * fabs(w[i]) + 1e-30);
  free(w);
  clr_exr_image_free(im);

  /* Half RGB, no sums. */
  o.half = 1;
  o.include_sums = 0;
  path_of(path, sizeof path, "half.exr");
  assert_int_equal(film_write(f, path, &o), CLR_SUCCESS);
  assert_int_equal(clr_exr_read(path, &im), CLR_SUCCESS);
  assert_null(clr_exr_image_channel(im, "weight"));
  const float *r = clr_exr_image_channel(im, "R");
  for (size_t i = 0; i < n; ++i)
    assert_true(fabsf(r[i] - rgb[3 * i]) <= 1e-3f * fabsf(rgb[3 * i]) + 1e-6f);
  clr_exr_image_free(im);
  /* PNG preview. */
  path_of(path, sizeof path, "preview.png");
  assert_int_equal(film_write_png(f, path, 1.0f), CLR_SUCCESS);
  struct stat st;
  assert_int_equal(stat(path, &st), 0);
  assert_true(st.st_size > 100);
  free(rgb);
  free(s);
  film_release(f);
}

static double max_rel_diff(const float *a, const float *b, size_t n) {
  double mean = 0;
  for (size_t i = 0; i < n; ++i) mean += fabs(b[i]);
  mean /= (double)n;
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    double ref = fabs(b[i]) > mean ? fabs(b[i]) : mean;
    double d = fabs((double)a[i] - (double)b[i]) / ref;
    if (d > worst) worst = d;
  }
  return worst;
}

/* Reads R,G,B of `path` over the full frame (pixels outside its data window stay 0). */
static float *read_rgb(const char *path) {
  clr_exr_image *im = NULL;
  assert_int_equal(clr_exr_read(path, &im), CLR_SUCCESS);
  float *rgb = calloc((size_t)W * H * 3, sizeof(float));
  const char *names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    const float *p = clr_exr_image_channel(im, names[c]);
    assert_non_null(p);
    for (int y = 0; y < im->height; ++y)
      for (int x = 0; x < im->width; ++x)
        rgb[3 * ((size_t)(y + im->data_window.y0) * W + x + im->data_window.x0) + c] =
            p[(size_t)y * im->width + x];
  }
  clr_exr_image_free(im);
  return rgb;
}

static void test_merge_quarters_and_passes(void **state) {
  (void)state;
  const clr_filter_type filters[] = {CLR_FILTER_BOX, CLR_FILTER_GAUSSIAN, CLR_FILTER_SINC};
  for (int fi = 0; fi < 3; ++fi) {
    size_t n = 30000;
    clr_film_sample *s = random_samples(n, 7 + fi);
    clr_film full = make_film(filters[fi], 0, 1, 0, 1);
    assert_int_equal(film_add_samples(full, s, n), CLR_SUCCESS);
    char full_path[300], paths[4][300], merged[300];
    path_of(full_path, sizeof full_path, "full.exr");
    assert_int_equal(film_write(full, full_path, NULL), CLR_SUCCESS);
    const float q[4][4] = {{0, .5f, 0, .5f}, {.5f, 1, 0, .5f}, {0, .5f, .5f, 1}, {.5f, 1, .5f, 1}};
    const char *inputs[4];
    for (int k = 0; k < 4; ++k) {
      clr_film part = make_film(filters[fi], q[k][0], q[k][1], q[k][2], q[k][3]);
      assert_int_equal(film_add_samples(part, s, n), CLR_SUCCESS);
      char name[32];
      snprintf(name, sizeof name, "quarter%d.exr", k);
      path_of(paths[k], sizeof paths[k], name);
      assert_int_equal(film_write(part, paths[k], NULL), CLR_SUCCESS);
      inputs[k] = paths[k];
      film_release(part);
    }
    path_of(merged, sizeof merged, "merged.exr");
    assert_int_equal(film_merge_files(ctx, inputs, 4, merged), CLR_SUCCESS);
    float *a = read_rgb(merged), *b = read_rgb(full_path);
    assert_true(max_rel_diff(a, b, (size_t)W * H * 3) <= 1e-5);
    free(a);
    /* The CLI does the same. */
    char cmd[2048];
    path_of(merged, sizeof merged, "merged_cli.exr");
    snprintf(cmd, sizeof cmd, "%s merge %s %s %s %s -o %s", CLR_CLI_PATH, paths[0], paths[1],
             paths[2], paths[3], merged);
    assert_int_equal(system(cmd), 0);
    a = read_rgb(merged);
    assert_true(max_rel_diff(a, b, (size_t)W * H * 3) <= 1e-5);
    free(a);
    /* Two independent passes (halves of the samples) merge into the film of all samples. */
    for (int k = 0; k < 2; ++k) {
      clr_film pass = make_film(filters[fi], 0, 1, 0, 1);
      assert_int_equal(film_add_samples(pass, s + k * (n / 2), n / 2), CLR_SUCCESS);
      char name[32];
      snprintf(name, sizeof name, "pass%d.exr", k);
      path_of(paths[k], sizeof paths[k], name);
      assert_int_equal(film_write(pass, paths[k], NULL), CLR_SUCCESS);
      film_release(pass);
    }
    path_of(merged, sizeof merged, "passes.exr");
    assert_int_equal(film_merge_files(ctx, inputs, 2, merged), CLR_SUCCESS);
    a = read_rgb(merged);
    assert_true(max_rel_diff(a, b, (size_t)W * H * 3) <= 1e-5);
    free(a);
    free(b);
    free(s);
    film_release(full);
  }
}

static void test_merge_refuses_mismatches(void **state) {
  (void)state;
  clr_film_sample *s = random_samples(1000, 3);
  clr_film a = make_film(CLR_FILTER_BOX, 0, 1, 0, 1),
           b = make_film(CLR_FILTER_TRIANGLE, 0, 1, 0, 1);
  assert_int_equal(film_add_samples(a, s, 1000), CLR_SUCCESS);
  assert_int_equal(film_add_samples(b, s, 1000), CLR_SUCCESS);
  char pa[300], pb[300], pc[300], out[300];
  path_of(pa, sizeof pa, "box.exr");
  path_of(pb, sizeof pb, "triangle.exr");
  path_of(pc, sizeof pc, "nosums.exr");
  path_of(out, sizeof out, "refused.exr");
  assert_int_equal(film_write(a, pa, NULL), CLR_SUCCESS);
  assert_int_equal(film_write(b, pb, NULL), CLR_SUCCESS);
  clr_film_write_options o;
  clr_film_write_options_init(&o);
  o.include_sums = 0;
  assert_int_equal(film_write(a, pc, &o), CLR_SUCCESS);
  const char *mismatch[] = {pa, pb};
  assert_int_equal(film_merge_files(ctx, mismatch, 2, out), CLR_ERROR_INVALID_FILM);
  assert_non_null(strstr(clr_last_error_message(), "triangle"));
  const char *nosums[] = {pa, pc};
  assert_int_equal(film_merge_files(ctx, nosums, 2, out), CLR_ERROR_FILE_FORMAT);
  assert_non_null(strstr(clr_last_error_message(), "nosums.exr"));
  const char *missing[] = {pa, "/nonexistent/x.exr"};
  assert_int_equal(film_merge_files(ctx, missing, 2, out), CLR_ERROR_IO);
  assert_int_not_equal(access(out, F_OK), 0);
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s merge %s %s -o %s 2>/dev/null", CLR_CLI_PATH, pa, pb, out);
  assert_int_equal(WEXITSTATUS(system(cmd)), 1);
  snprintf(cmd, sizeof cmd, "%s merge %s 2>/dev/null", CLR_CLI_PATH, pa);
  assert_int_equal(WEXITSTATUS(system(cmd)), 2);
  assert_int_not_equal(access(out, F_OK), 0);
  /* Unwritable output path: specific error, nothing written. */
  assert_int_equal(film_write(a, "/nonexistent/dir/out.exr", NULL), CLR_ERROR_IO);
  assert_int_equal(film_write(NULL, pa, NULL), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_write(a, NULL, NULL), CLR_ERROR_NULL_POINTER);
  free(s);
  film_release(a);
  film_release(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_exr_round_trip),
      cmocka_unit_test(test_merge_quarters_and_passes),
      cmocka_unit_test(test_merge_refuses_mismatches),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
