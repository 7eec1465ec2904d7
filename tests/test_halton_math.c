/* Halton sampler math: exact radical inverses, pbrt-v3's tables, pixel-to-index mapping, and the
 * device build of kernels/halton_funcs.h giving the host's bits. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>
#include "clrender.h"
#include "global_sampler_funcs.h"
#include "halton_host.h"
#include "halton_tables.h"

/* ---- references written the plain way pbrt-v3 does it (64-bit division, float ops) ---- */

static float ref_radical_inverse(clr_u64 base, clr_u64 a) {
  const float inv_base = (float)1 / (float)base;
  clr_u64 reversed = 0;
  float inv_base_n = 1;
  while (a) {
    clr_u64 next = a / base;
    reversed = reversed * base + (a - next * base);
    inv_base_n *= inv_base;
    a = next;
  }
  float v = reversed * inv_base_n;
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
}

static float ref_scrambled(clr_u64 base, const clr_u16 *perm, clr_u64 a) {
  const float inv_base = (float)1 / (float)base;
  clr_u64 reversed = 0;
  float inv_base_n = 1;
  while (a) {
    clr_u64 next = a / base;
    reversed = reversed * base + perm[a - next * base];
    inv_base_n *= inv_base;
    a = next;
  }
  float v = inv_base_n * (reversed + inv_base * perm[0] / (1 - inv_base));
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
}

/* pbrt-v3 RadicalInverse(0, a) with real double arithmetic. */
static float ref_base2_double(clr_u64 a) {
  return (float)((double)clr_reverse_bits64(a) * 0x1p-64);
}

static clr_u64 random_u64(clr_pcg32 *rng) {
  clr_u64 hi = clr_pcg32_next(rng);
  return (hi << 32) | clr_pcg32_next(rng);
}

static clr_u32 float_bits(float f) { return clr_as_uint(f); }

#define assert_float_bits_equal(a, b) assert_int_equal(float_bits(a), float_bits(b))

/* ---- tables ---- */

static void test_primes(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u32 first[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29};
  for (int i = 0; i < 10; ++i) assert_int_equal(pr[i].base, first[i]);
  assert_int_equal(pr[999].base, 7919);
  assert_int_equal(pr[500].base, 3581);
  clr_u32 offset = 0;
  for (int i = 0; i < CLR_HALTON_PRIMES; ++i) {
    clr_u32 b = pr[i].base;
    if (i > 0) assert_true(b > pr[i - 1].base);
    for (clr_u32 d = 2; d * d <= b; ++d) assert_true(b % d != 0);
    assert_int_equal(pr[i].perm_offset, offset);
    assert_float_bits_equal(pr[i].inv_base, 1.0f / (float)b);
    offset += b;
  }
  assert_int_equal(offset, CLR_HALTON_PERMUTATION_COUNT);
  /* Base 2, perm {1, 0}: tail = 0.5 * 1 / 0.5 = 1 exactly. Base 5, perm[0] = 3: 0.2f*3/0.8f. */
  assert_float_bits_equal(pr[0].scramble_tail, 1.0f);
  assert_float_bits_equal(pr[2].scramble_tail, (0.2f * 3.0f) / (1.0f - 0.2f));
  assert_float_equal(pr[2].scramble_tail, 0.75f, 1e-7f);
  assert_float_bits_equal(CLR_HALTON_INV_3, 1.0f / 3.0f);
  /* pbrt-v3's invBaseN after k digits is the running float product. */
  float running = 1.0f;
  for (int k = 0; k <= CLR_HALTON_MAX_DIGITS32; ++k, running *= pr[2].inv_base)
    assert_float_bits_equal(pr[2].inv_base_pow[k], running);
  /* pbrt-v4's nDigits (DigitPermutation's loop), and whether base^nDigits fits 32 bits. */
  const struct {
    int record;
    clr_u32 digits, fits32;
  } v4[] = {{0, 25, 1}, {1, 17, 1}, {2, 12, 1}, {3, 10, 1}, {30, 5, 0}, {999, 3, 0}};
  for (int i = 0; i < 6; ++i) {
    assert_int_equal(pr[v4[i].record].v4_digits, v4[i].digits);
    assert_int_equal(pr[v4[i].record].v4_reversed32, v4[i].fits32);
  }
  for (int i = 0; i < CLR_HALTON_PRIMES; ++i)
    assert_true(pr[i].v4_digits <= CLR_HALTON_MAX_DIGITS32);
  /* Chunks: base 5 takes 4 digits (625), 11 three (1331), 127 two, 131 one (its permutation). */
  assert_int_equal(pr[2].chunk_base, 625);
  assert_int_equal(pr[4].chunk_digits, 3);
  assert_int_equal(pr[30].base, 127);
  assert_int_equal(pr[30].chunk_base, 127 * 127);
  assert_int_equal(pr[31].chunk_digits, 1);
  assert_int_equal(pr[31].chunk_offset, pr[31].perm_offset);
  /* The unscrambled base-3 record of dimension 1. */
  const clr_halton_prime *b3 = &pr[CLR_HALTON_BASE3_RECORD];
  const clr_u16 *perms = clr_halton_permutations(NULL);
  assert_int_equal(b3->base, 3);
  assert_int_equal(b3->chunk_base, 243);
  assert_float_bits_equal(b3->scramble_tail, 0.0f);
  for (clr_u16 d = 0; d < 3; ++d) assert_int_equal(perms[b3->perm_offset + d], d);
  /* 5-digit chunk 1 = 00001_3 reversed is 10000_3 = 81; tail of 5 = 12_3 is 21_3 = 7, 2 digits. */
  assert_int_equal(perms[b3->chunk_offset + 1], 81);
  assert_int_equal(perms[b3->tail_offset + 5], (1u << b3->tail_shift) | 7u);
}

static void test_permutations(void **state) {
  (void)state;
  size_t count = 0;
  const clr_u16 *perms = clr_halton_permutations(&count);
  assert_int_equal(count, CLR_HALTON_TABLE_ENTRIES);
  assert_ptr_equal(clr_halton_permutations(NULL), perms);
  const clr_halton_prime *pr = clr_halton_primes();
  static unsigned char seen[8000];
  for (int i = 0; i < CLR_HALTON_PRIMES; ++i) {
    memset(seen, 0, pr[i].base);
    for (clr_u32 j = 0; j < pr[i].base; ++j) {
      clr_u16 v = perms[pr[i].perm_offset + j];
      assert_true(v < pr[i].base);
      assert_false(seen[v]);
      seen[v] = 1;
    }
  }
  /* Values from an independent big-integer script of pbrt-v3's default RNG + Shuffle. */
  const clr_u16 p2[] = {1, 0}, p3[] = {1, 0, 2}, p5[] = {3, 2, 1, 4, 0},
                p7[] = {3, 1, 0, 5, 2, 4, 6}, p11[] = {0, 9, 5, 3, 4, 2, 10, 6, 8, 1, 7};
  const clr_u16 p3581[] = {1857, 1710, 290, 1785, 1130, 2792, 3314, 2893};
  const clr_u16 p7919[] = {3238, 4543, 7597, 5332, 4638, 877, 5077, 5885};
  assert_memory_equal(perms + pr[0].perm_offset, p2, sizeof p2);
  assert_memory_equal(perms + pr[1].perm_offset, p3, sizeof p3);
  assert_memory_equal(perms + pr[2].perm_offset, p5, sizeof p5);
  assert_memory_equal(perms + pr[3].perm_offset, p7, sizeof p7);
  assert_memory_equal(perms + pr[4].perm_offset, p11, sizeof p11);
  assert_memory_equal(perms + pr[500].perm_offset, p3581, sizeof p3581);
  assert_memory_equal(perms + pr[999].perm_offset, p7919, sizeof p7919);
}

