/* OpenEXR reading and writing through OpenEXRCore: scanline chunks, ZIP, float32/half planes. */
#include "exr_io.h"

#include <openexr.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "atomic_file.h"
#include "clr_internal.h"
#include "exr_zip.h"
#include "clrender/film.h"
#include "input_file.h"

/* ---- half precision ---------------------------------------------------------------------- */

uint16_t clr_float_to_half(float f) {
  uint32_t x;
  memcpy(&x, &f, sizeof x);
  uint32_t sign = (x >> 16) & 0x8000u;
  uint32_t abs = x & 0x7fffffffu;
  if (abs > 0x7f800000u) return (uint16_t)(sign | 0x7e00u | ((abs >> 13) & 0x3ffu)); /* NaN */
  if (abs >= 0x477ff000u) return (uint16_t)(sign | 0x7c00u); /* >= 65520 (and inf) -> inf */
  if (abs < 0x33000000u) return (uint16_t)sign;              /* <= 2^-25 exactly -> zero */
  uint32_t exponent = abs >> 23, result, rest, halfway;
  if (abs < 0x38800000u) { /* half subnormal: units of 2^-24 */
    uint32_t mantissa = (abs & 0x7fffffu) | 0x800000u, shift = 126u - exponent;
    result = mantissa >> shift;
    rest = mantissa & ((1u << shift) - 1u);
    halfway = 1u << (shift - 1u);
  } else {
    result = ((exponent - 112u) << 10) | ((abs >> 13) & 0x3ffu);
    rest = abs & 0x1fffu;
    halfway = 0x1000u;
  }
  if (rest > halfway || (rest == halfway && (result & 1u))) ++result; /* carries are exact */
  return (uint16_t)(sign | result);
}

float clr_half_to_float(uint16_t h) {
  uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
  uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu, bits;
  if (exponent == 0) {
    float magnitude = (float)mantissa * 5.9604644775390625e-8f; /* exact: mantissa * 2^-24 */
    return sign ? -magnitude : magnitude;
  }
  if (exponent == 31)
    bits = sign | 0x7f800000u | (mantissa << 13);
  else
    bits = sign | ((exponent + 112u) << 23) | (mantissa << 13);
  float f;
  memcpy(&f, &bits, sizeof f);
  return f;
}

/* ---- error reporting --------------------------------------------------------------------- */

/* OpenEXR's detailed message for the call in progress on this thread (its error handler). */
static _Thread_local char exr_detail[512];

static void capture_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  (void)ctxt;
  (void)code;
  snprintf(exr_detail, sizeof exr_detail, "%s", msg ? msg : "");
}

typedef struct exr_job {
  const char *path;
  int reading;
  clr_result result;  /* first failure */
  uint64_t file_size; /* reading: the file's size, bounds what its header may claim */
} exr_job;

static clr_result map_exr_error(exr_result_t rv, int reading) {
  if (rv == EXR_ERR_OUT_OF_MEMORY) return CLR_ERROR_OUT_OF_MEMORY;
  if (rv == EXR_ERR_FILE_ACCESS || rv == EXR_ERR_WRITE_IO) return CLR_ERROR_IO;
  return reading ? CLR_ERROR_FILE_FORMAT : CLR_ERROR_OPENEXR;
}

/* Returns 1 on success; otherwise records the first failure, naming call, file and error. */
static int exr_check(exr_job *job, exr_result_t rv, const char *call) {
  if (rv == EXR_ERR_SUCCESS) return 1;
  if (job->result == CLR_SUCCESS)
    job->result =
        clr_fail(NULL, map_exr_error(rv, job->reading), "%s failed for '%s': %s (%s)", call,
                 job->path, exr_detail[0] ? exr_detail : exr_get_default_error_message(rv),
                 exr_get_error_code_as_string(rv));
  return 0;
}

/* Calls OpenEXR function `fn` with fresh detail text and checks it. */
#define EXR_TRY(job, fn, ...) exr_check((job), (exr_detail[0] = 0, fn(__VA_ARGS__)), #fn)

static int job_fail(exr_job *job, clr_result code, const char *what) {
  if (job->result == CLR_SUCCESS) job->result = clr_fail(NULL, code, "'%s': %s", job->path, what);
  return 0;
}

/* ---- writing ----------------------------------------------------------------------------- */

