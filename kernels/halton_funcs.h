/* pbrt-v3's Halton sampler math (core/lowdiscrepancy, samplers/halton), bit-exact on the host and
 * on any OpenCL 1.2 device (no fp64, no division where the digits are taken from a table). */
#ifndef CLR_HALTON_FUNCS_H
#define CLR_HALTON_FUNCS_H

#include "clr_platform.h"
#include "sampler_types.h"
#include "pcg32.h"

/* Everything is inlined into the kernel: PoCL can vectorise a work-group loop only when its body
 * has no calls and no loops left after unrolling (define CLR_HALTON_INDEX32 for that). */
#if CLR_DEVICE
#define CLR_HALTON_INLINE static inline __attribute__((always_inline))
#else
#define CLR_HALTON_INLINE CLR_INLINE
#endif

/* Records in clr_halton_primes(): one per prime (dimension d >= 2 uses record d), then one
 * unscrambled base-3 record (identity permutation, scramble_tail 0) for dimension 1. */
#define CLR_HALTON_BASE3_RECORD CLR_HALTON_PRIMES
#define CLR_HALTON_PRIME_RECORDS (CLR_HALTON_PRIMES + 1)
/* Values below 2^32 are split into chunks of m digits, chunk base B = base^m >= 128, so that at
 * most 5 chunks (table lookups) make a radical inverse, in a loop-free (vectorisable) body. */
#define CLR_HALTON_CHUNK_MIN 128u
#define CLR_HALTON_MAX_CHUNKS32 5
/* Digits of a 32-bit value in base 2: the most of any base. */
#define CLR_HALTON_MAX_DIGITS32 32
/* Halton pair table, for a launch whose arguments are a < limit <= 2^28: a = hi * B + lo
 * (B = base^m <= 16384) takes two lookups. u16 layout: B, the magic (low, high half) and shift
 * of hi = (a * magic) >> shift, m, the count shift c, the offset of the lane rows (low, high half;
 * 0: none), base^0..base^7 (0 past the top entries' most digits), then B entries for lo below a
 * nonzero hi (its m digits permuted, reversed, | m << c), then max(ceil(limit / B), B) top entries
 * (the significant digits of the entry's number permuted, reversed, | their count << c; lo's when
 * hi is 0), then, for B <= CLR_HALTON_PAIR_MOST_ROW_CHUNK, B lane rows of 8 entries: row r holds
 * the lo entries of (r + j * step) mod B, j = 0..7, for 8 lanes whose arguments step by `step`
 * (the launch's index stride; for dimension 1 scale[0]). The host picks m for the fewest entries
 * such that entries fit 16 bits, counts add up to at most 14 and the reversed digits stay below
 * 2^31 (host/lib/sampling/halton_tables.c). Where value and count do not share 16 bits (two-digit
 * top parts of bases 131-251), the count shift is CLR_HALTON_PAIR_DERIVED_COUNTS, the entries hold
 * values only and the kernel counts digits by comparison with base^k: hi's for a nonzero hi (lo
 * then has m), lo's (a's) for a zero hi. */
#define CLR_HALTON_PAIR_HEADER 16
#define CLR_HALTON_PAIR_MOST_ENTRIES 16384u
#define CLR_HALTON_PAIR_MOST_TOPS 65536u
#define CLR_HALTON_PAIR_ARGUMENT_BITS 28u
#define CLR_HALTON_PAIR_MAX_DIGITS 7
#define CLR_HALTON_PAIR_ROW 8
#define CLR_HALTON_PAIR_MOST_ROW_CHUNK 4096u
#define CLR_HALTON_PAIR_DERIVED_COUNTS 16u

/* One radical-inverse base, filled on the host by clr_halton_primes(). All offsets index the
 * single u16 table of clr_halton_permutations(). 32-bit scalars only. */
