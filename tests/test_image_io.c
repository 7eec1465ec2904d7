/* Image files: EXR round trips (float, half, crop, attributes), sRGB PNG values, atomic writes. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "read_file_test_util.h"
#include "atomic_file.h"
#include "clrender/image.h"
#include "exr_io.h"
#include "png_io.h"

static char dir[512];

static const char *in_dir(const char *name) {
  static char paths[4][1024];
  static int next;
  char *p = paths[next++ % 4];
  snprintf(p, sizeof paths[0], "%s/%s", dir, name);
  return p;
}

static int count_dir_entries(const char *path) {
  DIR *d = opendir(path);
  assert_non_null(d);
  int n = 0;
  for (struct dirent *e; (e = readdir(d));)
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) ++n;
  closedir(d);
  return n;
}

static void empty_dir(void) {
  DIR *d = opendir(dir);
  assert_non_null(d);
  for (struct dirent *e; (e = readdir(d));)
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) unlink(in_dir(e->d_name));
  closedir(d);
}

static int setup(void **state) {
  (void)state;
  snprintf(dir, sizeof dir, "%s/test_image_io.XXXXXX", CLR_BINARY_DIR);
  return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  empty_dir();
  return rmdir(dir);
}

static int file_exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

static void write_bytes(const char *path, const void *data, size_t size) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(data, 1, size, f), size);
  assert_int_equal(fclose(f), 0);
}

static float pattern(int channel, int x, int y) {
  return (float)(channel + 1) * 0.37f * (float)x - 1.25f * (float)y + (float)channel * 1000.5f +
         1e-3f * (float)(x * y);
}

/* ---- half conversion ---------------------------------------------------------------------- */

static void test_half_conversion(void **state) {
  (void)state;
  assert_int_equal(clr_float_to_half(1.f), 0x3c00);
  assert_int_equal(clr_float_to_half(-2.f), 0xc000);
  assert_int_equal(clr_float_to_half(0.1f), 0x2e66);
  assert_int_equal(clr_float_to_half(65504.f), 0x7bff);
  assert_int_equal(clr_float_to_half(65519.f), 0x7bff);
  assert_int_equal(clr_float_to_half(65520.f), 0x7c00);          /* ties to even overflow to inf */
  assert_int_equal(clr_float_to_half(ldexpf(1.f, -24)), 0x0001); /* smallest subnormal */
  assert_int_equal(clr_float_to_half(ldexpf(1.f, -25)), 0x0000); /* tie -> even (zero) */
  assert_int_equal(clr_float_to_half(ldexpf(1.5f, -25)), 0x0001);
  assert_int_equal(clr_float_to_half(ldexpf(3.f, -25)), 0x0002);       /* 1.5 units tie -> 2 */
  assert_int_equal(clr_float_to_half(1.f + ldexpf(1.f, -11)), 0x3c00); /* tie -> even */
  assert_int_equal(clr_float_to_half(1.f + 3.f * ldexpf(1.f, -11)), 0x3c02);
  assert_int_equal(clr_float_to_half(INFINITY), 0x7c00);
  assert_true((clr_float_to_half(NAN) & 0x7c00) == 0x7c00 && (clr_float_to_half(NAN) & 0x3ff));
  /* Every non-NaN half survives half -> float -> half exactly. */
  for (uint32_t h = 0; h < 65536; ++h) {
    if ((h & 0x7c00) == 0x7c00 && (h & 0x3ff)) continue;
    assert_int_equal(clr_float_to_half(clr_half_to_float((uint16_t)h)), h);
  }
  assert_true(clr_half_to_float(0x3555) == 0.333251953125f);
  assert_true(clr_half_to_float(0x8001) == -ldexpf(1.f, -24));
}

/* ---- EXR ---------------------------------------------------------------------------------- */

typedef struct planes4 {
  float *data[4];
} planes4;

