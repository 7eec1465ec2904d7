/* pbrt-v3 FilmTile for host threads: per-pixel float sums over the pixels a sample region
 * reaches, filled with the same math as the kernels, merged into the film under its lock. */
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "film_internal.h"
#include "film_tile_add.h"

struct clr_film_tile_t {
  clr_film film; /* retained */
  clr_bounds2i bounds;
  float *sums; /* CLR_FILM_SUM_FLOATS per pixel of bounds, row-major */
  uint64_t accepted, dropped, outside;
  int merged;
};

clr_result film_get_tile(clr_film film, clr_bounds2i region, clr_film_tile *out) {
  if (!film || !out)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_get_tile: %s is NULL",
                    !film ? "film" : "out");
  *out = NULL;
  if (region.x0 >= region.x1 || region.y0 >= region.y1)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_PIXEL_RANGE,
                    "film_get_tile: sample region [%d,%d)x[%d,%d) is empty", region.x0, region.x1,
                    region.y0, region.y1);
  const clr_film_params *p = &film->params;
  const clr_filter_params *f = &film->filter;
  clr_bounds2i b;
  b.x0 = (int32_t)ceilf((float)region.x0 - 0.5f - f->radius_x);
  b.y0 = (int32_t)ceilf((float)region.y0 - 0.5f - f->radius_y);
  b.x1 = (int32_t)floorf((float)region.x1 - 0.5f + f->radius_x) + 1;
  b.y1 = (int32_t)floorf((float)region.y1 - 0.5f + f->radius_y) + 1;
  if (b.x0 < p->pixel_x0) b.x0 = p->pixel_x0;
  if (b.y0 < p->pixel_y0) b.y0 = p->pixel_y0;
  if (b.x1 > p->pixel_x1) b.x1 = p->pixel_x1;
  if (b.y1 > p->pixel_y1) b.y1 = p->pixel_y1;
  if (b.x1 < b.x0) b.x1 = b.x0;
  if (b.y1 < b.y0) b.y1 = b.y0;
  clr_film_tile tile = calloc(1, sizeof *tile);
  size_t n = (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0);
  if (tile) tile->sums = calloc(n ? n * CLR_FILM_SUM_FLOATS : 1, sizeof(float));
  if (!tile || !tile->sums) {
    free(tile);
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_get_tile: no memory for %zu pixels",
                    n);
  }
  film_retain(film);
  tile->film = film;
  tile->bounds = b;
  *out = tile;
  return CLR_SUCCESS;
}

clr_bounds2i film_tile_pixel_bounds(clr_film_tile tile) {
  clr_bounds2i none = {0, 0, 0, 0};
  return tile ? tile->bounds : none;
}

clr_result film_tile_add_samples(clr_film_tile tile, const clr_film_sample *samples, size_t count) {
  if (!tile || !samples)
    return clr_fail(tile ? tile->film->ctx : NULL, CLR_ERROR_NULL_POINTER,
                    "film_tile_add_samples: %s is NULL", !tile ? "tile" : "samples");
  clr_film film = tile->film;
  if (count == 0)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "film_tile_add_samples: count is 0");
  if (tile->merged)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_TILE,
                    "film_tile_add_samples: tile already merged");
  clr_tile_adder a;
  clr_tile_adder_init(&a, &film->params, &film->filter, film->factors);
  clr_tile_counts n = {0, 0, 0};
  clr_tile_add_samples(&a, samples, count, tile->bounds, tile->sums, &n);
  tile->accepted += n.accepted;
  tile->dropped += n.dropped;
  tile->outside += n.outside;
  return CLR_SUCCESS;
}

clr_result film_merge_tile(clr_film film, clr_film_tile tile) {
  if (!film || !tile)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "film_merge_tile: %s is NULL",
                    !film ? "film" : "tile");
  if (tile->film != film)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_TILE,
                    "film_merge_tile: the tile belongs to another film");
  if (tile->merged)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_TILE, "film_merge_tile: tile already merged");
  pthread_mutex_lock(&film->lock);
  if (tile->bounds.x1 > tile->bounds.x0 && tile->bounds.y1 > tile->bounds.y0)
    clr_film_add_block(film, tile->bounds, tile->sums, 1);
  film->accepted += tile->accepted;
  film->dropped += tile->dropped;
  film->outside += tile->outside;
  pthread_mutex_unlock(&film->lock);
  tile->merged = 1;
  return CLR_SUCCESS;
}