/* Record `r` of set `t` holds the same values as record `r` of the full set `all`: the same
 * permutation, chunk and tail tables (at the set's own offsets) and constants. */
static void assert_same_record(const clr_halton_tables *t, const clr_halton_tables *all, int r) {
  const clr_halton_prime *a = &t->primes[r], *b = &all->primes[r];
  assert_int_equal(a->base, b->base);
  assert_memory_equal(t->permutations + a->perm_offset, all->permutations + b->perm_offset,
                      a->base * sizeof(clr_u16));
  assert_true(a->scramble_tail == b->scramble_tail);
  assert_memory_equal(a->inv_base_pow, b->inv_base_pow, sizeof a->inv_base_pow);
  assert_int_equal(a->chunk_base, b->chunk_base);
  assert_int_equal(a->div_magic, b->div_magic);
  assert_int_equal(a->chunk_magic, b->chunk_magic);
  assert_int_equal(a->tail_shift, b->tail_shift);
  assert_memory_equal(t->permutations + a->chunk_offset, all->permutations + b->chunk_offset,
                      a->chunk_base * sizeof(clr_u16));
  assert_memory_equal(t->permutations + a->tail_offset, all->permutations + b->tail_offset,
                      a->chunk_base * sizeof(clr_u16));
}

/* The smaller table sets (a render reads only its layout's dimensions) agree with the full one on
 * every prime they cover and on the base-3 record, and leave the others empty. */
static void test_table_sets(void **state) {
  (void)state;
  const clr_halton_tables *all = clr_halton_tables_covering(CLR_HALTON_PRIMES);
  assert_int_equal(all->extent, CLR_HALTON_PRIMES);
  assert_ptr_equal(all->primes, clr_halton_primes());
  assert_ptr_equal(clr_halton_tables_covering(1001), all);
  const int dims[] = {0, 64, 65, 256};
  const int extents[] = {64, 64, 256, 256};
  for (int k = 0; k < 4; ++k) {
    const clr_halton_tables *t = clr_halton_tables_covering(dims[k]);
    assert_int_equal(t->extent, extents[k]);
    assert_int_equal(t->entries, all->entries - CLR_HALTON_PERMUTATION_COUNT +
                                     all->primes[t->extent].perm_offset);
    for (int r = 0; r < t->extent; ++r) assert_same_record(t, all, r);
    assert_same_record(t, all, CLR_HALTON_BASE3_RECORD);
    assert_int_equal(t->primes[t->extent].base, 0);
    assert_int_equal(t->primes[CLR_HALTON_PRIMES - 1].base, 0);
  }
  clr_request_slot slots[3] = {
      {2, 0, 0, 0, 0, 0.0f, 0, 0}, {1, 0, 2, 2, 0, 0.0f, 0, 0}, {2, 4, 3, 70, 0, 0.25f, 0, 0}};
  assert_int_equal(clr_halton_layout_dimensions(slots, 2), 3);
  assert_int_equal(clr_halton_layout_dimensions(slots, 3), 72);
}

static void test_division_magic(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  clr_pcg32 rng = clr_pcg32_sequence(7);
  for (int i = 0; i < CLR_HALTON_PRIMES; ++i) {
    clr_u32 d = pr[i].base;
    clr_u32 top = 0xffffffffu / d * d;
    const clr_u32 edges[] = {0,       1,   d - 1,       d,           d + 1,      2 * d - 1,
                             top - 1, top, 0xffffffffu, 0x80000000u, 0x7fffffffu};
    for (size_t k = 0; k < sizeof edges / sizeof edges[0]; ++k)
      assert_int_equal(clr_halton_div32(edges[k], pr[i].div_magic, pr[i].div_shift), edges[k] / d);
    for (int k = 0; k < 2000; ++k) {
      clr_u32 n = clr_pcg32_next(&rng) >> (k % 32);
      assert_int_equal(clr_halton_div32(n, pr[i].div_magic, pr[i].div_shift), n / d);
    }
  }
  /* Dense sweeps for the smallest and largest odd bases. */
  const int sweep[] = {1, 999};
  for (int s = 0; s < 2; ++s) {
    const clr_halton_prime *p = &pr[sweep[s]];
    for (clr_u32 n = 0; n < (1u << 22); ++n)
      if (clr_halton_div32(n, p->div_magic, p->div_shift) != n / p->base) fail();
    for (clr_u32 n = 0xffffffffu; n > 0xffffffffu - (1u << 22); --n)
      if (clr_halton_div32(n, p->div_magic, p->div_shift) != n / p->base) fail();
  }
}

/* ---- radical inverses ---- */

static void test_base2_exact(void **state) {
  (void)state;
  assert_float_bits_equal(clr_radical_inverse_base2(0), 0.0f);
  assert_float_bits_equal(clr_radical_inverse_base2(1), 0.5f);
  assert_float_bits_equal(clr_radical_inverse_base2(2), 0.25f);
  assert_float_bits_equal(clr_radical_inverse_base2(3), 0.75f);
  assert_float_bits_equal(clr_radical_inverse_base2(6), 0.375f);
  assert_float_bits_equal(clr_radical_inverse_base2(5), 0.625f);
  assert_float_bits_equal(clr_radical_inverse_base2((clr_u64)1 << 32), 0x1p-33f);
  assert_float_bits_equal(clr_radical_inverse_base2((clr_u64)1 << 63), 0x1p-64f);
  assert_float_bits_equal(clr_radical_inverse_base2(((clr_u64)1 << 63) | 1u), 0.5f);
  /* 0.111...1 (25 ones) = 1 - 2^-25 is a tie between 0x1.fffffep-1 and 1: even wins, so pbrt-v3
   * (no clamp on this path) returns 1. 24 ones stay below one. */
  assert_float_bits_equal(clr_radical_inverse_base2((1u << 25) - 1u), 1.0f);
  assert_float_bits_equal(clr_radical_inverse_base2((1u << 24) - 1u), 0x1.fffffep-1f);
  /* Double rounding: 2^-1 + 2^-25 + 2^-55 is above the float tie at 2^-25, but 2^-55 is below
   * half a double ulp (2^-54), so the double is the tie itself, which rounds to even: 0.5.
   * A single rounding would give 0.5 + 2^-24. */
  clr_u64 a = 1u | ((clr_u64)1 << 24) | ((clr_u64)1 << 54);
  assert_float_bits_equal(clr_radical_inverse_base2(a), 0.5f);
  assert_float_bits_equal(ref_base2_double(a), 0.5f);
  /* Adding 2^-54 puts the double past the tie (rounds up to + 2^-53): 0.5 + 2^-24. */
  a |= (clr_u64)1 << 53;
  assert_float_bits_equal(clr_radical_inverse_base2(a), 0.5f + 0x1p-24f);
}