static planes4 make_planes(int w, int h, int x0, int y0) {
  planes4 p;
  for (int c = 0; c < 4; ++c) {
    p.data[c] = malloc(sizeof(float) * (size_t)(w * h));
    assert_non_null(p.data[c]);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) p.data[c][y * w + x] = pattern(c, x0 + x, y0 + y);
  }
  return p;
}

static void free_planes(planes4 *p) {
  for (int c = 0; c < 4; ++c) free(p->data[c]);
}

static void test_exr_float_round_trip(void **state) {
  (void)state;
  const int w = 7, h = 37; /* three ZIP chunks of 16 lines, the last partial */
  planes4 p = make_planes(w, h, 0, 0);
  p.data[0][3] = -0.f;
  p.data[0][4] = 3.4e38f;
  p.data[0][5] = 1e-42f; /* float subnormal */
  /* Given out of order: the file sorts them (A, B, G, R). */
  clr_exr_channel channels[4] = {
      {"R", p.data[0], 0}, {"G", p.data[1], 0}, {"B", p.data[2], 0}, {"A", p.data[3], 0}};
  const char *path = in_dir("float.exr");
  assert_int_equal(clr_exr_write(path, w, h, (clr_bounds2i){0, 0, w, h}, channels, 4, NULL, 0),
                   CLR_SUCCESS);
  assert_int_equal(count_dir_entries(dir), 1); /* no temporary left */
  clr_exr_image *img = NULL;
  assert_int_equal(clr_exr_read(path, &img), CLR_SUCCESS);
  assert_int_equal(img->display_width, w);
  assert_int_equal(img->display_height, h);
  assert_int_equal(img->width, w);
  assert_int_equal(img->height, h);
  assert_int_equal(img->data_window.x0, 0);
  assert_int_equal(img->data_window.y1, h);
  assert_int_equal(img->channel_count, 4);
  const char *sorted[4] = {"A", "B", "G", "R"};
  for (int c = 0; c < 4; ++c) {
    assert_string_equal(img->channel_names[c], sorted[c]);
    assert_int_equal(img->channel_types[c], 2);
  }
  for (int c = 0; c < 4; ++c) {
    const float *plane = clr_exr_image_channel(img, channels[c].name);
    assert_non_null(plane);
    assert_memory_equal(plane, p.data[c], sizeof(float) * (size_t)(w * h)); /* bit exact */
  }
  assert_null(clr_exr_image_channel(img, "Z"));
  clr_exr_image_free(img);
  free_planes(&p);
}

static void test_exr_half_round_trip(void **state) {
  (void)state;
  const int w = 19, h = 17;
  planes4 p = make_planes(w, h, 0, 0);
  p.data[0][0] = 1e-6f;   /* half subnormal */
  p.data[0][1] = 70000.f; /* beyond half range: inf */
  clr_exr_channel channels[3] = {{"Y", p.data[0], 1}, {"Z", p.data[1], 0}, {"X", p.data[2], 1}};
  const char *path = in_dir("half.exr");
  assert_int_equal(clr_exr_write(path, w, h, (clr_bounds2i){0, 0, w, h}, channels, 3, NULL, 0),
                   CLR_SUCCESS);
  clr_exr_image *img = NULL;
  assert_int_equal(clr_exr_read(path, &img), CLR_SUCCESS);
  assert_int_equal(img->channel_count, 3);
  assert_string_equal(img->channel_names[0], "X");
  assert_int_equal(img->channel_types[0], 1); /* half */
  assert_int_equal(img->channel_types[2], 2); /* Z float */
  const float *y = clr_exr_image_channel(img, "Y"), *x = clr_exr_image_channel(img, "X");
  for (int i = 0; i < w * h; ++i) {
    /* Within half precision (relative 2^-11 for normals), and exactly the rounded half. */
    if (i > 1) assert_true(fabsf(y[i] - p.data[0][i]) <= fabsf(p.data[0][i]) * 0x1p-11f);
    assert_true(fabsf(x[i] - p.data[2][i]) <= fabsf(p.data[2][i]) * 0x1p-11f);
    assert_true(y[i] == clr_half_to_float(clr_float_to_half(p.data[0][i])));
  }
  assert_true(fabsf(y[0] - 1e-6f) <= 0x1p-25f);
  assert_true(isinf(y[1]));
  assert_memory_equal(clr_exr_image_channel(img, "Z"), p.data[1], sizeof(float) * (size_t)(w * h));
  clr_exr_image_free(img);
  free_planes(&p);
}

