/* The host's fast Halton values: per-record pair tables for a sampler's indices, and the sample
 * vector of one batch item from them. */
#include "halton_host.h"

#include <stdlib.h>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

/* Entries of one set's tables at most (4 MiB); records past it keep the chunk loop. */
#define HOST_PAIR_BUDGET ((size_t)1 << 21)

/* The record of dimension d >= 1 and the limit of its arguments for indices below index_limit
 * (capped where pair tables end). */
static int record_of(int d) { return d == 1 ? CLR_HALTON_BASE3_RECORD : d; }

static uint64_t argument_limit(int d, uint64_t index_limit, clr_u32 scale1) {
  uint64_t limit = d == 1 ? index_limit / scale1 + (index_limit % scale1 != 0) : index_limit;
  uint64_t most = (uint64_t)1 << CLR_HALTON_PAIR_ARGUMENT_BITS;
  return limit < most ? limit : most;
}

clr_halton_host_pairs *clr_halton_host_pairs_create(int dimensions, uint64_t index_limit,
                                                    clr_u32 scale1) {
  if (dimensions > CLR_HALTON_PRIMES) dimensions = CLR_HALTON_PRIMES;
  clr_halton_host_pairs *hp = calloc(1, sizeof *hp);
  if (!hp) return NULL;
  hp->tables = clr_halton_tables_covering(dimensions);
  hp->dimensions = dimensions;
  hp->index_limit = index_limit;
  const clr_halton_prime *primes = hp->tables->primes;
  clr_halton_pair_shape shapes[CLR_HALTON_PRIME_RECORDS] = {{0, 0}};
  size_t size = 0;
  for (int d = 1; d < dimensions; ++d) {
    int r = record_of(d);
    uint64_t limit = argument_limit(d, index_limit, scale1);
    clr_halton_pair_shape shape = clr_halton_pair_shape_for(&primes[r], limit);
    if (shape.digits == 0 || limit == 0) continue;
    size_t entries = clr_halton_pair_entries(&primes[r], shape);
    if (size + entries > HOST_PAIR_BUDGET) continue;
    shapes[r] = shape;
    hp->limit[r] = (clr_u32)limit;
    hp->offset[r] = (clr_u32)size;
    size += entries;
  }
  hp->entries = malloc(sizeof(clr_u16) * (size ? size : 1));
  if (!hp->entries) {
    free(hp);
    return NULL;
  }
  for (int r = 0; r < CLR_HALTON_PRIME_RECORDS; ++r)
    if (hp->limit[r])
      clr_halton_pair_table(&primes[r], hp->tables->permutations, shapes[r],
                            hp->entries + hp->offset[r]);
  return hp;
}

void clr_halton_host_pairs_free(clr_halton_host_pairs *hp) {
  while (hp) {
    clr_halton_host_pairs *older = hp->older;
    free(hp->entries);
    free(hp);
    hp = older;
  }
}

/* clr_halton_pair_value's table reads with the header read once: the same integers and float
 * operations, so the same bits. */
typedef struct pair_reader {
  const clr_u16 *low_entries, *top_entries, *powers;
  const float *inv_base_pow;
  float scramble_tail;
  clr_u32 chunk, magic, shift, count_shift, value_mask, low_digits;
  clr_u32 reach[CLR_HALTON_PAIR_ROW]; /* the header's powers, UINT32_MAX past the top */
} pair_reader;

static pair_reader pair_reader_of(const clr_halton_prime *pr, const clr_u16 *pt) {
  pair_reader r;
  r.chunk = pt[0];
  r.magic = (clr_u32)pt[1] | (clr_u32)pt[2] << 16u;
  r.shift = pt[3];
  r.low_digits = pt[4];
  r.count_shift = pt[5];
  r.value_mask = (1u << r.count_shift) - 1u;
  r.powers = pt + 8;
  int top = 0;
  while (top < CLR_HALTON_PAIR_ROW && pt[8 + top] != 0u) ++top;
  for (int k = 0; k < CLR_HALTON_PAIR_ROW; ++k) r.reach[k] = k < top ? pt[8 + k] : UINT32_MAX;
  r.low_entries = pt + CLR_HALTON_PAIR_HEADER;
  r.top_entries = r.low_entries + r.chunk;
  r.inv_base_pow = pr->inv_base_pow;
  r.scramble_tail = pr->scramble_tail;
  return r;
}