static void test_base2_matches_double(void **state) {
  (void)state;
  clr_pcg32 rng = clr_pcg32_sequence(11);
  for (int i = 0; i < 100000; ++i) {
    clr_u64 a = random_u64(&rng) >> (clr_pcg32_next(&rng) % 64);
    if (clr_radical_inverse_base2(a) != ref_base2_double(a) &&
        float_bits(clr_radical_inverse_base2(a)) != float_bits(ref_base2_double(a)))
      fail_msg("a = 0x%llx", (unsigned long long)a);
  }
  /* Reversed values built around both rounding points: 24-bit mantissa, then tie-ish patterns at
   * the float's half bit, the double's half bit and the sticky bits. */
  const clr_u64 mid[] = {0, 0xfffffffull, 0x5555555ull, 0x8000000ull, 1};
  const clr_u64 low[] = {0, 0x400, 0x3ff, 0x401, 0x7ff, 1, 0x200};
  for (int i = 0; i < 20000; ++i) {
    clr_u64 v = ((clr_u64)(clr_pcg32_next(&rng) | 0x800000u) & 0xffffffu) << 40;
    v |= (clr_u64)(clr_pcg32_next(&rng) & 1u) << 39;
    v |= mid[clr_pcg32_next(&rng) % 5] << 11;
    v |= low[clr_pcg32_next(&rng) % 7];
    v >>= clr_pcg32_next(&rng) % 12;
    clr_u64 a = clr_reverse_bits64(v);
    if (float_bits(clr_radical_inverse_base2(a)) != float_bits(ref_base2_double(a)))
      fail_msg("a = 0x%llx", (unsigned long long)a);
  }
}

static void test_radical_inverse_values(void **state) {
  (void)state;
  const float third = 1.0f / 3.0f;
  assert_float_bits_equal(clr_radical_inverse(3, third, 0), 0.0f);
  assert_float_bits_equal(clr_radical_inverse(3, third, 1), third);
  assert_float_bits_equal(clr_radical_inverse(3, third, 2), 2.0f * third);
  /* 5 = 12_3 -> 0.21_3 = 2/3 + 1/9 = 7/9, as 7 * (third * third) in float. */
  assert_float_bits_equal(clr_radical_inverse(3, third, 5), 7.0f * (third * third));
  assert_float_equal(clr_radical_inverse(3, third, 5), 7.0f / 9.0f, 1e-7f);
  /* 3 = 10_3 -> 0.01_3 = 1/9. */
  assert_float_equal(clr_radical_inverse(3, third, 3), 1.0f / 9.0f, 1e-8f);
  assert_float_bits_equal(clr_radical_inverse(2, 0.5f, 6), 0.375f);
  assert_float_equal(clr_radical_inverse(5, 0.2f, 7), 2.0f / 5.0f + 1.0f / 25.0f, 1e-7f);
  /* Near-one values clamp to OneMinusEpsilon: 3^20 - 1 has 20 digits 2. */
  clr_u64 all_twos = 3486784400ull;
  assert_true(clr_radical_inverse(3, third, all_twos) <= CLR_ONE_MINUS_EPSILON);

  const clr_u32 bases[] = {2, 3, 5, 7, 11, 131, 7919};
  clr_pcg32 rng = clr_pcg32_sequence(3);
  for (int i = 0; i < 30000; ++i) {
    clr_u32 b = bases[i % 7];
    clr_u64 a = random_u64(&rng) >> (clr_pcg32_next(&rng) % 64);
    assert_float_bits_equal(clr_radical_inverse(b, (float)1 / (float)b, a),
                            ref_radical_inverse(b, a));
  }
}

static void test_scrambled_values(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  /* Base 2, perm {1,0}: a = 0 means every digit 0 -> 1: 0.111... = 1, clamped. */
  assert_float_bits_equal(clr_scrambled_radical_inverse(&pr[0], perms, 0), CLR_ONE_MINUS_EPSILON);
  /* Base 5, perm {3,2,1,4,0}: a = 1 -> digits 2, then 3 forever: 2/5 + (3/25) / (4/5) = 0.55. */
  float v = clr_scrambled_radical_inverse(&pr[2], perms, 1);
  assert_float_bits_equal(v, 0.2f * (2.0f + pr[2].scramble_tail));
  assert_float_equal(v, 0.55f, 1e-7f);
  /* a = 7 = 12_5 -> digits 2 -> 1, 1 -> 2: 0.12333..._5 = 1/5 + 2/25 + 3/125/(4/5) = 0.31. */
  assert_float_equal(clr_scrambled_radical_inverse(&pr[2], perms, 7), 0.31f, 1e-7f);

  clr_pcg32 rng = clr_pcg32_sequence(5);
  for (int i = 0; i < 60000; ++i) {
    int dim = (int)(clr_pcg32_next(&rng) % CLR_HALTON_PRIMES);
    clr_u64 a = random_u64(&rng) >> (clr_pcg32_next(&rng) % 64);
    float got = clr_scrambled_radical_inverse(&pr[dim], perms, a);
    float want = ref_scrambled(pr[dim].base, perms + pr[dim].perm_offset, a);
    if (float_bits(got) != float_bits(want))
      fail_msg("dim %d a 0x%llx: %a != %a", dim, (unsigned long long)a, got, want);
  }
}

/* The loop-free 32-bit path (chunk tables) against the plain digit loop, for every record. */
static void test_chunked_path(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  clr_pcg32 rng = clr_pcg32_sequence(21);
  for (int r = 0; r < CLR_HALTON_PRIME_RECORDS; ++r) {
    clr_u32 b = pr[r].base;
    const clr_u16 *perm = perms + pr[r].perm_offset;
    clr_u32 values[64 + 40];
    int n = 0;
    values[n++] = 0;
    values[n++] = 0xffffffffu;
    for (clr_u64 power = b; power <= 0xffffffffull && n < 40; power *= b) {
      values[n++] = (clr_u32)power;
      values[n++] = (clr_u32)(power - 1);
      values[n++] = (clr_u32)(power + 1);
    }
    while (n < (int)(sizeof values / sizeof values[0]))
      values[n++] = clr_pcg32_next(&rng) >> (clr_pcg32_next(&rng) % 32);
    for (int i = 0; i < n; ++i) {
      float got = clr_scrambled_radical_inverse32(&pr[r], perms, values[i]);
      float want = ref_scrambled(b, perm, values[i]);
      if (float_bits(got) != float_bits(want))
        fail_msg("record %d a %u: %a != %a", r, values[i], got, want);
      if (r == CLR_HALTON_BASE3_RECORD)
        assert_float_bits_equal(got, ref_radical_inverse(3, values[i]));
    }
  }
}

/* A pair table's lane rows (kernels/halton_funcs.h): row r holds the lo entries of
 * (r + j * step) mod B, so lane j of arguments a_0 + j * step, a_0 = hi * B + r with hi > 0,
 * finds its lo entry at row r, column j; the header gives the rows' offset. Index strides of a
 * 512^2 film (31104) and a 7x5 one (8 * 9), dimension 1's step scale[0]; arguments below
 * 31104 * 16 (base 7919 has no pair table for them). Tables with B above
 * CLR_HALTON_PAIR_MOST_ROW_CHUNK have none. */