static clr_result validate_write(const char *path, int32_t display_width, int32_t display_height,
                                 clr_bounds2i dw, const clr_exr_channel *channels,
                                 int32_t channel_count, int computed,
                                 const clr_exr_attribute *attrs, int32_t attr_count) {
  if (!path) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_exr_write: path is NULL");
  if (display_width <= 0 || display_height <= 0)
    return clr_fail(NULL, CLR_ERROR_INVALID_RESOLUTION,
                    "clr_exr_write '%s': display size %dx%d must be positive", path,
                    (int)display_width, (int)display_height);
  if (dw.x0 < 0 || dw.y0 < 0 || dw.x1 > display_width || dw.y1 > display_height || dw.x0 >= dw.x1 ||
      dw.y0 >= dw.y1)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "clr_exr_write '%s': data window [%d,%d)x[%d,%d) is empty or outside the "
                    "display window [0,%d)x[0,%d)",
                    path, (int)dw.x0, (int)dw.x1, (int)dw.y0, (int)dw.y1, (int)display_width,
                    (int)display_height);
  if (channel_count <= 0 || !channels)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "clr_exr_write '%s': channel_count %d needs at least one channel", path,
                    (int)channel_count);
  for (int32_t c = 0; c < channel_count; ++c) {
    if (!channels[c].name || !channels[c].name[0] || (!computed && !channels[c].data))
      return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                      "clr_exr_write '%s': channel %d has no name or no data", path, (int)c);
    for (int32_t d = 0; d < c; ++d)
      if (strcmp(channels[c].name, channels[d].name) == 0)
        return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                        "clr_exr_write '%s': channel name '%s' appears twice", path,
                        channels[c].name);
  }
  if (attr_count < 0 || (attr_count > 0 && !attrs))
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "clr_exr_write '%s': attr_count %d without attributes", path, (int)attr_count);
  for (int32_t a = 0; a < attr_count; ++a) {
    const clr_exr_attribute *at = &attrs[a];
    if (!at->name || !at->name[0] || at->kind < CLR_EXR_ATTR_STRING ||
        at->kind > CLR_EXR_ATTR_INT || (at->kind == CLR_EXR_ATTR_STRING && !at->s))
      return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                      "clr_exr_write '%s': attribute %d ('%s', kind %d) is incomplete", path,
                      (int)a, at->name ? at->name : "(null)", (int)at->kind);
  }
  return CLR_SUCCESS;
}

static int64_t write_to_atomic_file(exr_const_context_t ctxt, void *user, const void *buffer,
                                    uint64_t size, uint64_t offset,
                                    exr_stream_error_func_ptr_t error_cb) {
  if (clr_atomic_file_pwrite(user, buffer, size, offset) != CLR_SUCCESS) {
    error_cb(ctxt, EXR_ERR_WRITE_IO, "%s", clr_last_error_message());
    return -1;
  }
  return (int64_t)size;
}

/* What the chunks are packed from: the file-typed plane of each of the caller's channels, and
 * the caller's channel of each of the file's (sorted) channels. */
typedef struct exr_planes {
  const clr_exr_channel *channels;
  int32_t count;
  const void **data; /* float or half plane per channel */
  int32_t width;
  int32_t y0, y1;
  int32_t *file_order;  /* count entries, filled once the header is defined */
  int32_t chunk_lines;  /* scanlines of a whole chunk (the last may hold fewer) */
  clr_exr_rows_fn rows; /* when set, computes each chunk's rows instead of `data` */
  void *rows_user;
} exr_planes;

/* zlib level of the ZIP chunks: the float sums barely compress past level 1, which costs a
 * quarter of the default level's time (profile of a 1-spp render's output). */
#define CLR_EXR_ZIP_LEVEL 1

static int define_header(exr_job *job, exr_context_t ctxt, int32_t display_width,
                         int32_t display_height, clr_bounds2i dw, const clr_exr_channel *channels,
                         int32_t channel_count, const clr_exr_attribute *attrs,
                         int32_t attr_count) {
  int part = 0;
  exr_attr_box2i_t display = {{{{0, 0}}}, {{{display_width - 1, display_height - 1}}}};
  exr_attr_box2i_t data = {{{{dw.x0, dw.y0}}}, {{{dw.x1 - 1, dw.y1 - 1}}}};
  exr_attr_v2f_t center = {{{0.f, 0.f}}};
  if (!EXR_TRY(job, exr_add_part, ctxt, NULL, EXR_STORAGE_SCANLINE, &part) ||
      !EXR_TRY(job, exr_initialize_required_attr, ctxt, part, &display, &data, 1.f, &center, 1.f,
               EXR_LINEORDER_INCREASING_Y, EXR_COMPRESSION_ZIP) ||
      !EXR_TRY(job, exr_set_zip_compression_level, ctxt, part, CLR_EXR_ZIP_LEVEL))
    return 0;
  for (int32_t c = 0; c < channel_count; ++c)
    if (!EXR_TRY(job, exr_add_channel, ctxt, part, channels[c].name,
                 channels[c].half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC,
                 1, 1))
      return 0;
  for (int32_t a = 0; a < attr_count; ++a) {
    const clr_exr_attribute *at = &attrs[a];
    int ok;
    if (at->kind == CLR_EXR_ATTR_STRING)
      ok = EXR_TRY(job, exr_attr_set_string, ctxt, part, at->name, at->s);
    else if (at->kind == CLR_EXR_ATTR_FLOAT)
      ok = EXR_TRY(job, exr_attr_set_float, ctxt, part, at->name, at->f);
    else
      ok = EXR_TRY(job, exr_attr_set_int, ctxt, part, at->name, at->i);
    if (!ok) return 0;
  }
  return EXR_TRY(job, exr_write_header, ctxt);
}

