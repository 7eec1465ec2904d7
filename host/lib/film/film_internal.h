/* Film internals shared by film.c (lifetime, resolve, merges), film_accumulate.c (binning,
 * kernels, host reference) and film_tile.c (host-thread tiles). */
#ifndef CLR_FILM_INTERNAL_H
#define CLR_FILM_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>
#include "clrender/film.h"
#include "film_types.h"
#include "filter_internal.h"

/* Device resources of the weigh and gather kernels, grown on demand (guarded by the film's
 * lock). */
typedef struct clr_film_device {
  cl_kernel kernel, weigh;
  cl_kernel pixel_gather;    /* portable shape's per-pixel gather, made on first use */
  cl_kernel weigh8, gather8; /* SIMD shape's 8-lane kernels, made on first use */
  cl_kernel gather8_add;     /* gather8 adding into the double sums, made on first use */
  /* During a film_add_samples call whose kernels add into the film's double sums themselves:
   * buffers over rgb_sum and weight_sum (CL_MEM_USE_HOST_PTR); NULL otherwise. */
  cl_mem rgb_sums, weight_sums;
  size_t group_size; /* automatic work-group size (runs of pixels) */
  cl_mem table;      /* the filter's separable table factors, 2 * CLR_FILTER_TABLE_SIZE floats */
  cl_mem binned, weighed, starts, sums;
  size_t binned_bytes, weighed_bytes, starts_bytes, sums_bytes;
} clr_film_device;

/* Most threads of the host binning (a chunk is split into up to this many consecutive parts;
 * the binned order does not depend on their number). */
#define CLR_FILM_BIN_THREADS_MAX 16
/* Fewest samples per binning part (a thread costs ~50 us). */
#define CLR_FILM_BIN_PART_MIN 4096

/* Host scratch of the binning (stable counting sorts by bin row, then by bin column), grown on
 * demand. */
typedef struct clr_film_bins {
  uint32_t *keys;   /* per chunk sample: packed bin (y << 16 | x, from the key origin), or none */
  float *values;    /* per chunk sample: its binned values (CLR_FILM_BINNED_FLOATS), when keyed and
                     the film clamps luminance (else pass 2 reads the samples) */
  uint32_t *starts; /* per bin: first binned sample (+ one past the end) */
  uint32_t *starts_sent;   /* the previous chunk's starts, source of a write that may be pending */
  uint32_t *cursor;        /* per part and bin row: count, then fill position */
  struct row_entry *rowed; /* binned samples sorted by bin row only, with their bin column */
  uint32_t *columns;       /* per part and bin column: fill position of the row sort */
  float *binned;           /* host copy of the binned samples (reference path) */
  float *sums;             /* host per-pixel sums (reference path) */
  size_t keys_cap, values_cap, starts_cap, starts_sent_cap, cursor_cap, rowed_cap, columns_cap,
      binned_cap, sums_cap;
} clr_film_bins;

struct clr_film_t {
  atomic_int refcount;
  clr_context ctx;
  clr_film_params params;
  clr_filter_params filter;
  float table[CLR_FILTER_TABLE_SIZE * CLR_FILTER_TABLE_SIZE]; /* pbrt's 16x16 table */
  float factors[2 * CLR_FILTER_TABLE_SIZE]; /* its separable factors: 16 x, then 16 y */
  float scale;
  clr_film_desc desc;    /* as created */
  int32_t width, height; /* of the pixel bounds */
  size_t pixel_count;
  double *rgb_sum;    /* 3 per pixel */
  double *weight_sum; /* 1 per pixel */
  double *splat_rgb;  /* 3 per pixel, NULL until the first splat */
  uint64_t accepted, dropped, outside;
  pthread_mutex_t lock;
  clr_film_device dev;
  clr_film_bins bins;
  size_t group_size_override; /* 0: automatic (tests set it) */
  int bin_threads;            /* host binning threads, 1..CLR_FILM_BIN_THREADS_MAX */
};

