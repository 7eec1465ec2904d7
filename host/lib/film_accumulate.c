/* film_add_samples: the host checks the samples and bins them to accumulation tiles (a sample
 * goes to every tile its filter reaches, batch order kept), the kernel sums each tile's pixels,
 * the host adds the read-back float sums into the film's double sums. Also the host reference. */
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "film_funcs.h"
#include "film_internal.h"

/* Tiles of the film that prepared sample s reaches: inclusive ranges; 0 when none. */
static int sample_tiles(const clr_film_params *p, const clr_film_prepared *s, int32_t *tx0,
                        int32_t *tx1, int32_t *ty0, int32_t *ty1) {
  int32_t x0 = s->x0 > p->pixel_x0 ? s->x0 : p->pixel_x0;
  int32_t x1 = s->x1 < p->pixel_x1 - 1 ? s->x1 : p->pixel_x1 - 1;
  int32_t y0 = s->y0 > p->pixel_y0 ? s->y0 : p->pixel_y0;
  int32_t y1 = s->y1 < p->pixel_y1 - 1 ? s->y1 : p->pixel_y1 - 1;
  if (x0 > x1 || y0 > y1) return 0;
  *tx0 = (x0 - p->pixel_x0) / p->tile_size;
  *tx1 = (x1 - p->pixel_x0) / p->tile_size;
  *ty0 = (y0 - p->pixel_y0) / p->tile_size;
  *ty1 = (y1 - p->pixel_y0) / p->tile_size;
  return 1;
}

static clr_i32 prepare_sample(clr_film film, const clr_film_sample *s, clr_film_prepared *out) {
  return clr_film_prepare(&film->params, &film->filter, s->x, s->y, s->r, s->g, s->b, s->weight,
                          out);
}

static void count_status(clr_film film, clr_i32 status) {
  if (status == CLR_FILM_SAMPLE_OK) ++film->accepted;
  else if (status == CLR_FILM_SAMPLE_DROPPED) ++film->dropped;
  else ++film->outside;
}

static int grow(void **ptr, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 1;
  size_t n = need + need / 2 + 16;
  void *p = realloc(*ptr, n * elem);
  if (!p) return 0;
  *ptr = p;
  *cap = n;
  return 1;
}

/* Makes room for `need` touched tiles (+1 for the final start) in the per-slot arrays. */
static int grow_slots(clr_film_bins *b, size_t need) {
  if (need + 1 <= b->tiles_cap) return 1;
  size_t n = 2 * (need + 1) + 16;
  uint32_t *tiles = realloc(b->tiles, n * sizeof *tiles);
  if (!tiles) return 0;
  b->tiles = tiles;
  uint32_t *starts = realloc(b->starts, n * sizeof *starts);
  if (!starts) return 0;
  b->starts = starts;
  uint32_t *cursor = realloc(b->cursor, n * sizeof *cursor);
  if (!cursor) return 0;
  b->cursor = cursor;
  b->tiles_cap = n;
  return 1;
}

/* Runs `body` with `tile` set to every film tile prepared sample s reaches (row-major). */
#define FOR_EACH_TILE(p, s, tile, body)                                              \
  do {                                                                               \
    int32_t tx0_, tx1_, ty0_, ty1_;                                                  \
    if (!sample_tiles((p), (s), &tx0_, &tx1_, &ty0_, &ty1_)) break;                  \
    for (int32_t ty_ = ty0_; ty_ <= ty1_; ++ty_)                                     \
      for (int32_t tx_ = tx0_; tx_ <= tx1_; ++tx_) {                                 \
        uint32_t tile = (uint32_t)ty_ * (uint32_t)(p)->tiles_x + (uint32_t)tx_;      \
        body                                                                         \
      }                                                                              \
  } while (0)

/* Fills film->bins for samples[0..count): the touched tiles and, per tile, the sample indices
 * (+ index_base) in batch order; counts the samples' outcomes. Caller holds the lock. */
