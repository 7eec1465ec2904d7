/* Device side of clr_sampler_generate: kernels specialised per sampler with -D and cached with the
 * small buffers they use, the global samplers' split index/value passes, the pixel samplers'
 * per-pixel and per-tile launches. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "global_sampler_funcs.h"
#include "halton_tables.h"
#include "pixel_sampler_funcs.h"
#include "pbrt_v4_sampler_funcs.h"
#include "sampler_device.h"
#include "sobol_tables.h"
#include "v4_digit_tables.h"

#define MAX_KERNELS 24
/* Work-items per work-group wanted; the device's and the kernel's limits may lower it
 * (clr_context_group_size). */
#define GROUP_SIZE 64
/* Build define of the portable kernel shape (include/clrender/kernels.h). */
#define PORTABLE_DEFINE " -DCLR_KERNELS_PORTABLE"
/* Batch items per work-item of the global samplers (CLR_LANES in global_sampler_simd.h). */
#define CLR_GLOBAL_LANES 8
/* Pixels per work-item of the pixel samplers with per-pixel seeding (CLR_PIXEL_LANES in
 * pixel_sampler_simd.h). */
#define CLR_PIXEL_LANES 8

typedef struct cached_kernel {
  char name[48];
  char defines[224];
  cl_kernel kernel;
} cached_kernel;

/* A device buffer that is reused and grows on demand. */
typedef struct grow_buffer {
  cl_mem mem;
  size_t bytes;
} grow_buffer;

/* One record's pair table with its lane rows as build_pair_tables last made it, and its key. */
typedef struct cached_pair_table {
  const clr_halton_tables *tables;
  clr_halton_pair_shape shape;
  clr_u32 step;
  size_t rows, entries; /* entries: the table's and its rows' */
  clr_u16 *table;       /* NULL: none */
} cached_pair_table;

/* Entries the cached tables hold at most together (8 MiB). */
#define PAIR_CACHE_BUDGET ((size_t)1 << 22)

struct clr_sampler_device {
  clr_context ctx;
  pthread_mutex_t lock;
  cached_kernel kernels[MAX_KERNELS];
  int kernel_count;
  grow_buffer plan, index_plan, indices, scratch, slots, bounded, pmj, pair;
  /* pbrt-v4 halton's digit permutations (host tables and their device copies) */
  clr_v4_digit_tables digits;
  grow_buffer digit_perms, digit_offsets;
  /* Values read back into host memory, kept between calls: a buffer made per call costs the
   * implementation fresh pages (page faults) in every batch, and their release a TLB shootdown */
  grow_buffer host_out;
  cl_uint *bounded_host; /* 4 per bound b = 1..bounded_count (clr_pcg32x8_bounded) */
  int bounded_count;
  /* Host copies of the last launch's plans (read by non-blocking writes until the call ends). */
  clr_value_plan values[CLR_MAX_VALUES_PER_SAMPLE], scratch_plan[CLR_MAX_VALUES_PER_SAMPLE];
  clr_index_plan index_slots[CLR_MAX_VALUES_PER_SAMPLE + 1];
  int slot_first[CLR_MAX_VALUES_PER_SAMPLE + 2];
  clr_request_slot slots_copy[CLR_MAX_REQUESTS];
  /* Halton pair tables of the last launch: their (record, shape) keys, host copy. */
  int pair_count; /* -1: the device buffer holds nothing valid */
  int pair_records[CLR_HALTON_PRIME_RECORDS];
  clr_u32 pair_steps[2]; /* the lane rows' steps: index stride, scale[0] (dimension 1) */
  size_t pair_rows[CLR_HALTON_PRIME_RECORDS]; /* each table's lane row entries (0: none) */
  clr_halton_pair_shape pair_shapes[CLR_HALTON_PRIME_RECORDS];
  clr_u16 *pair_host;
  size_t pair_capacity;
  /* each record's last built table (a new plan, e.g. a shorter layout prefix, reuses it) */
  cached_pair_table pair_cache[CLR_HALTON_PRIME_RECORDS];
  size_t pair_cache_entries; /* at most PAIR_CACHE_BUDGET */
};

clr_result clr_sampler_device_create(clr_context ctx, clr_sampler_device **out) {
  clr_sampler_device *d = calloc(1, sizeof *d);
  if (!d) return clr_fail(ctx, CLR_ERROR_OUT_OF_MEMORY, "clr_sampler_create: out of memory");
  if (pthread_mutex_init(&d->lock, NULL) != 0) {
    free(d);
    return clr_fail(ctx, CLR_ERROR_INTERNAL, "clr_sampler_create: pthread_mutex_init failed");
  }
  d->ctx = ctx;
  d->pair_count = -1;
  *out = d;
  return CLR_SUCCESS;
}

static void release_kernels(clr_sampler_device *d) {
  for (int i = 0; i < d->kernel_count; ++i) clReleaseKernel(d->kernels[i].kernel);
  d->kernel_count = 0;
}

void clr_sampler_device_release(clr_sampler_device *d) {
  if (!d) return;
  release_kernels(d);
  grow_buffer *buffers[] = {&d->plan,     &d->index_plan,  &d->indices,      &d->scratch,
                            &d->slots,    &d->bounded,     &d->pmj,          &d->pair,
                            &d->host_out, &d->digit_perms, &d->digit_offsets};
  for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; ++i)
    if (buffers[i]->mem) clReleaseMemObject(buffers[i]->mem);
  pthread_mutex_destroy(&d->lock);
  free(d->bounded_host);
  free(d->pair_host);
  clr_v4_digit_tables_free(&d->digits);
  for (int r = 0; r < CLR_HALTON_PRIME_RECORDS; ++r) free(d->pair_cache[r].table);
  free(d);
}