typedef struct clr_halton_prime {
  clr_u32 base;
  clr_u32 perm_offset; /* pbrt-v3's digit permutation of this base (PrimeSums[d]) */
  float inv_base;      /* (float)1 / (float)base */
  float scramble_tail; /* inv_base * perm[0] / (1 - inv_base), in float, pbrt-v3's order */
  /* n / base for 32-bit n: t = mulhi32(n, div_magic), (t + ((n - t) >> 1)) >> div_shift */
  clr_u32 div_magic, div_shift;
  clr_u32 chunk_base; /* B = base^chunk_digits, the smallest power >= 128 */
  clr_u32 chunk_digits;
  clr_u32 chunk_magic, chunk_shift; /* n / B, as div_magic */
  clr_u32 chunk_offset; /* B entries: chunk value D -> its m digits permuted, reversed */
  clr_u32 tail_offset;  /* B entries: D -> only its significant digits permuted, reversed, with
                           (their count - 1) << tail_shift (for the top chunk) */
  clr_u32 tail_shift;   /* bits of a reversed chunk value (values < B <= 2^tail_shift) */
  float inv_base_pow[CLR_HALTON_MAX_DIGITS32 + 1]; /* [k]: pbrt-v3's invBaseN after k digits */
  clr_u32 v4_digits;     /* pbrt-v4's nDigits in this base (clr_v4_scrambled_digits) */
  clr_u32 v4_reversed32; /* base^v4_digits <= 2^32: its reversed digits fit 32 bits */
} clr_halton_prime;

/* (float)1 / (float)3, written out so that devices never divide. */
#define CLR_HALTON_INV_3 0x1.555556p-2f

/* High half of a 32x32-bit product. Written as a 64-bit product rather than OpenCL's mul_hi,
 * which PoCL emulates with 16-bit pieces and does not vectorise. */
CLR_HALTON_INLINE clr_u32 clr_halton_mulhi32(clr_u32 a, clr_u32 b) {
  return (clr_u32)(((clr_u64)a * b) >> 32u);
}

CLR_HALTON_INLINE clr_u32 clr_halton_clz64(clr_u64 x) {
#if CLR_DEVICE
  return (clr_u32)clz(x);
#else
  return x ? (clr_u32)__builtin_clzll(x) : 64u;
#endif
}

/* n / base for any 32-bit n, with the magic constants of the base's clr_halton_prime. */
CLR_HALTON_INLINE clr_u32 clr_halton_div32(clr_u32 n, clr_u32 magic, clr_u32 shift) {
  clr_u32 t = clr_halton_mulhi32(n, magic);
  return (t + ((n - t) >> 1u)) >> shift;
}

/* Bit i of the result is bit 31 - i of n. Written nibble by nibble through a table held in a
 * constant (the reversed nibbles of 0..15 are the nibbles of CLR_REV4_NIBBLES; the SIMD code uses
 * rev4(x) = rev4(x & 7) | x >> 3, the reversals of 0..7 being the nibbles of 0xE6A2C480):
 * shift-and-mask code is the idiom compilers turn into the llvm.bitreverse intrinsic, which not
 * every OpenCL implementation can run (Oclgrind cannot), while variable shifts stay plain. */
#define CLR_REV3_NIBBLES 0xE6A2C480u
#define CLR_REV4_NIBBLES 0xF7B3D591E6A2C480UL
CLR_HALTON_INLINE clr_u32 clr_reverse_nibble(clr_u32 x) {
  return (clr_u32)(CLR_REV4_NIBBLES >> (x * 4u)) & 15u;
}

/* One serial chain (r shifted each step): no OR-reduction tree for the SLP vectoriser to turn
 * into llvm.vector.reduce.or, which Oclgrind cannot run either. */
CLR_HALTON_INLINE clr_u32 clr_reverse_bits32(clr_u32 n) {
#if CLR_DEVICE
  clr_u32 r = 0u;
  for (clr_u32 i = 0u; i < 8u; ++i) {
    r = (r << 4u) | clr_reverse_nibble(n & 15u);
    n >>= 4u;
  }
  return r;
#else /* the host: bytes (bswap), then nibbles, bit pairs and bits swapped */
  n = __builtin_bswap32(n);
  n = ((n >> 4u) & 0x0F0F0F0Fu) | ((n & 0x0F0F0F0Fu) << 4u);
  n = ((n >> 2u) & 0x33333333u) | ((n & 0x33333333u) << 2u);
  return ((n >> 1u) & 0x55555555u) | ((n & 0x55555555u) << 1u);
#endif
}

