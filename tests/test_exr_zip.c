/* The EXR writer's own ZIP chunk compression (exr_zip.c): the same bytes as OpenEXRCore's encoder
 * for one-chunk images, a lossless round trip for any length, and whole multi-chunk images (half
 * and float channels, a crop, a short last chunk, helper threads) read back exactly; rows computed
 * chunk by chunk (clr_exr_write_rows) make the same file as whole planes. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>
#include <cmocka.h>

#include "read_file_test_util.h"
#include "exr_io.h"
#include "exr_zip.h"

/* A fixed pseudo-random byte stream (xorshift32). */
static uint32_t next_random(uint32_t *s) {
  *s ^= *s << 13;
  *s ^= *s >> 17;
  *s ^= *s << 5;
  return *s;
}

/* ---- OpenEXRCore's own encoder as the reference: one chunk, one FLOAT channel ------------- */

typedef struct captured {
  uint8_t *bytes;
  size_t size;
} captured;

static int64_t discard_write(exr_const_context_t ctxt, void *user, const void *buffer,
                             uint64_t size, uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  (void)ctxt, (void)user, (void)buffer, (void)offset, (void)error_cb;
  return (int64_t)size;
}

static exr_result_t capture_chunk(exr_encode_pipeline_t *enc) {
  captured *c = enc->encoding_user_data;
  c->bytes = malloc(enc->compressed_bytes);
  if (!c->bytes) return EXR_ERR_OUT_OF_MEMORY;
  memcpy(c->bytes, enc->compressed_buffer, enc->compressed_bytes);
  c->size = enc->compressed_bytes;
  return EXR_ERR_SUCCESS;
}

/* OpenEXR's ZIP bytes of a width x lines FLOAT image (lines <= 16: one chunk) at `level`. */
static captured openexr_chunk(const float *plane, int width, int lines, int level) {
  captured out = {NULL, 0};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.write_fn = discard_write;
  exr_context_t ctxt = NULL;
  int part = 0;
  exr_attr_box2i_t box = {{{{0, 0}}}, {{{width - 1, lines - 1}}}};
  exr_attr_v2f_t center = {{{0.f, 0.f}}};
  assert_int_equal(exr_start_write(&ctxt, "reference.exr", EXR_WRITE_FILE_DIRECTLY, &init),
                   EXR_ERR_SUCCESS);
  assert_int_equal(exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part), EXR_ERR_SUCCESS);
  assert_int_equal(exr_initialize_required_attr(ctxt, part, &box, &box, 1.f, &center, 1.f,
                                                EXR_LINEORDER_INCREASING_Y, EXR_COMPRESSION_ZIP),
                   EXR_ERR_SUCCESS);
  assert_int_equal(exr_set_zip_compression_level(ctxt, part, level), EXR_ERR_SUCCESS);
  assert_int_equal(
      exr_add_channel(ctxt, part, "Y", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
      EXR_ERR_SUCCESS);
  assert_int_equal(exr_write_header(ctxt), EXR_ERR_SUCCESS);
  exr_chunk_info_t cinfo;
  assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, 0, &cinfo), EXR_ERR_SUCCESS);
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  assert_int_equal(exr_encoding_initialize(ctxt, part, &cinfo, &enc), EXR_ERR_SUCCESS);
  enc.channels[0].user_bytes_per_element = 4;
  enc.channels[0].user_data_type = EXR_PIXEL_FLOAT;
  enc.channels[0].user_pixel_stride = 4;
  enc.channels[0].user_line_stride = 4 * width;
  enc.channels[0].encode_from_ptr = (const uint8_t *)plane;
  assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &enc), EXR_ERR_SUCCESS);
  enc.write_fn = capture_chunk;
  enc.yield_until_ready_fn = NULL;
  enc.encoding_user_data = &out;
  assert_int_equal(exr_encoding_run(ctxt, part, &enc), EXR_ERR_SUCCESS);
  assert_int_equal(exr_encoding_destroy(ctxt, &enc), EXR_ERR_SUCCESS);
  exr_finish(&ctxt); /* no chunk was written: its error is of no interest here */
  assert_non_null(out.bytes);
  return out;
}

/* One stream for every chunk of a test: reset between chunks, made again when the level changes. */
static clr_exr_zip_stream *stream;