/* The kernel `name` of sampler_kernels.cl built with `defines`, created once per sampler. */
static clr_result get_kernel(clr_sampler_device *d, const char *name, const char *defines,
                             cl_kernel *out) {
  for (int i = 0; i < d->kernel_count; ++i)
    if (strcmp(d->kernels[i].name, name) == 0 && strcmp(d->kernels[i].defines, defines) == 0) {
      *out = d->kernels[i].kernel;
      return CLR_SUCCESS;
    }
  if (strlen(name) >= sizeof d->kernels[0].name || strlen(defines) >= sizeof d->kernels[0].defines)
    return clr_fail(d->ctx, CLR_ERROR_INTERNAL, "sampler kernel %s: defines \"%s\" too long", name,
                    defines);
  if (d->kernel_count == MAX_KERNELS) release_kernels(d);
  CLR_CHECK(clr_context_kernel(d->ctx, "sampler_kernels.cl", defines, name, out));
  cached_kernel *c = &d->kernels[d->kernel_count++];
  snprintf(c->name, sizeof c->name, "%s", name);
  snprintf(c->defines, sizeof c->defines, "%s", defines);
  c->kernel = *out;
  return CLR_SUCCESS;
}

/* Makes b hold at least `bytes`, keeping it when it already does. */
static clr_result grow(clr_context ctx, grow_buffer *b, size_t bytes, cl_mem_flags flags,
                       const char *what) {
  if (bytes == 0) bytes = 4;
  if (b->mem && b->bytes >= bytes) return CLR_SUCCESS;
  if (b->mem) clReleaseMemObject(b->mem);
  b->mem = NULL;
  b->bytes = 0;
  cl_int err = CL_SUCCESS;
  b->mem = clCreateBuffer(clr_context_cl_context(ctx), flags, bytes, NULL, &err);
  if (err != CL_SUCCESS) {
    b->mem = NULL;
    return clr_fail(ctx, CLR_ERROR_OPENCL, "clCreateBuffer(%s, %zu bytes) failed: %s (%d)", what,
                    bytes, clr_cl_error_name(err), (int)err);
  }
  b->bytes = bytes;
  return CLR_SUCCESS;
}

/* Copies host data (alive until the call's end) into b, growing it first. */
static clr_result upload(clr_context ctx, grow_buffer *b, const void *data, size_t bytes,
                         const char *what) {
  CLR_CHECK(grow(ctx, b, bytes, CL_MEM_READ_ONLY, what));
  if (bytes == 0) return CLR_SUCCESS;
  CLR_CL_CHECK(ctx, clEnqueueWriteBuffer(clr_context_cl_queue(ctx), b->mem, CL_FALSE, 0, bytes,
                                         data, 0, NULL, NULL));
  return CLR_SUCCESS;
}

#define SET_ARG(ctx, k, i, v) CLR_CL_CHECK(ctx, clSetKernelArg(k, i, sizeof(v), &(v)))

/* `items` work-items, padded to whole groups (the kernels clamp or skip their item ids). */
static clr_result launch(clr_context ctx, cl_kernel k, size_t items, const char *name) {
  return clr_context_launch(ctx, k, items, GROUP_SIZE, name);
}

static size_t batch_items(const clr_sampler_params *p) {
  return (size_t)p->batch_width * (size_t)p->batch_height * (size_t)p->sample_count;
}

/* Constants of n / dv = (n * magic) >> shift for 1 <= dv < 2^31: magic = ceil(2^(31+l) / dv),
 * l = ceil(log2 dv), shift = 31 + l; exact for every n below 2^31 (Granlund-Montgomery). */
static void udiv31_magic(uint32_t dv, uint32_t *magic, uint32_t *shift) {
  uint32_t l = 0;
  while (((uint64_t)1 << l) < dv) ++l;
  uint64_t one = (uint64_t)1 << (31 + l);
  *magic = (uint32_t)((one + dv - 1) / dv);
  *shift = 31 + l;
}

static clr_item_divisors item_divisors(const clr_sampler_params *p) {
  clr_item_divisors d;
  udiv31_magic((uint32_t)p->sample_count, &d.sample_magic, &d.sample_shift);
  udiv31_magic((uint32_t)p->batch_width, &d.width_magic, &d.width_shift);
  return d;
}

typedef struct global_plan {
  int slot_count;      /* index slots */
  int64_t frame_limit; /* sample numbers are below it */
} global_plan;

/* Index slot of element j of an array of n (slot 0: the sample itself). Slots of one array size
 * are shared by every array of that size. */
static int array_slot(clr_sampler_device *d, global_plan *g, int n, int j) {
  for (int s = 1; s < g->slot_count; ++s)
    if (d->index_slots[s].scale == n && d->index_slots[s].offset == 0) return s + j;
  int base = g->slot_count;
  for (int k = 0; k < n; ++k) d->index_slots[base + k] = (clr_index_plan){n, k};
  g->slot_count += n;
  return base + j;
}

/* Fills d->values, every value of the sample vector sorted by index slot (kernels compute each
 * slot's index once), and d->index_slots. */
static void build_global_plan(clr_sampler_device *d, const clr_sampler_params *p,
                              const clr_request_slot *slots, global_plan *g) {
  d->index_slots[0] = (clr_index_plan){1, 0};
  g->slot_count = 1;
  int64_t end = (int64_t)p->first_sample + p->sample_count;
  g->frame_limit = end;
  clr_value_plan *unsorted = d->scratch_plan;
  int n = 0;
  for (int r = 0; r < p->request_count; ++r) {
    const clr_request_slot *sl = &slots[r];
    if (sl->skipped) continue; /* no values to make */
    int elements = sl->array_size ? sl->array_size : 1;
    if (sl->array_size && end * sl->array_size > g->frame_limit)
      g->frame_limit = end * sl->array_size;
    for (int j = 0; j < elements; ++j)
      for (int c = 0; c < sl->dims; ++c) {
        clr_value_plan *e = &unsorted[n++];
        e->value = sl->first_value + j * sl->dims + c;
        e->dim = sl->source + c;
        e->index_slot = sl->array_size ? array_slot(d, g, sl->array_size, j) : 0;
        e->shape = 0;
        e->pair_table = -1;
      }
  }
  /* Stable counting sort by slot. */
  int *first = d->slot_first;
  memset(first, 0, sizeof(int) * (size_t)(g->slot_count + 1));
  for (int i = 0; i < n; ++i) ++first[unsorted[i].index_slot + 1];
  for (int s = 0; s < g->slot_count; ++s) first[s + 1] += first[s];
  for (int i = 0; i < n; ++i) d->values[first[unsorted[i].index_slot]++] = unsorted[i];
}

