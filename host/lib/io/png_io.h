/* 8-bit sRGB PNG files (libpng) and extension-dispatched linear RGB image loading. */
#ifndef CLR_PNG_IO_H
#define CLR_PNG_IO_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/result.h"

/* pbrt-v3 InverseGammaCorrect: v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055)^2.4. */
float clr_inverse_gamma_correct(float v);
/* pbrt-v3's 8-bit value: clamp(255 * GammaCorrect(v) + 0.5, 0, 255) truncated (NaN -> 0). */
uint8_t clr_to_srgb8(float v);

/* Byte count of an interleaved RGB image of `element`-byte values, 0 if invalid or overflowing. */
size_t clr_rgb_bytes(int32_t width, int32_t height, size_t element);

/* Writes interleaved linear RGB (width * height * 3 floats, top row first) as an 8-bit sRGB PNG.
 * The file appears at `path` only when complete (temporary file renamed); nothing is left behind
 * on failure. */
clr_result clr_png_write_srgb(const char *path, int32_t width, int32_t height, const float *rgb);
/* The same with the 8-bit sRGB values given (width * height * 3 bytes, clr_to_srgb8's). */
clr_result clr_png_write_srgb8(const char *path, int32_t width, int32_t height,
                               const uint8_t *srgb);

/* Reads any PNG (gray, palette, alpha composited onto black, 16-bit) as interleaved linear RGB:
 * each 8-bit sRGB value v becomes InverseGammaCorrect(v / 255). *rgb is malloc'ed (free()). */
clr_result clr_png_read(const char *path, int32_t *width, int32_t *height, float **rgb);

#endif
