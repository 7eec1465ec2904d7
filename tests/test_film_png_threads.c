/* film_write_png converts the film to 8-bit sRGB (on two threads for large films) into the very
 * file clr_png_write_srgb makes from film_get_rgb's values, for large and small films with
 * splats; a non-finite splat scale is refused as film_get_rgb refuses it. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "read_file_test_util.h"
#include "clrender.h"
#include "clrender/film.h"
#include "png_io.h"

static void check_film(int w, int h) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = w;
  d.y_resolution = h;
  clr_film film = NULL;
  assert_int_equal(film_create(NULL, &d, &film), CLR_SUCCESS);
  size_t n = (size_t)w * (size_t)h;
  double *rgb = malloc(n * 3 * sizeof *rgb), *weight = malloc(n * sizeof *weight);
  assert_non_null(rgb);
  assert_non_null(weight);
  uint32_t s = 2024u;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      s = s * 1664525u + 1013904223u;
      rgb[3 * i + c] = (double)(s >> 8) * 0x1p-22 - 0.5; /* some negative: clamped to 0 */
    }
    weight[i] = i % 7 == 0 ? 0.0 : 1.0 + (double)(i % 5);
  }
  assert_int_equal(film_merge_sums(film, film_pixel_bounds(film), rgb, weight, NULL), CLR_SUCCESS);
  assert_int_equal(film_add_splat(film, 1.5f, 0.5f, 3.0f, 0.25f, 0.0f), CLR_SUCCESS);
  float *resolved = malloc(n * 3 * sizeof *resolved);
  assert_non_null(resolved);
  assert_int_equal(film_get_rgb(film, resolved, 0.5f), CLR_SUCCESS);
  char a[1024], b[1024];
  snprintf(a, sizeof a, "%s/test_film_png_threads_a_%d.png", CLR_BINARY_DIR, (int)getpid());
  snprintf(b, sizeof b, "%s/test_film_png_threads_b_%d.png", CLR_BINARY_DIR, (int)getpid());
  assert_int_equal(film_write_png(film, a, 0.5f), CLR_SUCCESS);
  assert_int_equal(clr_png_write_srgb(b, w, h, resolved), CLR_SUCCESS);
  assert_files_equal(a, b);
  assert_int_equal(unlink(a), 0);
  assert_int_equal(unlink(b), 0);
  assert_int_equal(film_write_png(film, a, NAN), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "splat_scale = nan"));
  assert_int_equal(access(a, F_OK), -1);
  free(resolved);
  free(rgb);
  free(weight);
  film_release(film);
}

static void test_png_same_file(void **state) {
  (void)state;
  check_film(256, 160); /* 40960 pixels: two threads */
  check_film(37, 11);   /* one thread */
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_png_same_file)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