/* a > b ? a - b : 0 for a, b < 2^31, in signed arithmetic: the unsigned form is the idiom
 * compilers turn into llvm.usub.sat, which Oclgrind cannot run. */
CLR_HALTON_INLINE clr_u32 clr_halton_excess(clr_u32 a, clr_u32 b) {
  clr_i32 d = (clr_i32)a - (clr_i32)b;
  return (clr_u32)(d > 0 ? d : 0);
}

CLR_HALTON_INLINE clr_u64 clr_reverse_bits64(clr_u64 n) {
  return ((clr_u64)clr_reverse_bits32((clr_u32)n) << 32u) | clr_reverse_bits32((clr_u32)(n >> 32u));
}

/* v / 2^shift rounded to nearest, ties to even (shift in [0, 63]). */
CLR_HALTON_INLINE clr_u64 clr_halton_round_shift(clr_u64 v, clr_u32 shift) {
  if (shift == 0u) return v;
  clr_u64 q = v >> shift;
  clr_u64 rem = v & ((((clr_u64)1) << shift) - 1u);
  clr_u64 tie = ((clr_u64)1) << (shift - 1u);
  return q + ((rem > tie || (rem == tie && (q & 1u))) ? 1u : 0u);
}

/* pbrt-v3 RadicalInverse(0, a) = ReverseBits64(a) * 0x1p-64: the product is a double, rounded to
 * float on return. The two roundings (to 53, then to 24 significant bits) are done on integers so
 * that devices without fp64 agree. Like pbrt-v3 it is not clamped: it can return 1.0f (when the
 * lowest 25 bits of a are all ones). */
CLR_HALTON_INLINE float clr_radical_inverse_base2(clr_u64 a) {
  if ((a >> 32u) == 0u) /* at most 32 significant bits: the double is exact */
    return (float)clr_reverse_bits32((clr_u32)a) * 0x1p-32f;
  clr_u64 v = clr_reverse_bits64(a);
  clr_u32 bits = 64u - clr_halton_clz64(v);
  clr_u32 shift53 = clr_halton_excess(bits, 53u);
  clr_u64 q53 = clr_halton_round_shift(v, shift53); /* the double is q53 * 2^shift53 */
  clr_u32 bits53 = bits > 53u ? 53u : bits;         /* q53 == 2^53 after a carry rounds exactly */
  clr_u32 shift24 = clr_halton_excess(bits53, 24u);
  clr_u32 q24 = (clr_u32)clr_halton_round_shift(q53, shift24); /* <= 2^24: exact in float */
  clr_u32 exponent = shift53 + shift24;                        /* value = q24 * 2^(exponent-64) */
  return (float)q24 * clr_as_float((127u + exponent - 64u) << 23u);
}

/* pbrt-v3 RadicalInverseSpecialized<base>(a) in float: digits accumulate in a u64, invBaseN is
 * the running float product of inv_base, result min((float)reversed * invBaseN, 1 - eps).
 * Digits of a >= 2^32 use 64-bit division, the rest 32-bit division (a constant divisor when
 * base is a literal and the call is inlined). */
CLR_HALTON_INLINE float clr_radical_inverse(clr_u32 base, float inv_base, clr_u64 a) {
  clr_u64 reversed = 0u;
  float inv_base_n = 1.0f;
  while ((a >> 32u) != 0u) {
    clr_u64 next = a / base;
    reversed = reversed * base + (a - next * base);
    inv_base_n *= inv_base;
    a = next;
  }
  clr_u32 a32 = (clr_u32)a;
  while (a32 != 0u) {
    clr_u32 next = a32 / base;
    reversed = reversed * base + (a32 - next * base);
    inv_base_n *= inv_base;
    a32 = next;
  }
  float v = (float)reversed * inv_base_n;
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
}

/* ScrambledRadicalInverseSpecialized for a < 2^32, loop-free after unrolling: chunk by chunk
 * (at most 5 of base B = base^m) the table gives the permuted digits already reversed; the top
 * chunk uses the tail table, which keeps only its significant digits. The integer `reversed`
 * and the digit count k are pbrt-v3's, so inv_base_pow[k] is its invBaseN. */