static void test_pair_lane_rows(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  const int records[] = {2, 3, 7, 40, 500, CLR_HALTON_PRIMES - 1, CLR_HALTON_BASE3_RECORD};
  const clr_u32 steps[] = {31104, 72, 128, 8};
  int tested = 0;
  for (size_t i = 0; i < sizeof records / sizeof records[0]; ++i)
    for (size_t k = 0; k < sizeof steps / sizeof steps[0]; ++k) {
      const clr_halton_prime *p = &pr[records[i]];
      clr_halton_pair_shape shape = clr_halton_pair_shape_for(p, 31104u * 16u);
      if (shape.digits == 0) continue;
      size_t entries = clr_halton_pair_entries(p, shape);
      size_t rows = clr_halton_pair_row_entries(p, shape);
      clr_u32 chunk = 1;
      for (clr_u32 m = 0; m < shape.digits; ++m) chunk *= p->base;
      assert_int_equal(rows, chunk <= CLR_HALTON_PAIR_MOST_ROW_CHUNK ? 8u * chunk : 0u);
      clr_u16 *t = calloc(entries + rows, sizeof *t);
      assert_non_null(t);
      clr_halton_pair_table(p, perms, shape, t);
      assert_int_equal(t[6] | t[7] << 16, 0);
      if (rows) {
        clr_halton_pair_rows(p, shape, steps[k], t);
        ++tested;
        assert_int_equal((size_t)(t[6] | (clr_u32)t[7] << 16), entries);
        for (clr_u32 a0 = chunk; a0 < 31104u * 8u; a0 += 997u) {
          clr_u32 r = a0 % chunk;
          for (clr_u32 j = 0; j < 8; ++j) {
            clr_u32 lo = (a0 + j * steps[k]) % chunk;
            assert_int_equal(t[entries + 8u * r + j], t[CLR_HALTON_PAIR_HEADER + lo]);
          }
        }
      }
      free(t);
    }
  assert_true(tested >= 20);
}

/* Every record's pair table, read by clr_halton_pair_value (the scalar form of the kernel's
 * clr_halton_pair8), against pbrt-v3's scrambled radical inverse, for arguments of a 512^2
 * film (index stride 31104) at 16 and 64 spp: every 7th argument, the tables' last ones and the
 * ends of each hi (a zero hi, one digit, two digits). At 16 spp the bases 131-181 (dimensions
 * 31-41, the path tracer's 41-value layout ends at dimension 40) and 191-251 have two-digit top
 * parts whose counts do not fit beside the values: their tables derive the counts. */
static void test_pair_tables_decode(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  const clr_u32 limits[] = {31104u * 16u, 31104u * 64u};
  for (size_t l = 0; l < 2; ++l) {
    int covered = 0, derived = 0, largest = 0;
    for (int r = 1; r < CLR_HALTON_PRIME_RECORDS; ++r) {
      const clr_halton_prime *p = &pr[r];
      clr_halton_pair_shape shape = clr_halton_pair_shape_for(p, limits[l]);
      if (l == 0 && r >= 31 && r <= 40) assert_int_not_equal(shape.digits, 0);
      if (shape.digits == 0) continue;
      ++covered;
      if (r < CLR_HALTON_PRIMES) largest = r;
      size_t entries = clr_halton_pair_entries(p, shape);
      clr_u16 *t = calloc(entries, sizeof *t);
      assert_non_null(t);
      clr_halton_pair_table(p, perms, shape, t);
      derived += t[5] == CLR_HALTON_PAIR_DERIVED_COUNTS;
      if (l == 0 && r >= 31 && r <= 40) assert_int_equal(t[5], CLR_HALTON_PAIR_DERIVED_COUNTS);
      const clr_u16 *perm = perms + p->perm_offset;
      clr_u64 b = p->base, c = t[0];
      const clr_u64 edges[] = {0, 1, c - 1, c, c * b - 1, c * b, c * b * b - 1, limits[l] - 1};
      for (size_t e = 0; e < sizeof edges / sizeof edges[0]; ++e)
        if (edges[e] < limits[l])
          assert_float_bits_equal(clr_halton_pair_value(p, t, (clr_u32)edges[e]),
                                  ref_scrambled(b, perm, edges[e]));
      clr_u32 step = (r >= 31 && r <= 53) ? 7u : 997u;
      for (clr_u32 a = r % 7; a < limits[l]; a += step)
        assert_float_bits_equal(clr_halton_pair_value(p, t, a), ref_scrambled(b, perm, a));
      free(t);
    }
    /* 16 spp: all but the 72 bases 257-701 (two-digit top parts above 16 bits), 23 with derived
     * counts (131-251); 64 spp: 831; the largest base, 7919, has a table at both */
    assert_int_equal(covered, l == 0 ? 928 : 831);
    assert_int_equal(derived, l == 0 ? 23 : 27);
    assert_int_equal(largest, CLR_HALTON_PRIMES - 1);
  }
}

static void test_inverse_radical_inverse(void **state) {
  (void)state;
  assert_int_equal(clr_inverse_radical_inverse(2, 1, 3), 4);  /* 001 -> 100 */
  assert_int_equal(clr_inverse_radical_inverse(2, 6, 3), 3);  /* 110 -> 011 */
  assert_int_equal(clr_inverse_radical_inverse(3, 5, 2), 7);  /* 12_3 -> 21_3 */
  assert_int_equal(clr_inverse_radical_inverse(3, 5, 3), 21); /* 012_3 -> 210_3 */
  assert_int_equal(clr_inverse_radical_inverse(3, 5, 0), 0);
  assert_int_equal(clr_inverse_radical_inverse(2, 127, 4), 15); /* only the low 4 digits */
  const clr_u32 bases[] = {2, 3, 5, 7919};
  const int digits[] = {20, 12, 9, 2};
  clr_pcg32 rng = clr_pcg32_sequence(9);
  for (int b = 0; b < 4; ++b) {
    clr_u64 range = 1;
    for (int d = 0; d < digits[b]; ++d) range *= bases[b];
    for (int i = 0; i < 2000; ++i) {
      clr_u64 v = random_u64(&rng) % range;
      clr_u64 r = clr_inverse_radical_inverse(bases[b], v, digits[b]);
      assert_true(r < range);
      assert_int_equal(clr_inverse_radical_inverse(bases[b], r, digits[b]), v);
      int n32 = digits[b] < 5 ? digits[b] : 5; /* base^n32 < 2^32 */
      assert_int_equal(clr_halton_inverse_digits32(bases[b], (clr_u32)(v % 243), n32),
                       clr_inverse_radical_inverse(bases[b], v % 243, n32));
      if (bases[b] == 2) /* Phi_2 of the reversed index is v / 2^digits exactly. */
        assert_float_bits_equal(clr_radical_inverse_base2(r), (float)v * 0x1p-20f);
    }
  }
}

/* ---- sampler ---- */

static clr_u32 mod128(clr_i32 v) { return (clr_u32)(((v % 128) + 128) % 128); }

static clr_sampler_params halton_params(int x0, int y0, int x1, int y1) {
  clr_sampler_params p;
  memset(&p, 0, sizeof p);
  p.type = CLR_SAMPLER_TYPE_HALTON;
  p.sample_x0 = x0;
  p.sample_y0 = y0;
  p.sample_x1 = x1;
  p.sample_y1 = y1;
  clr_halton_setup(&p);
  return p;
}