static int host_is_little_endian(void) {
  const uint16_t one = 1;
  uint8_t first;
  memcpy(&first, &one, 1);
  return first == 1;
}

/* Maps each of the file's channels (OpenEXR sorts them by name) to the caller's channel. */
static int find_file_order(exr_job *job, exr_context_t ctxt, exr_planes *p) {
  const exr_attr_chlist_t *list = NULL;
  if (!EXR_TRY(job, exr_get_channels, ctxt, 0, &list)) return 0;
  if (!list || list->num_channels != p->count)
    return job_fail(job, CLR_ERROR_INTERNAL, "the header's channel list does not match");
  for (int32_t c = 0; c < p->count; ++c) {
    int32_t k = 0;
    while (k < p->count && strcmp(p->channels[k].name, list->entries[c].name.str) != 0) ++k;
    if (k == p->count) return job_fail(job, CLR_ERROR_INTERNAL, "header channel not found");
    p->file_order[c] = k;
  }
  return 1;
}

/* Lays out `lines` lines as an EXR scanline chunk: per line, each file channel's row of
 * little-endian values; src[k] points at the chunk's first row of the caller's channel k. */
static void pack_chunk(const exr_planes *p, const uint8_t *const *src, int32_t lines,
                       uint8_t *out) {
  int swap = !host_is_little_endian();
  for (int32_t line = 0; line < lines; ++line) {
    for (int32_t c = 0; c < p->count; ++c) {
      int32_t k = p->file_order[c];
      size_t element = p->channels[k].half ? 2 : 4, bytes = element * (size_t)p->width;
      memcpy(out, src[k] + (size_t)line * bytes, bytes);
      for (size_t i = 0; swap && i < bytes; i += element)
        for (size_t lo = i, hi = i + element - 1; lo < hi; ++lo, --hi) {
          uint8_t t = out[lo];
          out[lo] = out[hi];
          out[hi] = t;
        }
      out += bytes;
    }
  }
}

/* One chunk, compressed ahead and written in file order. */
typedef struct exr_chunk_out {
  int32_t y, lines;
  uint8_t *data;
  size_t size;
  int ready; /* 0: not compressed (yet, or its coder ran out of memory) */
} exr_chunk_out;

/* A thread's packing and compression buffers, sized for a whole chunk. */
typedef struct chunk_coder {
  uint8_t *packed, *scratch;
  const uint8_t **src; /* per caller channel: the chunk's first row */
  float *rows;         /* computed rows (planes->rows): a whole chunk of every channel */
  uint16_t *halves;    /* the half channels' rows, converted */
  clr_exr_zip_stream *zip;
} chunk_coder;

static size_t chunk_bytes(const exr_planes *p, int32_t lines) {
  size_t line = 0;
  for (int32_t c = 0; c < p->count; ++c) line += (p->channels[c].half ? 2u : 4u) * (size_t)p->width;
  return line * (size_t)lines;
}

/* Points coder->src at chunk `out`'s rows: in the caller's planes, or computed by planes->rows
 * into the coder's buffers (half channels converted). Returns 0 when out of memory. */
static int chunk_sources(const exr_planes *p, chunk_coder *coder, const exr_chunk_out *out) {
  size_t row = (size_t)p->width, plane = row * (size_t)p->chunk_lines;
  if (!coder->src) coder->src = malloc((size_t)p->count * sizeof *coder->src);
  if (!coder->src) return 0;
  if (!p->rows) {
    for (int32_t k = 0; k < p->count; ++k)
      coder->src[k] = (const uint8_t *)p->data[k] +
                      (size_t)(out->y - p->y0) * row * (p->channels[k].half ? 2u : 4u);
    return 1;
  }
  if (!coder->rows) coder->rows = malloc((size_t)p->count * plane * sizeof *coder->rows);
  if (!coder->halves) coder->halves = malloc((size_t)p->count * plane * sizeof *coder->halves);
  float **rows = malloc((size_t)p->count * sizeof *rows);
  if (!coder->rows || !coder->halves || !rows) {
    free(rows);
    return 0;
  }
  for (int32_t k = 0; k < p->count; ++k) rows[k] = coder->rows + (size_t)k * plane;
  p->rows(p->rows_user, out->y, out->lines, rows);
  for (int32_t k = 0; k < p->count; ++k) {
    coder->src[k] = (const uint8_t *)rows[k];
    if (!p->channels[k].half) continue;
    uint16_t *h = coder->halves + (size_t)k * plane;
    for (size_t i = 0; i < row * (size_t)out->lines; ++i) h[i] = clr_float_to_half(rows[k][i]);
    coder->src[k] = (const uint8_t *)h;
  }
  free(rows);
  return 1;
}