static clr_result bin_samples(clr_film film, const clr_film_sample *samples, size_t count,
                              uint32_t index_base, size_t *touched_out) {
  const clr_film_params *p = &film->params;
  clr_film_bins *b = &film->bins;
  size_t ntiles = (size_t)p->tiles_x * (size_t)p->tiles_y;
  if (!b->tile_slot && !(b->tile_slot = calloc(ntiles, sizeof *b->tile_slot)))
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_add_samples: no memory for bins");
  size_t touched = 0, entries = 0;
  int ok = 1;
  for (size_t i = 0; i < count && ok; ++i) {
    clr_film_prepared s;
    clr_i32 status = prepare_sample(film, &samples[i], &s);
    count_status(film, status);
    if (status != CLR_FILM_SAMPLE_OK) continue;
    FOR_EACH_TILE(p, &s, tile, {
      if (b->tile_slot[tile] == 0) {
        if (!(ok = grow_slots(b, touched + 1))) break;
        b->tiles[touched] = tile;
        b->cursor[touched] = 0;
        b->tile_slot[tile] = (int32_t)++touched;
      }
      ++b->cursor[b->tile_slot[tile] - 1];
      ++entries;
    });
  }
  if (ok) ok = grow((void **)&b->order, &b->order_cap, entries ? entries : 1, sizeof *b->order);
  if (!ok) {
    for (size_t t = 0; t < touched; ++t) b->tile_slot[b->tiles[t]] = 0;
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY,
                    "film_add_samples: no memory to bin %zu samples", count);
  }
  uint32_t at = 0;
  for (size_t t = 0; t < touched; ++t) {
    b->starts[t] = at;
    at += b->cursor[t];
    b->cursor[t] = b->starts[t];
  }
  b->starts[touched] = at;
  for (size_t i = 0; i < count; ++i) {
    clr_film_prepared s;
    if (prepare_sample(film, &samples[i], &s) != CLR_FILM_SAMPLE_OK) continue;
    FOR_EACH_TILE(p, &s, tile, {
      b->order[b->cursor[b->tile_slot[tile] - 1]++] = index_base + (uint32_t)i;
    });
  }
  for (size_t t = 0; t < touched; ++t) b->tile_slot[b->tiles[t]] = 0;
  *touched_out = touched;
  return CLR_SUCCESS;
}

/* Device buffer of at least `bytes`, replaced when too small. */
static clr_result ensure_buffer(clr_film film, cl_mem *buf, size_t *have, size_t bytes,
                                cl_mem_flags flags, const char *what) {
  if (*buf && *have >= bytes) return CLR_SUCCESS;
  if (*buf) clReleaseMemObject(*buf);
  *buf = NULL;
  *have = 0;
  size_t size = bytes + bytes / 2 + 256;
  cl_int err = CL_SUCCESS;
  *buf = clCreateBuffer(clr_context_cl_context(film->ctx), flags, size, NULL, &err);
  if (err != CL_SUCCESS) {
    *buf = NULL;
    return clr_fail(film->ctx, CLR_ERROR_OPENCL, "film_add_samples: clCreateBuffer(%s, %zu bytes) "
                    "failed: %s (%d)", what, size, clr_cl_error_name(err), (int)err);
  }
  *have = size;
  return CLR_SUCCESS;
}