/* (float)reversed, converted into a zeroed register where the compiler has SSE2: the plain
 * conversion merges into its destination, which chains each value's float operations to the
 * previous value's. */
static inline float int_to_float(clr_i32 reversed) {
#if defined(__SSE2__)
  return _mm_cvtss_f32(_mm_cvtsi32_ss(_mm_setzero_ps(), reversed));
#else
  return (float)reversed;
#endif
}

/* clr_halton_pair_value(a). derived: the table's count shift is CLR_HALTON_PAIR_DERIVED_COUNTS. */
static inline float pair_read(const pair_reader *r, int derived, clr_u32 a) {
  clr_u32 hi = (clr_u32)(((clr_u64)a * r->magic) >> r->shift);
  clr_u32 lo = a - hi * r->chunk;
  clr_u32 low = (hi == 0u ? r->top_entries : r->low_entries)[lo];
  clr_u32 high = r->top_entries[hi];
  clr_u32 count = high >> r->count_shift, digits = (low >> r->count_shift) + count;
  if (derived) {
    clr_u32 x = hi != 0u ? hi : a, c = 0u;
    for (int k = 0; k < CLR_HALTON_PAIR_ROW; ++k) c += x >= r->reach[k] ? 1u : 0u;
    count = hi != 0u ? c : 0u;
    digits = c + (hi != 0u ? r->low_digits : 0u);
  }
  clr_u32 reversed = (low & r->value_mask) * r->powers[count] + (high & r->value_mask);
  float v = r->inv_base_pow[digits] * (int_to_float((clr_i32)reversed) + r->scramble_tail);
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
}

/* The pair-table argument of index: index / scale[1] for dimension 1 (base3), else index. */
static inline clr_u64 pair_argument(const clr_sampler_params *p, int base3, clr_u64 index) {
  return base3 ? clr_halton_drop_base3_digits(p, index) : index;
}

/* out[i * stride] for the items of index whose arguments are below limit (the others are left);
 * 1 when there were such. The reader is copied so that its fields stay in registers. */
static inline int read_run(const pair_reader *reader, int derived, const clr_sampler_params *p,
                           int base3, clr_u64 limit, const clr_u64 *index, clr_i32 n, float *out,
                           size_t stride) {
  const pair_reader r = *reader;
  int past_limit = 0;
  for (clr_i32 i = 0; i < n; ++i) {
    clr_u64 a = pair_argument(p, base3, index[i]);
    if (a >= limit) {
      past_limit = 1;
      continue;
    }
    out[(size_t)i * stride] = pair_read(&r, derived, (clr_u32)a);
  }
  return past_limit;
}

/* One dimension's values, from its pair table where the argument is below its limit, else from
 * clr_halton_sampler_value. base3: the arguments are index / scale[1] (dimension 1). */
static void pair_values(const clr_halton_host_pairs *hp, const clr_sampler_params *p, int record,
                        int base3, const clr_u64 *index, clr_i32 n, float *out, size_t stride) {
  const clr_halton_prime *primes = hp->tables->primes, *pr = &primes[record];
  const clr_u16 *pt = hp->entries + hp->offset[record], *perms = hp->tables->permutations;
  clr_u64 limit = hp->limit[record];
  const pair_reader r = pair_reader_of(pr, pt);
  const int derived = r.count_shift == CLR_HALTON_PAIR_DERIVED_COUNTS;
  /* constant flags where they matter, so that each kind of table gets its own loop */
  int past_limit = base3     ? read_run(&r, derived, p, 1, limit, index, n, out, stride)
                   : derived ? read_run(&r, 1, p, 0, limit, index, n, out, stride)
                             : read_run(&r, 0, p, 0, limit, index, n, out, stride);
  if (!past_limit) return;
  for (clr_i32 i = 0; i < n; ++i)
    if (pair_argument(p, base3, index[i]) >= limit)
      out[(size_t)i * stride] =
          clr_halton_sampler_value(p, primes, perms, index[i], base3 ? 1 : record);
}

