/* Film internals shared by film.c (lifetime, resolve, merges), film_accumulate.c (binning,
 * kernels, host reference) and film_tile.c (host-thread tiles). */
#ifndef CLR_FILM_INTERNAL_H
#define CLR_FILM_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>
#include "clrender/film.h"
#include "film_types.h"
#include "filter_types.h"

/* Device resources of the accumulation kernel, grown on demand (guarded by the film's lock). */
typedef struct clr_film_device {
  cl_kernel kernel;
  size_t group_size;      /* work-items per tile group */
  cl_mem table;           /* filter table, CLR_FILTER_TABLE_SIZE^2 floats */
  cl_mem samples;         /* upload buffer for host samples */
  size_t samples_bytes;
  cl_mem tiles, starts, order, sums;
  size_t tiles_bytes, starts_bytes, order_bytes, sums_bytes;
} clr_film_device;

/* Host scratch of the binning, grown on demand. */
typedef struct clr_film_bins {
  int32_t *tile_slot;  /* per film tile: 0 = untouched in this chunk, else slot + 1 */
  uint32_t *tiles;     /* touched tiles, in order of first touch */
  uint32_t *starts;    /* per slot: first entry in order (+ one past the end) */
  uint32_t *cursor;    /* per slot: fill position */
  uint32_t *order;     /* sample indices grouped by tile, batch order inside a tile */
  float *sums;         /* read-back per-slot pixel sums */
  size_t tiles_cap, order_cap, sums_cap;
} clr_film_bins;

struct clr_film_t {
  atomic_int refcount;
  clr_context ctx;
  clr_film_params params;
  clr_filter_params filter;
  float table[CLR_FILTER_TABLE_SIZE * CLR_FILTER_TABLE_SIZE];
  float scale;
  clr_film_desc desc; /* as created */
  int32_t width, height; /* of the pixel bounds */
  size_t pixel_count;
  double *rgb_sum;    /* 3 per pixel */
  double *weight_sum; /* 1 per pixel */
  double *splat_rgb;  /* 3 per pixel */
  uint64_t accepted, dropped, outside;
  pthread_mutex_t lock;
  clr_film_device dev;
  clr_film_bins bins;
  size_t group_size_override; /* 0: automatic (tests set it) */
};

/* Adds per-pixel float sums (CLR_FILM_SUM_FLOATS per pixel, row-major over `block`, which may
 * reach past the pixel bounds: those pixels are skipped) into the film's double sums. Caller
 * holds the lock. */
void clr_film_add_block(clr_film film, clr_bounds2i block, const float *sums);

/* Host reference of film_add_samples: the same chunks, checks and per-pixel float sums in batch
 * order, computed by the C build of kernels/film_funcs.h. */
clr_result film_add_samples_reference(clr_film film, const clr_film_sample *samples, size_t count);
/* Forces the accumulation kernel's work-group size (1..CLR_FILM_GROUP_MAX; 0 = automatic). */
clr_result film_set_group_size(clr_film film, size_t group_size);
/* Releases the device resources and binning scratch. */
void clr_film_accumulate_release(clr_film film);

#endif
