/* The public image type: EXR or PNG read as linear RGB, PNG previews written. */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "clrender/image.h"
#include "exr_io.h"
#include "png_io.h"

static int has_extension(const char *path, const char *ext) {
  size_t n = strlen(path), e = strlen(ext);
  if (n < e) return 0;
  for (size_t i = 0; i < e; ++i)
    if (tolower((unsigned char)path[n - e + i]) != ext[i]) return 0;
  return 1;
}

/* Interleaves R, G, B (or Y three times) of an EXR image. */
static clr_result exr_to_rgb(const char *path, const clr_exr_image *image, float **rgb) {
  const float *planes[3] = {clr_exr_image_channel(image, "R"), clr_exr_image_channel(image, "G"),
                            clr_exr_image_channel(image, "B")};
  if (!planes[0] || !planes[1] || !planes[2]) {
    const float *y = clr_exr_image_channel(image, "Y");
    if (!y)
      return clr_fail(NULL, CLR_ERROR_FILE_FORMAT,
                      "EXR '%s' has neither R, G and B channels nor a Y channel (first channel "
                      "'%s')",
                      path, image->channel_names[0]);
    planes[0] = planes[1] = planes[2] = y;
  }
  size_t bytes = clr_rgb_bytes(image->width, image->height, sizeof(float));
  float *out = bytes ? malloc(bytes) : NULL;
  if (!out) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "EXR '%s': out of memory", path);
  size_t pixels = (size_t)image->width * (size_t)image->height;
  for (size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c) out[3 * i + (size_t)c] = planes[c][i];
  *rgb = out;
  return CLR_SUCCESS;
}

clr_result clr_image_read(const char *path, clr_image *out) {
  if (!path || !out) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_image_read: NULL argument");
  memset(out, 0, sizeof *out);
  if (has_extension(path, ".png")) return clr_png_read(path, &out->width, &out->height, &out->rgb);
  if (!has_extension(path, ".exr"))
    return clr_fail(NULL, CLR_ERROR_FILE_FORMAT,
                    "cannot read image '%s': unknown extension (expected .exr or .png)", path);
  clr_exr_image *image = NULL;
  CLR_CHECK(clr_exr_read(path, &image));
  clr_result result = exr_to_rgb(path, image, &out->rgb);
  if (result == CLR_SUCCESS) {
    out->width = image->width;
    out->height = image->height;
  }
  clr_exr_image_free(image);
  return result;
}

void clr_image_free(clr_image *image) {
  if (!image) return;
  free(image->rgb);
  memset(image, 0, sizeof *image);
}

clr_result clr_image_write_png(const char *path, const clr_image *image) {
  if (!path || !image || !image->rgb)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_image_write_png: NULL argument");
  return clr_png_write_srgb(path, image->width, image->height, image->rgb);
}
