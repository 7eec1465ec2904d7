/* OpenEXR's ZIP chunk compression (the file format's reorder, predictor and zlib stream) in
 * loops the compiler vectorises: OpenEXRCore 3.1 runs the same steps a byte at a time. */
#include "exr_zip.h"

#include <string.h>
#include <zlib.h>

size_t clr_exr_zip_bound(size_t bytes) { return (size_t)compressBound((uLong)bytes); }

/* OpenEXR's two passes in one: out = even bytes of `in`, then odd bytes, each byte after the first
 * replaced by (byte - previous byte + 128) mod 256. */
static void reorder_with_deltas(const uint8_t *restrict in, size_t n, uint8_t *restrict out) {
  if (n == 0) return;
  size_t evens = (n + 1) / 2, odds = n / 2;
  out[0] = in[0];
  for (size_t i = 1; i < evens; ++i) out[i] = (uint8_t)(in[2 * i] - in[2 * i - 2] + 128u);
  if (odds) out[evens] = (uint8_t)(in[1] - in[2 * (evens - 1)] + 128u);
  for (size_t j = 1; j < odds; ++j)
    out[evens + j] = (uint8_t)(in[2 * j + 1] - in[2 * j - 1] + 128u);
}

int clr_exr_zip_compress(const uint8_t *packed, size_t bytes, int level, uint8_t *scratch,
                         uint8_t *out, size_t *out_bytes) {
  reorder_with_deltas(packed, bytes, scratch);
  uLongf size = (uLongf)clr_exr_zip_bound(bytes);
  if (compress2(out, &size, scratch, (uLong)bytes, level) != Z_OK) return 0;
  if (size > bytes) { /* incompressible: OpenEXR stores the packed bytes */
    memcpy(out, packed, bytes);
    size = (uLongf)bytes;
  }
  *out_bytes = (size_t)size;
  return 1;
}