/* Packs and compresses chunk `out` (ready on success; 0 if memory or zlib failed). */
static int compress_chunk(const exr_planes *p, chunk_coder *coder, exr_chunk_out *out) {
  size_t bytes = chunk_bytes(p, out->lines), whole = chunk_bytes(p, p->chunk_lines);
  if (!coder->packed) coder->packed = malloc(whole);
  if (!coder->scratch) coder->scratch = malloc(whole);
  out->data = malloc(clr_exr_zip_bound(bytes));
  if (!coder->packed || !coder->scratch || !out->data || !chunk_sources(p, coder, out)) return 0;
  pack_chunk(p, coder->src, out->lines, coder->packed);
  out->ready = clr_exr_zip_compress(&coder->zip, coder->packed, bytes, CLR_EXR_ZIP_LEVEL,
                                    coder->scratch, out->data, &out->size);
  return out->ready;
}

static void free_coder(chunk_coder *coder) {
  free(coder->packed);
  free(coder->scratch);
  free(coder->src);
  free(coder->rows);
  free(coder->halves);
  clr_exr_zip_stream_free(coder->zip);
}

typedef struct exr_encoders {
  const exr_planes *planes;
  exr_chunk_out *chunks;
  int count, first, step;
} exr_encoders;

/* A helper thread: compresses chunks first, first + step, ...; the caller compresses any it
 * could not. */
static void *encode_chunks_main(void *arg) {
  exr_encoders *e = arg;
  chunk_coder coder = {NULL, NULL, NULL, NULL, NULL, NULL};
  for (int i = e->first; i < e->count; i += e->step)
    if (!compress_chunk(e->planes, &coder, &e->chunks[i])) break;
  free_coder(&coder);
  return NULL;
}

/* Threads compressing an image's chunks besides the caller: zlib is most of the output's time. */
#define CLR_EXR_ENCODE_THREADS 4

static int encode_helpers(int chunks) {
  long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  int n = cpus > 1 ? (int)cpus - 1 : 0;
  if (n > CLR_EXR_ENCODE_THREADS - 1) n = CLR_EXR_ENCODE_THREADS - 1;
  if (n > chunks / 4) n = chunks / 4; /* small images: not worth a thread */
  return n;
}

/* Compresses the chunks (the helpers' share on their threads, the rest here) and writes them in
 * file order. */
static int write_chunks(exr_job *job, exr_context_t ctxt, exr_planes *planes) {
  int32_t lines = 0;
  if (!EXR_TRY(job, exr_get_scanlines_per_chunk, ctxt, 0, &lines)) return 0;
  if (lines <= 0) return job_fail(job, CLR_ERROR_OPENEXR, "bad scanlines per chunk");
  planes->chunk_lines = lines;
  int count = (int)(((int64_t)planes->y1 - planes->y0 + lines - 1) / lines), ok = 1;
  exr_chunk_out *chunks = calloc((size_t)count, sizeof *chunks);
  if (!chunks) return job_fail(job, CLR_ERROR_OUT_OF_MEMORY, "no memory for the chunk table");
  for (int i = 0; i < count; ++i) {
    chunks[i].y = planes->y0 + i * lines;
    chunks[i].lines = planes->y1 - chunks[i].y < lines ? planes->y1 - chunks[i].y : lines;
  }
  int helpers = encode_helpers(count), running = 0;
  pthread_t threads[CLR_EXR_ENCODE_THREADS];
  exr_encoders work[CLR_EXR_ENCODE_THREADS];
  for (int t = 0; t < helpers; ++t) {
    work[t] = (exr_encoders){planes, chunks, count, t + 1, helpers + 1};
    if (pthread_create(&threads[running], NULL, encode_chunks_main, &work[t]) != 0) break;
    ++running;
  }
  if (running < helpers) { /* a thread failed to start: its chunks are compressed below */
    for (int t = 0; t < running; ++t) pthread_join(threads[t], NULL);
    running = 0;
  }
  chunk_coder coder = {NULL, NULL, NULL, NULL, NULL, NULL};
  for (int i = 0; running && i < count; i += running + 1) /* the caller's share */
    compress_chunk(planes, &coder, &chunks[i]);
  for (int t = 0; t < running; ++t) pthread_join(threads[t], NULL);
  for (int i = 0; ok && i < count; ++i) {
    if (!chunks[i].ready) {
      free(chunks[i].data);
      chunks[i].data = NULL;
      if (!compress_chunk(planes, &coder, &chunks[i]))
        ok = job_fail(job, CLR_ERROR_OUT_OF_MEMORY, "no memory to compress a chunk");
    }
    if (ok)
      ok = EXR_TRY(job, exr_write_scanline_chunk, ctxt, 0, chunks[i].y, chunks[i].data,
                   chunks[i].size);
  }
  free_coder(&coder);
  for (int i = 0; i < count; ++i) free(chunks[i].data);
  free(chunks);
  return ok;
}

