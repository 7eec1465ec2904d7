/* OpenEXR's ZIP chunk compression (the file format's reorder, predictor and zlib stream) in
 * loops the compiler vectorises: OpenEXRCore 3.1 runs the same steps a byte at a time. */
#include "exr_zip.h"

#include <limits.h>
#include <stdlib.h>
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

struct clr_exr_zip_stream {
  z_stream z;
  int level;
};

/* A fresh stream (deflateInit) or the kept one reset (the same state: zlib's deflateReset). */
static int start_stream(clr_exr_zip_stream **stream, int level) {
  if (*stream && (*stream)->level != level) {
    clr_exr_zip_stream_free(*stream);
    *stream = NULL;
  }
  if (*stream) return deflateReset(&(*stream)->z) == Z_OK;
  clr_exr_zip_stream *s = calloc(1, sizeof *s);
  if (!s) return 0;
  if (deflateInit(&s->z, level) != Z_OK) {
    free(s);
    return 0;
  }
  s->level = level;
  *stream = s;
  return 1;
}

int clr_exr_zip_compress(clr_exr_zip_stream **stream, const uint8_t *packed, size_t bytes,
                         int level, uint8_t *scratch, uint8_t *out, size_t *out_bytes) {
  reorder_with_deltas(packed, bytes, scratch);
  size_t bound = clr_exr_zip_bound(bytes), size = 0;
  if (bytes > UINT_MAX || bound > UINT_MAX) { /* beyond one deflate call's counts */
    uLongf n = (uLongf)bound;
    if (compress2(out, &n, scratch, (uLong)bytes, level) != Z_OK) return 0;
    size = (size_t)n;
  } else {
    if (!start_stream(stream, level)) return 0;
    z_stream *z = &(*stream)->z;
    z->next_in = scratch;
    z->avail_in = (uInt)bytes;
    z->next_out = out;
    z->avail_out = (uInt)bound;
    if (deflate(z, Z_FINISH) != Z_STREAM_END) return 0;
    size = (size_t)z->total_out;
  }
  if (size > bytes) { /* incompressible: OpenEXR stores the packed bytes */
    memcpy(out, packed, bytes);
    size = bytes;
  }
  *out_bytes = size;
  return 1;
}

void clr_exr_zip_stream_free(clr_exr_zip_stream *stream) {
  if (!stream) return;
  deflateEnd(&stream->z);
  free(stream);
}