static int bits_for(uint64_t limit) { /* bits of the values below `limit` */
  int b = 0;
  while (b < 64 && ((uint64_t)1 << b) < limit) ++b;
  return b;
}

/* Halton plan entries' shape: the chunks of clr_scrambled_radical_inverse8 that cover every
 * argument below `limit`, and (bit 8) whether base^(digits of limit - 1) <= 2^32, i.e. whether
 * the reversed digits fit 32 bits. */
/* The Halton tables covering the dimensions of the plan's values. */
static const clr_halton_tables *plan_tables(const clr_sampler_device *d, int value_count) {
  int dims = 0;
  for (int i = 0; i < value_count; ++i)
    if (d->values[i].dim >= dims) dims = d->values[i].dim + 1;
  return clr_halton_tables_covering(dims);
}

static void halton_value_shapes(clr_sampler_device *d, int value_count, uint64_t limit) {
  const clr_halton_prime *primes = plan_tables(d, value_count)->primes;
  for (int i = 0; i < value_count; ++i) {
    int dim = d->values[i].dim;
    if (dim < 1 || dim >= CLR_HALTON_PRIMES) continue;
    const clr_halton_prime *pr = &primes[dim == 1 ? CLR_HALTON_BASE3_RECORD : dim];
    uint64_t reach = pr->chunk_base;
    int chunks = 1;
    while (reach < limit && chunks < CLR_HALTON_MAX_CHUNKS32) {
      reach *= pr->chunk_base;
      ++chunks;
    }
    uint64_t power = 1; /* base^digits(limit - 1), stopped past 2^32 */
    for (uint64_t rest = limit - 1; rest != 0 && power <= ((uint64_t)1 << 32); rest /= pr->base)
      power *= pr->base;
    d->values[i].shape = chunks | (power <= ((uint64_t)1 << 32) ? 1 << 8 : 0);
  }
}

/* A launch's pair tables (clr_halton_pair8) hold at most PAIR_BUDGET entries; other dimensions
 * keep the chunk loop. */
#define PAIR_BUDGET ((size_t)1 << 20)

/* The lane step of record's arguments: the index stride, for dimension 1 scale[0]. */
static clr_u32 lane_step(const clr_u32 *steps, int record) {
  return steps[record == CLR_HALTON_BASE3_RECORD];
}

/* Lane rows (8 entries per lo entry) are added in plan order while a launch's rows stay within
 * ROW_BUDGET entries: past the caches a row costs more than the lane-by-lane lookups it saves. */
#define ROW_BUDGET ((size_t)1 << 15)

/* Record's table (with `rows` lane row entries for lanes `step` apart; `entries` in all) from
 * d's cache, built there unless its key matches; NULL when the cache cannot hold it (the caller
 * builds it in place). */
static const clr_u16 *cached_table(clr_sampler_device *d, const clr_halton_tables *t, int record,
                                   clr_halton_pair_shape shape, clr_u32 step, size_t rows,
                                   size_t entries) {
  cached_pair_table *c = &d->pair_cache[record];
  if (c->table && c->tables == t && c->shape.digits == shape.digits &&
      c->shape.tops == shape.tops && c->step == step && c->rows == rows && c->entries == entries)
    return c->table;
  size_t others = d->pair_cache_entries - (c->table ? c->entries : 0);
  if (others + entries > PAIR_CACHE_BUDGET) return NULL;
  clr_u16 *table = realloc(c->table, sizeof(clr_u16) * entries);
  if (!table) return NULL;
  const clr_halton_prime *pr = &t->primes[record];
  clr_halton_pair_table(pr, t->permutations, shape, table);
  if (rows) clr_halton_pair_rows(pr, shape, step, table);
  *c = (cached_pair_table){t, shape, step, rows, entries, table};
  d->pair_cache_entries = others + entries;
  return table;
}

/* Builds the launch's pair tables into d->pair_host (count tables, `size` entries), with lane
 * rows for work-items whose 8 lanes are consecutive samples of one pixel. */
static clr_result build_pair_tables(clr_sampler_device *d, const clr_halton_tables *t, int count,
                                    size_t size) {
  if (size > d->pair_capacity) {
    clr_u16 *t = realloc(d->pair_host, sizeof(clr_u16) * size);
    if (!t) return clr_fail(d->ctx, CLR_ERROR_OUT_OF_MEMORY, "clr_sampler_generate: out of memory");
    d->pair_host = t;
    d->pair_capacity = size;
  }
  size_t at = 0;
  for (int j = 0; j < count; ++j) {
    int record = d->pair_records[j];
    const clr_halton_prime *pr = &t->primes[record];
    clr_u32 step = lane_step(d->pair_steps, record);
    size_t entries = clr_halton_pair_entries(pr, d->pair_shapes[j]) + d->pair_rows[j];
    const clr_u16 *cached =
        cached_table(d, t, record, d->pair_shapes[j], step, d->pair_rows[j], entries);
    if (cached) {
      memcpy(d->pair_host + at, cached, sizeof(clr_u16) * entries);
    } else {
      clr_halton_pair_table(pr, t->permutations, d->pair_shapes[j], d->pair_host + at);
      if (d->pair_rows[j]) clr_halton_pair_rows(pr, d->pair_shapes[j], step, d->pair_host + at);
    }
    at += entries;
  }
  return CLR_SUCCESS;
}

/* The halton plan's pair tables: one per (record, shape) where the arguments (below `limit`) fit
 * two parts; sets each entry's pair_table and uploads the tables unless the last launch had the
 * same ones. *any: whether there is one. */