static clr_result ensure_kernel(clr_film film) {
  clr_film_device *d = &film->dev;
  if (d->kernel) return CLR_SUCCESS;
  cl_kernel k = NULL;
  CLR_CHECK(clr_context_kernel(film->ctx, "film_kernels.cl", NULL, "clr_film_accumulate_tiles", &k));
  cl_device_id dev = clr_context_cl_device(film->ctx);
  size_t kmax = 0, dmax = 0;
  cl_int err = clGetKernelWorkGroupInfo(k, dev, CL_KERNEL_WORK_GROUP_SIZE, sizeof kmax, &kmax, NULL);
  if (err == CL_SUCCESS)
    err = clGetDeviceInfo(dev, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof dmax, &dmax, NULL);
  if (err != CL_SUCCESS) {
    clReleaseKernel(k);
    return clr_fail(film->ctx, CLR_ERROR_OPENCL, "film: work-group size query failed: %s (%d)",
                    clr_cl_error_name(err), (int)err);
  }
  size_t g = (size_t)film->params.tile_size * (size_t)film->params.tile_size;
  if (g > CLR_FILM_GROUP_MAX) g = CLR_FILM_GROUP_MAX;
  if (g > kmax) g = kmax;
  if (g > dmax) g = dmax;
  if (!d->table) {
    size_t have = 0;
    clr_result r = ensure_buffer(film, &d->table, &have, sizeof film->table, CL_MEM_READ_ONLY,
                                 "filter table");
    if (r == CLR_SUCCESS) {
      err = clEnqueueWriteBuffer(clr_context_cl_queue(film->ctx), d->table, CL_TRUE, 0,
                                 sizeof film->table, film->table, 0, NULL, NULL);
      if (err != CL_SUCCESS)
        r = clr_fail(film->ctx, CLR_ERROR_OPENCL, "film: filter table upload failed: %s (%d)",
                     clr_cl_error_name(err), (int)err);
    }
    if (r != CLR_SUCCESS) {
      clReleaseKernel(k);
      return r;
    }
  }
  d->kernel = k;
  d->group_size = g ? g : 1;
  return CLR_SUCCESS;
}

/* Runs the kernel over the binned tiles of `samples` (device) and adds the sums to the film. */
static clr_result accumulate_binned(clr_film film, cl_mem samples, size_t touched) {
  clr_film_device *d = &film->dev;
  clr_film_bins *b = &film->bins;
  cl_command_queue q = clr_context_cl_queue(film->ctx);
  const clr_film_params *p = &film->params;
  size_t group = film->group_size_override ? film->group_size_override : d->group_size;
  size_t tile_floats = (size_t)p->tile_size * p->tile_size * CLR_FILM_SUM_FLOATS;
  size_t entries = b->starts[touched];
  CLR_CHECK(ensure_buffer(film, &d->tiles, &d->tiles_bytes, touched * 4, CL_MEM_READ_ONLY, "tiles"));
  CLR_CHECK(ensure_buffer(film, &d->starts, &d->starts_bytes, (touched + 1) * 4, CL_MEM_READ_ONLY,
                          "starts"));
  CLR_CHECK(ensure_buffer(film, &d->order, &d->order_bytes, (entries ? entries : 1) * 4,
                          CL_MEM_READ_ONLY, "order"));
  CLR_CHECK(ensure_buffer(film, &d->sums, &d->sums_bytes, touched * tile_floats * sizeof(float),
                          CL_MEM_WRITE_ONLY, "sums"));
  if (!grow((void **)&b->sums, &b->sums_cap, touched * tile_floats, sizeof(float)))
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_add_samples: no memory for sums");
  CLR_CL_CHECK(film->ctx, clEnqueueWriteBuffer(q, d->tiles, CL_FALSE, 0, touched * 4, b->tiles, 0,
                                               NULL, NULL));
  CLR_CL_CHECK(film->ctx, clEnqueueWriteBuffer(q, d->starts, CL_FALSE, 0, (touched + 1) * 4,
                                               b->starts, 0, NULL, NULL));
  if (entries)
    CLR_CL_CHECK(film->ctx, clEnqueueWriteBuffer(q, d->order, CL_FALSE, 0, entries * 4, b->order,
                                                 0, NULL, NULL));
  cl_kernel k = d->kernel;
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 0, sizeof film->params, &film->params));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 1, sizeof film->filter, &film->filter));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 2, sizeof(cl_mem), &d->table));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 3, sizeof(cl_mem), &samples));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 4, sizeof(cl_mem), &d->tiles));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 5, sizeof(cl_mem), &d->starts));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 6, sizeof(cl_mem), &d->order));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 7, sizeof(cl_mem), &d->sums));
  size_t global = touched * group;
  CLR_CL_CHECK(film->ctx, clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &group, 0, NULL, NULL));
  CLR_CL_CHECK(film->ctx, clEnqueueReadBuffer(q, d->sums, CL_TRUE, 0,
                                              touched * tile_floats * sizeof(float), b->sums, 0,
                                              NULL, NULL));
  for (size_t t = 0; t < touched; ++t) {
    clr_bounds2i block;
    block.x0 = p->pixel_x0 + (int32_t)(b->tiles[t] % (uint32_t)p->tiles_x) * p->tile_size;
    block.y0 = p->pixel_y0 + (int32_t)(b->tiles[t] / (uint32_t)p->tiles_x) * p->tile_size;
    block.x1 = block.x0 + p->tile_size;
    block.y1 = block.y0 + p->tile_size;
    clr_film_add_block(film, block, b->sums + t * tile_floats);
  }
  return CLR_SUCCESS;
}