void clr_halton_host_values(const clr_halton_host_pairs *hp, const clr_sampler_params *p,
                            clr_i32 dim, const clr_u64 *index, clr_i32 n, float *out,
                            size_t stride) {
  clr_u32 udim = (clr_u32)dim;
  if (udim == 0u && !p->sample_pixel_center) {
    clr_u32 shift = (clr_u32)p->halton_exponent[0];
    for (clr_i32 i = 0; i < n; ++i)
      out[(size_t)i * stride] = clr_radical_inverse_base2(index[i] >> shift);
    return;
  }
  if (udim == 1u && !p->sample_pixel_center && hp->limit[CLR_HALTON_BASE3_RECORD]) {
    pair_values(hp, p, CLR_HALTON_BASE3_RECORD, 1, index, n, out, stride);
    return;
  }
  if (udim >= 2u && udim < CLR_HALTON_PRIMES && hp->limit[udim]) {
    pair_values(hp, p, dim, 0, index, n, out, stride);
    return;
  }
  const clr_halton_prime *primes = hp->tables->primes;
  const clr_u16 *perms = hp->tables->permutations;
  for (clr_i32 i = 0; i < n; ++i)
    out[(size_t)i * stride] = clr_halton_sampler_value(p, primes, perms, index[i], dim);
}

/* Items [first, first + n) of the batch: indices of sample numbers s * scale + offset (slot 0:
 * the item's own sample, arrays: element `offset` of `scale`), one pixel's offset per pixel. */
static void block_indices(const clr_sampler_params *p, clr_i32 first, clr_i32 n, clr_i64 scale,
                          clr_i64 offset, clr_u64 *index) {
  clr_i32 pixel = -1;
  clr_u64 pixel_offset = 0;
  for (clr_i32 i = 0; i < n; ++i) {
    clr_i32 item = first + i, at = item / p->sample_count;
    if (at != pixel) {
      pixel = at;
      pixel_offset = clr_halton_sampler_index(p, p->batch_x0 + at % p->batch_width,
                                              p->batch_y0 + at / p->batch_width, 0);
    }
    clr_i64 s = p->first_sample + (item - at * p->sample_count);
    index[i] = pixel_offset + (clr_u64)(s * scale + offset) * (clr_u64)(clr_u32)p->halton_stride;
  }
}

void clr_halton_host_batch(const clr_halton_host_pairs *hp, const clr_sampler_params *p,
                           const clr_request_slot *slots, float *values, clr_u64 *indices) {
  clr_i32 items = p->batch_width * p->batch_height * p->sample_count;
  size_t per_sample = (size_t)p->values_per_sample;
  clr_u64 own[CLR_HALTON_HOST_BLOCK], element[CLR_HALTON_HOST_BLOCK];
  for (clr_i32 first = 0; first < items; first += CLR_HALTON_HOST_BLOCK) {
    clr_i32 n = items - first < CLR_HALTON_HOST_BLOCK ? items - first : CLR_HALTON_HOST_BLOCK;
    float *out = values + (size_t)first * per_sample;
    block_indices(p, first, n, 1, 0, own);
    if (indices)
      for (clr_i32 i = 0; i < n; ++i) indices[first + i] = own[i];
    for (clr_i32 r = 0; r < p->request_count; ++r) {
      const clr_request_slot *sl = &slots[r];
      if (sl->skipped) continue;
      if (sl->array_size == 0) {
        for (clr_i32 c = 0; c < sl->dims; ++c)
          clr_halton_host_values(hp, p, sl->source + c, own, n, out + sl->first_value + c,
                                 per_sample);
        continue;
      }
      for (clr_i32 j = 0; j < sl->array_size; ++j) {
        block_indices(p, first, n, sl->array_size, j, element);
        for (clr_i32 c = 0; c < sl->dims; ++c)
          clr_halton_host_values(hp, p, sl->source + c, element, n,
                                 out + sl->first_value + j * sl->dims + c, per_sample);
      }
    }
  }
}