static clr_result halton_pair_tables(clr_sampler_device *d, const clr_sampler_params *p,
                                     int value_count, uint64_t limit, int *any) {
  const clr_halton_tables *t = plan_tables(d, value_count);
  const clr_halton_prime *primes = t->primes;
  int records[CLR_HALTON_PRIME_RECORDS];
  clr_halton_pair_shape shapes[CLR_HALTON_PRIME_RECORDS];
  size_t offsets[CLR_HALTON_PRIME_RECORDS], rows[CLR_HALTON_PRIME_RECORDS], size = 0, all_rows = 0;
  int count = 0;
  uint64_t scale1 = (uint64_t)p->halton_scale[1];
  for (int i = 0; i < value_count; ++i) {
    clr_value_plan *e = &d->values[i];
    if (e->dim < 1 || e->dim >= CLR_HALTON_PRIMES) continue;
    int record = e->dim == 1 ? CLR_HALTON_BASE3_RECORD : e->dim;
    uint64_t arguments = e->dim == 1 ? (limit + scale1 - 1) / scale1 : limit;
    clr_halton_pair_shape shape = clr_halton_pair_shape_for(&primes[record], arguments);
    if (shape.digits == 0) continue;
    int j = 0;
    while (j < count && (records[j] != record || shapes[j].digits != shape.digits ||
                         shapes[j].tops != shape.tops))
      ++j;
    if (j == count) {
      size_t row_entries = clr_halton_pair_row_entries(&primes[record], shape);
      if (all_rows + row_entries > ROW_BUDGET) row_entries = 0;
      size_t entries = clr_halton_pair_entries(&primes[record], shape) + row_entries;
      if (size + entries > PAIR_BUDGET) continue;
      records[count] = record;
      shapes[count] = shape;
      rows[count] = row_entries;
      offsets[count++] = size;
      size += entries;
      all_rows += row_entries;
    }
    e->pair_table = (int)offsets[j];
  }
  *any = count > 0;
  clr_u32 steps[2] = {(clr_u32)p->halton_stride, (clr_u32)p->halton_scale[0]};
  if (count == 0 || (count == d->pair_count &&
                     memcmp(records, d->pair_records, sizeof(int) * (size_t)count) == 0 &&
                     memcmp(shapes, d->pair_shapes, sizeof shapes[0] * (size_t)count) == 0 &&
                     memcmp(steps, d->pair_steps, sizeof steps) == 0))
    return CLR_SUCCESS;
  d->pair_count = -1;
  memcpy(d->pair_steps, steps, sizeof steps);
  memcpy(d->pair_records, records, sizeof(int) * (size_t)count);
  memcpy(d->pair_shapes, shapes, sizeof shapes[0] * (size_t)count);
  memcpy(d->pair_rows, rows, sizeof rows[0] * (size_t)count);
  CLR_CHECK(build_pair_tables(d, t, count, size));
  CLR_CHECK(upload(d->ctx, &d->pair, d->pair_host, sizeof(clr_u16) * size, "halton pair tables"));
  d->pair_count = count;
  return CLR_SUCCESS;
}

/* Sobol's frame bits of a launch: its sample numbers are below 2^it (at most 52 - 2m). */
static int sobol_frame_bits(const clr_sampler_params *p, const global_plan *g) {
  int frame_bits = bits_for((uint64_t)g->frame_limit);
  int most = CLR_SOBOL_INDEX_BITS - 2 * p->sobol_log2_resolution;
  return frame_bits < most ? frame_bits : most;
}

/* Build defines of the global samplers (p: the launch's, sobol_frame_bits set); whether indices
 * fit 32 bits. Nothing that varies with the resolution or sample count: each new define would
 * cost a program build (seconds on PoCL). */
static int global_defines(clr_sampler_device *d, const clr_sampler_params *p, const global_plan *g,
                          char *out, size_t size) {
  if (p->type == CLR_SAMPLER_TYPE_SOBOL) {
    int index32 = 2 * p->sobol_log2_resolution + p->sobol_frame_bits <= 32;
    snprintf(out, size, "-DCLR_SAMPLER_TYPE=%d%s", (int)p->type, index32 ? " -DCLR_INDEX32" : "");
    return index32;
  }
  uint64_t limit = (uint64_t)p->halton_stride * (uint64_t)g->frame_limit; /* indices below it */
  if (limit > ((uint64_t)1 << 32)) {
    snprintf(out, size, "-DCLR_SAMPLER_TYPE=%d", (int)p->type);
    return 0;
  }
  halton_value_shapes(d, p->values_per_sample, limit);
  snprintf(out, size, "-DCLR_SAMPLER_TYPE=%d -DCLR_INDEX32 -DCLR_HALTON_INDEX32", (int)p->type);
  return 1;
}

static _Alignas(4096) clr_u32 sobol_groups[CLR_SOBOL_DIMENSIONS * CLR_SOBOL_GROUP_TABLE];
static pthread_once_t sobol_groups_once = PTHREAD_ONCE_INIT;

static void build_sobol_groups(void) {
  for (int d = 0; d < CLR_SOBOL_DIMENSIONS; ++d)
    for (int g = 0; g < CLR_SOBOL_GROUPS; ++g)
      for (int x = 0; x < CLR_SOBOL_GROUP_ENTRIES; ++x) {
        clr_u32 v = 0;
        for (int b = 0; b < 3; ++b) {
          int column = 3 * g + b;
          if ((x >> b & 1) && column < CLR_SOBOL_MATRIX_SIZE)
            v ^= clr_sobol_matrices32[d * CLR_SOBOL_MATRIX_SIZE + column];
        }
        sobol_groups[(d * CLR_SOBOL_GROUPS + g) * CLR_SOBOL_GROUP_ENTRIES + x] = v;
      }
}

/* The generator matrices as 3-bit group tables (CLR_SOBOL_GROUPS in global_sampler_funcs.h),
 * built once. */
static const clr_u32 *sobol_group_tables(void) {
  pthread_once(&sobol_groups_once, build_sobol_groups);
  return sobol_groups;
}

/* The Sobol' generator matrices as 32-bit columns, shared by the context's kernels. */
static clr_result share_sobol_matrices(clr_context ctx, cl_mem *matrices32) {
  return clr_context_shared_buffer(ctx, "sobol_matrices32", clr_sobol_matrices32,
                                   sizeof(clr_u32) * CLR_SOBOL_DIMENSIONS * CLR_SOBOL_MATRIX_SIZE,
                                   matrices32);
}