/* One chunk: bins host copies `samples`; the kernel reads them from `device_samples`, where the
 * chunk starts at sample `index_base`, or from an upload of `samples` when it is NULL. */
static clr_result add_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                            cl_mem device_samples, uint32_t index_base) {
  size_t touched = 0;
  CLR_CHECK(bin_samples(film, samples, count, index_base, &touched));
  if (touched == 0) return CLR_SUCCESS;
  if (!device_samples) {
    clr_film_device *d = &film->dev;
    size_t bytes = count * sizeof *samples;
    CLR_CHECK(ensure_buffer(film, &d->samples, &d->samples_bytes, bytes, CL_MEM_READ_ONLY,
                            "samples"));
    CLR_CL_CHECK(film->ctx, clEnqueueWriteBuffer(clr_context_cl_queue(film->ctx), d->samples,
                                                 CL_FALSE, 0, bytes, samples, 0, NULL, NULL));
    device_samples = d->samples;
  }
  return accumulate_binned(film, device_samples, touched);
}

static clr_result check_add_args(clr_film film, const void *samples, size_t count,
                                 const char *fn) {
  if (!film || !samples)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "%s: %s is NULL", fn,
                    !film ? "film" : "samples");
  if (count == 0)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "%s: count is 0", fn);
  if (count > UINT32_MAX)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "%s: count %zu exceeds %u", fn, count,
                    UINT32_MAX);
  return CLR_SUCCESS;
}

clr_result film_add_samples(clr_film film, const clr_film_sample *samples, size_t count) {
  clr_clear_error();
  CLR_CHECK(check_add_args(film, samples, count, "film_add_samples"));
  pthread_mutex_lock(&film->lock);
  clr_result r = ensure_kernel(film);
  for (size_t at = 0; at < count && r == CLR_SUCCESS; at += CLR_FILM_CHUNK_SAMPLES) {
    size_t n = count - at < CLR_FILM_CHUNK_SAMPLES ? count - at : CLR_FILM_CHUNK_SAMPLES;
    r = add_chunk(film, samples + at, n, NULL, 0);
  }
  pthread_mutex_unlock(&film->lock);
  return r;
}

clr_result film_add_samples_buffer(clr_film film, cl_mem samples, size_t count) {
  clr_clear_error();
  CLR_CHECK(check_add_args(film, samples, count, "film_add_samples_buffer"));
  size_t size = 0;
  CLR_CL_CHECK(film->ctx, clGetMemObjectInfo(samples, CL_MEM_SIZE, sizeof size, &size, NULL));
  if (size / sizeof(clr_film_sample) < count)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_add_samples_buffer: buffer of %zu bytes holds fewer than %zu samples",
                    size, count);
  clr_film_sample *host = malloc(count * sizeof *host);
  if (!host)
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY,
                    "film_add_samples_buffer: no memory for %zu samples", count);
  pthread_mutex_lock(&film->lock);
  clr_result r = ensure_kernel(film);
  if (r == CLR_SUCCESS) {
    cl_int err = clEnqueueReadBuffer(clr_context_cl_queue(film->ctx), samples, CL_TRUE, 0,
                                     count * sizeof *host, host, 0, NULL, NULL);
    if (err != CL_SUCCESS)
      r = clr_fail(film->ctx, CLR_ERROR_OPENCL, "film_add_samples_buffer: clEnqueueReadBuffer "
                   "failed: %s (%d)", clr_cl_error_name(err), (int)err);
  }
  for (size_t at = 0; at < count && r == CLR_SUCCESS; at += CLR_FILM_CHUNK_SAMPLES) {
    size_t n = count - at < CLR_FILM_CHUNK_SAMPLES ? count - at : CLR_FILM_CHUNK_SAMPLES;
    r = add_chunk(film, host + at, n, samples, (uint32_t)at);
  }
  pthread_mutex_unlock(&film->lock);
  free(host);
  return r;
}