static void test_exr_crop_window(void **state) {
  (void)state;
  const int W = 64, H = 48;
  const clr_bounds2i dw = {10, 5, 50, 42}; /* 40 x 37, rows 5..41: chunks not aligned to 16 */
  const int w = dw.x1 - dw.x0, h = dw.y1 - dw.y0;
  planes4 p = make_planes(w, h, dw.x0, dw.y0);
  clr_exr_channel channels[3] = {{"R", p.data[0], 0}, {"G", p.data[1], 1}, {"B", p.data[2], 0}};
  const char *path = in_dir("crop.exr");
  assert_int_equal(clr_exr_write(path, W, H, dw, channels, 3, NULL, 0), CLR_SUCCESS);
  clr_exr_image *img = NULL;
  assert_int_equal(clr_exr_read(path, &img), CLR_SUCCESS);
  assert_int_equal(img->display_width, W);
  assert_int_equal(img->display_height, H);
  assert_int_equal(img->display_window.x0, 0);
  assert_int_equal(img->display_window.y1, H);
  assert_memory_equal(&img->data_window, &dw, sizeof dw);
  assert_int_equal(img->width, w);
  assert_int_equal(img->height, h);
  const float *r = clr_exr_image_channel(img, "R"), *g = clr_exr_image_channel(img, "G");
  assert_memory_equal(r, p.data[0], sizeof(float) * (size_t)(w * h));
  /* Pixel (x, y) of the display lives at [(y - y0) * w + (x - x0)]. */
  assert_true(r[(17 - dw.y0) * w + (33 - dw.x0)] == pattern(0, 33, 17));
  assert_true(g[(41 - dw.y0) * w + (10 - dw.x0)] ==
              clr_half_to_float(clr_float_to_half(pattern(1, 10, 41))));
  clr_exr_image_free(img);

  /* A data window outside the display window is refused before anything is written. */
  const clr_bounds2i outside = {60, 0, 65, 10};
  assert_int_equal(clr_exr_write(in_dir("bad.exr"), W, H, outside, channels, 3, NULL, 0),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_false(file_exists(in_dir("bad.exr")));
  free_planes(&p);
  empty_dir();
}

static void test_exr_attributes(void **state) {
  (void)state;
  float v[4] = {1.f, 2.f, 3.f, 4.f};
  clr_exr_channel ch = {"Y", v, 0};
  clr_exr_attribute attrs[4] = {
      {"renderer", CLR_EXR_ATTR_STRING, "clrender 0.1 (sobol, gaussian)", 0.f, 0},
      {"exposureScale", CLR_EXR_ATTR_FLOAT, NULL, 1.5f, 0},
      {"samplesPerPixel", CLR_EXR_ATTR_INT, NULL, 0.f, 1024},
      {"emptyNote", CLR_EXR_ATTR_STRING, "", 0.f, 0}};
  const char *path = in_dir("attrs.exr");
  assert_int_equal(clr_exr_write(path, 2, 2, (clr_bounds2i){0, 0, 2, 2}, &ch, 1, attrs, 4),
                   CLR_SUCCESS);
  clr_exr_image *img = NULL;
  assert_int_equal(clr_exr_read(path, &img), CLR_SUCCESS);
  assert_string_equal(clr_exr_image_string_attr(img, "renderer"), "clrender 0.1 (sobol, gaussian)");
  assert_string_equal(clr_exr_image_string_attr(img, "emptyNote"), "");
  float f = 0.f;
  int32_t i = 0;
  assert_true(clr_exr_image_float_attr(img, "exposureScale", &f));
  assert_true(f == 1.5f);
  assert_true(clr_exr_image_int_attr(img, "samplesPerPixel", &i));
  assert_int_equal(i, 1024);
  /* Standard float attributes written by the library are readable too. */
  assert_true(clr_exr_image_float_attr(img, "pixelAspectRatio", &f));
  assert_true(f == 1.f);
  /* Absent or of another type. */
  assert_null(clr_exr_image_string_attr(img, "samplesPerPixel"));
  assert_false(clr_exr_image_int_attr(img, "exposureScale", &i));
  assert_false(clr_exr_image_float_attr(img, "nope", &f));
  assert_int_equal(i, 1024);
  clr_exr_image_free(img);
  empty_dir();
}

static void test_exr_failures_leave_nothing(void **state) {
  (void)state;
  float v[4] = {1.f, 2.f, 3.f, 4.f};
  clr_exr_channel ch = {"Y", v, 1};
  const clr_bounds2i all = {0, 0, 2, 2};
  /* Unwritable directory: CLR_ERROR_IO naming the path. */
  assert_int_equal(clr_exr_write("/nonexistent/dir/x.exr", 2, 2, all, &ch, 1, NULL, 0),
                   CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "/nonexistent/dir/x.exr"));
  assert_false(file_exists("/nonexistent/dir/x.exr"));

  /* A failure inside OpenEXR after the temporary exists ("channels" is a reserved chlist
   * attribute): the error names the call and the file, the old file at path is untouched and no
   * temporary is left. */
  const char *path = in_dir("keep.exr");
  assert_int_equal(clr_exr_write(path, 2, 2, all, &ch, 1, NULL, 0), CLR_SUCCESS);
  size_t before_size = 0, after_size = 0;
  void *before = read_file_bytes(path, &before_size);
  clr_exr_attribute bad = {"channels", CLR_EXR_ATTR_STRING, "oops", 0.f, 0};
  float w[4] = {9.f, 9.f, 9.f, 9.f};
  clr_exr_channel ch2 = {"Y", w, 0};
  assert_int_equal(clr_exr_write(path, 2, 2, all, &ch2, 1, &bad, 1), CLR_ERROR_OPENEXR);
  assert_non_null(strstr(clr_last_error_message(), "exr_attr_set_string"));
  assert_non_null(strstr(clr_last_error_message(), path));
  assert_int_equal(count_dir_entries(dir), 1);
  void *after = read_file_bytes(path, &after_size);
  assert_int_equal(before_size, after_size);
  assert_memory_equal(before, after, before_size);
  free(before);
  free(after);

  /* Bad arguments. */
  assert_int_equal(clr_exr_write(path, 2, 2, all, &ch, 0, NULL, 0), CLR_ERROR_INVALID_ARGUMENT);
  clr_exr_channel dup[2] = {ch, ch};
  assert_int_equal(clr_exr_write(path, 2, 2, all, dup, 2, NULL, 0), CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(clr_exr_write(path, 0, 2, all, &ch, 1, NULL, 0), CLR_ERROR_INVALID_RESOLUTION);
  assert_int_equal(clr_exr_write(NULL, 2, 2, all, &ch, 1, NULL, 0), CLR_ERROR_NULL_POINTER);
  assert_int_equal(count_dir_entries(dir), 1);
  empty_dir();
}

static void test_exr_bad_files(void **state) {
  (void)state;
  clr_exr_image *img = (clr_exr_image *)&img;
  assert_int_equal(clr_exr_read(in_dir("missing.exr"), &img), CLR_ERROR_IO);
  assert_null(img);
  assert_non_null(strstr(clr_last_error_message(), "exr_start_read"));
  assert_non_null(strstr(clr_last_error_message(), "missing.exr"));

  char garbage[300];
  for (int i = 0; i < 300; ++i) garbage[i] = (char)(i * 37 + 11);
  write_bytes(in_dir("garbage.exr"), garbage, sizeof garbage);
  assert_int_equal(clr_exr_read(in_dir("garbage.exr"), &img), CLR_ERROR_FILE_FORMAT);
  assert_null(img);
  assert_non_null(strstr(clr_last_error_message(), "garbage.exr"));

  /* A real file cut short, at several lengths (header only, mid chunk table, mid pixels). */
  const int w = 40, h = 40;
  planes4 p = make_planes(w, h, 0, 0);
  clr_exr_channel channels[2] = {{"R", p.data[0], 0}, {"G", p.data[1], 1}};
  assert_int_equal(
      clr_exr_write(in_dir("full.exr"), w, h, (clr_bounds2i){0, 0, w, h}, channels, 2, NULL, 0),
      CLR_SUCCESS);
  size_t size = 0;
  unsigned char *bytes = read_file_bytes(in_dir("full.exr"), &size);
  const size_t cuts[] = {4, 40, 300, 330, size / 2, size - 5};
  for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; ++k) {
    write_bytes(in_dir("cut.exr"), bytes, cuts[k]);
    clr_result r = clr_exr_read(in_dir("cut.exr"), &img);
    if (r != CLR_ERROR_FILE_FORMAT)
      print_message("cut at %zu of %zu: %s\n", cuts[k], size, clr_last_error_message());
    assert_int_equal(r, CLR_ERROR_FILE_FORMAT);
    assert_null(img);
    assert_non_null(strstr(clr_last_error_message(), "cut.exr"));
  }
  /* Flipped bytes inside the compressed pixel data. */
  for (size_t i = size - 200; i < size - 100; ++i) bytes[i] ^= 0x5a;
  write_bytes(in_dir("corrupt.exr"), bytes, size);
  clr_result r = clr_exr_read(in_dir("corrupt.exr"), &img);
  assert_int_equal(r, CLR_ERROR_FILE_FORMAT);
  free(bytes);
  free_planes(&p);
  empty_dir();
}