/* The VdC Sobol' matrices and their inverses, shared by the context's kernels. */
static clr_result share_vdc_matrices(clr_context ctx, cl_mem *vdc, cl_mem *vdc_inv) {
  CLR_CHECK(clr_context_shared_buffer(ctx, "vdc_sobol", clr_vdc_sobol_matrices,
                                      sizeof clr_vdc_sobol_matrices, vdc));
  return clr_context_shared_buffer(ctx, "vdc_sobol_inv", clr_vdc_sobol_matrices_inv,
                                   sizeof clr_vdc_sobol_matrices_inv, vdc_inv);
}

/* The Halton prime records and permutations covering the slots' dimensions, shared. */
static clr_result share_halton_tables(clr_context ctx, const clr_sampler_params *p,
                                      const clr_request_slot *slots, cl_mem *primes,
                                      cl_mem *perms) {
  const clr_halton_tables *t =
      clr_halton_tables_covering(clr_halton_layout_dimensions(slots, p->request_count));
  CLR_CHECK(clr_context_shared_buffer(ctx, t->primes_key, t->primes,
                                      sizeof(clr_halton_prime) * CLR_HALTON_PRIME_RECORDS, primes));
  return clr_context_shared_buffer(ctx, t->permutations_key, t->permutations,
                                   sizeof(clr_u16) * t->entries, perms);
}

/* The batch's request slots, copied (the caller's may not outlive the enqueued write). */
static clr_result upload_slots(clr_sampler_device *d, const clr_sampler_params *p,
                               const clr_request_slot *slots) {
  memcpy(d->slots_copy, slots, sizeof(clr_request_slot) * (size_t)p->request_count);
  return upload(d->ctx, &d->slots, d->slots_copy,
                sizeof(clr_request_slot) * (size_t)p->request_count, "request slots");
}

/* Portable shape: one work-item per batch item, the host reference's scalar functions. */
static clr_result run_global_portable(clr_sampler_device *d, const clr_sampler_params *p,
                                      const clr_request_slot *slots, cl_mem values,
                                      int write_indices) {
  clr_context ctx = d->ctx;
  size_t items = batch_items(p);
  cl_mem sobol32 = NULL, vdc = NULL, vdc_inv = NULL, primes = NULL, perms = NULL;
  if (p->type == CLR_SAMPLER_TYPE_SOBOL) {
    CLR_CHECK(share_sobol_matrices(ctx, &sobol32));
    CLR_CHECK(share_vdc_matrices(ctx, &vdc, &vdc_inv));
  } else {
    CLR_CHECK(share_halton_tables(ctx, p, slots, &primes, &perms));
  }
  CLR_CHECK(upload_slots(d, p, slots));
  CLR_CHECK(grow(ctx, &d->indices, write_indices ? items * sizeof(cl_ulong) : 8, CL_MEM_READ_WRITE,
                 "sample indices"));
  char defines[64];
  snprintf(defines, sizeof defines, "-DCLR_SAMPLER_TYPE=%d" PORTABLE_DEFINE, (int)p->type);
  const char *name = "clr_global_generate_portable";
  cl_kernel k;
  CLR_CHECK(get_kernel(d, name, defines, &k));
  cl_int count = (cl_int)items, write = write_indices;
  int a = 0;
  SET_ARG(ctx, k, a++, *p);
  SET_ARG(ctx, k, a++, d->slots.mem);
  SET_ARG(ctx, k, a++, sobol32);
  SET_ARG(ctx, k, a++, vdc);
  SET_ARG(ctx, k, a++, vdc_inv);
  SET_ARG(ctx, k, a++, primes);
  SET_ARG(ctx, k, a++, perms);
  SET_ARG(ctx, k, a++, values);
  SET_ARG(ctx, k, a++, d->indices.mem);
  SET_ARG(ctx, k, a++, write);
  SET_ARG(ctx, k, a++, count);
  return launch(ctx, k, items, name);
}

static clr_result run_global(clr_sampler_device *d, const clr_sampler_params *p,
                             const clr_request_slot *slots, cl_mem values, int write_indices) {
  clr_context ctx = d->ctx;
  if (clr_context_portable(ctx)) return run_global_portable(d, p, slots, values, write_indices);
  global_plan g;
  build_global_plan(d, p, slots, &g);
  int sobol = p->type == CLR_SAMPLER_TYPE_SOBOL;
  clr_sampler_params launch_params = *p;
  if (sobol) launch_params.sobol_frame_bits = sobol_frame_bits(p, &g);
  char defines[224];
  int index32 = global_defines(d, &launch_params, &g, defines, sizeof defines);
  size_t items = batch_items(p);
  cl_mem tables[3] = {NULL, NULL, NULL};
  if (sobol) {
    if (index32)
      CLR_CHECK(clr_context_shared_buffer(
          ctx, "sobol_groups", sobol_group_tables(),
          sizeof(clr_u32) * CLR_SOBOL_DIMENSIONS * CLR_SOBOL_GROUP_TABLE, &tables[0]));
    else
      CLR_CHECK(share_sobol_matrices(ctx, &tables[0]));
    CLR_CHECK(share_vdc_matrices(ctx, &tables[1], &tables[2]));
  } else {
    CLR_CHECK(share_halton_tables(ctx, p, slots, &tables[0], &tables[1]));
    int pairs = 0;
    if (index32)
      CLR_CHECK(halton_pair_tables(d, p, p->values_per_sample,
                                   (uint64_t)p->halton_stride * (uint64_t)g.frame_limit, &pairs));
    if (pairs) tables[2] = d->pair.mem;
  }
  CLR_CHECK(upload(ctx, &d->plan, d->values, sizeof(clr_value_plan) * (size_t)p->values_per_sample,
                   "sample value plan"));
  CLR_CHECK(upload(ctx, &d->index_plan, d->index_slots,
                   sizeof(clr_index_plan) * (size_t)g.slot_count, "sample index plan"));
  CLR_CHECK(grow(ctx, &d->indices, write_indices ? items * sizeof(cl_ulong) : 8, CL_MEM_READ_WRITE,
                 "sample indices"));
  const char *name = "clr_global_generate";
  cl_kernel k;
  CLR_CHECK(get_kernel(d, name, defines, &k));
  clr_item_divisors div = item_divisors(p);
  cl_int count = (cl_int)items, write = write_indices;
  int a = 0;
  SET_ARG(ctx, k, a++, launch_params);
  SET_ARG(ctx, k, a++, div);
  SET_ARG(ctx, k, a++, d->plan.mem);
  SET_ARG(ctx, k, a++, d->index_plan.mem);
  for (int t = 0; t < 3; ++t) SET_ARG(ctx, k, a++, tables[t]);
  SET_ARG(ctx, k, a++, values);
  SET_ARG(ctx, k, a++, d->indices.mem);
  SET_ARG(ctx, k, a++, write);
  SET_ARG(ctx, k, a++, count);
  return launch(ctx, k, (items + CLR_GLOBAL_LANES - 1) / CLR_GLOBAL_LANES, name);
}