static void compare_with_openexr(const float *plane, int width, int lines, int level) {
  size_t bytes = (size_t)width * (size_t)lines * 4;
  uint8_t *scratch = malloc(bytes), *out = malloc(clr_exr_zip_bound(bytes));
  assert_non_null(scratch);
  assert_non_null(out);
  size_t size = 0;
  assert_int_equal(
      clr_exr_zip_compress(&stream, (const uint8_t *)plane, bytes, level, scratch, out, &size), 1);
  clr_exr_zip_stream *fresh = NULL; /* a new stream gives the same bytes */
  size_t fresh_size = 0;
  uint8_t *again = malloc(clr_exr_zip_bound(bytes));
  assert_non_null(again);
  assert_int_equal(clr_exr_zip_compress(&fresh, (const uint8_t *)plane, bytes, level, scratch,
                                        again, &fresh_size),
                   1);
  clr_exr_zip_stream_free(fresh);
  assert_int_equal(fresh_size, size);
  assert_memory_equal(again, out, size);
  free(again);
  captured ref = openexr_chunk(plane, width, lines, level);
  assert_int_equal(size, ref.size);
  assert_memory_equal(out, ref.bytes, size);
  free(ref.bytes);
  free(scratch);
  free(out);
}

static void test_same_bytes_as_openexr(void **state) {
  (void)state;
  enum { W = 37, L = 16 };
  float plane[W * L];
  uint32_t s = 12345u;
  for (int level = 1; level <= 9; level += 5) {
    memset(plane, 0, sizeof plane); /* zeros: long runs */
    compare_with_openexr(plane, W, L, level);
    for (int i = 0; i < W * L; ++i) plane[i] = 0.25f + 0.001f * (float)i; /* a smooth ramp */
    compare_with_openexr(plane, W, L, level);
    for (int i = 0; i < W * L; ++i) /* noisy sums with specials */
      plane[i] = i % 97 == 0   ? INFINITY
                 : i % 89 == 0 ? NAN
                               : (float)(next_random(&s) % 100000u) * 1e-3f;
    compare_with_openexr(plane, W, 11, level); /* a short chunk */
    for (int i = 0; i < W * L; ++i) {          /* random bits: stored as they are */
      uint32_t bits = next_random(&s);
      memcpy(&plane[i], &bits, 4);
    }
    compare_with_openexr(plane, W, L, level);
  }
  clr_exr_zip_stream_free(stream);
  stream = NULL;
}

/* Undoes OpenEXR's predictor and reorder (the reader's steps) to check a round trip. */
static void unzip(const uint8_t *stored, size_t stored_size, size_t bytes, uint8_t *out) {
  if (stored_size == bytes) { /* stored uncompressed */
    memcpy(out, stored, bytes);
    return;
  }
  uint8_t *t = malloc(bytes ? bytes : 1);
  assert_non_null(t);
  uLongf n = (uLongf)bytes;
  assert_int_equal(uncompress(t, &n, stored, (uLong)stored_size), Z_OK);
  assert_int_equal(n, bytes);
  for (size_t i = 1; i < bytes; ++i) t[i] = (uint8_t)(t[i - 1] + t[i] - 128u);
  size_t evens = (bytes + 1) / 2;
  for (size_t i = 0; i < bytes; ++i) out[i] = i % 2 == 0 ? t[i / 2] : t[evens + i / 2];
  free(t);
}

static void test_round_trip_any_length(void **state) {
  (void)state;
  const size_t lengths[] = {0, 1, 2, 3, 4, 5, 17, 64, 1001, 40000};
  uint32_t s = 777u;
  for (size_t k = 0; k < sizeof lengths / sizeof lengths[0]; ++k) {
    size_t n = lengths[k];
    uint8_t *in = malloc(n + 1), *scratch = malloc(n + 1), *out = malloc(clr_exr_zip_bound(n)),
            *back = malloc(n + 1);
    assert_true(in && scratch && out && back);
    for (size_t i = 0; i < n; ++i) /* half compressible: a slow ramp with noise every 4th byte */
      in[i] = (uint8_t)(i % 4 == 3 ? next_random(&s) : i / 64);
    size_t size = 0;
    assert_int_equal(clr_exr_zip_compress(&stream, in, n, 1, scratch, out, &size), 1);
    assert_true(size <= n);
    unzip(out, size, n, back);
    if (n) assert_memory_equal(back, in, n);
    free(in);
    free(scratch);
    free(out);
    free(back);
  }
  clr_exr_zip_stream_free(stream);
  stream = NULL;
}

/* ---- whole images through clr_exr_write ---------------------------------------------------- */

