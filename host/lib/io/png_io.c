/* 8-bit sRGB PNG output/input through libpng's simplified API. */
#define _POSIX_C_SOURCE 200809L
#include "png_io.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "atomic_file.h"
#include "clr_internal.h"
#include "clrender/film.h"
#include "input_file.h"

static float gamma_correct(float v) {
  if (v <= 0.0031308f) return 12.92f * v;
  return 1.055f * powf(v, 1.f / 2.4f) - 0.055f;
}

float clr_inverse_gamma_correct(float v) {
  if (v <= 0.04045f) return v / 12.92f;
  return powf((v + 0.055f) / 1.055f, 2.4f);
}

uint8_t clr_to_srgb8(float v) {
  float scaled = 255.f * gamma_correct(v) + 0.5f;
  if (!(scaled > 0.f)) return 0; /* also NaN */
  if (scaled > 255.f) return 255;
  return (uint8_t)scaled;
}

/* Byte count of an interleaved RGB image, 0 if the size is invalid or overflows. */
size_t clr_rgb_bytes(int32_t width, int32_t height, size_t element) {
  if (width <= 0 || height <= 0) return 0;
  size_t pixels = (size_t)width * (size_t)height;
  if (pixels / (size_t)width != (size_t)height || pixels > SIZE_MAX / 3 / element) return 0;
  return pixels * 3 * element;
}

clr_result clr_png_write_srgb(const char *path, int32_t width, int32_t height, const float *rgb) {
  if (!path || !rgb)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_png_write_srgb: NULL path or rgb");
  size_t bytes = clr_rgb_bytes(width, height, 1);
  if (!bytes)
    return clr_fail(NULL, CLR_ERROR_INVALID_RESOLUTION, "clr_png_write_srgb '%s': bad size %dx%d",
                    path, (int)width, (int)height);
  uint8_t *srgb = malloc(bytes);
  if (!srgb)
    return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "clr_png_write_srgb '%s': out of memory", path);
  for (size_t i = 0; i < bytes; ++i) srgb[i] = clr_to_srgb8(rgb[i]);
  clr_result result = clr_png_write_srgb8(path, width, height, srgb);
  free(srgb);
  return result;
}

clr_result clr_png_write_srgb8(const char *path, int32_t width, int32_t height,
                               const uint8_t *srgb) {
  if (!path || !srgb)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_png_write_srgb8: NULL path or values");
  if (!clr_rgb_bytes(width, height, 1))
    return clr_fail(NULL, CLR_ERROR_INVALID_RESOLUTION, "clr_png_write_srgb '%s': bad size %dx%d",
                    path, (int)width, (int)height);
  clr_atomic_file file;
  FILE *stream = NULL;
  clr_result result = clr_atomic_file_open(&file, path); /* leaves `file` abortable on failure */
  if (result == CLR_SUCCESS) result = clr_atomic_file_stream(&file, &stream);
  if (result == CLR_SUCCESS) {
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)width;
    image.height = (png_uint_32)height;
    image.format = PNG_FORMAT_RGB;
    image.flags = PNG_IMAGE_FLAG_FAST; /* zlib's fast level: the preview is written every render */
    if (!png_image_write_to_stdio(&image, stream, 0, srgb, 0, NULL))
      result = clr_fail(NULL, CLR_ERROR_PNG, "png_image_write_to_stdio failed for '%s': %s", path,
                        image.message);
    png_image_free(&image);
  }
  if (result == CLR_SUCCESS)
    result = clr_atomic_file_commit(&file);
  else
    clr_atomic_file_abort(&file); /* safe after a failed open too */
  return result;
}

clr_result clr_png_read(const char *path, int32_t *width, int32_t *height, float **rgb) {
  if (!path || !width || !height || !rgb)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_png_read: NULL argument");
  *rgb = NULL;
  FILE *stream = NULL;
  uint64_t file_size = 0;
  CLR_CHECK(clr_input_file_open(path, "PNG", &stream, &file_size));
  png_image image;
  memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  uint8_t *srgb = NULL;
  clr_result result = CLR_SUCCESS;
  if (!png_image_begin_read_from_stdio(&image, stream)) {
    result = clr_fail(NULL, CLR_ERROR_FILE_FORMAT,
                      "png_image_begin_read_from_stdio failed for "
                      "'%s': %s",
                      path, image.message);
  } else {
    image.format = PNG_FORMAT_RGB;
    /* The header's size must fit the pixel limit and the file: every row holds at least a
     * filter byte and one bit per pixel, which zlib shrinks at most ~1032 times. */
    uint64_t pixels = (uint64_t)image.width * (uint64_t)image.height;
    uint64_t raw = (uint64_t)image.height * (1 + ((uint64_t)image.width + 7) / 8);
    int fits = pixels <= (uint64_t)CLR_FILM_MAX_PIXELS && raw / 2048 <= file_size;
    size_t bytes = fits ? clr_rgb_bytes((int32_t)image.width, (int32_t)image.height, 1) : 0;
    srgb = bytes ? calloc(bytes, 1) : NULL; /* zeros: alpha is composited onto black */
    if (!bytes)
      result = clr_fail(NULL, CLR_ERROR_FILE_FORMAT,
                        "PNG '%s' is corrupt: its header declares %lux%lu pixels (limit %d "
                        "pixels, file of %llu bytes)",
                        path, (unsigned long)image.width, (unsigned long)image.height,
                        (int)CLR_FILM_MAX_PIXELS, (unsigned long long)file_size);
    else if (!srgb)
      result = clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "PNG '%s': out of memory", path);
    else if (!png_image_finish_read(&image, NULL, srgb, 0, NULL))
      result = clr_fail(NULL, CLR_ERROR_FILE_FORMAT, "png_image_finish_read failed for '%s': %s",
                        path, image.message);
    float *linear = result == CLR_SUCCESS ? malloc(bytes * sizeof(float)) : NULL;
    if (result == CLR_SUCCESS && !linear)
      result = clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "PNG '%s': out of memory", path);
    if (result == CLR_SUCCESS) {
      for (size_t i = 0; i < bytes; ++i) linear[i] = clr_inverse_gamma_correct(srgb[i] / 255.f);
      *width = (int32_t)image.width;
      *height = (int32_t)image.height;
      *rgb = linear;
    }
  }
  png_image_free(&image);
  fclose(stream);
  free(srgb);
  return result;
}