CLR_HALTON_INLINE float clr_scrambled_radical_inverse32(CLR_GLOBAL const clr_halton_prime *pr,
                                                        CLR_GLOBAL const clr_u16 *perms,
                                                        clr_u32 a) {
  clr_u32 base = pr->base, chunk_base = pr->chunk_base, chunk_digits = pr->chunk_digits;
  clr_u32 magic = pr->chunk_magic, shift = pr->chunk_shift;
  clr_u32 chunk_offset = pr->chunk_offset, tail_offset = pr->tail_offset;
  clr_u32 tail_shift = pr->tail_shift, value_mask = (1u << tail_shift) - 1u;
  /* for base^count of a top chunk of count <= chunk_digits <= 7 digits (7: base 2, 5: base 3) */
  clr_u32 base2 = base * base, base4 = base2 * base2;
  clr_u64 reversed = 0u;
  clr_u32 digits = 0u;
#if CLR_DEVICE
#pragma unroll
#endif
  for (int chunk = 0; chunk < CLR_HALTON_MAX_CHUNKS32; ++chunk) {
    clr_u32 next = clr_halton_div32(a, magic, shift);
    clr_u32 d = a - next * chunk_base;
    clr_u32 top = next == 0u;
    clr_u32 entry = perms[(top ? tail_offset : chunk_offset) + d];
    clr_u32 count = top ? (entry >> tail_shift) + 1u : chunk_digits;
    clr_u32 value = entry & value_mask;
    clr_u32 scale = ((count & 1u) ? base : 1u) * ((count & 2u) ? base2 : 1u) *
                    ((count & 4u) ? base4 : 1u); /* base^count */
    clr_u32 active = a != 0u;
    reversed = active ? reversed * scale + value : reversed;
    digits += active ? count : 0u;
    a = next;
  }
  float v = pr->inv_base_pow[digits] * ((float)reversed + pr->scramble_tail);
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
}

/* Significant base-b digits of x < base^top, from a pair table's powers base^0..base^top (the
 * header's nonzero entries 8..15): how many of them x reaches. */
CLR_HALTON_INLINE clr_u32 clr_halton_pair_digits(CLR_GLOBAL const clr_u16 *pt, clr_u32 x) {
  clr_u32 c = 0u;
  for (int k = 0; k < CLR_HALTON_PAIR_ROW && pt[8 + k] != 0u; ++k) c += x >= pt[8 + k] ? 1u : 0u;
  return c;
}

/* clr_scrambled_radical_inverse32(pr, perms, a) for a below the limit of the record's pair table
 * `pt` (layout: CLR_HALTON_PAIR_HEADER), one value: the scalar form of clr_halton_pair8 in
 * global_sampler_simd.h. a = hi * B + lo; lo's entry is its m digits below a nonzero hi, else its
 * significant ones; hi's entry its significant digits (none for 0); reversed = lo's value *
 * base^(hi's count) + hi's, below 2^31, with at most 14 digits. Same integers and float
 * operations as the chunk loop, so the same bits. */
CLR_HALTON_INLINE float clr_halton_pair_value(CLR_GLOBAL const clr_halton_prime *pr,
                                              CLR_GLOBAL const clr_u16 *pt, clr_u32 a) {
  clr_u32 chunk = pt[0], magic = (clr_u32)pt[1] | (clr_u32)pt[2] << 16u, count_shift = pt[5];
  clr_u32 hi = (clr_u32)(((clr_u64)a * magic) >> pt[3]);
  clr_u32 lo = a - hi * chunk;
  clr_u32 low = pt[CLR_HALTON_PAIR_HEADER + (hi == 0u ? chunk : 0u) + lo];
  clr_u32 high = pt[CLR_HALTON_PAIR_HEADER + chunk + hi];
  clr_u32 count = high >> count_shift, digits = (low >> count_shift) + count;
  if (count_shift == CLR_HALTON_PAIR_DERIVED_COUNTS) {
    clr_u32 c = clr_halton_pair_digits(pt, hi != 0u ? hi : a);
    count = hi != 0u ? c : 0u;
    digits = c + (hi != 0u ? (clr_u32)pt[4] : 0u);
  }
  clr_u32 value_mask = (1u << count_shift) - 1u;
  clr_u32 reversed = (low & value_mask) * pt[8u + count] + (high & value_mask);
  float v = pr->inv_base_pow[digits] * ((float)(clr_i32)reversed + pr->scramble_tail);
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
}