static void test_multi_chunk_image_reads_back(void **state) {
  (void)state;
  /* 70 lines from y = 3: five chunks (the last of 9 lines), so the writer uses helper threads on
   * a machine with more than one CPU; channels given out of name order, float and half. */
  enum { DW = 41, DH = 80, W = 37, H = 70 };
  clr_bounds2i dw = {2, 3, 2 + W, 3 + H};
  static float planes[4][W * H];
  uint32_t s = 99u;
  for (int c = 0; c < 4; ++c)
    for (int i = 0; i < W * H; ++i)
      planes[c][i] = c == 3 ? 0.0f : (float)(next_random(&s) % 1000000u) * 1e-4f - 20.0f;
  clr_exr_channel ch[4] = {
      {"sum.R", planes[0], 0}, {"B", planes[1], 1}, {"A", planes[2], 0}, {"zero", planes[3], 1}};
  char path[1024];
  snprintf(path, sizeof path, "%s/test_exr_zip_%d.exr", CLR_BINARY_DIR, (int)getpid());
  assert_int_equal(clr_exr_write(path, DW, DH, dw, ch, 4, NULL, 0), CLR_SUCCESS);
  clr_exr_image *im = NULL;
  assert_int_equal(clr_exr_read(path, &im), CLR_SUCCESS);
  assert_int_equal(im->width, W);
  assert_int_equal(im->height, H);
  assert_int_equal(im->data_window.y0, 3);
  assert_int_equal(im->channel_count, 4);
  assert_string_equal(im->channel_names[0], "A"); /* sorted in the file */
  assert_string_equal(im->channel_names[3], "zero");
  for (int c = 0; c < 4; ++c) {
    const float *got = clr_exr_image_channel(im, ch[c].name);
    assert_non_null(got);
    for (int i = 0; i < W * H; ++i) {
      float want = ch[c].half ? clr_half_to_float(clr_float_to_half(planes[c][i])) : planes[c][i];
      assert_memory_equal(&got[i], &want, sizeof want);
    }
  }
  clr_exr_image_free(im);
  assert_int_equal(unlink(path), 0);
}

/* The rows callback of test_rows_write_same_file: rows of the planes of rows_image. */
typedef struct rows_image {
  const float *planes[4];
  int32_t width, y0;
  int calls;
} rows_image;

static void copy_rows(void *user, int32_t y, int32_t lines, float *const *rows) {
  rows_image *im = user;
  for (int c = 0; c < 4; ++c)
    memcpy(rows[c], im->planes[c] + (size_t)(y - im->y0) * (size_t)im->width,
           (size_t)lines * (size_t)im->width * sizeof(float));
  __atomic_fetch_add(&im->calls, 1, __ATOMIC_RELAXED);
}

static void test_rows_write_same_file(void **state) {
  (void)state;
  enum { W = 29, H = 83 }; /* six chunks, the last of 3 lines */
  clr_bounds2i dw = {1, 5, 1 + W, 5 + H};
  static float planes[4][W * H];
  uint32_t s = 4242u;
  for (int c = 0; c < 4; ++c)
    for (int i = 0; i < W * H; ++i) planes[c][i] = (float)(next_random(&s) % 4096u) * 0.125f - 7.0f;
  clr_exr_channel ch[4] = {
      {"weight", planes[0], 0}, {"G", planes[1], 1}, {"R", planes[2], 0}, {"B", planes[3], 1}};
  clr_exr_attribute attr = {"note", CLR_EXR_ATTR_STRING, "rows", 0.f, 0};
  char a[1024], b[1024];
  snprintf(a, sizeof a, "%s/test_exr_zip_planes_%d.exr", CLR_BINARY_DIR, (int)getpid());
  snprintf(b, sizeof b, "%s/test_exr_zip_rows_%d.exr", CLR_BINARY_DIR, (int)getpid());
  assert_int_equal(clr_exr_write(a, 40, 90, dw, ch, 4, &attr, 1), CLR_SUCCESS);
  rows_image im = {{planes[0], planes[1], planes[2], planes[3]}, W, 5, 0};
  clr_exr_channel names[4] = {{"weight", NULL, 0}, {"G", NULL, 1}, {"R", NULL, 0}, {"B", NULL, 1}};
  assert_int_equal(clr_exr_write_rows(b, 40, 90, dw, names, 4, copy_rows, &im, &attr, 1),
                   CLR_SUCCESS);
  assert_int_equal(im.calls, 6); /* once per chunk */
  assert_files_equal(a, b);
  assert_int_equal(unlink(a), 0);
  assert_int_equal(unlink(b), 0);
  assert_int_equal(clr_exr_write_rows(b, 40, 90, dw, names, 4, NULL, &im, NULL, 0),
                   CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_exr_write(b, 40, 90, dw, names, 4, NULL, 0), CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(access(b, F_OK), -1); /* nothing written by the failures */
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_same_bytes_as_openexr),
      cmocka_unit_test(test_round_trip_any_length),
      cmocka_unit_test(test_multi_chunk_image_reads_back),
      cmocka_unit_test(test_rows_write_same_file),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