/* ---- PNG ---------------------------------------------------------------------------------- */

static void read_png_bytes(const char *path, uint8_t *out, size_t size, int *w, int *h) {
  png_image image;
  memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&image, path));
  image.format = PNG_FORMAT_RGB;
  assert_int_equal(PNG_IMAGE_SIZE(image), size);
  assert_true(png_image_finish_read(&image, NULL, out, 0, NULL));
  *w = (int)image.width;
  *h = (int)image.height;
}

static void test_png_srgb_values(void **state) {
  (void)state;
  /* Known pbrt-v3 8-bit values: clamp(255 * GammaCorrect(v) + 0.5, 0, 255), truncated. */
  const float in[8] = {0.f, 0.0031308f, 0.5f, 1.f, 2.f, -0.5f, 0.18f, 0.001f};
  const uint8_t expected[8] = {0, 10, 188, 255, 255, 0, 118, 3};
  float rgb[8 * 2 * 3];
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 8; ++x) {
      float *px = &rgb[3 * (y * 8 + x)];
      px[0] = in[x];
      px[1] = y ? 0.f : in[7 - x];
      px[2] = y ? 1.f : 0.5f;
    }
  const char *path = in_dir("srgb.png");
  assert_int_equal(clr_png_write_srgb(path, 8, 2, rgb), CLR_SUCCESS);
  assert_int_equal(count_dir_entries(dir), 1);
  uint8_t bytes[8 * 2 * 3];
  int w = 0, h = 0;
  read_png_bytes(path, bytes, sizeof bytes, &w, &h);
  assert_int_equal(w, 8);
  assert_int_equal(h, 2);
  for (int x = 0; x < 8; ++x) {
    assert_int_equal(bytes[3 * x + 0], expected[x]);
    assert_int_equal(bytes[3 * x + 1], expected[7 - x]);
    assert_int_equal(bytes[3 * x + 2], 188);
    assert_int_equal(bytes[3 * (8 + x) + 1], 0);
    assert_int_equal(bytes[3 * (8 + x) + 2], 255);
  }
  assert_int_equal(clr_to_srgb8(NAN), 0);
  assert_int_equal(clr_to_srgb8(INFINITY), 255);

  /* clr_png_read returns InverseGammaCorrect(byte / 255). */
  float *lin = NULL;
  int32_t rw = 0, rh = 0;
  assert_int_equal(clr_png_read(path, &rw, &rh, &lin), CLR_SUCCESS);
  assert_int_equal(rw, 8);
  assert_int_equal(rh, 2);
  for (int i = 0; i < 8 * 2 * 3; ++i)
    assert_true(lin[i] == clr_inverse_gamma_correct((float)bytes[i] / 255.f));
  assert_true(lin[0] == 0.f);
  assert_true(lin[3 * 3] == 1.f);
  assert_true(fabsf(lin[3 * 2] - 0.5f) < 0.004f); /* 188 -> 0.5029 */
  assert_true(fabsf(clr_inverse_gamma_correct(10.f / 255.f) - 10.f / 255.f / 12.92f) == 0.f);
  free(lin);
  empty_dir();
}