static void test_setup(void **state) {
  (void)state;
  clr_sampler_params p = halton_params(-2, -2, 66, 34); /* 68 x 36 */
  assert_int_equal(p.halton_scale[0], 128);
  assert_int_equal(p.halton_exponent[0], 7);
  assert_int_equal(p.halton_scale[1], 81);
  assert_int_equal(p.halton_exponent[1], 4);
  assert_int_equal(p.halton_stride, 128 * 81);
  assert_int_equal(p.halton_mult_inverse[0], 49); /* 81 * 49 = 3969 = 31 * 128 + 1 */
  assert_int_equal(p.halton_mult_inverse[1], 50); /* 128 * 50 = 6400 = 79 * 81 + 1 */
  p = halton_params(0, 0, 1280, 720);
  assert_int_equal(p.halton_scale[0], 128);
  assert_int_equal(p.halton_scale[1], 243);
  assert_int_equal(p.halton_exponent[1], 5);
  assert_int_equal(p.halton_mult_inverse[0], 59);
  assert_int_equal(p.halton_mult_inverse[1], 131);
  p = halton_params(3, 3, 4, 4);
  assert_int_equal(p.halton_scale[0], 1);
  assert_int_equal(p.halton_scale[1], 1);
  assert_int_equal(p.halton_stride, 1);
  assert_int_equal(p.halton_mult_inverse[0], 0);
  assert_int_equal(p.halton_mult_inverse[1], 0);
  p = halton_params(0, 0, 5, 4); /* 8 x 9: exponents 3 and 2 */
  assert_int_equal(p.halton_scale[0], 8);
  assert_int_equal(p.halton_scale[1], 9);
  assert_int_equal(p.halton_mult_inverse[0], 1); /* 9 = 1 mod 8 */
  assert_int_equal(p.halton_mult_inverse[1], 8); /* 8 * 8 = 64 = 7 * 9 + 1 */
  for (int i = 0; i < 2; ++i)
    assert_int_equal((clr_u64)p.halton_scale[1 - i] * p.halton_mult_inverse[i] % p.halton_scale[i],
                     1);
}

/* The cell of the scale0 x scale1 grid that Phi_2(index), Phi_3(index) fall in, from the digits:
 * floor(Phi_b(index) * b^e) is the e lowest base-b digits of index, reversed. */
static void index_cell(const clr_sampler_params *p, clr_u64 index, clr_u32 *cx, clr_u32 *cy) {
  *cx = (clr_u32)clr_inverse_radical_inverse(2, index, p->halton_exponent[0]);
  *cy = (clr_u32)clr_inverse_radical_inverse(3, index, p->halton_exponent[1]);
}

/* clr_halton_sampler_index against pbrt-v3's formula written out with 64-bit arithmetic. */
static void test_index_matches_pbrt_form(void **state) {
  (void)state;
  const int bounds[][4] = {{-2, -2, 66, 34}, {0, 0, 1280, 720}, {0, 0, 5, 4},
                           {10, 10, 11, 40}, {0, 0, 3, 200},    {-7, 3, 1, 4}};
  clr_pcg32 rng = clr_pcg32_sequence(23);
  for (int b = 0; b < 6; ++b) {
    clr_sampler_params p = halton_params(bounds[b][0], bounds[b][1], bounds[b][2], bounds[b][3]);
    for (int i = 0; i < 3000; ++i) {
      clr_i32 px = (clr_i32)(clr_pcg32_next(&rng) % 1000) - 500;
      clr_i32 py = (clr_i32)(clr_pcg32_next(&rng) % 1000) - 500;
      clr_i64 s = clr_pcg32_next(&rng) % 5000;
      clr_u64 stride = (clr_u64)p.halton_stride, offset = 0;
      clr_u64 d0 = clr_inverse_radical_inverse(2, mod128(px), p.halton_exponent[0]);
      clr_u64 d1 = clr_inverse_radical_inverse(3, mod128(py), p.halton_exponent[1]);
      offset += d0 * (stride / (clr_u64)p.halton_scale[0]) * p.halton_mult_inverse[0];
      offset += d1 * (stride / (clr_u64)p.halton_scale[1]) * p.halton_mult_inverse[1];
      offset %= stride;
      assert_int_equal(clr_halton_sampler_index(&p, px, py, s), offset + (clr_u64)s * stride);
    }
  }
}

static void test_index_lands_in_pixel(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  clr_sampler_params p = halton_params(-2, -2, 66, 34);
  const clr_i32 pixels[][2] = {{-2, -2},   {-1, 5},     {0, 0},     {65, 33},   {7, 20},
                               {130, 200}, {-130, -50}, {127, 127}, {128, -129}};
  for (size_t k = 0; k < sizeof pixels / sizeof pixels[0]; ++k) {
    clr_i32 px = pixels[k][0], py = pixels[k][1];
    for (int i = 0; i < 64; ++i) {
      clr_u64 index = clr_halton_sampler_index(&p, px, py, i);
      assert_int_equal(index % (clr_u64)p.halton_stride, clr_halton_sampler_index(&p, px, py, 0));
      assert_int_equal(index / (clr_u64)p.halton_stride, (clr_u64)i);
      clr_u32 cx, cy;
      index_cell(&p, index, &cx, &cy);
      assert_int_equal(cx, mod128(px) % (clr_u32)p.halton_scale[0]);
      assert_int_equal(cy, mod128(py) % (clr_u32)p.halton_scale[1]);
      /* The float values agree: Phi_2(index) * 128 = cx + dim0 value (both exact here). */
      float u = clr_halton_sampler_value(&p, pr, perms, index, 0);
      assert_true(u >= 0.0f && u < 1.0f);
      assert_float_bits_equal(clr_radical_inverse_base2(index) * 128.0f, (float)cx + u);
      float w = clr_halton_sampler_value(&p, pr, perms, index, 1);
      assert_true(w >= 0.0f && w < 1.0f);
      assert_float_equal(clr_radical_inverse(3, CLR_HALTON_INV_3, index) * 81.0f, (float)cy + w,
                         1e-4f);
    }
  }
  /* Sample numbers past 2^32 / stride take the 64-bit paths. */
  clr_u64 big = clr_halton_sampler_index(&p, 5, 6, 3000000000ll);
  assert_true(big > 0xffffffffull);
  clr_u32 cx, cy;
  index_cell(&p, big, &cx, &cy);
  assert_int_equal(cx, 5);
  assert_int_equal(cy, 6);
}

static void test_stratification(void **state) {
  (void)state;
  const int bounds[][4] = {{-2, -2, 66, 34}, {0, 0, 1280, 720}, {0, 0, 5, 4}, {10, 10, 11, 40}};
  for (int b = 0; b < 4; ++b) {
    clr_sampler_params p = halton_params(bounds[b][0], bounds[b][1], bounds[b][2], bounds[b][3]);
    clr_u32 s0 = (clr_u32)p.halton_scale[0], s1 = (clr_u32)p.halton_scale[1];
    unsigned char *hits = calloc((size_t)s0 * s1, 1);
    assert_non_null(hits);
    for (clr_u64 index = 0; index < (clr_u64)p.halton_stride; ++index) {
      clr_u32 cx, cy;
      index_cell(&p, index, &cx, &cy);
      assert_true(cx < s0 && cy < s1);
      assert_int_equal(hits[cy * s0 + cx]++, 0);
    }
    for (clr_u32 y = 0; y < s1; ++y)
      for (clr_u32 x = 0; x < s0; ++x) {
        clr_u64 index = clr_halton_sampler_index(&p, (clr_i32)x, (clr_i32)y, 0);
        assert_true(index < (clr_u64)p.halton_stride);
        clr_u32 cx, cy;
        index_cell(&p, index, &cx, &cy);
        /* Pixels are taken modulo 128 first: with scale 243, rows 128.. reuse rows 0.. */
        assert_int_equal(cx, x);
        assert_int_equal(cy, y % CLR_HALTON_MAX_RESOLUTION);
      }
    free(hits);
  }
}