/* Writes the whole EXR stream into the open temporary file. */
static clr_result write_exr_stream(const char *path, clr_atomic_file *file, int32_t display_width,
                                   int32_t display_height, clr_bounds2i dw, exr_planes *planes,
                                   const clr_exr_attribute *attrs, int32_t attr_count) {
  exr_job job = {path, 0, CLR_SUCCESS, 0};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = capture_exr_error;
  init.user_data = file;
  init.write_fn = write_to_atomic_file;
  exr_context_t ctxt = NULL;
  if (EXR_TRY(&job, exr_start_write, &ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init) &&
      define_header(&job, ctxt, display_width, display_height, dw, planes->channels, planes->count,
                    attrs, attr_count) &&
      find_file_order(&job, ctxt, planes))
    write_chunks(&job, ctxt, planes);
  if (ctxt) EXR_TRY(&job, exr_finish, &ctxt); /* writes the chunk offset table */
  return job.result;
}

/* clr_exr_write, or clr_exr_write_rows when `rows` is set. */
static clr_result write_exr(const char *path, int32_t display_width, int32_t display_height,
                            clr_bounds2i data_window, const clr_exr_channel *channels,
                            int32_t channel_count, clr_exr_rows_fn rows, void *rows_user,
                            const clr_exr_attribute *attrs, int32_t attr_count) {
  CLR_CHECK(validate_write(path, display_width, display_height, data_window, channels,
                           channel_count, rows != NULL, attrs, attr_count));
  int32_t width = data_window.x1 - data_window.x0;
  size_t pixels = (size_t)width * (size_t)(data_window.y1 - data_window.y0);
  const void **data = calloc((size_t)channel_count, sizeof *data);
  uint16_t **halves = calloc((size_t)channel_count, sizeof *halves);
  int32_t *file_order = calloc((size_t)channel_count, sizeof *file_order);
  clr_result result = CLR_SUCCESS;
  if (!data || !halves || !file_order)
    result = clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "clr_exr_write '%s': out of memory", path);
  for (int32_t c = 0; result == CLR_SUCCESS && !rows && c < channel_count; ++c) {
    data[c] = channels[c].data;
    if (!channels[c].half) continue;
    halves[c] = malloc(pixels * sizeof(uint16_t));
    if (!halves[c]) {
      result = clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "clr_exr_write '%s': out of memory", path);
      break;
    }
    for (size_t i = 0; i < pixels; ++i) halves[c][i] = clr_float_to_half(channels[c].data[i]);
    data[c] = halves[c];
  }
  clr_atomic_file file;
  if (result == CLR_SUCCESS) result = clr_atomic_file_open(&file, path);
  if (result == CLR_SUCCESS) {
    exr_planes planes = {channels,       channel_count, data, width, data_window.y0,
                         data_window.y1, file_order,    0,    rows,  rows_user};
    result = write_exr_stream(path, &file, display_width, display_height, data_window, &planes,
                              attrs, attr_count);
    if (result == CLR_SUCCESS)
      result = clr_atomic_file_commit(&file);
    else
      clr_atomic_file_abort(&file);
  }
  for (int32_t c = 0; halves && c < channel_count; ++c) free(halves[c]);
  free(halves);
  free(data);
  free(file_order);
  return result;
}

clr_result clr_exr_write(const char *path, int32_t display_width, int32_t display_height,
                         clr_bounds2i data_window, const clr_exr_channel *channels,
                         int32_t channel_count, const clr_exr_attribute *attrs,
                         int32_t attr_count) {
  return write_exr(path, display_width, display_height, data_window, channels, channel_count, NULL,
                   NULL, attrs, attr_count);
}

clr_result clr_exr_write_rows(const char *path, int32_t display_width, int32_t display_height,
                              clr_bounds2i data_window, const clr_exr_channel *channels,
                              int32_t channel_count, clr_exr_rows_fn rows, void *rows_user,
                              const clr_exr_attribute *attrs, int32_t attr_count) {
  if (!rows) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_exr_write_rows: rows is NULL");
  return write_exr(path, display_width, display_height, data_window, channels, channel_count, rows,
                   rows_user, attrs, attr_count);
}

/* ---- reading ----------------------------------------------------------------------------- */

static char *copy_string(const char *s, size_t n) {
  char *copy = malloc(n + 1);
  if (!copy) return NULL;
  memcpy(copy, s, n);
  copy[n] = 0;
  return copy;
}

void clr_exr_image_free(clr_exr_image *image) {
  if (!image) return;
  for (int32_t c = 0; c < image->channel_count; ++c) {
    if (image->channel_names) free(image->channel_names[c]);
    if (image->channels) free(image->channels[c]);
  }
  free(image->channel_names);
  free(image->channel_types);
  free(image->channels);
  for (int32_t a = 0; a < image->attr_count; ++a) {
    free((char *)image->attrs[a].name);
    free((char *)image->attrs[a].s);
  }
  free(image->attrs);
  free(image);
}