static void test_png_failures(void **state) {
  (void)state;
  float rgb[3] = {0.5f, 0.5f, 0.5f};
  assert_int_equal(clr_png_write_srgb("/nonexistent/dir/x.png", 1, 1, rgb), CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "/nonexistent/dir/x.png"));
  assert_int_equal(clr_png_write_srgb(in_dir("z.png"), 0, 1, rgb), CLR_ERROR_INVALID_RESOLUTION);
  assert_int_equal(count_dir_entries(dir), 0);

  float *lin = (float *)&lin;
  int32_t w = 0, h = 0;
  assert_int_equal(clr_png_read(in_dir("missing.png"), &w, &h, &lin), CLR_ERROR_IO);
  assert_null(lin);
  assert_non_null(strstr(clr_last_error_message(), "missing.png"));
  write_bytes(in_dir("garbage.png"), "this is not a PNG file at all", 29);
  assert_int_equal(clr_png_read(in_dir("garbage.png"), &w, &h, &lin), CLR_ERROR_FILE_FORMAT);
  assert_non_null(strstr(clr_last_error_message(), "garbage.png"));

  float big[32 * 32 * 3];
  for (int i = 0; i < 32 * 32 * 3; ++i) big[i] = (float)((i * 7919) % 1000) / 1000.f;
  assert_int_equal(clr_png_write_srgb(in_dir("full.png"), 32, 32, big), CLR_SUCCESS);
  size_t size = 0;
  unsigned char *bytes = read_file_bytes(in_dir("full.png"), &size);
  const size_t cuts[] = {8, 20, 50, size / 2, size - 13};
  for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; ++k) {
    write_bytes(in_dir("cut.png"), bytes, cuts[k]);
    assert_int_equal(clr_png_read(in_dir("cut.png"), &w, &h, &lin), CLR_ERROR_FILE_FORMAT);
    assert_null(lin);
    assert_non_null(strstr(clr_last_error_message(), "cut.png"));
  }
  free(bytes);
  empty_dir();
}