static void test_sampler_values(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  clr_sampler_params p = halton_params(0, 0, 1280, 720);
  clr_pcg32 rng = clr_pcg32_sequence(13);
  for (int i = 0; i < 2000; ++i) {
    clr_u64 index = random_u64(&rng) >> (clr_pcg32_next(&rng) % 64);
    assert_float_bits_equal(clr_halton_sampler_value(&p, pr, perms, index, 0),
                            ref_base2_double(index >> 7));
    assert_float_bits_equal(clr_halton_sampler_value(&p, pr, perms, index, 1),
                            ref_radical_inverse(3, index / 243));
    int dim = 2 + (int)(clr_pcg32_next(&rng) % (CLR_HALTON_PRIMES - 2));
    assert_float_bits_equal(clr_halton_sampler_value(&p, pr, perms, index, dim),
                            ref_scrambled(pr[dim].base, perms + pr[dim].perm_offset, index));
    const clr_i32 past[] = {1000, 1001, 5000, -1};
    for (int k = 0; k < 4; ++k) {
      float v = clr_halton_sampler_value(&p, pr, perms, index, past[k]);
      assert_true(v >= 0.0f && v < 1.0f);
      assert_float_bits_equal(v, clr_halton_sampler_value(&p, pr, perms, index, past[k]));
    }
  }
  assert_true(clr_halton_sampler_value(&p, pr, perms, 1, 1000) !=
              clr_halton_sampler_value(&p, pr, perms, 1, 1001));
  assert_true(clr_halton_sampler_value(&p, pr, perms, 1, 1000) !=
              clr_halton_sampler_value(&p, pr, perms, 2, 1000));
  p.sample_pixel_center = 1;
  assert_float_bits_equal(clr_halton_sampler_value(&p, pr, perms, 12345, 0), 0.5f);
  assert_float_bits_equal(clr_halton_sampler_value(&p, pr, perms, 12345, 1), 0.5f);
  assert_float_bits_equal(clr_halton_sampler_value(&p, pr, perms, 12345, 2),
                          clr_scrambled_radical_inverse(&pr[2], perms, 12345));
}

/* ---- the host's fast values (host/lib/sampling/halton_host.c) ---- */

/* The host's bit reversal (byte swap and masks) against one bit at a time. */
static void test_reverse_bits_host(void **state) {
  (void)state;
  clr_pcg32 rng = clr_pcg32_sequence(29);
  for (int i = 0; i < 100000; ++i) {
    clr_u32 n = i < 64 ? (i < 32 ? 1u << i : ~(1u << (i - 32))) : clr_pcg32_next(&rng);
    clr_u32 want = 0;
    for (int b = 0; b < 32; ++b) want |= ((n >> b) & 1u) << (31 - b);
    assert_int_equal(clr_reverse_bits32(n), want);
  }
  assert_int_equal(clr_reverse_bits32(0u), 0u);
  assert_int_equal(clr_reverse_bits32(0xFFFFFFFFu), 0xFFFFFFFFu);
}

/* Indices of test_host_values_match_reference: the ends of the tables' limits, of 2^28 (where
 * pair tables end) and of 2^32, random ones below the limit and random 64-bit ones. */
static int host_test_indices(clr_u64 limit, clr_pcg32 *rng, clr_u64 *out) {
  const clr_u64 edges[] = {0,
                           1,
                           2,
                           limit - 1,
                           limit,
                           limit + 1,
                           ((clr_u64)1 << 28) - 1,
                           (clr_u64)1 << 28,
                           0xFFFFFFFFull,
                           (clr_u64)1 << 32,
                           UINT64_MAX};
  int n = 0;
  for (size_t e = 0; e < sizeof edges / sizeof edges[0]; ++e) out[n++] = edges[e];
  for (int i = 0; i < 160; ++i) out[n++] = (((clr_u64)clr_pcg32_next(rng) << 32) | i) % limit;
  for (int i = 0; i < 20; ++i) out[n++] = random_u64(rng) >> (clr_pcg32_next(rng) % 64);
  return n;
}

/* The host's fast values (clr_halton_host_values: pair tables where the argument is below the
 * record's limit, else the chunk loop) against clr_halton_sampler_value and, for the scrambled
 * dimensions, pbrt-v3's plain form: every dimension of sets of 10, 41, 300 and 1000 dimensions
 * (the last past the tables' entry budget and with bases 257-701, which get no table at 16 spp),
 * the dimensions past the primes (1000, 1001: the stand-in), for films of 512^2 (index stride
 * 31104), 7x5 and 1280x720 at 1, 16, 64 and 8192 spp, with and without sample_pixel_center. */
static void test_host_values_match_reference(void **state) {
  (void)state;
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  const int films[][2] = {{512, 512}, {7, 5}, {1280, 720}};
  const int spps[] = {1, 16, 64, 8192};
  const int dim_sets[] = {10, 41, 300, 1000};
  clr_pcg32 rng = clr_pcg32_sequence(31);
  enum { MOST = 200 };
  clr_u64 index[MOST];
  float got[2 * MOST];
  int tabled_most = 0, untabled_most = 0;
  for (int f = 0; f < 3; ++f)
    for (int k = 0; k < 4; ++k)
      for (int ds = 0; ds < 4; ++ds) {
        if (ds == 3 && (f != 0 || k == 3)) continue; /* 1000 dimensions: 512^2 at 1, 16, 64 spp */
        clr_sampler_params p = halton_params(0, 0, films[f][0], films[f][1]);
        clr_u64 limit = (clr_u64)p.halton_stride * (clr_u64)spps[k];
        clr_halton_host_pairs *hp =
            clr_halton_host_pairs_create(dim_sets[ds], limit, (clr_u32)p.halton_scale[1]);
        assert_non_null(hp);
        assert_int_not_equal(hp->limit[CLR_HALTON_BASE3_RECORD], 0);
        if (spps[k] <= 64) assert_int_not_equal(hp->limit[2], 0);
        int tabled = 0;
        for (int r = 0; r < CLR_HALTON_PRIME_RECORDS; ++r) tabled += hp->limit[r] != 0;
        if (ds == 3) {
          tabled_most = tabled;
          untabled_most = dim_sets[ds] - tabled;
        }
        int n = host_test_indices(limit, &rng, index);
        for (int center = 0; center < 2; ++center) {
          p.sample_pixel_center = center;
          for (int dim = 0; dim < dim_sets[ds] + 2; ++dim) {
            int d = dim < dim_sets[ds] ? dim : 1000 + (dim - dim_sets[ds]);
            if (dim >= 60 && dim < dim_sets[ds] && dim % 7 != 0) continue; /* time */
            clr_halton_host_values(hp, &p, d, index, n, got, 2); /* stride 2: every other slot */
            for (int i = 0; i < n; ++i) {
              float want = clr_halton_sampler_value(&p, pr, perms, index[i], d);
              if (float_bits(got[2 * i]) != float_bits(want))
                fail_msg("film %d spp %d dims %d: index 0x%llx dim %d: host %a reference %a", f,
                         spps[k], dim_sets[ds], (unsigned long long)index[i], d, got[2 * i], want);
              if (d >= 2 && d < CLR_HALTON_PRIMES)
                assert_float_bits_equal(
                    got[2 * i], ref_scrambled(pr[d].base, perms + pr[d].perm_offset, index[i]));
            }
          }
        }
        clr_halton_host_pairs_free(hp);
      }
  /* 1000 dimensions at 64 spp: the budget and the two-digit top parts leave some without tables */
  assert_true(tabled_most > 100 && untabled_most > 50);
}

