/* Moving film sums between processes and passes (issue #13): film tiles serialized and
 * deserialized merge bit for bit as the originals (in tile order), bad bytes are refused;
 * film_merge_film adds a pass exactly (into an empty film) and refuses another geometry;
 * film_merge_file refuses a file of another film and returns the header attributes. */
#define _GNU_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "clrender/film.h"

#include "context_fixture.h"
#include "lcg_test_random.h"

static clr_film make_film(int xres, int yres, float radius) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = xres;
  d.y_resolution = yres;
  d.filter.type = CLR_FILTER_GAUSSIAN;
  d.filter.radius[0] = d.filter.radius[1] = radius;
  clr_film f = NULL;
  assert_int_equal(film_create(ctx, &d, &f), CLR_SUCCESS);
  return f;
}

/* Samples of sample region r (deterministic values). */
static void fill_tile(clr_film_tile t, clr_bounds2i r, uint32_t seed) {
  clr_film_sample s[64];
  uint32_t h = seed * 2654435761u + 1u;
  for (int i = 0; i < 64; ++i) {
    float u = lcg_float(&h);
    float v = lcg_float(&h);
    s[i] = (clr_film_sample){(float)r.x0 + u * (float)(r.x1 - r.x0),
                             (float)r.y0 + v * (float)(r.y1 - r.y0),
                             u,
                             v,
                             u * v,
                             1.0f};
  }
  assert_int_equal(film_tile_add_samples(t, s, 64), CLR_SUCCESS);
}

/* Merges a tile of region r filled by fill_tile(seed) into f. */
static void merge_filled_tile(clr_film f, clr_bounds2i r, uint32_t seed) {
  clr_film_tile t = NULL;
  assert_int_equal(film_get_tile(f, r, &t), CLR_SUCCESS);
  fill_tile(t, r, seed);
  assert_int_equal(film_merge_tile(f, t), CLR_SUCCESS);
  film_tile_release(t);
}

static void test_serialized_tiles_merge_bit_for_bit(void **state) {
  (void)state;
  clr_film a = make_film(24, 16, 2.0f), b = make_film(24, 16, 2.0f);
  clr_bounds2i regions[4] = {{0, 0, 12, 8}, {12, 0, 24, 8}, {0, 8, 12, 16}, {12, 8, 24, 16}};
  for (int k = 0; k < 4; ++k) {
    clr_film_tile t = NULL, copy = NULL;
    assert_int_equal(film_get_tile(a, regions[k], &t), CLR_SUCCESS);
    fill_tile(t, regions[k], (uint32_t)k);
    size_t n = film_tile_serialized_size(t);
    assert_true(n > 64);
    char *buf = malloc(n);
    assert_non_null(buf);
    assert_int_equal(film_tile_serialize(t, buf, n), CLR_SUCCESS);
    assert_int_equal(film_tile_serialize(t, buf, n - 1), CLR_ERROR_INVALID_ARGUMENT);
    assert_int_equal(film_tile_deserialize(b, buf, n, &copy), CLR_SUCCESS);
    assert_int_equal(film_merge_tile(a, t), CLR_SUCCESS);
    assert_int_equal(film_merge_tile(b, copy), CLR_SUCCESS);
    film_tile_release(t);
    film_tile_release(copy);
    free(buf);
  }
  double sa[24 * 16 * 3], sb[24 * 16 * 3], wa[24 * 16], wb[24 * 16];
  assert_int_equal(film_get_sums(a, sa, wa, NULL), CLR_SUCCESS);
  assert_int_equal(film_get_sums(b, sb, wb, NULL), CLR_SUCCESS);
  assert_memory_equal(sa, sb, sizeof sa);
  assert_memory_equal(wa, wb, sizeof wa);
  assert_int_equal(film_sample_count(a), 256);
  assert_int_equal(film_sample_count(b), 256);
  film_release(a);
  film_release(b);
}

