/* Builds pbrt-v3's Halton prime and permutation tables once, and the sampler's base scales. */
#include "halton_tables.h"
#include "pbrt_v4_sampler_funcs.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* The 1000th prime is 7919. */
#define CLR_HALTON_SIEVE_LIMIT 7920

/* A table set: records, then the u16 table (permutations of `extent` primes, the base-3 identity,
 * the chunk tables), aligned so that devices sharing host memory can use it in place
 * (clr_context_shared_buffer). */
typedef struct halton_set {
  clr_halton_prime *records;
  clr_u16 *table;
  clr_u32 permutation_entries; /* sum of the first `extent` primes */
  clr_halton_tables tables;
} halton_set;

#define SET_ENTRIES(sum) ((sum) + CLR_HALTON_CHUNK_ENTRIES)
static clr_halton_prime records64[CLR_HALTON_PRIME_RECORDS], records256[CLR_HALTON_PRIME_RECORDS],
    records_all[CLR_HALTON_PRIME_RECORDS];
static _Alignas(4096) clr_u16 table64[SET_ENTRIES(8893u)];
static _Alignas(4096) clr_u16 table256[SET_ENTRIES(191755u)];
static _Alignas(4096) clr_u16 table_all[CLR_HALTON_TABLE_ENTRIES];

static halton_set sets[3] = {
    {records64,
     table64,
     8893u,
     {records64, table64, SET_ENTRIES(8893u), 64, "halton_primes_64", "halton_perms_64"}},
    {records256,
     table256,
     191755u,
     {records256, table256, SET_ENTRIES(191755u), 256, "halton_primes_256", "halton_perms_256"}},
    {records_all,
     table_all,
     CLR_HALTON_PERMUTATION_COUNT,
     {records_all, table_all, CLR_HALTON_TABLE_ENTRIES, CLR_HALTON_PRIMES, "halton_primes",
      "halton_perms"}},
};
static pthread_once_t set_once[3] = {PTHREAD_ONCE_INIT, PTHREAD_ONCE_INIT, PTHREAD_ONCE_INIT};

static void sieve_primes(clr_u32 *primes) {
  static unsigned char composite[CLR_HALTON_SIEVE_LIMIT];
  memset(composite, 0, sizeof composite);
  int count = 0;
  for (clr_u32 n = 2; n < CLR_HALTON_SIEVE_LIMIT && count < CLR_HALTON_PRIMES; ++n) {
    if (composite[n]) continue;
    primes[count++] = n;
    for (clr_u32 m = n * n; m < CLR_HALTON_SIEVE_LIMIT; m += n) composite[m] = 1;
  }
}

/* Identity then pbrt-v3's Shuffle: for i in [0,n) swap perm[i] with perm[i + UniformUInt32(n-i)]. */
static void shuffled_permutation(clr_u16 *perm, clr_u32 n, clr_pcg32 *rng) {
  for (clr_u32 i = 0; i < n; ++i) perm[i] = (clr_u16)i;
  for (clr_u32 i = 0; i < n; ++i) {
    clr_u32 other = i + clr_pcg32_bounded(rng, n - i);
    clr_u16 t = perm[i];
    perm[i] = perm[other];
    perm[other] = t;
  }
}

/* Constants of clr_halton_div32 for divisor d >= 2. */
static void division_magic(clr_u32 d, clr_u32 *magic, clr_u32 *shift) {
  clr_u32 l = 0;
  while (((clr_u64)1 << l) < d) ++l;
  *magic = (clr_u32)((((clr_u64)1 << l) - d) * ((clr_u64)1 << 32) / d + 1u);
  *shift = l - 1u;
}

/* The digits of x (exactly `digits` of them, or all significant ones when digits < 0) through
 * perm, reversed; *count receives how many were taken. */
static clr_u32 permuted_reversal(const clr_u16 *perm, clr_u32 base, clr_u32 x, int digits,
                                 clr_u32 *count) {
  clr_u32 v = 0, n = 0;
  while (digits < 0 ? x != 0 : (int)n < digits) {
    v = v * base + perm[x % base];
    x /= base;
    ++n;
  }
  *count = n;
  return v;
}

/* Fills the record of `base` whose pbrt-v3 permutation starts at perm_offset; appends its chunk
 * tables at *table_end when a chunk needs more than one digit. */