/* Checks the part is a plain scanline image and fills the image's windows. */
static int read_layout(exr_job *job, exr_context_t ctxt, clr_exr_image *image) {
  int parts = 0;
  exr_storage_t storage;
  exr_attr_box2i_t display, data;
  if (!EXR_TRY(job, exr_get_count, ctxt, &parts) ||
      !EXR_TRY(job, exr_get_storage, ctxt, 0, &storage) ||
      !EXR_TRY(job, exr_get_display_window, ctxt, 0, &display) ||
      !EXR_TRY(job, exr_get_data_window, ctxt, 0, &data))
    return 0;
  if (storage != EXR_STORAGE_SCANLINE)
    return job_fail(job, CLR_ERROR_FILE_FORMAT,
                    "only scanline EXR images are supported (tiled "
                    "or deep storage found)");
  int64_t w = (int64_t)data.max.x - data.min.x + 1, h = (int64_t)data.max.y - data.min.y + 1;
  int64_t dwid = (int64_t)display.max.x - display.min.x + 1;
  int64_t dhgt = (int64_t)display.max.y - display.min.y + 1;
  if (w <= 0 || h <= 0 || w > INT32_MAX || h > INT32_MAX || dwid <= 0 || dhgt <= 0 ||
      dwid > INT32_MAX || dhgt > INT32_MAX || data.max.x == INT32_MAX || data.max.y == INT32_MAX ||
      display.max.x == INT32_MAX || display.max.y == INT32_MAX)
    return job_fail(job, CLR_ERROR_FILE_FORMAT, "invalid data or display window");
  image->display_window =
      (clr_bounds2i){display.min.x, display.min.y, display.max.x + 1, display.max.y + 1};
  image->display_width = (int32_t)dwid;
  image->display_height = (int32_t)dhgt;
  image->data_window = (clr_bounds2i){data.min.x, data.min.y, data.max.x + 1, data.max.y + 1};
  image->width = (int32_t)w;
  image->height = (int32_t)h;
  if (w * h > CLR_FILM_MAX_PIXELS) {
    char what[160];
    snprintf(what, sizeof what, "corrupt EXR: data window %lldx%lld exceeds the limit of %d pixels",
             (long long)w, (long long)h, (int)CLR_FILM_MAX_PIXELS);
    return job_fail(job, CLR_ERROR_FILE_FORMAT, what);
  }
  return 1;
}

/* Largest ratio of decoded to stored bytes each compression can reach (generous bounds: zlib's
 * is ~1032, RLE's 64): a header claiming more pixels than the file could hold is corrupt. */
static uint64_t max_expansion(exr_compression_t c) {
  switch (c) {
    case EXR_COMPRESSION_NONE:
      return 1;
    case EXR_COMPRESSION_RLE:
      return 128;
    case EXR_COMPRESSION_ZIPS:
    case EXR_COMPRESSION_ZIP:
      return 4096;
    default:
      return (uint64_t)1 << 16;
  }
}

/* Checks the header's sizes against the file: one 8-byte offset per chunk must fit, and the
 * decoded pixels cannot exceed what the compression could expand the file to. */
static int check_sizes(exr_job *job, exr_context_t ctxt, const clr_exr_image *image) {
  const exr_attr_chlist_t *list = NULL;
  int32_t lines = 0;
  exr_compression_t compression = EXR_COMPRESSION_NONE;
  if (!EXR_TRY(job, exr_get_channels, ctxt, 0, &list) ||
      !EXR_TRY(job, exr_get_scanlines_per_chunk, ctxt, 0, &lines) ||
      !EXR_TRY(job, exr_get_compression, ctxt, 0, &compression))
    return 0;
  if (lines <= 0)
    return job_fail(job, CLR_ERROR_FILE_FORMAT, "corrupt EXR: bad scanlines per chunk");
  uint64_t chunks = ((uint64_t)image->height + (uint64_t)lines - 1) / (uint64_t)lines;
  uint64_t channels = list && list->num_channels > 0 ? (uint64_t)list->num_channels : 1;
  uint64_t decoded = (uint64_t)image->width * (uint64_t)image->height * channels * 2;
  char what[256];
  if (chunks * 8 > job->file_size || decoded / max_expansion(compression) > job->file_size) {
    snprintf(what, sizeof what,
             "corrupt EXR: the header declares %dx%d pixels x %llu channels, more than the "
             "file's %llu bytes can hold",
             (int)image->width, (int)image->height, (unsigned long long)channels,
             (unsigned long long)job->file_size);
    return job_fail(job, CLR_ERROR_FILE_FORMAT, what);
  }
  return 1;
}