/* pbrt-v3 ScrambledRadicalInverseSpecialized(perm, a):
 *   min(invBaseN * ((float)reversed + scramble_tail), 1 - eps), digits d replaced by perm[d].
 * `pr` is the prime's record in the global table (clr_halton_primes()), `perms` the whole u16
 * table (clr_halton_permutations()). With CLR_HALTON_INDEX32 defined (the caller guarantees
 * a < 2^32) only the loop-free 32-bit path is compiled: define it in kernels whenever the largest
 * index of a launch is below 2^32, so that the work-item loop can be vectorised. */
CLR_HALTON_INLINE float clr_scrambled_radical_inverse(CLR_GLOBAL const clr_halton_prime *pr,
                                                      CLR_GLOBAL const clr_u16 *perms, clr_u64 a) {
#ifdef CLR_HALTON_INDEX32
  return clr_scrambled_radical_inverse32(pr, perms, (clr_u32)a);
#else
  if ((a >> 32u) == 0u) return clr_scrambled_radical_inverse32(pr, perms, (clr_u32)a);
  CLR_GLOBAL const clr_u16 *perm = perms + pr->perm_offset;
  clr_u32 base = pr->base;
  float inv_base = pr->inv_base;
  clr_u64 reversed = 0u;
  float inv_base_n = 1.0f;
  while ((a >> 32u) != 0u) {
    clr_u64 next = a / base;
    reversed = reversed * base + perm[(clr_u32)(a - next * base)];
    inv_base_n *= inv_base;
    a = next;
  }
  clr_u32 a32 = (clr_u32)a;
  while (a32 != 0u) {
    clr_u32 next = clr_halton_div32(a32, pr->div_magic, pr->div_shift);
    reversed = reversed * base + perm[a32 - next * base];
    inv_base_n *= inv_base;
    a32 = next;
  }
  float v = inv_base_n * ((float)reversed + pr->scramble_tail);
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
#endif
}

/* pbrt-v3 InverseRadicalInverse<base>(inverse, nDigits): the index whose n_digits lowest base-b
 * digits, reversed, are the lowest digits of `inverse`. */
CLR_HALTON_INLINE clr_u64 clr_inverse_radical_inverse(clr_u32 base, clr_u64 inverse,
                                                      clr_i32 n_digits) {
  clr_u64 index = 0u;
  for (clr_i32 i = 0; i < n_digits; ++i) {
    clr_u64 next = inverse / base;
    index = index * base + (inverse - next * base);
    inverse = next;
  }
  return index;
}

/* Same for small values, in 32 bits. */
CLR_HALTON_INLINE clr_u32 clr_halton_inverse_digits32(clr_u32 base, clr_u32 inverse,
                                                      clr_i32 n_digits) {
  clr_u32 index = 0u;
  for (clr_i32 i = 0; i < n_digits; ++i) {
    clr_u32 next = inverse / base;
    index = index * base + (inverse - next * base);
    inverse = next;
  }
  return index;
}

/* v / 3^n for n <= 5 (the base-3 exponent never exceeds 5: 3^5 = 243 >= 128), loop-free. */
CLR_HALTON_INLINE clr_u32 clr_halton_div_pow3(clr_u32 v, clr_i32 n) {
#if CLR_DEVICE
#pragma unroll
#endif
  for (clr_i32 i = 0; i < 5; ++i) v = i < n ? v / 3u : v;
  return v;
}

/* pbrt-v3 HaltonSampler::GetIndexForSample for the absolute pixel (px, py): the global index of
 * the pixel's sample `sample_number`. Pixels are taken modulo 128 like pbrt-v3's Mod (p & 127,
 * negatives included). pbrt-v3's offset (d0 * scale1 * inv0 + d1 * scale0 * inv1) mod stride is
 * formed from its two CRT terms reduced mod scale0 and scale1 (same value, no runtime division). */