static void fill_record(clr_u16 *table, clr_u32 entries, clr_halton_prime *pr, clr_u32 base,
                        clr_u32 perm_offset, clr_u32 *table_end) {
  const clr_u16 *perm = table + perm_offset;
  pr->base = base;
  pr->perm_offset = perm_offset;
  pr->inv_base = (float)1 / (float)base;
  /* pbrt-v3: invBase * perm[0] / (1 - invBase), all float. */
  pr->scramble_tail = pr->inv_base * (float)perm[0] / (1.0f - pr->inv_base);
  division_magic(base, &pr->div_magic, &pr->div_shift);
  pr->inv_base_pow[0] = 1.0f;
  for (int k = 1; k <= CLR_HALTON_MAX_DIGITS32; ++k)
    pr->inv_base_pow[k] = pr->inv_base_pow[k - 1] * pr->inv_base;
  pr->v4_digits = (clr_u32)clr_v4_scrambled_digits(pr);
  uint64_t bound = 1u;
  for (clr_u32 k = 0; k < pr->v4_digits && bound <= ((uint64_t)1 << 32u); ++k) bound *= base;
  pr->v4_reversed32 = bound <= ((uint64_t)1 << 32u);
  clr_u32 chunk_base = base, digits = 1;
  while (chunk_base < CLR_HALTON_CHUNK_MIN) {
    chunk_base *= base;
    ++digits;
  }
  pr->chunk_base = chunk_base;
  pr->chunk_digits = digits;
  division_magic(chunk_base, &pr->chunk_magic, &pr->chunk_shift);
  pr->tail_shift = 0;
  while ((1u << pr->tail_shift) < chunk_base) ++pr->tail_shift;
  if (digits == 1) { /* the permutation itself serves as both tables (count - 1 = 0) */
    pr->chunk_offset = pr->tail_offset = perm_offset;
    return;
  }
  /* value and count - 1 must share 16 bits */
  if ((chunk_base - 1u) >> pr->tail_shift || (digits - 1u) >> (16u - pr->tail_shift)) abort();
  if (*table_end + 2u * chunk_base > entries) abort(); /* constant out of date */
  pr->chunk_offset = *table_end;
  pr->tail_offset = *table_end + chunk_base;
  clr_u16 *chunk = table + pr->chunk_offset;
  clr_u16 *tail = table + pr->tail_offset;
  for (clr_u32 d = 0; d < chunk_base; ++d) {
    clr_u32 count;
    chunk[d] = (clr_u16)permuted_reversal(perm, base, d, (int)digits, &count);
    clr_u32 value = permuted_reversal(perm, base, d, -1, &count);
    tail[d] = (clr_u16)(count ? ((count - 1u) << pr->tail_shift) | value : 0u);
  }
  *table_end += 2u * chunk_base;
}

static void build_set(halton_set *set) {
  clr_u32 primes[CLR_HALTON_PRIMES];
  sieve_primes(primes);
  const int extent = set->tables.extent;
  const clr_u32 entries = (clr_u32)set->tables.entries;
  clr_pcg32 rng = clr_pcg32_default();
  clr_u32 offset = 0;
  for (int i = 0; i < extent; ++i) {
    shuffled_permutation(set->table + offset, primes[i], &rng);
    offset += primes[i];
  }
  if (offset != set->permutation_entries) abort(); /* the constant is out of date */
  /* The unscrambled base 3 of dimension 1: identity permutation (scramble_tail 0). */
  clr_u32 identity3 = offset;
  for (clr_u16 d = 0; d < 3; ++d) set->table[identity3 + d] = d;
  clr_u32 table_end = identity3 + 3u, perm_offset = 0;
  for (int i = 0; i < extent; ++i) {
    fill_record(set->table, entries, &set->records[i], primes[i], perm_offset, &table_end);
    perm_offset += primes[i];
  }
  fill_record(set->table, entries, &set->records[CLR_HALTON_BASE3_RECORD], 3u, identity3,
              &table_end);
  if (table_end != entries) abort(); /* the constant is out of date */
}

static void build_set64(void) { build_set(&sets[0]); }
static void build_set256(void) { build_set(&sets[1]); }
static void build_set_all(void) { build_set(&sets[2]); }

const clr_halton_tables *clr_halton_tables_covering(int dimensions) {
  static void (*const build[3])(void) = {build_set64, build_set256, build_set_all};
  int i = dimensions <= 64 ? 0 : dimensions <= 256 ? 1 : 2;
  (void)pthread_once(&set_once[i], build[i]);
  return &sets[i].tables;
}