static int pbrt_tiles(const clr_sampler_params *p, int *tx0, int *ty0, int *wide, int *high) {
  *tx0 = (p->batch_x0 - p->sample_x0) / CLR_PBRT_TILE_SIZE;
  *ty0 = (p->batch_y0 - p->sample_y0) / CLR_PBRT_TILE_SIZE;
  int tx1 = (p->batch_x0 + p->batch_width - 1 - p->sample_x0) / CLR_PBRT_TILE_SIZE;
  int ty1 = (p->batch_y0 + p->batch_height - 1 - p->sample_y0) / CLR_PBRT_TILE_SIZE;
  *wide = tx1 - *tx0 + 1;
  *high = ty1 - *ty0 + 1;
  return *wide * *high;
}

/* Device constants of UniformUInt32(b) for b = 1..most: the rejection threshold (-b) % b and
 * Granlund-Montgomery's magic and shifts for v / b (exact for every 32-bit v), uploaded. */
static clr_result upload_bounded_table(clr_sampler_device *d, int most) {
  if (most < 1) most = 1;
  if (most > d->bounded_count) {
    cl_uint *t = realloc(d->bounded_host, sizeof(cl_uint) * 4 * (size_t)most);
    if (!t) return clr_fail(d->ctx, CLR_ERROR_OUT_OF_MEMORY, "clr_sampler_generate: out of memory");
    d->bounded_host = t;
    for (int b = d->bounded_count + 1; b <= most; ++b) {
      uint32_t l = 0;
      while (((uint64_t)1 << l) < (uint64_t)b) ++l;
      cl_uint *k = &t[4 * (b - 1)];
      k[0] = (uint32_t)(0u - (uint32_t)b) % (uint32_t)b;
      k[1] = (uint32_t)(((((uint64_t)1 << l) - (uint64_t)b) << 32) / (uint64_t)b + 1u);
      k[2] = l ? 1u : 0u;
      k[3] = l ? l - 1u : 0u;
    }
    d->bounded_count = most;
  }
  return upload(d->ctx, &d->bounded, d->bounded_host, sizeof(cl_uint) * 4 * (size_t)most,
                "bounded draw constants");
}

static clr_result run_pixel(clr_sampler_device *d, const clr_sampler_params *p,
                            const clr_request_slot *slots, cl_mem values) {
  clr_context ctx = d->ctx;
  int portable = clr_context_portable(ctx);
  char defines[64];
  snprintf(defines, sizeof defines, "-DCLR_SAMPLER_TYPE=%d%s", (int)p->type,
           portable ? PORTABLE_DEFINE : "");
  int tiled = p->seeding == CLR_SEEDING_TYPE_PBRT_V3;
  int lanes = tiled || portable ? 1 : CLR_PIXEL_LANES; /* pixels per work-item */
  const char *name = tiled      ? "clr_generate_tiles"
                     : portable ? "clr_pixel_generate_portable"
                                : "clr_pixel_generate";
  cl_kernel k;
  CLR_CHECK(get_kernel(d, name, defines, &k));
  int tx0 = 0, ty0 = 0, wide = 0, high = 0;
  size_t pixels = (size_t)p->batch_width * (size_t)p->batch_height;
  /* Work-items: one per tile, or one per `lanes` pixels, each with its own scratch. */
  size_t items = tiled ? (size_t)pbrt_tiles(p, &tx0, &ty0, &wide, &high)
                       : (pixels + (size_t)lanes - 1) / (size_t)lanes;
  size_t scratch_floats = (size_t)p->scratch_floats * (size_t)lanes;
  CLR_CHECK(upload_slots(d, p, slots));
  /* The SIMD kernel's padding work-items repeat the last pixels with their own scratch. */
  size_t group = clr_context_group_size(ctx, k, GROUP_SIZE); /* as launch() */
  size_t padded = tiled || portable ? items : (items + group - 1) / group * group;
  CLR_CHECK(grow(ctx, &d->scratch, padded * scratch_floats * sizeof(float), CL_MEM_READ_WRITE,
                 "sampler scratch"));
  int a = 0;
  SET_ARG(ctx, k, a++, *p);
  SET_ARG(ctx, k, a++, d->slots.mem);
  SET_ARG(ctx, k, a++, values);
  SET_ARG(ctx, k, a++, d->scratch.mem);
  if (!tiled && !portable) { /* bounds of UniformUInt32: shuffles of spp points and arrays */
    CLR_CHECK(upload_bounded_table(d, p->scratch_floats / 2));
    SET_ARG(ctx, k, a++, d->bounded.mem);
  }
  if (tiled) {
    cl_int x0 = tx0, y0 = ty0, w = wide, count = (cl_int)items;
    SET_ARG(ctx, k, a++, x0);
    SET_ARG(ctx, k, a++, y0);
    SET_ARG(ctx, k, a++, w);
    SET_ARG(ctx, k, a++, count);
  } else {
    cl_int count = (cl_int)pixels;
    SET_ARG(ctx, k, a++, count);
  }
  return launch(ctx, k, items, name);
}

/* Dimensions a pbrt-v4 halton layout reads: the pixel's two, then each request's (an upper bound;
 * at most the primes, where pbrt-v4 wraps to dimension 2). */
static int v4_layout_dimensions(const clr_sampler_params *p, const clr_request_slot *slots) {
  long dims = 2;
  for (int r = 0; r < p->request_count; ++r) {
    long elements = slots[r].array_size ? slots[r].array_size : 1;
    dims += elements * (r == p->film_request ? 2 : slots[r].dims);
    if (dims >= CLR_HALTON_PRIMES) return CLR_HALTON_PRIMES;
  }
  return (int)dims;
}