/* Allocates one float plane per channel (plus a half staging plane for half channels). */
static int allocate_channels(exr_job *job, exr_context_t ctxt, clr_exr_image *image,
                             uint16_t ***halves) {
  const exr_attr_chlist_t *list = NULL;
  if (!EXR_TRY(job, exr_get_channels, ctxt, 0, &list)) return 0;
  if (!list || list->num_channels <= 0)
    return job_fail(job, CLR_ERROR_FILE_FORMAT, "the image has no channels");
  size_t n = (size_t)list->num_channels, pixels = (size_t)image->width * (size_t)image->height;
  if (pixels > SIZE_MAX / sizeof(float) / n)
    return job_fail(job, CLR_ERROR_FILE_FORMAT, "the image is too large");
  image->channel_names = calloc(n, sizeof(char *));
  image->channel_types = calloc(n, sizeof(int32_t));
  image->channels = calloc(n, sizeof(float *));
  *halves = calloc(n, sizeof(uint16_t *));
  if (!image->channel_names || !image->channel_types || !image->channels || !*halves)
    return job_fail(job, CLR_ERROR_OUT_OF_MEMORY, "out of memory");
  image->channel_count = (int32_t)n;
  for (size_t c = 0; c < n; ++c) {
    const exr_attr_chlist_entry_t *e = &list->entries[c];
    if (e->x_sampling != 1 || e->y_sampling != 1)
      return job_fail(job, CLR_ERROR_FILE_FORMAT, "subsampled channels are not supported");
    image->channel_names[c] = copy_string(e->name.str, (size_t)e->name.length);
    image->channel_types[c] = (int32_t)e->pixel_type;
    image->channels[c] = malloc(pixels * sizeof(float));
    if (e->pixel_type == EXR_PIXEL_HALF) (*halves)[c] = malloc(pixels * sizeof(uint16_t));
    if (!image->channel_names[c] || !image->channels[c] ||
        (e->pixel_type == EXR_PIXEL_HALF && !(*halves)[c]))
      return job_fail(job, CLR_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  return 1;
}

/* Decodes each channel in its stored type: half into the staging plane, float and uint into the
 * float plane (uint is converted in place afterwards). */
static int point_decoder_at_chunk(exr_job *job, exr_decode_pipeline_t *dec,
                                  const clr_exr_image *image, uint16_t **halves) {
  for (int c = 0; c < dec->channel_count; ++c) {
    exr_coding_channel_info_t *ch = &dec->channels[c];
    int32_t k = 0;
    while (k < image->channel_count && strcmp(image->channel_names[k], ch->channel_name) != 0) ++k;
    if (k == image->channel_count)
      return job_fail(job, CLR_ERROR_INTERNAL, "decoder channel not found");
    int32_t bytes = ch->bytes_per_element;
    size_t row = (size_t)(dec->chunk.start_y - image->data_window.y0) * (size_t)image->width;
    uint8_t *plane = halves[k] ? (uint8_t *)halves[k] : (uint8_t *)image->channels[k];
    ch->user_bytes_per_element = (int16_t)bytes;
    ch->user_data_type = ch->data_type;
    ch->user_pixel_stride = bytes;
    ch->user_line_stride = bytes * image->width;
    ch->decode_to_ptr = plane + row * (size_t)bytes;
  }
  return 1;
}

static int read_chunks(exr_job *job, exr_context_t ctxt, clr_exr_image *image, uint16_t **halves) {
  int32_t lines = 0;
  if (!EXR_TRY(job, exr_get_scanlines_per_chunk, ctxt, 0, &lines)) return 0;
  if (lines <= 0) return job_fail(job, CLR_ERROR_FILE_FORMAT, "bad scanlines per chunk");
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int started = 0, ok = 1;
  for (int64_t y = image->data_window.y0; ok && y < image->data_window.y1; y += lines) {
    exr_chunk_info_t cinfo;
    ok = EXR_TRY(job, exr_read_scanline_chunk_info, ctxt, 0, (int)y, &cinfo);
    if (ok && !started)
      ok = started = EXR_TRY(job, exr_decoding_initialize, ctxt, 0, &cinfo, &dec);
    else if (ok)
      ok = EXR_TRY(job, exr_decoding_update, ctxt, 0, &cinfo, &dec);
    ok = ok && point_decoder_at_chunk(job, &dec, image, halves);
    if (ok && y == image->data_window.y0)
      ok = EXR_TRY(job, exr_decoding_choose_default_routines, ctxt, 0, &dec);
    ok = ok && EXR_TRY(job, exr_decoding_run, ctxt, 0, &dec);
  }
  if (started && !EXR_TRY(job, exr_decoding_destroy, ctxt, &dec)) ok = 0;
  return ok;
}

static void convert_planes(clr_exr_image *image, uint16_t **halves) {
  size_t pixels = (size_t)image->width * (size_t)image->height;
  for (int32_t c = 0; c < image->channel_count; ++c) {
    float *plane = image->channels[c];
    if (halves[c]) {
      for (size_t i = 0; i < pixels; ++i) plane[i] = clr_half_to_float(halves[c][i]);
    } else if (image->channel_types[c] == EXR_PIXEL_UINT) {
      for (size_t i = 0; i < pixels; ++i) {
        uint32_t u;
        memcpy(&u, &plane[i], sizeof u);
        plane[i] = (float)u;
      }
    }
  }
}

/* Copies the string, float, double (as float) and int header attributes. */
static int read_attributes(exr_job *job, exr_context_t ctxt, clr_exr_image *image) {
  int32_t count = 0;
  if (!EXR_TRY(job, exr_get_attribute_count, ctxt, 0, &count)) return 0;
  image->attrs = calloc(count > 0 ? (size_t)count : 1u, sizeof *image->attrs);
  if (!image->attrs) return job_fail(job, CLR_ERROR_OUT_OF_MEMORY, "out of memory");
  for (int32_t i = 0; i < count; ++i) {
    const exr_attribute_t *attr = NULL;
    if (!EXR_TRY(job, exr_get_attribute_by_index, ctxt, 0, EXR_ATTR_LIST_FILE_ORDER, i, &attr))
      return 0;
    clr_exr_attribute *out = &image->attrs[image->attr_count];
    if (attr->type == EXR_ATTR_STRING) {
      out->kind = CLR_EXR_ATTR_STRING;
      out->s = copy_string(attr->string->str ? attr->string->str : "",
                           attr->string->str ? (size_t)attr->string->length : 0u);
      if (!out->s) return job_fail(job, CLR_ERROR_OUT_OF_MEMORY, "out of memory");
    } else if (attr->type == EXR_ATTR_FLOAT || attr->type == EXR_ATTR_DOUBLE) {
      out->kind = CLR_EXR_ATTR_FLOAT;
      out->f = attr->type == EXR_ATTR_FLOAT ? attr->f : (float)attr->d;
    } else if (attr->type == EXR_ATTR_INT) {
      out->kind = CLR_EXR_ATTR_INT;
      out->i = attr->i;
    } else {
      continue;
    }
    ++image->attr_count; /* counted before the name so free() sees a partly filled entry */
    out->name = copy_string(attr->name, strlen(attr->name));
    if (!out->name) return job_fail(job, CLR_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  return 1;
}

clr_result clr_exr_read(const char *path, clr_exr_image **out) {
  if (!out) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_exr_read: out is NULL");
  *out = NULL;
  if (!path) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_exr_read: path is NULL");
  exr_job job = {path, 1, CLR_SUCCESS, 0};
  /* A missing file is left to exr_start_read, whose message names the call. */
  if (clr_input_file_exists(path)) CLR_CHECK(clr_input_file_check(path, "EXR", &job.file_size));
  clr_exr_image *image = calloc(1, sizeof *image);
  uint16_t **halves = NULL;
  if (!image)
    return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "clr_exr_read '%s': out of memory", path);
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = capture_exr_error;
  exr_context_t ctxt = NULL;
  if (EXR_TRY(&job, exr_start_read, &ctxt, path, &init) && read_layout(&job, ctxt, image) &&
      check_sizes(&job, ctxt, image) && allocate_channels(&job, ctxt, image, &halves) &&
      read_chunks(&job, ctxt, image, halves) && read_attributes(&job, ctxt, image))
    convert_planes(image, halves);
  if (ctxt) EXR_TRY(&job, exr_finish, &ctxt);
  for (int32_t c = 0; halves && c < image->channel_count; ++c) free(halves[c]);
  free(halves);
  if (job.result != CLR_SUCCESS) {
    clr_exr_image_free(image);
    return job.result;
  }
  *out = image;
  return CLR_SUCCESS;
}

/* ---- lookups ----------------------------------------------------------------------------- */

const float *clr_exr_image_channel(const clr_exr_image *image, const char *name) {
  if (!image || !name) return NULL;
  for (int32_t c = 0; c < image->channel_count; ++c)
    if (strcmp(image->channel_names[c], name) == 0) return image->channels[c];
  return NULL;
}

static const clr_exr_attribute *find_attr(const clr_exr_image *image, const char *name,
                                          int32_t kind) {
  if (!image || !name) return NULL;
  for (int32_t a = 0; a < image->attr_count; ++a)
    if (image->attrs[a].kind == kind && strcmp(image->attrs[a].name, name) == 0)
      return &image->attrs[a];
  return NULL;
}

const char *clr_exr_image_string_attr(const clr_exr_image *image, const char *name) {
  const clr_exr_attribute *a = find_attr(image, name, CLR_EXR_ATTR_STRING);
  return a ? a->s : NULL;
}

int clr_exr_image_float_attr(const clr_exr_image *image, const char *name, float *value) {
  const clr_exr_attribute *a = find_attr(image, name, CLR_EXR_ATTR_FLOAT);
  if (!a || !value) return 0;
  *value = a->f;
  return 1;
}

int clr_exr_image_int_attr(const clr_exr_image *image, const char *name, int32_t *value) {
  const clr_exr_attribute *a = find_attr(image, name, CLR_EXR_ATTR_INT);
  if (!a || !value) return 0;
  *value = a->i;
  return 1;
}