/* Slots of a global sampler's layout (clr_request_slot) for the host batch test. */
static int host_test_slots(clr_request_slot *slots) {
  const int dims[] = {2, 1, 2, 1, 2, 2, 1, 2};
  const int arrays[] = {0, 0, 3, 2, 0, 0, 0, 0};
  const int sources[] = {0, 2, 3, 5, 6, 30, 39, 290};
  int value = 0;
  for (int r = 0; r < 8; ++r) {
    memset(&slots[r], 0, sizeof slots[r]);
    slots[r].dims = dims[r];
    slots[r].array_size = arrays[r];
    slots[r].first_value = value;
    slots[r].source = sources[r];
    value += dims[r] * (arrays[r] ? arrays[r] : 1);
  }
  return value;
}

/* clr_halton_host_batch (the host reference's halton batches) against clr_global_sample_vector
 * item by item: values and indices, a layout with arrays, dimensions 30-40 (derived digit counts)
 * and 290-291 (bases past the two-part limits), batches across pixels, spp 16 (whole pixels,
 * samples 3-15), spp 4096 near its end and 2^18 near its end (indices past 2^32), pixel centres. */
static void test_host_batch_matches_vectors(void **state) {
  (void)state;
  clr_request_slot slots[8];
  int per_sample = host_test_slots(slots);
  struct {
    int spp, first, count, x0, y0, w, h, center;
  } cases[] = {
      {16, 0, 16, 0, 0, 5, 3, 0},         {16, 3, 13, 300, 301, 4, 2, 0},
      {4096, 4090, 6, 300, 301, 3, 2, 0}, {1 << 18, (1 << 18) - 4, 4, 511, 0, 1, 3, 0},
      {16, 0, 16, 100, 7, 2, 2, 1},
  };
  const clr_halton_tables *t = clr_halton_tables_covering(clr_halton_layout_dimensions(slots, 8));
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    clr_sampler_params p = halton_params(0, 0, 512, 512);
    p.batch_x0 = cases[c].x0;
    p.batch_y0 = cases[c].y0;
    p.batch_width = cases[c].w;
    p.batch_height = cases[c].h;
    p.first_sample = cases[c].first;
    p.sample_count = cases[c].count;
    p.values_per_sample = per_sample;
    p.request_count = 8;
    p.spp = cases[c].spp;
    p.sample_pixel_center = cases[c].center;
    size_t items = (size_t)cases[c].w * cases[c].h * cases[c].count;
    clr_halton_host_pairs *hp = clr_halton_host_pairs_create(
        clr_halton_layout_dimensions(slots, 8),
        (clr_u64)p.halton_stride * (clr_u64)cases[c].spp * 3u, (clr_u32)p.halton_scale[1]);
    assert_non_null(hp);
    float *got = malloc(items * per_sample * sizeof(float));
    float *want = malloc(items * per_sample * sizeof(float));
    clr_u64 *got_index = malloc(items * sizeof(clr_u64));
    assert_true(got && want && got_index);
    clr_halton_host_batch(hp, &p, slots, got, got_index);
    for (size_t i = 0; i < items; ++i) {
      clr_u64 index = 0;
      clr_global_sample_vector(&p, slots, NULL, NULL, NULL, t->primes, t->permutations, (clr_i32)i,
                               want + i * per_sample, &index);
      assert_int_equal(got_index[i], index);
    }
    assert_memory_equal(got, want, items * per_sample * sizeof(float));
    if (c == 3) assert_true(got_index[0] > UINT32_MAX);
    clr_halton_host_batch(hp, &p, slots, got, NULL); /* indices not asked */
    assert_memory_equal(got, want, items * per_sample * sizeof(float));
    free(got);
    free(want);
    free(got_index);
    clr_halton_host_pairs_free(hp);
  }
}

/* ---- device ---- */

static const char *device_source =
    "#include \"halton_funcs.h\"\n"
    "__kernel void values(__global const clr_sampler_params *params,\n"
    "                     __global const clr_halton_prime *primes, __global const ushort *perms,\n"
    "                     __global const ulong *indices, int dims, __global float *out) {\n"
    "  size_t i = get_global_id(0);\n"
    "  clr_sampler_params p = *params;\n"
    "  ulong index = indices[i];\n"
    "  for (int d = 0; d < dims; ++d)\n"
    "    out[i * dims + d] = clr_halton_sampler_value(&p, primes, perms, index, d);\n"
    "  out[i * dims] = clr_radical_inverse_base2(index);\n"
    "}\n"
    "__kernel void pixel_values(__global const clr_sampler_params *params,\n"
    "                     __global const clr_halton_prime *primes, __global const ushort *perms,\n"
    "                     int width, int spp, int dims, __global float *out) {\n"
    "  int i = (int)get_global_id(0);\n"
    "  int pixel = i / spp, s = i - pixel * spp;\n"
    "  clr_sampler_params p = *params;\n"
    "  ulong index = clr_halton_sampler_index(&p, pixel % width, pixel / width, s);\n"
    "  for (int d = 0; d < dims; ++d)\n"
    "    out[(size_t)i * dims + d] = clr_halton_sampler_value(&p, primes, perms, index, d);\n"
    "}\n"
    "__kernel void one_value(__global const clr_sampler_params *params,\n"
    "                     __global const clr_halton_prime *primes, __global const ushort *perms,\n"
    "                     int width, int spp, int dims, __global float *out) {\n"
    "  int i = (int)get_global_id(0);\n"
    "  int sample = i / dims, d = i - sample * dims;\n"
    "  int pixel = sample / spp, s = sample - pixel * spp;\n"
    "  clr_sampler_params p = *params;\n"
    "  ulong index = clr_halton_sampler_index(&p, pixel % width, pixel / width, s);\n"
    "  out[i] = clr_halton_sampler_value(&p, primes, perms, index, d);\n"
    "}\n"
    "__kernel void pair_values(__global const clr_halton_prime *primes, int record,\n"
    "                     __global const ushort *table, __global const uint *args,\n"
    "                     __global float *out) {\n"
    "  size_t i = get_global_id(0);\n"
    "  out[i] = clr_halton_pair_value(primes + record, table, args[i]);\n"
    "}\n";

typedef struct device_fixture {
  clr_context ctx;
  cl_program program;
  cl_mem params, primes, perms;
} device_fixture;

static cl_mem make_buffer(cl_context cl, size_t bytes, const void *data) {
  cl_int err = 0;
  cl_mem m = clCreateBuffer(cl, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes,
                            (void *)data, &err);
  assert_int_equal(err, CL_SUCCESS);
  return m;
}