static void test_bad_tile_bytes_refused(void **state) {
  (void)state;
  clr_film a = make_film(24, 16, 1.0f), small = make_film(8, 8, 1.0f);
  clr_film_tile t = NULL, out = NULL;
  clr_bounds2i r = {8, 4, 24, 16};
  assert_int_equal(film_get_tile(a, r, &t), CLR_SUCCESS);
  fill_tile(t, r, 7);
  size_t n = film_tile_serialized_size(t);
  char *buf = malloc(n);
  assert_non_null(buf);
  assert_int_equal(film_tile_serialize(t, buf, n), CLR_SUCCESS);
  assert_int_equal(film_tile_deserialize(a, buf, n - 4, &out), CLR_ERROR_INVALID_ARGUMENT);
  assert_null(out);
  assert_int_equal(film_tile_deserialize(a, buf, 8, &out), CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(film_tile_deserialize(small, buf, n, &out), CLR_ERROR_INVALID_TILE);
  assert_null(out);
  assert_non_null(strstr(clr_last_error_message(), "outside the film's pixel bounds"));
  buf[0] ^= 0x5a; /* the magic */
  assert_int_equal(film_tile_deserialize(a, buf, n, &out), CLR_ERROR_INVALID_TILE);
  assert_non_null(strstr(clr_last_error_message(), "not a serialized tile (magic 0x"));
  assert_int_equal(film_tile_deserialize(NULL, buf, n, &out), CLR_ERROR_NULL_POINTER);
  assert_int_equal(film_tile_serialized_size(NULL), 0);
  free(buf);
  film_tile_release(t);
  film_release(a);
  film_release(small);
}

static void test_merge_film_adds_a_pass(void **state) {
  (void)state;
  clr_film frame = make_film(16, 16, 2.0f), pass = make_film(16, 16, 2.0f),
           other = make_film(16, 8, 2.0f);
  merge_filled_tile(pass, (clr_bounds2i){0, 0, 16, 16}, 3);
  assert_int_equal(film_merge_film(frame, pass), CLR_SUCCESS);
  double s1[16 * 16 * 3], s2[16 * 16 * 3];
  assert_int_equal(film_get_sums(frame, s1, NULL, NULL), CLR_SUCCESS);
  assert_int_equal(film_get_sums(pass, s2, NULL, NULL), CLR_SUCCESS);
  assert_memory_equal(s1, s2, sizeof s1); /* 0 + x is exact */
  assert_int_equal(film_sample_count(frame), 64);
  assert_int_equal(film_merge_film(frame, other), CLR_ERROR_INVALID_FILM);
  assert_int_equal(film_merge_film(frame, frame), CLR_ERROR_INVALID_FILM);
  assert_int_equal(film_merge_film(NULL, pass), CLR_ERROR_NULL_POINTER);
  film_release(frame);
  film_release(pass);
  film_release(other);
}

static void test_merge_file_checks_the_film(void **state) {
  (void)state;
  char path[] = CLR_BINARY_DIR "/clr_transfer_XXXXXX";
  assert_non_null(mkdtemp(path));
  char file[sizeof path + 16];
  snprintf(file, sizeof file, "%s/f.exr", path);
  clr_film f = make_film(16, 16, 2.0f), same = make_film(16, 16, 2.0f),
           other = make_film(16, 16, 1.0f);
  merge_filled_tile(f, (clr_bounds2i){0, 0, 16, 16}, 5);
  clr_film_write_options wo;
  clr_film_write_options_init(&wo);
  wo.spp = 4;
  const char *keys[1] = {"clrender.scene"}, *vals[1] = {"abc"};
  wo.metadata_keys = keys;
  wo.metadata_values = vals;
  wo.metadata_count = 1;
  assert_int_equal(film_write(f, file, &wo), CLR_SUCCESS);
  const char *names[3] = {"clrender.scene", "clrender.spp", "clrender.missing"};
  char values[3][32];
  assert_int_equal(film_merge_file(other, file, 3, names, &values[0][0], 32),
                   CLR_ERROR_INVALID_FILM);
  assert_int_equal(film_merge_file(same, file, 3, names, &values[0][0], 32), CLR_SUCCESS);
  assert_string_equal(values[0], "abc");
  assert_string_equal(values[1], "4");
  assert_string_equal(values[2], "");
  assert_int_equal(film_sample_count(same), 64);
  double s1[16 * 16 * 3], s2[16 * 16 * 3];
  assert_int_equal(film_get_sums(f, s1, NULL, NULL), CLR_SUCCESS);
  assert_int_equal(film_get_sums(same, s2, NULL, NULL), CLR_SUCCESS);
  for (int i = 0; i < 16 * 16 * 3; ++i) assert_true(s1[i] == s2[i]); /* hi + lo: the doubles */
  char missing[sizeof path + 16];
  snprintf(missing, sizeof missing, "%s/none.exr", path);
  assert_int_not_equal(film_merge_file(same, missing, 0, NULL, NULL, 0), CLR_SUCCESS);
  film_release(f);
  film_release(same);
  film_release(other);
  remove(file);
  remove(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_serialized_tiles_merge_bit_for_bit),
      cmocka_unit_test(test_bad_tile_bytes_refused),
      cmocka_unit_test(test_merge_film_adds_a_pass),
      cmocka_unit_test(test_merge_file_checks_the_film),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