/* Blocking copies of d->digits to the device (the host tables change with the next seed). */
static clr_result copy_digit_tables(clr_sampler_device *d) {
  size_t perm_bytes = d->digits.count * sizeof(uint16_t);
  size_t offset_bytes = (size_t)d->digits.dims * sizeof(uint32_t);
  CLR_CHECK(
      grow(d->ctx, &d->digit_perms, perm_bytes, CL_MEM_READ_ONLY, "halton digit permutations"));
  CLR_CHECK(
      grow(d->ctx, &d->digit_offsets, offset_bytes, CL_MEM_READ_ONLY, "halton digit permutations"));
  cl_command_queue q = clr_context_cl_queue(d->ctx);
  if (perm_bytes)
    CLR_CL_CHECK(d->ctx, clEnqueueWriteBuffer(q, d->digit_perms.mem, CL_TRUE, 0, perm_bytes,
                                              d->digits.perms, 0, NULL, NULL));
  if (offset_bytes)
    CLR_CL_CHECK(d->ctx, clEnqueueWriteBuffer(q, d->digit_offsets.mem, CL_TRUE, 0, offset_bytes,
                                              d->digits.offsets, 0, NULL, NULL));
  return CLR_SUCCESS;
}

/* pbrt-v4 halton with permuted digits: the layout's DigitPermutation tables on the device (built
 * and copied when the seed or the dimensions change); *dims: how many dimensions they cover (0 for
 * other samplers, whose kernels ignore the tables). */
static clr_result upload_digit_tables(clr_sampler_device *d, const clr_sampler_params *p,
                                      const clr_request_slot *slots, cl_int *dims) {
  *dims = 0; /* the buffers exist either way: they are kernel arguments */
  CLR_CHECK(grow(d->ctx, &d->digit_perms, 0, CL_MEM_READ_ONLY, "halton digit permutations"));
  CLR_CHECK(grow(d->ctx, &d->digit_offsets, 0, CL_MEM_READ_ONLY, "halton digit permutations"));
  if (p->v4_sampler != CLR_V4_HALTON || p->randomization != CLR_RANDOMIZE_TYPE_PERMUTEDIGITS)
    return CLR_SUCCESS;
  int made = clr_v4_digit_tables_make(&d->digits, p->seed, v4_layout_dimensions(p, slots));
  if (made < 0)
    return clr_fail(d->ctx, CLR_ERROR_OUT_OF_MEMORY, "halton digit permutations: out of memory");
  if (made) {
    clr_result r = copy_digit_tables(d);
    if (r != CLR_SUCCESS) {
      clr_v4_digit_tables_free(&d->digits); /* rebuilt and copied by the next call */
      return r;
    }
  }
  *dims = d->digits.dims;
  return CLR_SUCCESS;
}

/* pbrt-v4's samplers: one work-item per batch item or pixel; on SIMD contexts zsobol,
 * paddedsobol and pmj02bn one per 8 pixels, sobol, halton, independent and stratified one per 8
 * batch items. */
static clr_result run_v4(clr_sampler_device *d, const clr_sampler_params *p,
                         const clr_request_slot *slots, const float *pmj_pixels, cl_mem values) {
  clr_context ctx = d->ctx;
  size_t items = batch_items(p);
  cl_mem sobol32 = NULL, sobol_groups = NULL, vdc = NULL, vdc_inv = NULL, primes = NULL;
  CLR_CHECK(share_sobol_matrices(ctx, &sobol32));
  CLR_CHECK(share_vdc_matrices(ctx, &vdc, &vdc_inv));
  int portable = clr_context_portable(ctx);
  if (p->v4_sampler == CLR_V4_SOBOL && !portable) /* clr_v4_generate8's 32-bit indices */
    CLR_CHECK(clr_context_shared_buffer(
        ctx, "sobol_groups", sobol_group_tables(),
        sizeof(clr_u32) * CLR_SOBOL_DIMENSIONS * CLR_SOBOL_GROUP_TABLE, &sobol_groups));
  if (p->v4_sampler == CLR_V4_HALTON) /* the others leave it NULL: its tables take 15 ms */
    CLR_CHECK(clr_context_shared_buffer(ctx, "halton_primes", clr_halton_primes(),
                                        sizeof(clr_halton_prime) * CLR_HALTON_PRIME_RECORDS,
                                        &primes));
  CLR_CHECK(upload_slots(d, p, slots));
  size_t pmj_bytes = pmj_pixels ? sizeof(float) * ((size_t)clr_v4_pmj02_pixel_floats(p) +
                                                   2 * CLR_PMJ02_SETS * (size_t)p->spp)
                                : 0;
  CLR_CHECK(upload(ctx, &d->pmj, pmj_pixels, pmj_bytes, "pmj02bn pixel and point-set tables"));
  cl_int digit_dims = 0;
  CLR_CHECK(upload_digit_tables(d, p, slots, &digit_dims));
  /* zsobol, paddedsobol and pmj02bn: one work-item per pixel, (pixel, dimension) parts once;
   * on SIMD contexts one per 8 pixels (a pixel per lane), sobol, halton, independent and
   * stratified one per 8 batch items. */
  int per_pixel = p->v4_sampler == CLR_V4_ZSOBOL || p->v4_sampler == CLR_V4_PADDEDSOBOL ||
                  p->v4_sampler == CLR_V4_PMJ02BN;
  int lanes = !portable ? CLR_PIXEL_LANES : 1;
  const char *name = !per_pixel  ? (lanes > 1 ? "clr_v4_generate8" : "clr_v4_generate")
                     : lanes > 1 ? "clr_v4_generate_pixels8"
                                 : "clr_v4_generate_pixels";
  size_t pixels = (size_t)p->batch_width * (size_t)p->batch_height;
  size_t units = per_pixel ? pixels : items; /* the kernel's pixels or batch items */
  items = (units + (size_t)lanes - 1) / (size_t)lanes;
  cl_kernel k;
  CLR_CHECK(get_kernel(d, name,
                       portable ? "-DCLR_SAMPLER_TYPE=-1 -DCLR_SAMPLER_V4" PORTABLE_DEFINE
                                : "-DCLR_SAMPLER_TYPE=-1 -DCLR_SAMPLER_V4",
                       &k));
  cl_int count = (cl_int)units;
  int a = 0;
  SET_ARG(ctx, k, a++, *p);
  SET_ARG(ctx, k, a++, d->slots.mem);
  SET_ARG(ctx, k, a++, sobol32);
  SET_ARG(ctx, k, a++, sobol_groups);
  SET_ARG(ctx, k, a++, vdc);
  SET_ARG(ctx, k, a++, vdc_inv);
  SET_ARG(ctx, k, a++, primes);
  SET_ARG(ctx, k, a++, d->pmj.mem);
  SET_ARG(ctx, k, a++, d->digit_perms.mem);
  SET_ARG(ctx, k, a++, d->digit_offsets.mem);
  SET_ARG(ctx, k, a++, digit_dims);
  SET_ARG(ctx, k, a++, values);
  SET_ARG(ctx, k, a++, count);
  return launch(ctx, k, items, name);
}

