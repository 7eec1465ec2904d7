/* OpenEXR's ZIP chunk compression done here (OpenEXRCore's encoder, byte for byte, faster). */
#ifndef CLR_EXR_ZIP_H
#define CLR_EXR_ZIP_H

#include <stddef.h>
#include <stdint.h>

/* A zlib stream kept between one thread's chunks: deflateReset instead of a deflateInit per
 * chunk (compress2 allocates and zeroes ~270 KiB of fresh pages for every chunk). */
typedef struct clr_exr_zip_stream clr_exr_zip_stream;

/* Bytes `out` must hold for a chunk of `bytes` packed bytes. */
size_t clr_exr_zip_bound(size_t bytes);

/* Compresses one chunk's packed bytes as OpenEXR's ZIP does: even bytes then odd bytes, each
 * replaced by its difference to the byte before (+128), deflated by zlib at `level`; a chunk that
 * would grow is stored as it is. `scratch` holds `bytes` bytes, `out` clr_exr_zip_bound(bytes).
 * *stream (NULL at first) is made or reused. Returns 1 and the stored size in *out_bytes, 0 if
 * zlib failed or memory ran out. */
int clr_exr_zip_compress(clr_exr_zip_stream **stream, const uint8_t *packed, size_t bytes,
                         int level, uint8_t *scratch, uint8_t *out, size_t *out_bytes);

void clr_exr_zip_stream_free(clr_exr_zip_stream *stream);

#endif