CLR_HALTON_INLINE clr_u64 clr_halton_sampler_index(const clr_sampler_params *p, clr_i32 px,
                                                   clr_i32 py, clr_i64 sample_number) {
  clr_u32 scale0 = (clr_u32)p->halton_scale[0], scale1 = (clr_u32)p->halton_scale[1];
  clr_u32 stride = (clr_u32)p->halton_stride;
  clr_i32 exponent1 = p->halton_exponent[1];
  clr_u32 mx = (clr_u32)px & (CLR_HALTON_MAX_RESOLUTION - 1u);
  clr_u32 my = (clr_u32)py & (CLR_HALTON_MAX_RESOLUTION - 1u);
  /* InverseRadicalInverse<2>(mx, e0): the e0 low bits reversed (e0 <= 7). */
  clr_u32 d0 = (clr_reverse_bits32(mx) >> (31u - (clr_u32)p->halton_exponent[0])) >> 1u;
  /* InverseRadicalInverse<3>(my, e1), e1 <= 5. */
  clr_u32 d1 = 0u;
#if CLR_DEVICE
#pragma unroll
#endif
  for (clr_i32 i = 0; i < 5; ++i) {
    clr_u32 next = my / 3u;
    d1 = i < exponent1 ? d1 * 3u + (my - next * 3u) : d1;
    my = next;
  }
  clr_u32 x0 = (d0 * p->halton_mult_inverse[0]) & (scale0 - 1u);
  clr_u32 y1 = d1 * p->halton_mult_inverse[1];
  clr_u32 x1 = y1 - clr_halton_div_pow3(y1, exponent1) * scale1;
  clr_u32 offset = x0 * scale1 + x1 * scale0;
  offset = offset >= stride ? offset - stride : offset;
  return (clr_u64)offset + (clr_u64)sample_number * (clr_u64)stride;
}

/* index / scale[1] (scale[1] = 3^exponent[1]). */
CLR_HALTON_INLINE clr_u64 clr_halton_drop_base3_digits(const clr_sampler_params *p, clr_u64 index) {
#ifndef CLR_HALTON_INDEX32
  if ((index >> 32u) != 0u) return index / (clr_u64)(clr_u32)p->halton_scale[1];
#endif
  return clr_halton_div_pow3((clr_u32)index, p->halton_exponent[1]);
}

/* pbrt-v3 HaltonSampler::SampleDimension(index, dim):
 *   dims 0, 1: 0.5 with sample_pixel_center; else Phi_2(index >> exponent[0]) and
 *              Phi_3(index / scale[1]), the offset inside the pixel (unscrambled; dim 1 uses
 *              record CLR_HALTON_BASE3_RECORD);
 *   dims 2..999: ScrambledRadicalInverse with primes[dim] and its permutation.
 * `primes` holds CLR_HALTON_PRIME_RECORDS records, `perms` the whole clr_halton_permutations().
 * Where pbrt-v3 aborts (dim >= 1000, or dim < 0) this returns a documented stand-in:
 *   clr_hash_float(clr_mix64(index) ^ (clr_u32)dim), uniform in [0, 1). */
CLR_HALTON_INLINE float clr_halton_sampler_value(const clr_sampler_params *p,
                                                 CLR_GLOBAL const clr_halton_prime *primes,
                                                 CLR_GLOBAL const clr_u16 *perms, clr_u64 index,
                                                 clr_i32 dim) {
  /* Select-based so that work items with different dims vectorise together. */
  clr_u32 udim = (clr_u32)dim;
  clr_u32 scrambled = udim >= 2u && udim < CLR_HALTON_PRIMES;
  clr_u32 record = udim == 1u ? CLR_HALTON_BASE3_RECORD : scrambled ? udim : 2u;
  clr_u64 a = udim == 1u ? clr_halton_drop_base3_digits(p, index) : index;
  float table_value = clr_scrambled_radical_inverse(primes + record, perms, a);
  clr_u64 a2 = index >> (clr_u32)p->halton_exponent[0];
#ifdef CLR_HALTON_INDEX32
  float base2_value = (float)clr_reverse_bits32((clr_u32)a2) * 0x1p-32f;
#else
  float base2_value = clr_radical_inverse_base2(a2);
#endif
  float past_tables = clr_hash_float(clr_mix64(index) ^ (clr_u64)udim);
  float v = udim == 0u ? base2_value : udim < CLR_HALTON_PRIMES ? table_value : past_tables;
  return (udim <= 1u && p->sample_pixel_center) ? 0.5f : v;
}

#endif