void film_tile_release(clr_film_tile tile) {
  if (!tile) return;
  film_release(tile->film);
  free(tile->sums);
  free(tile);
}

/* Serialized tile: magic, pixel bounds, counters, then the float sums (native byte order). */
typedef struct tile_header {
  uint32_t magic, reserved;
  int32_t bounds[4];
  uint64_t accepted, dropped, outside;
} tile_header;
#define TILE_MAGIC 0x544c5243u /* "CRLT" */

static size_t tile_pixels(clr_bounds2i b) { return (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0); }

size_t film_tile_serialized_size(clr_film_tile tile) {
  if (!tile) return 0;
  return sizeof(tile_header) + tile_pixels(tile->bounds) * CLR_FILM_SUM_FLOATS * sizeof(float);
}

clr_result film_tile_serialize(clr_film_tile tile, void *buf, size_t size) {
  if (!tile || !buf)
    return clr_fail(tile ? tile->film->ctx : NULL, CLR_ERROR_NULL_POINTER,
                    "film_tile_serialize: %s is NULL", !tile ? "tile" : "buf");
  size_t need = film_tile_serialized_size(tile);
  if (size < need)
    return clr_fail(tile->film->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_tile_serialize: size %zu, the tile needs %zu bytes", size, need);
  tile_header h = {TILE_MAGIC,
                   0,
                   {tile->bounds.x0, tile->bounds.y0, tile->bounds.x1, tile->bounds.y1},
                   tile->accepted,
                   tile->dropped,
                   tile->outside};
  memcpy(buf, &h, sizeof h);
  memcpy((char *)buf + sizeof h, tile->sums, need - sizeof h);
  return CLR_SUCCESS;
}

clr_result film_tile_deserialize(clr_film film, const void *buf, size_t size, clr_film_tile *out) {
  if (!film || !buf || !out)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER,
                    "film_tile_deserialize: %s is NULL",
                    !film  ? "film"
                    : !buf ? "buf"
                           : "out");
  *out = NULL;
  tile_header h;
  if (size < sizeof h)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_tile_deserialize: %zu bytes, shorter than a tile header", size);
  memcpy(&h, buf, sizeof h);
  const clr_film_params *p = &film->params;
  clr_bounds2i b = {h.bounds[0], h.bounds[1], h.bounds[2], h.bounds[3]};
  if (h.magic != TILE_MAGIC)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_TILE,
                    "film_tile_deserialize: not a serialized tile (magic 0x%08x, expected 0x%08x)",
                    h.magic, TILE_MAGIC);
  if (b.x0 < p->pixel_x0 || b.y0 < p->pixel_y0 || b.x1 > p->pixel_x1 || b.y1 > p->pixel_y1 ||
      b.x1 < b.x0 || b.y1 < b.y0)
    return clr_fail(
        film->ctx, CLR_ERROR_INVALID_TILE,
        "film_tile_deserialize: bounds [%d,%d)x[%d,%d) are inverted or outside the film's pixel "
        "bounds [%d,%d)x[%d,%d)",
        b.x0, b.x1, b.y0, b.y1, p->pixel_x0, p->pixel_x1, p->pixel_y0, p->pixel_y1);
  size_t floats = tile_pixels(b) * CLR_FILM_SUM_FLOATS;
  if (size != sizeof h + floats * sizeof(float))
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_tile_deserialize: %zu bytes, a [%d,%d)x[%d,%d) tile has %zu", size, b.x0,
                    b.x1, b.y0, b.y1, sizeof h + floats * sizeof(float));
  clr_film_tile tile = calloc(1, sizeof *tile);
  if (tile) tile->sums = malloc(floats ? floats * sizeof(float) : 1);
  if (!tile || !tile->sums) {
    free(tile);
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_tile_deserialize: %zu floats",
                    floats);
  }
  memcpy(tile->sums, (const char *)buf + sizeof h, floats * sizeof(float));
  film_retain(film);
  tile->film = film;
  tile->bounds = b;
  tile->accepted = h.accepted;
  tile->dropped = h.dropped;
  tile->outside = h.outside;
  *out = tile;
  return CLR_SUCCESS;
}