static void device_setup(device_fixture *f, const clr_sampler_params *p, const char *defines) {
  assert_int_equal(clr_context_create(NULL, &f->ctx), CLR_SUCCESS);
  cl_context cl = clr_context_cl_context(f->ctx);
  cl_device_id dev = clr_context_cl_device(f->ctx);
  cl_int err = 0;
  f->program = clCreateProgramWithSource(cl, 1, &device_source, NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  char options[1024];
  snprintf(options, sizeof options, "-cl-std=CL1.2 -I %s/kernels %s", CLR_SOURCE_DIR, defines);
  err = clBuildProgram(f->program, 1, &dev, options, NULL, NULL);
  if (err != CL_SUCCESS) {
    char log[8192] = {0};
    clGetProgramBuildInfo(f->program, dev, CL_PROGRAM_BUILD_LOG, sizeof log - 1, log, NULL);
    fail_msg("build failed: %s", log);
  }
  size_t count = 0;
  const clr_u16 *perms = clr_halton_permutations(&count);
  f->params = make_buffer(cl, sizeof *p, p);
  f->primes =
      make_buffer(cl, sizeof(clr_halton_prime) * CLR_HALTON_PRIME_RECORDS, clr_halton_primes());
  f->perms = make_buffer(cl, sizeof(clr_u16) * count, perms);
}

static void device_teardown(device_fixture *f) {
  clReleaseMemObject(f->params);
  clReleaseMemObject(f->primes);
  clReleaseMemObject(f->perms);
  clReleaseProgram(f->program);
  clr_context_release(f->ctx);
}

static void test_device_matches_host(void **state) {
  (void)state;
  clr_sampler_params p = halton_params(-2, -2, 66, 34);
  device_fixture f;
  device_setup(&f, &p, "");
  cl_context cl = clr_context_cl_context(f.ctx);
  cl_command_queue q = clr_context_cl_queue(f.ctx);
  const cl_int dims = 40;
  enum { N = 8192 };
  static clr_u64 indices[N];
  static float out[N * 40];
  clr_pcg32 rng = clr_pcg32_sequence(17);
  for (int i = 0; i < N; ++i) {
    if (i < 4096)
      indices[i] = random_u64(&rng) >> (clr_pcg32_next(&rng) % 64);
    else
      indices[i] = clr_halton_sampler_index(&p, i % 70 - 3, i / 70, i % 37);
  }
  cl_mem idx = make_buffer(cl, sizeof indices, indices);
  cl_mem res = make_buffer(cl, sizeof out, NULL);
  cl_int err = 0;
  cl_kernel k = clCreateKernel(f.program, "values", &err);
  assert_int_equal(err, CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 0, sizeof(cl_mem), &f.params), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 1, sizeof(cl_mem), &f.primes), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 2, sizeof(cl_mem), &f.perms), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 3, sizeof(cl_mem), &idx), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 4, sizeof dims, &dims), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 5, sizeof(cl_mem), &res), CL_SUCCESS);
  size_t global = N;
  assert_int_equal(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, NULL, 0, NULL, NULL), CL_SUCCESS);
  assert_int_equal(clEnqueueReadBuffer(q, res, CL_TRUE, 0, sizeof out, out, 0, NULL, NULL),
                   CL_SUCCESS);
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  for (int i = 0; i < N; ++i) {
    assert_float_bits_equal(out[i * dims], ref_base2_double(indices[i]));
    for (int d = 1; d < dims; ++d) {
      float want = clr_halton_sampler_value(&p, pr, perms, indices[i], d);
      if (float_bits(out[i * dims + d]) != float_bits(want))
        fail_msg("index 0x%llx dim %d: device %a host %a", (unsigned long long)indices[i], d,
                 out[i * dims + d], want);
    }
  }
  clReleaseKernel(k);
  clReleaseMemObject(idx);
  clReleaseMemObject(res);
  device_teardown(&f);
}

/* clr_halton_pair_value built as OpenCL C gives the host's bits and pbrt-v3's: records with
 * stored and derived digit counts (dimension 40), the unscrambled base 3 and base 7919, at a
 * 512^2 film's 16 spp (arguments below 31104 * 16, their ends and those of each top part). */
static void test_device_pair_values(void **state) {
  (void)state;
  clr_sampler_params p = halton_params(0, 0, 512, 512);
  device_fixture f;
  device_setup(&f, &p, "");
  cl_context cl = clr_context_cl_context(f.ctx);
  cl_command_queue q = clr_context_cl_queue(f.ctx);
  const clr_halton_prime *pr = clr_halton_primes();
  const clr_u16 *perms = clr_halton_permutations(NULL);
  const cl_int records[] = {2, 3, 40, 500, CLR_HALTON_PRIMES - 1, CLR_HALTON_BASE3_RECORD};
  const clr_u32 limit = 31104u * 16u;
  enum { N = 4096 };
  static clr_u32 args[N];
  static float out[N];
  int derived = 0;
  for (size_t r = 0; r < sizeof records / sizeof records[0]; ++r) {
    const clr_halton_prime *rec = &pr[records[r]];
    clr_halton_pair_shape shape = clr_halton_pair_shape_for(rec, limit);
    assert_int_not_equal(shape.digits, 0);
    size_t entries = clr_halton_pair_entries(rec, shape);
    clr_u16 *t = calloc(entries, sizeof *t);
    assert_non_null(t);
    clr_halton_pair_table(rec, perms, shape, t);
    derived += t[5] == CLR_HALTON_PAIR_DERIVED_COUNTS;
    clr_u32 c = t[0];
    const clr_u32 edges[] = {0, 1, c - 1, c, c + 1, c * rec->base - 1, c * rec->base, limit - 1};
    for (int i = 0; i < N; ++i)
      args[i] = i < 8 ? (edges[i] < limit ? edges[i] : limit - 1) : (clr_u32)(i * 121u) % limit;
    cl_mem table = make_buffer(cl, entries * sizeof *t, t);
    cl_mem in = make_buffer(cl, sizeof args, args);
    cl_mem res = make_buffer(cl, sizeof out, NULL);
    cl_int err = 0;
    cl_kernel k = clCreateKernel(f.program, "pair_values", &err);
    assert_int_equal(err, CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 0, sizeof(cl_mem), &f.primes), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 1, sizeof records[r], &records[r]), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 2, sizeof(cl_mem), &table), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 3, sizeof(cl_mem), &in), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 4, sizeof(cl_mem), &res), CL_SUCCESS);
    size_t global = N;
    assert_int_equal(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, NULL, 0, NULL, NULL),
                     CL_SUCCESS);
    assert_int_equal(clEnqueueReadBuffer(q, res, CL_TRUE, 0, sizeof out, out, 0, NULL, NULL),
                     CL_SUCCESS);
    for (int i = 0; i < N; ++i) {
      float want = ref_scrambled(rec->base, perms + rec->perm_offset, args[i]);
      assert_float_bits_equal(clr_halton_pair_value(rec, t, args[i]), want);
      if (float_bits(out[i]) != float_bits(want))
        fail_msg("record %d argument %u: device %a, pbrt-v3 %a", (int)records[r], args[i], out[i],
                 want);
    }
    clReleaseKernel(k);
    clReleaseMemObject(table);
    clReleaseMemObject(in);
    clReleaseMemObject(res);
    free(t);
  }
  assert_int_equal(derived, 1);
  device_teardown(&f);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_primes),
      cmocka_unit_test(test_permutations),
      cmocka_unit_test(test_table_sets),
      cmocka_unit_test(test_division_magic),
      cmocka_unit_test(test_base2_exact),
      cmocka_unit_test(test_base2_matches_double),
      cmocka_unit_test(test_radical_inverse_values),
      cmocka_unit_test(test_scrambled_values),
      cmocka_unit_test(test_chunked_path),
      cmocka_unit_test(test_pair_lane_rows),
      cmocka_unit_test(test_pair_tables_decode),
      cmocka_unit_test(test_reverse_bits_host),
      cmocka_unit_test(test_host_values_match_reference),
      cmocka_unit_test(test_host_batch_matches_vectors),
      cmocka_unit_test(test_inverse_radical_inverse),
      cmocka_unit_test(test_index_matches_pbrt_form),
      cmocka_unit_test(test_setup),
      cmocka_unit_test(test_index_lands_in_pixel),
      cmocka_unit_test(test_stratification),
      cmocka_unit_test(test_sampler_values),
      cmocka_unit_test(test_device_matches_host),
      cmocka_unit_test(test_device_pair_values),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