/* ---- dispatch and writability ------------------------------------------------------------- */

static void test_image_read_dispatch(void **state) {
  (void)state;
  float r[6] = {0, 1, 2, 3, 4, 5}, g[6] = {10, 11, 12, 13, 14, 15}, b[6] = {-1, -2, -3, -4, -5, -6};
  clr_exr_channel rgb[3] = {{"B", b, 0}, {"G", g, 0}, {"R", r, 0}};
  const clr_bounds2i dw = {1, 1, 4, 3};
  assert_int_equal(clr_exr_write(in_dir("rgb.EXR"), 5, 4, dw, rgb, 3, NULL, 0), CLR_SUCCESS);
  clr_image image;
  assert_int_equal(clr_image_read(in_dir("rgb.EXR"), &image), CLR_SUCCESS);
  const float *out = image.rgb;
  assert_int_equal(image.width, 3);
  assert_int_equal(image.height, 2);
  for (int i = 0; i < 6; ++i) {
    assert_true(out[3 * i] == r[i]);
    assert_true(out[3 * i + 1] == g[i]);
    assert_true(out[3 * i + 2] == b[i]);
  }
  clr_image_free(&image);
  assert_null(image.rgb);

  clr_exr_channel gray = {"Y", g, 1};
  assert_int_equal(
      clr_exr_write(in_dir("y.exr"), 3, 2, (clr_bounds2i){0, 0, 3, 2}, &gray, 1, NULL, 0),
      CLR_SUCCESS);
  assert_int_equal(clr_image_read(in_dir("y.exr"), &image), CLR_SUCCESS);
  out = image.rgb;
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < 3; ++c) assert_true(out[3 * i + c] == g[i]);
  clr_image_free(&image);

  clr_exr_channel other = {"depth", g, 0};
  assert_int_equal(
      clr_exr_write(in_dir("z.exr"), 3, 2, (clr_bounds2i){0, 0, 3, 2}, &other, 1, NULL, 0),
      CLR_SUCCESS);
  assert_int_equal(clr_image_read(in_dir("z.exr"), &image), CLR_ERROR_FILE_FORMAT);
  assert_null(image.rgb);
  assert_non_null(strstr(clr_last_error_message(), "depth"));

  float px[6] = {0.f, 0.5f, 1.f, 1.f, 0.5f, 0.f};
  assert_int_equal(clr_png_write_srgb(in_dir("t.png"), 2, 1, px), CLR_SUCCESS);
  assert_int_equal(clr_image_read(in_dir("t.png"), &image), CLR_SUCCESS);
  out = image.rgb;
  assert_int_equal(image.width, 2);
  assert_true(out[0] == 0.f && out[2] == 1.f);
  assert_true(out[1] == clr_inverse_gamma_correct(188.f / 255.f));
  clr_image_free(&image);
  assert_int_equal(clr_image_read(in_dir("t.tga"), &image), CLR_ERROR_FILE_FORMAT);
  assert_non_null(strstr(clr_last_error_message(), "t.tga"));
  empty_dir();
}

