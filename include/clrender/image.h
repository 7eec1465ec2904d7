/* clrender images: linear RGB read from OpenEXR or PNG files, PNG previews written.
 *
 * Thread safety: every call is thread-safe on different images. Ownership: an image's pixels
 * belong to it until clr_image_free. NULL arguments return CLR_ERROR_NULL_POINTER. */
#ifndef CLRENDER_IMAGE_H
#define CLRENDER_IMAGE_H

#include <stdint.h>
#include "clrender/export.h"
#include "clrender/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Interleaved linear RGB, row-major, top row first: rgb[3 * (y * width + x) + c]. */
typedef struct clr_image {
  int32_t width, height;
  float *rgb;
} clr_image;

/* Reads `path` by its extension (case-insensitive): ".exr" (channels R, G, B, or Y as gray, over
 * the data window; half and uint converted) or ".png" (8/16-bit sRGB decoded with pbrt-v3's
 * InverseGammaCorrect; alpha composited on black). On failure *image is zeroed: CLR_ERROR_IO for a
 * missing or unreadable file, CLR_ERROR_FILE_FORMAT for an unknown extension or malformed file. */
CLR_API clr_result clr_image_read(const char *path, clr_image *image);
/* Frees the pixels and zeroes *image; NULL is ignored. */
CLR_API void clr_image_free(clr_image *image);
/* Writes an 8-bit sRGB PNG with pbrt-v3's gamma and rounding; the file appears only when
 * complete (temporary name, then rename). */
CLR_API clr_result clr_image_write_png(const char *path, const clr_image *image);

#ifdef __cplusplus
}
#endif
#endif