/* Whether the values go straight into out->host_values: no device buffer given and a device
 * sharing the host's memory (PoCL writes them in place of a copy from its own buffer). */
static int in_host_values(clr_context ctx, const clr_sample_output *out) {
  return out->host_values && !out->device_values && clr_context_unified_memory(ctx);
}

/* The in-place values' map and unmap: the host then reads them (OpenCL's rule for
 * CL_MEM_USE_HOST_PTR; no copy where the device wrote host_values itself). */
static clr_result sync_host_values(clr_context ctx, cl_command_queue q, cl_mem values,
                                   size_t bytes) {
  cl_int err = CL_SUCCESS;
  void *at = clEnqueueMapBuffer(q, values, CL_TRUE, CL_MAP_READ, 0, bytes, 0, NULL, NULL, &err);
  if (err != CL_SUCCESS)
    return clr_fail(ctx, CLR_ERROR_OPENCL, "clEnqueueMapBuffer(sample values) failed: %s (%d)",
                    clr_cl_error_name(err), (int)err);
  CLR_CL_CHECK(ctx, clEnqueueUnmapMemObject(q, values, at, 0, NULL, NULL));
  return CLR_SUCCESS;
}

static clr_result generate_locked(clr_sampler_device *d, const clr_sampler_params *p,
                                  const clr_request_slot *slots, const float *pmj_pixels,
                                  const clr_sample_output *out, cl_mem *temp) {
  clr_context ctx = d->ctx;
  size_t items = batch_items(p);
  size_t value_bytes = items * (size_t)p->values_per_sample * sizeof(float);
  cl_mem values = out->device_values;
  if (values) {
    size_t have = 0;
    CLR_CL_CHECK(ctx, clGetMemObjectInfo(values, CL_MEM_SIZE, sizeof have, &have, NULL));
    if (have < value_bytes)
      return clr_fail(ctx, CLR_ERROR_INVALID_ARGUMENT,
                      "clr_sampler_generate: device_values holds %zu bytes, the batch needs %zu",
                      have, value_bytes);
  } else if (in_host_values(ctx, out)) {
    /* host_values differs per call: a buffer over it for this call only */
    cl_int err = CL_SUCCESS;
    *temp = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR,
                           value_bytes, out->host_values, &err);
    if (err != CL_SUCCESS) {
      *temp = NULL;
      return clr_fail(ctx, CLR_ERROR_OPENCL,
                      "clCreateBuffer(sample values, %zu bytes) failed: %s (%d)", value_bytes,
                      clr_cl_error_name(err), (int)err);
    }
    values = *temp;
  } else {
    CLR_CHECK(grow(ctx, &d->host_out, value_bytes, CL_MEM_WRITE_ONLY, "sample values"));
    values = d->host_out.mem;
  }
  cl_command_queue q = clr_context_cl_queue(ctx);
  int global =
      !p->v4_sampler && (p->type == CLR_SAMPLER_TYPE_HALTON || p->type == CLR_SAMPLER_TYPE_SOBOL);
  if (p->v4_sampler) {
    CLR_CHECK(run_v4(d, p, slots, pmj_pixels, values));
    if (out->host_indices)
      for (size_t i = 0; i < items; ++i) out->host_indices[i] = UINT64_MAX;
  } else if (global) {
    CLR_CHECK(run_global(d, p, slots, values, out->host_indices != NULL));
  } else {
    CLR_CHECK(run_pixel(d, p, slots, values));
    if (out->host_indices)
      for (size_t i = 0; i < items; ++i) out->host_indices[i] = UINT64_MAX;
  }
  if (in_host_values(ctx, out))
    CLR_CHECK(sync_host_values(ctx, q, values, value_bytes));
  else if (out->host_values)
    CLR_CL_CHECK(ctx, clEnqueueReadBuffer(q, values, CL_TRUE, 0, value_bytes, out->host_values, 0,
                                          NULL, NULL));
  if (out->host_indices && global)
    CLR_CL_CHECK(ctx, clEnqueueReadBuffer(q, d->indices.mem, CL_TRUE, 0, items * sizeof(cl_ulong),
                                          out->host_indices, 0, NULL, NULL));
  return CLR_SUCCESS;
}

clr_result clr_sampler_device_generate(clr_sampler_device *d, const clr_sampler_params *p,
                                       const clr_request_slot *slots, const float *pmj_pixels,
                                       const clr_sample_output *out) {
  cl_mem temp = NULL;
  pthread_mutex_lock(&d->lock);
  clr_result r = generate_locked(d, p, slots, pmj_pixels, out, &temp);
  /* Also after a failure: queued work may still read the plans and buffers. */
  cl_int err = clFinish(clr_context_cl_queue(d->ctx));
  pthread_mutex_unlock(&d->lock);
  if (temp) clReleaseMemObject(temp);
  if (r == CLR_SUCCESS && err != CL_SUCCESS)
    r = clr_fail(d->ctx, CLR_ERROR_OPENCL, "clFinish failed: %s (%d)", clr_cl_error_name(err),
                 (int)err);
  return r;
}