static void test_check_writable(void **state) {
  (void)state;
  assert_int_equal(clr_check_writable(in_dir("out.exr")), CLR_SUCCESS);
  assert_int_equal(count_dir_entries(dir), 0);
  assert_int_equal(clr_check_writable("/nonexistent/dir/x.exr"), CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "/nonexistent/dir/x.exr"));
  assert_int_equal(clr_check_writable(dir), CLR_ERROR_IO); /* a directory */
  assert_non_null(strstr(clr_last_error_message(), "directory"));
  assert_int_equal(clr_check_writable(""), CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(clr_check_writable(NULL), CLR_ERROR_NULL_POINTER);
  if (geteuid() != 0) { /* root ignores permissions */
    char ro[700];
    snprintf(ro, sizeof ro, "%s/ro", dir);
    assert_int_equal(mkdir(ro, 0555), 0);
    strcat(ro, "/x.exr");
    assert_int_equal(clr_check_writable(ro), CLR_ERROR_IO);
    rmdir(in_dir("ro"));
  }
  assert_int_equal(count_dir_entries(dir), 0);
}

/* ---- independent readers ------------------------------------------------------------------ */

/* Runs `command`, returns its exit status and its output in `out`. */
static int run_tool(const char *command, char *out, size_t size) {
  FILE *p = popen(command, "r");
  assert_non_null(p);
  size_t n = fread(out, 1, size - 1, p);
  out[n] = 0;
  return pclose(p);
}