/* Host reference of one chunk: per-pixel float sums in batch order, then added like the device
 * path's tiles. */
static void reference_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                            float *sums) {
  const clr_film_params *p = &film->params;
  memset(sums, 0, film->pixel_count * CLR_FILM_SUM_FLOATS * sizeof *sums);
  for (size_t i = 0; i < count; ++i) {
    clr_film_prepared s;
    clr_i32 status = prepare_sample(film, &samples[i], &s);
    count_status(film, status);
    if (status != CLR_FILM_SAMPLE_OK) continue;
    int32_t x0 = s.x0 > p->pixel_x0 ? s.x0 : p->pixel_x0;
    int32_t x1 = s.x1 < p->pixel_x1 - 1 ? s.x1 : p->pixel_x1 - 1;
    int32_t y0 = s.y0 > p->pixel_y0 ? s.y0 : p->pixel_y0;
    int32_t y1 = s.y1 < p->pixel_y1 - 1 ? s.y1 : p->pixel_y1 - 1;
    for (int32_t y = y0; y <= y1; ++y)
      for (int32_t x = x0; x <= x1; ++x) {
        size_t pix = (size_t)(y - p->pixel_y0) * film->width + (size_t)(x - p->pixel_x0);
        clr_film_accumulate(&film->filter, film->table, &s, x, y, sums + pix * CLR_FILM_SUM_FLOATS);
      }
  }
  clr_bounds2i all = film_pixel_bounds(film);
  clr_film_add_block(film, all, sums);
}

clr_result film_add_samples_reference(clr_film film, const clr_film_sample *samples, size_t count) {
  clr_clear_error();
  CLR_CHECK(check_add_args(film, samples, count, "film_add_samples_reference"));
  float *sums = malloc(film->pixel_count * CLR_FILM_SUM_FLOATS * sizeof *sums);
  if (!sums)
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_add_samples_reference: no memory");
  pthread_mutex_lock(&film->lock);
  for (size_t at = 0; at < count; at += CLR_FILM_CHUNK_SAMPLES) {
    size_t n = count - at < CLR_FILM_CHUNK_SAMPLES ? count - at : CLR_FILM_CHUNK_SAMPLES;
    reference_chunk(film, samples + at, n, sums);
  }
  pthread_mutex_unlock(&film->lock);
  free(sums);
  return CLR_SUCCESS;
}

clr_result film_set_group_size(clr_film film, size_t group_size) {
  if (!film) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "film_set_group_size: film is NULL");
  if (group_size > CLR_FILM_GROUP_MAX)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "film_set_group_size: %zu > %d",
                    group_size, CLR_FILM_GROUP_MAX);
  pthread_mutex_lock(&film->lock);
  film->group_size_override = group_size;
  pthread_mutex_unlock(&film->lock);
  return CLR_SUCCESS;
}

void clr_film_accumulate_release(clr_film film) {
  clr_film_device *d = &film->dev;
  cl_mem *bufs[] = {&d->table, &d->samples, &d->tiles, &d->starts, &d->order, &d->sums};
  for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; ++i)
    if (*bufs[i]) clReleaseMemObject(*bufs[i]);
  if (d->kernel) clReleaseKernel(d->kernel);
  clr_film_bins *b = &film->bins;
  free(b->tile_slot);
  free(b->tiles);
  free(b->starts);
  free(b->cursor);
  free(b->order);
  free(b->sums);
}