int clr_halton_layout_dimensions(const clr_request_slot *slots, int count) {
  int n = 0;
  for (int i = 0; i < count; ++i)
    if (slots[i].source + slots[i].dims > n) n = slots[i].source + slots[i].dims;
  return n;
}

const clr_halton_prime *clr_halton_primes(void) {
  return clr_halton_tables_covering(CLR_HALTON_PRIMES)->primes;
}

const clr_u16 *clr_halton_permutations(size_t *count) {
  const clr_halton_tables *t = clr_halton_tables_covering(CLR_HALTON_PRIMES);
  if (count) *count = t->entries;
  return t->permutations;
}

static clr_u32 power_of(clr_u32 base, clr_u32 m) {
  clr_u32 v = 1;
  for (clr_u32 i = 0; i < m; ++i) v *= base;
  return v;
}

static clr_u32 bits_of(clr_u32 n) { /* bits of the values below n */
  clr_u32 b = 0;
  while (((clr_u64)1 << b) < n) ++b;
  return b;
}

static clr_u32 digits_of(clr_u32 base, clr_u32 n) { /* significant base-b digits of n */
  clr_u32 count = 0;
  for (; n != 0; n /= base) ++count;
  return count;
}

/* The count shift of a pair table (kernels/halton_funcs.h): the bits of its values when their
 * digit counts fit beside them in 16 bits, else CLR_HALTON_PAIR_DERIVED_COUNTS (the kernel derives
 * the counts from hi), or 0: the values alone need more than 16 bits. */
static clr_u32 pair_count_shift(clr_u32 chunk, clr_u32 digits, clr_u32 top_power,
                                clr_u32 top_digits) {
  clr_u32 value_bits = bits_of(chunk > top_power ? chunk : top_power);
  if (value_bits + bits_of((digits > top_digits ? digits : top_digits) + 1u) <= 16u)
    return value_bits;
  return value_bits <= 16u ? CLR_HALTON_PAIR_DERIVED_COUNTS : 0u;
}

clr_halton_pair_shape clr_halton_pair_shape_for(const clr_halton_prime *pr, uint64_t limit) {
  clr_halton_pair_shape best = {0, 0}, derived = {0, 0}; /* derived: counts not stored */
  if (limit > ((uint64_t)1 << CLR_HALTON_PAIR_ARGUMENT_BITS)) return best;
  uint64_t chunk = pr->base;
  for (clr_u32 m = 1; m <= CLR_HALTON_PAIR_MAX_DIGITS && chunk <= CLR_HALTON_PAIR_MOST_ENTRIES;
       ++m, chunk *= pr->base) {
    uint64_t tops = (limit + chunk - 1u) / chunk;
    if (tops < chunk) tops = chunk; /* the top table also serves lo below a zero top part */
    if (tops > CLR_HALTON_PAIR_MOST_TOPS) continue;
    clr_u32 top_digits = digits_of(pr->base, (clr_u32)tops - 1u);
    uint64_t top_power = power_of(pr->base, top_digits);
    if (top_digits > CLR_HALTON_PAIR_MAX_DIGITS || top_power >= (1u << 16) ||
        chunk * top_power > ((uint64_t)1 << 31))
      continue;
    clr_u32 shift = pair_count_shift((clr_u32)chunk, m, (clr_u32)top_power, top_digits);
    if (shift == 0u) continue;
    clr_halton_pair_shape *keep = shift == CLR_HALTON_PAIR_DERIVED_COUNTS ? &derived : &best;
    if (keep->digits == 0 || chunk + tops < power_of(pr->base, keep->digits) + keep->tops)
      *keep = (clr_halton_pair_shape){m, (clr_u32)tops};
  }
  return best.digits ? best : derived; /* stored counts cost the kernel no comparisons */
}

size_t clr_halton_pair_entries(const clr_halton_prime *pr, clr_halton_pair_shape shape) {
  return CLR_HALTON_PAIR_HEADER + (size_t)power_of(pr->base, shape.digits) + shape.tops;
}