static int tool_present(const char *name) {
  char cmd[256], out[16];
  snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1 && echo yes", name);
  run_tool(cmd, out, sizeof out);
  return strncmp(out, "yes", 3) == 0;
}

/* Writes the EXR the independent readers check. */
static const char *write_external_exr(planes4 *p) {
  const int W = 24, H = 20;
  const clr_bounds2i dw = {2, 3, 22, 19};
  *p = make_planes(dw.x1 - dw.x0, dw.y1 - dw.y0, dw.x0, dw.y0);
  clr_exr_channel channels[3] = {{"R", p->data[0], 1}, {"G", p->data[1], 0}, {"B", p->data[2], 1}};
  clr_exr_attribute attr = {"renderer", CLR_EXR_ATTR_STRING, "clrender-test", 0.f, 0};
  const char *path = in_dir("ext.exr");
  assert_int_equal(clr_exr_write(path, W, H, dw, channels, 3, &attr, 1), CLR_SUCCESS);
  return path;
}

/* OpenEXR's own tools (Debian openexr, installed by scripts/install-deps.sh) read our files. */
static void test_openexr_tools_read(void **state) {
  (void)state;
  static char out[65536];
  char cmd[1024];
  if (!tool_present("exrheader") || !tool_present("exrmaketiled"))
    fail_msg(
        "exrheader/exrmaketiled missing: install the Debian package openexr "
        "(scripts/install-deps.sh)");
  planes4 p;
  const char *path = write_external_exr(&p);
  snprintf(cmd, sizeof cmd, "exrheader '%s' 2>&1", path);
  assert_int_equal(run_tool(cmd, out, sizeof out), 0);
  assert_non_null(strstr(out, "zip, multi-scanline blocks"));
  assert_non_null(strstr(out, "(2 3) - (21 18)")); /* data window, inclusive */
  assert_non_null(strstr(out, "(0 0) - (23 19)")); /* display window */
  assert_non_null(strstr(out, "\"clrender-test\""));
  assert_non_null(strstr(out, "R, 16-bit floating-point"));
  assert_non_null(strstr(out, "G, 32-bit floating-point"));
  /* exrmaketiled decodes every pixel with the C++ library. */
  snprintf(cmd, sizeof cmd, "exrmaketiled '%s' '%s' 2>&1", path, in_dir("tiled.exr"));
  int status = run_tool(cmd, out, sizeof out);
  if (status != 0) print_message("exrmaketiled: %s\n", out);
  assert_int_equal(status, 0);
  free_planes(&p);
  empty_dir();
}

/* OpenImageIO's iinfo, when installed (not by default: its package pulls in 100+ others). */
static void test_openimageio_reads(void **state) {
  (void)state;
  if (!tool_present("iinfo")) {
    print_message("iinfo (openimageio-tools) is not installed: skipped\n");
    skip();
  }
  static char out[65536];
  char cmd[1024];
  planes4 p;
  const char *path = write_external_exr(&p);
  snprintf(cmd, sizeof cmd, "iinfo -v '%s' 2>&1", path);
  assert_int_equal(run_tool(cmd, out, sizeof out), 0);
  assert_non_null(strstr(out, "20 x 16"));
  assert_non_null(strstr(out, "clrender-test"));
  free_planes(&p);
  empty_dir();
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_half_conversion),     cmocka_unit_test(test_exr_float_round_trip),
      cmocka_unit_test(test_exr_half_round_trip), cmocka_unit_test(test_exr_crop_window),
      cmocka_unit_test(test_exr_attributes),      cmocka_unit_test(test_exr_failures_leave_nothing),
      cmocka_unit_test(test_exr_bad_files),       cmocka_unit_test(test_png_srgb_values),
      cmocka_unit_test(test_png_failures),        cmocka_unit_test(test_image_read_dispatch),
      cmocka_unit_test(test_check_writable),      cmocka_unit_test(test_openexr_tools_read),
      cmocka_unit_test(test_openimageio_reads),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