/* Adds per-pixel float sums (CLR_FILM_SUM_FLOATS per pixel, row-major over `block`, which may
 * reach past the pixel bounds: those pixels are skipped) into the film's double sums, with up to
 * `threads` threads (bands of rows) for large blocks (the same bits). Caller holds the lock. */
void clr_film_add_block(clr_film film, clr_bounds2i block, const float *sums, int threads);
/* Pixel i's RGB as film_get_rgb resolves it (i: row-major over the pixel bounds); the caller
 * holds the film's lock. */
void clr_film_resolve_pixel(clr_film film, size_t i, float splat_scale, float rgb[3]);

/* One chunk's per-pixel float sums (CLR_FILM_SUM_FLOATS per pixel, row-major over `block`),
 * owned by the accumulator until clr_film_chunk_sums_release. sums is NULL when no sample of
 * the chunk reached the film. */
typedef struct clr_film_chunk_sums {
  clr_bounds2i block;
  const float *sums;
  int mapped;     /* sums map the device's sum buffer */
  cl_event ready; /* NULL, or the event after which sums may be read */
} clr_film_chunk_sums;

/* Accumulates up to CLR_FILM_CHUNK_SAMPLES samples in the canonical order with the kernels, or
 * with the C build of kernels/film_funcs.h when `reference`. Caller holds the film's lock. */
clr_result clr_film_accumulate_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                                     int reference, clr_film_chunk_sums *out);
clr_result clr_film_chunk_sums_release(clr_film film, clr_film_chunk_sums *sums);
/* Around a film_add_samples call's chunks: where the device shares the host's memory and
 * computes in double, and the filter lets every chunk run in lanes, opens buffers over the film's
 * double sums so that the kernels add each chunk's sums into them (clr_film_gather8_add: the same
 * additions in the same order as clr_film_add_block); otherwise does nothing. Close hands the sums
 * back to the host (map and unmap) and releases the buffers; it is a no-op when none are open.
 * Caller holds the film's lock. */
clr_result clr_film_open_device_sums(clr_film film);
clr_result clr_film_close_device_sums(clr_film film);
/* film_add_samples' device path: the chunks of samples[0..count) through the kernels into the
 * film's double sums, in chunk order (the same bits as chunk by chunk), with each chunk's checks
 * and first two binning passes running while the device runs the previous chunk's kernels.
 * Caller holds the film's lock; the film has a context. */
clr_result clr_film_accumulate_overlapped(clr_film film, const clr_film_sample *samples,
                                          size_t count);

/* Host reference of film_add_samples: the same chunks, checks, binning and per-pixel float sums in
 * the canonical order, computed by the C build of kernels/film_funcs.h (one thread). */
clr_result film_add_samples_reference(clr_film film, const clr_film_sample *samples, size_t count);
/* Forces the gather kernel's work-group size in work-items, each a run of tile_size pixels
 * (1..CLR_FILM_GROUP_MAX; 0 = automatic). */
clr_result film_set_group_size(clr_film film, size_t group_size);
/* Sets the host binning's thread count (1..CLR_FILM_BIN_THREADS_MAX; 0 = automatic: the online
 * CPUs, at most 8). The film's sums do not depend on it. */
clr_result film_set_bin_threads(clr_film film, int threads);
/* The threads film_add_samples bins and adds chunk sums with (as set, else automatic). */
int clr_film_host_threads(clr_film film);
/* Bytes the film holds (the scratch only grows, so these are also the peaks): its sums (32 bytes
 * per pixel, 56 once splatted) and the accumulation's host and device scratch, bounded by
 * CLR_FILM_CHUNK_SAMPLES and the chunk's pixel footprint. */
size_t clr_film_sums_bytes(clr_film film);
size_t clr_film_scratch_bytes(clr_film film);
/* Releases the device resources and binning scratch. */
void clr_film_accumulate_release(clr_film film);

#endif