void clr_halton_pair_table(const clr_halton_prime *pr, const clr_u16 *permutations,
                           clr_halton_pair_shape shape, clr_u16 *out) {
  const clr_u16 *perm = permutations + pr->perm_offset;
  clr_u32 m = shape.digits, chunk = power_of(pr->base, m);
  clr_u32 top_digits = digits_of(pr->base, shape.tops - 1u);
  clr_u32 top_power = power_of(pr->base, top_digits);
  clr_u32 count_shift = pair_count_shift(chunk, m, top_power, top_digits);
  clr_u32 count_mask = count_shift < 16u ? 0xFFFFu : 0u; /* derived counts: none stored */
  /* n / chunk = (n * magic) >> shift for every n below 2^28: magic = ceil(2^(28 + l) / chunk)
   * < 2^29 with 2^l >= chunk (Granlund-Montgomery). */
  clr_u32 shift = CLR_HALTON_PAIR_ARGUMENT_BITS + bits_of(chunk);
  clr_u32 magic = (clr_u32)((((clr_u64)1 << shift) + chunk - 1u) / chunk);
  const clr_u16 header[8] = {(clr_u16)chunk, (clr_u16)magic, (clr_u16)(magic >> 16),
                             (clr_u16)shift, (clr_u16)m,     (clr_u16)count_shift};
  memcpy(out, header, sizeof header);
  for (clr_u32 k = 0; k < 8; ++k)
    out[8 + k] = (clr_u16)(k <= top_digits ? power_of(pr->base, k) : 0u);
  clr_u16 *low = out + CLR_HALTON_PAIR_HEADER, *top = low + chunk;
  clr_u32 count;
  for (clr_u32 d = 0; d < chunk; ++d)
    low[d] = (clr_u16)(permuted_reversal(perm, pr->base, d, (int)m, &count) |
                       ((m << count_shift) & count_mask));
  for (clr_u32 d = 0; d < shape.tops; ++d) {
    clr_u32 value = permuted_reversal(perm, pr->base, d, -1, &count);
    top[d] = (clr_u16)(value | ((count << count_shift) & count_mask));
  }
}

size_t clr_halton_pair_row_entries(const clr_halton_prime *pr, clr_halton_pair_shape shape) {
  clr_u32 chunk = power_of(pr->base, shape.digits);
  return chunk <= CLR_HALTON_PAIR_MOST_ROW_CHUNK ? (size_t)CLR_HALTON_PAIR_ROW * chunk : 0;
}

void clr_halton_pair_rows(const clr_halton_prime *pr, clr_halton_pair_shape shape, clr_u32 step,
                          clr_u16 *table) {
  size_t at = clr_halton_pair_entries(pr, shape);
  clr_u32 chunk = power_of(pr->base, shape.digits);
  const clr_u16 *low = table + CLR_HALTON_PAIR_HEADER;
  clr_u16 *row = table + at;
  for (clr_u32 r = 0; r < chunk; ++r, row += CLR_HALTON_PAIR_ROW)
    for (clr_u32 j = 0; j < CLR_HALTON_PAIR_ROW; ++j) row[j] = low[(r + (clr_u64)j * step) % chunk];
  table[6] = (clr_u16)at;
  table[7] = (clr_u16)(at >> 16);
}

/* x with a * x = 1 (mod n), in [0, n) (0 when n == 1); a and n coprime. Extended Euclid. */
static clr_i64 multiplicative_inverse(clr_i64 a, clr_i64 n) {
  clr_i64 r0 = a, r1 = n, x0 = 1, x1 = 0;
  while (r1 != 0) {
    clr_i64 q = r0 / r1, t = r0 - q * r1;
    r0 = r1;
    r1 = t;
    t = x0 - q * x1;
    x0 = x1;
    x1 = t;
  }
  clr_i64 m = x0 % n;
  return m < 0 ? m + n : m;
}

void clr_halton_setup(clr_sampler_params *p) {
  clr_i32 res[2] = {p->sample_x1 - p->sample_x0, p->sample_y1 - p->sample_y0};
  for (int i = 0; i < 2; ++i) {
    clr_i32 base = i == 0 ? 2 : 3, scale = 1, exponent = 0;
    clr_i32 target = res[i] < CLR_HALTON_MAX_RESOLUTION ? res[i] : CLR_HALTON_MAX_RESOLUTION;
    while (scale < target) {
      scale *= base;
      ++exponent;
    }
    p->halton_scale[i] = scale;
    p->halton_exponent[i] = exponent;
  }
  p->halton_stride = p->halton_scale[0] * p->halton_scale[1];
  p->halton_mult_inverse[0] =
      (clr_u32)multiplicative_inverse(p->halton_scale[1], p->halton_scale[0]);
  p->halton_mult_inverse[1] =
      (clr_u32)multiplicative_inverse(p->halton_scale[0], p->halton_scale[1]);
}
