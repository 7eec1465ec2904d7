/* Device-only: pbrt-v4's samplers in OpenCL vector types for SIMD contexts, 8 lanes per
 * work-item: zsobol, paddedsobol and pmj02bn one pixel per lane (clr_v4_pixel_vectors' paths),
 * sobol, halton, independent and stratified one sample vector per lane (clr_v4_sample_vector's).
 * Each lane runs the integer and float operations of the scalar functions
 * (pbrt_v4_sampler_funcs.h), so the bits are those of the host reference. 64-bit lanes are two
 * halves of 4 (ulong8 values would change the AVX2 ABI). */
#ifndef CLR_PBRT_V4_SAMPLER_SIMD_H
#define CLR_PBRT_V4_SAMPLER_SIMD_H

#include "pbrt_v4_sampler_funcs.h"
#include "lane_math.h"
#include "lane_store.h"
#include "pcg32_lanes.h"

#define CLR_V4_LANES 8

#define CLR_V4_INLINE static inline __attribute__((always_inline))

/* clr_v4_mix_bits in 4 lanes. */
CLR_V4_INLINE ulong4 clr_v4_mix_bits4(ulong4 v) {
  CLR_V4_MIX_BITS(v);
  return v;
}

/* The low 32 bits of clr_v4_mix_bits of 8 lanes given as two halves. */
CLR_V4_INLINE uint8 clr_v4_mix_bits_low8(ulong4 lo, ulong4 hi) {
  return (uint8)(convert_uint4(clr_v4_mix_bits4(lo)), convert_uint4(clr_v4_mix_bits4(hi)));
}

/* Byte `perm & 3` of the 32-bit word w (every lane its own). */
CLR_V4_INLINE uint8 clr_v4_byte8(uint w, uint8 perm) {
  return ((uint8)w >> ((perm & 3u) * 8u)) & 0xffu;
}

/* clr_v4_permute4(perm, digit) in every lane: the packed entry of permutation perm < 24 from the
 * six 32-bit words of CLR_V4_PERM4_WORD(0, 8, 16), then its 2-bit digit. */
CLR_V4_INLINE uint8 clr_v4_permute4x8(uint8 perm, uint8 digit) {
  const ulong w0 = CLR_V4_PERM4_WORD(0u), w8 = CLR_V4_PERM4_WORD(8u), w16 = CLR_V4_PERM4_WORD(16u);
  int8 low = (perm & 7u) < 4u;
  uint8 packed = select(clr_v4_byte8((uint)(w0 >> 32u), perm), clr_v4_byte8((uint)w0, perm), low);
  packed = select(packed,
                  select(clr_v4_byte8((uint)(w8 >> 32u), perm), clr_v4_byte8((uint)w8, perm), low),
                  perm >= 8u);
  packed = select(
      packed, select(clr_v4_byte8((uint)(w16 >> 32u), perm), clr_v4_byte8((uint)w16, perm), low),
      perm >= 16u);
  return (packed >> (2u * digit)) & 3u;
}

/* 64-bit values of the 8 lanes in two halves (the lanes' Morton indices, digit indices). */
typedef struct clr_v4_u64x8 {
  ulong4 lo, hi;
} clr_v4_u64x8;

/* (8 y + low) % 24 in every lane from y's parts: y = top 2^32 + mid below 2^37, low below 8. y
 * mod 3 by folding the 32-, 16- and 8-bit parts (2^32, 2^16 and 2^8 are 1 mod 3) to below 2^10,
 * where a 16-bit reciprocal is exact; no division (a 64-bit remainder has no vector
 * instruction). */
CLR_V4_INLINE uint8 clr_v4_mod24_parts8(uint8 top, uint8 mid, uint8 low) {
  uint8 t = (mid >> 16u) + (mid & 0xffffu) + top;
  t = (t >> 8u) + (t & 0xffu);
  uint8 q = (t * 21846u) >> 16u;
  return ((t - 3u * q) << 3u) | low;
}

/* (hash >> 24) % 24 of every lane's 64-bit hash (two halves): zsobol's digit permutation. */
CLR_V4_INLINE uint8 clr_v4_mod24x8(ulong4 lo, ulong4 hi) {
  uint8 top = (uint8)(convert_uint4(lo >> 59ul), convert_uint4(hi >> 59ul));
  uint8 mid = (uint8)(convert_uint4(lo >> 27ul), convert_uint4(hi >> 27ul));
  uint8 low = (uint8)(convert_uint4(lo >> 24ul), convert_uint4(hi >> 24ul)) & 7u;
  return clr_v4_mod24_parts8(top, mid, low);
}

/* The permutation (of 24) of the base-4 digit below bit `above` of every lane's m: a hash of the
 * bits from `above` up and the salt (clr_v4_zsobol_digits). */
CLR_V4_INLINE uint8 clr_v4_digit_perm8(const clr_v4_u64x8 *m, ulong above, ulong salt) {
  ulong4 hash_lo = clr_v4_mix_bits4((m->lo >> above) ^ salt);
  ulong4 hash_hi = clr_v4_mix_bits4((m->hi >> above) ^ salt);
  return clr_v4_mod24x8(hash_lo, hash_hi);
}

/* Base-4 digit `shift` (its low bit) of every lane's m. */
CLR_V4_INLINE uint8 clr_v4_digit8(const clr_v4_u64x8 *m, ulong shift) {
  return (uint8)(convert_uint4(m->lo >> shift), convert_uint4(m->hi >> shift)) & 3u;
}

/* The lowest base-4 digit in low..top (digit i at bit 2i - odd) that is the same in every lane's
 * m, with all bits above it (top + 1 when none is): such digits, and the bits their permutations
 * hash, are lane 0's. */
CLR_V4_INLINE int clr_v4_shared_digit(const clr_v4_u64x8 *m, int odd, int low, int top) {
  ulong m0 = m->lo.s0;
  ulong4 differ4 = (m->lo ^ m0) | (m->hi ^ m0);
  ulong2 differ2 = differ4.lo | differ4.hi;
  ulong differ = differ2.x | differ2.y; /* the bits where a lane is not lane 0 */
  int shared = low;
  while (shared <= top && (differ >> (ulong)(2 * shared - odd)) != 0ul) ++shared;
  return shared;
}

/* clr_v4_zsobol_pixel_part in every lane: the permuted digits of the pixels' Morton indices. The
 * top digits that are the same in every lane (neighbouring pixels share their high Morton bits),
 * and so hash the same bits, are permuted once, as scalars. */
CLR_V4_INLINE clr_v4_u64x8 clr_v4_zsobol_pixel_part8(const clr_sampler_params *p,
                                                     const clr_v4_u64x8 *m, ulong salt) {
  int odd = p->zsobol_log2_spp & 1, top = p->zsobol_base4_digits - 1;
  int shared = clr_v4_shared_digit(m, odd, clr_v4_zsobol_pixel_digit(p), top);
  clr_v4_u64x8 index;
  index.lo = index.hi = (ulong4)clr_v4_zsobol_digits(m->lo.s0, salt, odd, top, shared);
  for (int i = shared - 1; i >= clr_v4_zsobol_pixel_digit(p); --i) {
    ulong shift = (ulong)(2 * i - odd);
    uint8 e = clr_v4_permute4x8(clr_v4_digit_perm8(m, shift + 2ul, salt), clr_v4_digit8(m, shift));
    index.lo |= convert_ulong4(e.lo) << shift;
    index.hi |= convert_ulong4(e.hi) << shift;
  }
  return index;
}

/* zsobol's sample-digit permutations of the 8 lanes' pixels at one dimension. Digit i's is a hash
 * of the sample bits above it (and the pixel's), so over consecutive samples it changes only when
 * those do: 1 + 4 + 16 + ... hashes per pixel and dimension, not one per digit and sample. */
typedef struct clr_v4_zsobol_digits8 {
  uint8 perm[16]; /* digit i's permutation (of 24); sample numbers have at most 32 bits */
  uint8 flip;     /* the last binary digit's flip when spp is 2^odd */
  ulong last;     /* the sample number they were made for (~0: none yet) */
} clr_v4_zsobol_digits8;

/* clr_v4_zsobol_sample_part for sample `sample` of the 8 lanes' pixels (< 2^32: spp's bits),
 * rehashing only the digits whose higher sample bits differ from the last call's (c). */
CLR_V4_INLINE uint8 clr_v4_zsobol_sample_part8(const clr_sampler_params *p, const clr_v4_u64x8 *m,
                                               uint sample, ulong salt, clr_v4_zsobol_digits8 *c) {
  ulong changed = c->last ^ (ulong)sample;
  c->last = (ulong)sample;
  clr_v4_u64x8 s;
  s.lo = m->lo | (ulong)sample;
  s.hi = m->hi | (ulong)sample;
  int odd = p->zsobol_log2_spp & 1;
  uint8 index = (uint8)0u;
  for (int i = clr_v4_zsobol_pixel_digit(p) - 1; i >= odd; --i) {
    ulong shift = (ulong)(2 * i - odd);
    if ((changed >> (shift + 2ul)) != 0ul) c->perm[i] = clr_v4_digit_perm8(&s, shift + 2ul, salt);
    index |= clr_v4_permute4x8(c->perm[i], clr_v4_digit8(&s, shift)) << (uint)shift;
  }
  if (odd) {
    if ((changed >> 1ul) != 0ul)
      c->flip = clr_v4_mix_bits_low8((s.lo >> 1ul) ^ salt, (s.hi >> 1ul) ^ salt) & 1u;
    index |= ((uint8)(convert_uint4(s.lo), convert_uint4(s.hi)) & 1u) ^ c->flip;
  }
  return index;
}

/* clr_sobol_xor_columns32 of `bits` below 2^count in every lane. */
CLR_V4_INLINE uint8 clr_v4_xor_columns8(uint8 bits, int count, __global const uint *cols) {
  uint8 v = (uint8)0u;
  for (int b = 0; b < count; ++b)
    v ^= select((uint8)0u, (uint8)cols[b], ((bits >> (uint)b) & 1u) != 0u);
  return v;
}

/* clr_v4_sobol_bits of every lane's index a, whose bits are below 2^count. */
CLR_V4_INLINE uint8 clr_v4_sobol_bits8(const clr_v4_u64x8 *a, int count,
                                       __global const uint *cols) {
  uint8 low = (uint8)(convert_uint4(a->lo), convert_uint4(a->hi));
  uint8 high = (uint8)(convert_uint4(a->lo >> 32ul), convert_uint4(a->hi >> 32ul)) &
               ((1u << (CLR_SOBOL_INDEX_BITS - 32u)) - 1u);
  return clr_v4_xor_columns8(low, min(count, 32), cols) ^
         clr_v4_xor_columns8(high, count - 32, cols + 32);
}

/* clr_v4_owen in every lane. */
CLR_V4_INLINE uint8 clr_v4_owen8(uint8 v, uint8 seed) {
  v ^= (seed & 1u) << 31u;
  for (uint b = 1u; b < 32u; ++b) {
    uint8 key = (v & (0xffffffffu << (32u - b))) ^ seed;
    uint8 h = clr_v4_mix_bits_low8(convert_ulong4(key.lo), convert_ulong4(key.hi));
    v ^= select((uint8)0u, (uint8)(1u << (31u - b)), (h & (1u << b)) != 0u);
  }
  return v;
}

/* clr_v4_sobol_finish in every lane: the randomizer, then the value below one. */
CLR_V4_INLINE float8 clr_v4_sobol_finish8(uint8 v, int randomization, uint8 seed) {
  if (randomization == CLR_RANDOMIZE_TYPE_PERMUTEDIGITS) {
    v ^= seed;
  } else if (randomization == CLR_RANDOMIZE_TYPE_FASTOWEN) {
    v = clr_reverse_bits32x8(v);
    CLR_V4_FAST_OWEN_HASH(v, seed);
    v = clr_reverse_bits32x8(v);
  } else if (randomization == CLR_RANDOMIZE_TYPE_OWEN) {
    v = clr_v4_owen8(v, seed);
  }
  float8 f = convert_float8(v) * 0x1p-32f;
  return select((float8)CLR_ONE_MINUS_EPSILON, f, f < CLR_ONE_MINUS_EPSILON);
}

/* One Get1D (dims 1) or Get2D of every sample of the 8 lanes' pixels at `dimension`, stored at
 * value `first` of each sample. */
static inline void clr_v4_zsobol_values8(const clr_sampler_params *p, __global const uint *sobol32,
                                         const clr_v4_u64x8 *m, int dimension, int dims,
                                         __global float *values, const ulong *out, int first) {
  ulong salt = clr_v4_zsobol_salt(dimension);
  __global const uint *cols0 = sobol32, *cols1 = sobol32 + CLR_SOBOL_MATRIX_SIZE;
  clr_v4_u64x8 high = clr_v4_zsobol_pixel_part8(p, m, salt); /* the (pixel, dimension) part */
  int high_bits = 2 * p->zsobol_base4_digits;
  uint8 pixel0 = clr_v4_sobol_bits8(&high, high_bits, cols0);
  uint8 pixel1 = dims == 2 ? clr_v4_sobol_bits8(&high, high_bits, cols1) : (uint8)0u;
  ulong hash = clr_v4_hash8(clr_v4_pack(dimension + dims, (int)p->seed));
  clr_v4_zsobol_digits8 digits;
  digits.last = ~0ul;
  for (int k = 0; k < p->sample_count; ++k) {
    uint8 low = clr_v4_zsobol_sample_part8(p, m, (uint)(p->first_sample + k), salt, &digits);
    size_t at = (size_t)k * (size_t)p->values_per_sample + (size_t)first;
    float8 u0 = clr_v4_sobol_finish8(pixel0 ^ clr_v4_xor_columns8(low, p->zsobol_log2_spp, cols0),
                                     p->randomization, (uint8)(uint)hash);
    if (dims == 1) {
      clr_store_lanes8(values, out, at, u0);
      continue;
    }
    float8 u1 = clr_v4_sobol_finish8(pixel1 ^ clr_v4_xor_columns8(low, p->zsobol_log2_spp, cols1),
                                     p->randomization, (uint8)(uint)(hash >> 32u));
    clr_store_pairs8(values, out, at, u0, u1);
  }
}

/* x / l in every lane for a uniform l > 0, without eight scalar divisions: a shift for powers
 * of two, else Granlund and Montgomery's multiply by an invariant reciprocal (exact for every
 * 32-bit x; halton_tables.c's division_magic). */
CLR_V4_INLINE uint8 clr_v4_quotient8(uint8 x, uint l) {
  uint shift = 32u - clz(l - 1u); /* ceil(log2(l)) */
  /* not l & (l - 1): LLVM makes that a popcount, which Oclgrind cannot run */
  if (((ulong)1 << shift) == (ulong)l) return x >> shift;
  uint magic = (uint)((((ulong)1 << shift) - (ulong)l) * ((ulong)1 << 32) / (ulong)l + 1ul);
  uint8 t = clr_mul_hi8(x, magic);
  return (t + ((x - t) >> 1u)) >> (shift - 1u);
}

/* clr_v4_permutation_element(i, l, p) with every lane's own i and p: each lane walks its cycle
 * until its element is below l. */
CLR_V4_INLINE uint8 clr_v4_permutation_element8(uint8 i, uint l, uint8 p) {
  uint w = clr_v4_permutation_mask(l);
  uint8 v = i;
  int8 walking = (int8)-1;
  do {
    uint8 x = v;
    CLR_V4_PERMUTATION_STEP(x, p, w);
    v = select(v, x, walking);
    walking &= v >= l;
  } while (clr_any8(walking));
  v += p;
  return v - clr_v4_quotient8(v, l) * l;
}

/* paddedsobol's Get1D (dims 1) or Get2D of every sample of the 8 lanes' pixels at `dimension`
 * (clr_v4_pixel_dim_value), stored at value `first` of each sample. */
static inline void clr_v4_padded_values8(const clr_sampler_params *p, __global const uint *sobol32,
                                         const int *px, const int *py, int dimension, int dims,
                                         __global float *values, const ulong *out, int first) {
  uint low_hash[CLR_V4_LANES], high_hash[CLR_V4_LANES];
  for (int j = 0; j < CLR_V4_LANES; ++j) { /* Hash(pixel, dimension, seed), lane by lane */
    ulong hash = clr_v4_pixel_dim_hash(p, px[j], py[j], dimension);
    low_hash[j] = (uint)hash;
    high_hash[j] = (uint)(hash >> 32u);
  }
  uint8 permutation = vload8(0, low_hash), high = vload8(0, high_hash);
  int bits = 0; /* the permuted indices' bits: those of spp - 1 */
  while (bits < 32 && ((uint)(p->spp - 1) >> (uint)bits) != 0u) ++bits;
  __global const uint *cols0 = sobol32, *cols1 = sobol32 + CLR_SOBOL_MATRIX_SIZE;
  for (int k = 0; k < p->sample_count; ++k) {
    uint8 index =
        clr_v4_permutation_element8((uint8)(uint)(p->first_sample + k), (uint)p->spp, permutation);
    size_t at = (size_t)k * (size_t)p->values_per_sample + (size_t)first;
    float8 u0 = clr_v4_sobol_finish8(clr_v4_xor_columns8(index, bits, cols0), p->randomization,
                                     dims == 1 ? high : permutation);
    if (dims == 1) {
      clr_store_lanes8(values, out, at, u0);
      continue;
    }
    float8 u1 =
        clr_v4_sobol_finish8(clr_v4_xor_columns8(index, bits, cols1), p->randomization, high);
    clr_store_pairs8(values, out, at, u0, u1);
  }
}

/* clr_v4_div in every lane: in double where the device has fp64 (see clr_v4_div), else lane by
 * lane. */
CLR_V4_INLINE float8 clr_v4_div8(float8 a, uint b) {
  uint shift = 32u - clz(b - 1u); /* ceil(log2(b)) */
  /* a power of two: a * 2^-shift is exact, so it is the correctly rounded quotient (no a here
   * is small enough to lose bits: they are multiples of 2^-32) */
  if (((ulong)1 << shift) == (ulong)b) return a * (1.0f / (float)b);
#ifdef cl_khr_fp64
  return (float8)(convert_float4(convert_double4(a.lo) / (double)b),
                  convert_float4(convert_double4(a.hi) / (double)b));
#else
  float q[CLR_V4_LANES];
  vstore8(a, 0, q);
  for (int j = 0; j < CLR_V4_LANES; ++j) q[j] = clr_v4_div(q[j], b);
  return vload8(0, q);
#endif
}

/* clr_v4_below_one per lane. */
CLR_V4_INLINE float8 clr_v4_below_one8(float8 f) {
  return select((float8)CLR_ONE_MINUS_EPSILON, f, f < CLR_ONE_MINUS_EPSILON);
}

/* clr_v4_pmj02_rotate per lane. */
CLR_V4_INLINE float8 clr_v4_pmj02_rotate8(float8 v, float8 noise) {
  v += noise;
  return clr_v4_below_one8(select(v, v - 1.0f, v >= 1.0f));
}

/* Coordinates (c = 0, 1) of points `index` (every lane its own) of one pmj02bn point set. */
CLR_V4_INLINE float8 clr_v4_pmj02_points8(__global const float *set, uint8 index, int c) {
  uint8 at = 2u * index + (uint)c;
  return (float8)(set[at.s0], set[at.s1], set[at.s2], set[at.s3], set[at.s4], set[at.s5],
                  set[at.s6], set[at.s7]);
}

/* clr_v4_blue_noise_sample of the 8 lanes' pixels (m: their clr_v4_blue_noise_morton).
 * Its digit permutations take (uint32)(hash >> 24) % 24, as pbrt-v4's BlueNoiseSample does (not
 * zsobol's 64-bit remainder). The top digits shared by every lane are permuted once, as scalars
 * (clr_v4_shared_digit). */
CLR_V4_INLINE float8 clr_v4_blue_noise8(const clr_v4_u64x8 *m, int instance) {
  ulong salt = clr_v4_blue_noise_salt(instance);
  int shared = clr_v4_shared_digit(m, 0, 0, 7);
  uint8 index = (uint8)clr_v4_blue_noise_digits(m->lo.s0, salt, 7, shared);
  for (int i = shared - 1; i >= 0; --i) {
    ulong shift = (ulong)(2 * i);
    uint8 x = (uint8)(convert_uint4(clr_v4_mix_bits4((m->lo >> (shift + 2ul)) ^ salt) >> 24ul),
                      convert_uint4(clr_v4_mix_bits4((m->hi >> (shift + 2ul)) ^ salt) >> 24ul));
    uint8 perm = clr_v4_mod24_parts8((uint8)0u, x >> 3u, x & 7u);
    index |= clr_v4_permute4x8(perm, clr_v4_digit8(m, shift)) << (uint)shift;
  }
  return convert_float8(clr_reverse_bits32x8(index)) * 0x1p-32f;
}

/* pmj02bn's Get1D (dims 1) or Get2D of every sample of the 8 lanes' pixels at `dimension`
 * (clr_v4_pixel_dim_value), stored at value `first` of each sample: the (pixel, dimension)
 * hashes lane by lane, the blue noise, the samples' permutations and points in lanes. */
static inline void clr_v4_pmj02_values8(const clr_sampler_params *p, const clr_v4_tables *t,
                                        const int *px, const int *py, const clr_v4_u64x8 *m,
                                        int dimension, int dims, __global float *values,
                                        const ulong *out, int first) {
  int set = dimension / 2;
  uint hash[CLR_V4_LANES];
  for (int j = 0; j < CLR_V4_LANES; ++j) /* clr_v4_pixel_dim_part's */
    hash[j] = dims == 1 || set >= CLR_PMJ02_SETS
                  ? (uint)clr_v4_pixel_dim_hash(p, px[j], py[j], dimension)
                  : 0u;
  uint8 h = vload8(0, hash);
  float8 n0 = clr_v4_blue_noise8(m, dimension);
  float8 n1 = dims == 2 ? clr_v4_blue_noise8(m, dimension + 1) : (float8)0.0f;
  __global const float *points = t->pmj_sets + 2u * (uint)(set % CLR_PMJ02_SETS) * (uint)p->spp;
  for (int k = 0; k < p->sample_count; ++k) {
    uint8 sample = (uint8)(uint)(p->first_sample + k);
    size_t at = (size_t)k * (size_t)p->values_per_sample + (size_t)first;
    if (dims == 1) { /* clr_v4_pmj02_value1d */
      uint8 index = clr_v4_permutation_element8(sample, (uint)p->spp, h);
      clr_store_lanes8(values, out, at,
                       clr_v4_below_one8(clr_v4_div8(convert_float8(index) + n0, (uint)p->spp)));
      continue;
    }
    uint8 index = set < CLR_PMJ02_SETS ? sample /* clr_v4_pmj02_index2d */
                                       : clr_v4_permutation_element8(sample, (uint)p->spp, h);
    clr_store_pairs8(values, out, at,
                     clr_v4_pmj02_rotate8(clr_v4_pmj02_points8(points, index, 0), n0),
                     clr_v4_pmj02_rotate8(clr_v4_pmj02_points8(points, index, 1), n1));
  }
}

/* pmj02bn's GetPixel2D of every sample of the 8 lanes' pixels: their tile pixel's table entries. */
static inline void clr_v4_pmj02_pixel8(const clr_sampler_params *p, const clr_v4_tables *t,
                                       const int *px, const int *py, __global float *values,
                                       const ulong *out, int first) {
  uint at[CLR_V4_LANES];
  for (int j = 0; j < CLR_V4_LANES; ++j) {
    int x = clr_v4_mod(px[j], p->pmj_tile), y = clr_v4_mod(py[j], p->pmj_tile);
    at[j] = (uint)((x + y * p->pmj_tile) * p->spp);
  }
  uint8 row = vload8(0, at);
  for (int k = 0; k < p->sample_count; ++k) {
    uint8 index = row + (uint)(p->first_sample + k);
    clr_store_pairs8(values, out, (size_t)k * (size_t)p->values_per_sample + (size_t)first,
                     clr_v4_pmj02_points8(t->pmj_pixels, index, 0),
                     clr_v4_pmj02_points8(t->pmj_pixels, index, 1));
  }
}

/* The 8 lanes' pixels: raster coordinates, and Morton indices: zsobol's of their sample 0,
 * pmj02bn's blue noise's (clr_v4_blue_noise_morton). */
typedef struct clr_v4_lanes8 {
  int px[CLR_V4_LANES], py[CLR_V4_LANES];
  clr_v4_u64x8 morton;
} clr_v4_lanes8;

/* clr_v4_pixel_vectors for zsobol, paddedsobol and pmj02bn, 8 pixels (lane j's values start at
 * values[out[j]]). */
static inline void clr_v4_pixels8(const clr_sampler_params *p,
                                  __global const clr_request_slot *slots, const clr_v4_tables *t,
                                  const clr_v4_lanes8 *lanes, __global float *values,
                                  const ulong *out) {
  __global const uint *sobol32 = t->sobol32;
  int pmj = p->v4_sampler == CLR_V4_PMJ02BN;
  int dimension = pmj ? 2 : 0;
  for (int r = 0; r < p->request_count; ++r) {
    clr_request_slot sl = slots[r];
    int elements = sl.array_size ? sl.array_size : 1;
    if (sl.skipped) { /* never the film offset: its dimensions only */
      dimension += elements * sl.dims;
      continue;
    }
    int dims = r == p->film_request ? 2 : sl.dims;
    for (int j = 0; j < elements; ++j) {
      int first = sl.first_value + (sl.dims == 2 ? 2 * j : j);
      if (pmj && r == p->film_request) { /* its own table; no dimension */
        clr_v4_pmj02_pixel8(p, t, lanes->px, lanes->py, values, out, first);
        continue;
      }
      if (p->v4_sampler == CLR_V4_ZSOBOL)
        clr_v4_zsobol_values8(p, sobol32, &lanes->morton, dimension, dims, values, out, first);
      else if (pmj)
        clr_v4_pmj02_values8(p, t, lanes->px, lanes->py, &lanes->morton, dimension, dims, values,
                             out, first);
      else
        clr_v4_padded_values8(p, sobol32, lanes->px, lanes->py, dimension, dims, values, out,
                              first);
      dimension += dims;
    }
  }
}

/* The 8 batch items of a clr_v4_generate8 work-item, one per lane (past the end the last item
 * repeats): their pixels and sample numbers, and whether each is the next sample of the previous
 * lane's pixel. */
typedef struct clr_v4_lane_items8 {
  uint item[CLR_V4_LANES];
  int x[CLR_V4_LANES], y[CLR_V4_LANES], sample[CLR_V4_LANES];
  int next_in_pixel[CLR_V4_LANES];
} clr_v4_lane_items8;

/* clr_v4_lane_items8 of work-item `group`: lane 0's item by division, the others by counting on. */
CLR_V4_INLINE void clr_v4_walk_items8(const clr_sampler_params *p, size_t group, int item_count,
                                      clr_v4_lane_items8 *l) {
  uint first = (uint)(group * CLR_V4_LANES), item = min(first, (uint)item_count - 1u);
  int pixel = (int)(item / (uint)p->sample_count), row = pixel / p->batch_width;
  int column = pixel - row * p->batch_width, number = (int)item - pixel * p->sample_count;
  for (int j = 0; j < CLR_V4_LANES; ++j) {
    int next = j > 0 && first + (uint)j < (uint)item_count; /* lane j - 1's item's next */
    if (next) {
      ++item;
      if (++number == p->sample_count) {
        number = 0;
        if (++column == p->batch_width) {
          column = 0;
          ++row;
        }
      }
    }
    l->item[j] = item;
    l->x[j] = p->batch_x0 + column;
    l->y[j] = p->batch_y0 + row;
    l->sample[j] = p->first_sample + number;
    l->next_in_pixel[j] = next && number > 0;
  }
}

/* The bits of a launch's largest sample number, first_sample + sample_count - 1 (64 past 2^32). */
CLR_V4_INLINE int clr_v4_sample_number_bits(const clr_sampler_params *p) {
  ulong last = (ulong)((long)p->first_sample + (long)p->sample_count - 1l);
  return (last >> 32u) != 0ul ? 64 : 32 - (int)clz((uint)last);
}

/* The Sobol' matrices of clr_v4_global_vectors8: columns (sobol32), the 3-bit group tables
 * (groups; NULL: none), and the 8 lanes' indices, below 2^bits, also in 32 bits when bits <= 32. */
typedef struct clr_v4_sobol_lanes {
  __global const uint *sobol32, *groups;
  clr_v4_u64x8 index;
  uint8 index32;
  int bits;
} clr_v4_sobol_lanes;

/* clr_v4_sobol_bits of `dimension`'s matrix in every lane: one group lookup per 3 index bits
 * where the indices have at most 32 and the tables are there, else column by column. */
CLR_V4_INLINE uint8 clr_v4_sobol_matrix_bits8(const clr_v4_sobol_lanes *l, int dimension) {
  if (l->groups && l->bits <= 32)
    return clr_sobol_group_bits8(l->index32, l->groups + (size_t)dimension * CLR_SOBOL_GROUP_TABLE,
                                 l->bits);
  return clr_v4_sobol_bits8(&l->index, l->bits,
                            l->sobol32 + (size_t)dimension * CLR_SOBOL_MATRIX_SIZE);
}

/* SobolSampler's Get1D at `dimension` for the 8 lanes' indices. */
CLR_V4_INLINE float8 clr_v4_sobol_dimension8(const clr_sampler_params *p,
                                             const clr_v4_sobol_lanes *l, int dimension) {
  uint hash = (uint)clr_v4_hash8(clr_v4_pack(dimension, (int)p->seed));
  return clr_v4_sobol_finish8(clr_v4_sobol_matrix_bits8(l, dimension), p->randomization,
                              (uint8)hash);
}

/* clr_v4_sobol_pixel in every lane. */
CLR_V4_INLINE float8 clr_v4_sobol_pixel8(const clr_sampler_params *p, float8 u, float8 pixel) {
  float8 v = u * p->sobol_resolution - pixel;
  v = select(v, (float8)CLR_ONE_MINUS_EPSILON, v > CLR_ONE_MINUS_EPSILON);
  return select(v, (float8)0.0f, v < 0.0f);
}

/* The lanes' Sobol' state for clr_v4_global_vectors8: the matrices (groups may be NULL) and the
 * indices, with their bit count (that of their OR). */
CLR_V4_INLINE void clr_v4_sobol_lanes_init(clr_v4_sobol_lanes *l, __global const uint *sobol32,
                                           __global const uint *groups, const clr_v4_u64x8 *index) {
  ulong4 any = index->lo | index->hi;
  ulong2 any2 = any.lo | any.hi;
  ulong all = any2.x | any2.y;
  l->sobol32 = sobol32;
  l->groups = groups;
  l->index = *index;
  l->index32 = (uint8)(convert_uint4(index->lo), convert_uint4(index->hi));
  l->bits = 64 - (int)clz(all);
}

/* pbrt-v4's HaltonSampler with permuted digits (its default), 8 sample vectors per work-item
 * whose halton indices are below 2^32, with halton_exponent[1] >= 1 (so dimension 1's argument,
 * index / 3^e1, is below 2^32 / 3 and its reversed digits below 2^32). */

/* clr_v4_radical_inverse in base 2 of a < 2^32: its reversed digits r (k of them) are the
 * reversed bits of a shifted down past 32 - k zero bits, so (float)r * 2^-k is this float. */
CLR_V4_INLINE float8 clr_v4_radical_inverse2x8(uint8 a) {
  return clr_v4_below_one8(convert_float8(clr_reverse_bits32x8(a)) * 0x1p-32f);
}

/* clr_v4_radical_inverse in base 3 (record pr) of a < 2^32 / 3: digit by digit while a lane has
 * digits left; each lane multiplies its invBaseM once per digit of its own. */
CLR_V4_INLINE float8 clr_v4_radical_inverse3x8(__global const clr_halton_prime *pr, uint8 a) {
  const float inv_base = pr->inv_base;
  uint8 reversed = (uint8)0u;
  float8 inv_m = (float8)1.0f;
  int8 active = a != 0u;
  CLR_SCALAR_LOOP
  while (clr_any8(active)) {
    uint8 next = a / 3u;
    reversed = select(reversed, reversed * 3u + (a - next * 3u), active);
    inv_m = select(inv_m, inv_m * inv_base, active);
    a = next;
    active = a != 0u;
  }
  return clr_v4_below_one8(convert_float8(reversed) * inv_m);
}

/* The permuted zeros of digits i .. digits - 1 (permutation tables from perms on, base entries
 * each), the same in every lane whose own digits are spent: their reversed digits, and
 * base^(their count) at *scale. */
CLR_V4_INLINE ulong clr_v4_zero_digits(__global const ushort *perms, uint base, int i, int digits,
                                       ulong *scale) {
  ulong tail = 0ul, s = 1ul;
  for (; i < digits; ++i, perms += base) {
    tail = tail * base + perms[0];
    s *= base;
  }
  *scale = s;
  return tail;
}

/* clr_v4_scrambled_radical_inverse of a < 2^32 in every lane, digit i's permutation at perms +
 * i * base (the dimension's DigitPermutation table). The scalar loop permutes all nDigits digits
 * (zeros past a's own), so the lanes share its trip count; once every lane's digits are spent the
 * rest are permuted zeros, the same in every lane (clr_v4_zero_digits), and reversed *
 * base^(digits left) + their reversed digits is what the scalar loop sums. The reversed digits
 * (below base^nDigits) are summed in 32-bit lanes where that bound fits, else in 64-bit halves. */
CLR_V4_INLINE float8 clr_v4_scrambled_radical_inverse8(__global const clr_halton_prime *pr,
                                                       __global const ushort *perms, uint8 a) {
  const uint base = pr->base, magic = pr->div_magic, shift = pr->div_shift;
  const int digits = (int)pr->v4_digits;
  const float inv_m = pr->inv_base_pow[digits]; /* the scalar loop's invBaseM */
  float8 reversed;
  int i = 0;
  ulong scale;
  if (pr->v4_reversed32) {
    uint8 r = (uint8)0u;
    CLR_SCALAR_LOOP
    for (; i < digits && clr_any8(a != 0u); ++i, perms += base) {
      uint8 t = clr_mul_hi8(a, magic); /* clr_halton_div32 */
      uint8 next = (t + ((a - t) >> 1u)) >> shift;
      r = r * base + clr_gather_u16(perms, a - next * base);
      a = next;
    }
    uint tail = (uint)clr_v4_zero_digits(perms, base, i, digits, &scale);
    reversed = convert_float8(r * (uint)scale + tail);
  } else {
    ulong4 lo = (ulong4)0ul, hi = (ulong4)0ul;
    CLR_SCALAR_LOOP
    for (; i < digits && clr_any8(a != 0u); ++i, perms += base) {
      uint8 t = clr_mul_hi8(a, magic);
      uint8 next = (t + ((a - t) >> 1u)) >> shift;
      uint8 e = clr_gather_u16(perms, a - next * base);
      lo = lo * (ulong)base + convert_ulong4(e.lo);
      hi = hi * (ulong)base + convert_ulong4(e.hi);
      a = next;
    }
    ulong tail = clr_v4_zero_digits(perms, base, i, digits, &scale);
    reversed = (float8)(convert_float4(lo * scale + tail), convert_float4(hi * scale + tail));
  }
  return clr_v4_below_one8(inv_m * reversed);
}

/* clr_v4_halton_dimension with permuted digits in every lane: from the dimension's table, or past
 * the tables (clr_v4_tables) lane by lane with the digits' hashes. */
CLR_V4_INLINE float8 clr_v4_halton_dimension8(const clr_sampler_params *p, const clr_v4_tables *t,
                                              uint8 index, int dim) {
  __global const clr_halton_prime *pr = t->primes + dim;
  if (dim < t->digit_dims)
    return clr_v4_scrambled_radical_inverse8(pr, t->digit_perms + t->digit_offsets[dim], index);
  uint lanes[CLR_V4_LANES];
  float v[CLR_V4_LANES];
  vstore8(index, 0, lanes);
  for (int j = 0; j < CLR_V4_LANES; ++j)
    v[j] = clr_v4_scrambled_radical_inverse(pr, (ulong)lanes[j], p->seed, 0);
  return vload8(0, v);
}

/* The 8 lanes of pbrt-v4's global samplers: sobol's (its matrices and indices, the lanes'
 * pixels for GetPixel2D), or halton's (its tables and 32-bit indices). */
typedef struct clr_v4_global_lanes {
  clr_v4_sobol_lanes sobol;
  float8 px, py;
  const clr_v4_tables *halton;
  uint8 halton_index;
} clr_v4_global_lanes;

/* GetPixel2D in every lane: the unrandomized dimensions 0 and 1 (sobol's remapped into the
 * pixel; halton's second one of index / 3^e1, halton_scale[1]). */
CLR_V4_INLINE void clr_v4_global_pixel8(const clr_sampler_params *p, const clr_v4_global_lanes *g,
                                        float8 *u0, float8 *u1) {
  if (p->v4_sampler == CLR_V4_HALTON) {
    uint8 base3 = g->halton_index;
    CLR_UNROLL
    for (int i = 0; i < 5; ++i)
      if (i < p->halton_exponent[1]) base3 = base3 / 3u;
    *u0 = clr_v4_radical_inverse2x8(g->halton_index >> (uint)p->halton_exponent[0]);
    *u1 = clr_v4_radical_inverse3x8(g->halton->primes + 1, base3);
    return;
  }
  *u0 = clr_v4_sobol_pixel8(
      p, clr_v4_sobol_finish8(clr_v4_sobol_matrix_bits8(&g->sobol, 0), 0, (uint8)0u), g->px);
  *u1 = clr_v4_sobol_pixel8(
      p, clr_v4_sobol_finish8(clr_v4_sobol_matrix_bits8(&g->sobol, 1), 0, (uint8)0u), g->py);
}

/* Get1D at `dimension` in every lane. */
CLR_V4_INLINE float8 clr_v4_global_value8(const clr_sampler_params *p, const clr_v4_global_lanes *g,
                                          int dimension) {
  return p->v4_sampler == CLR_V4_HALTON
             ? clr_v4_halton_dimension8(p, g->halton, g->halton_index, dimension)
             : clr_v4_sobol_dimension8(p, &g->sobol, dimension);
}

/* clr_v4_sample_vector for pbrt-v4's SobolSampler and HaltonSampler (permuted digits), 8 batch
 * items (lane j's values at values[out[j]]): GetPixel2D, then every other value the next
 * dimension, wrapping to 2 past sobol's tables or halton's primes (skipped requests too). */
static inline void clr_v4_global_vectors8(const clr_sampler_params *p,
                                          __global const clr_request_slot *slots,
                                          const clr_v4_global_lanes *g, __global float *values,
                                          const ulong *out) {
  const int wrap = p->v4_sampler == CLR_V4_HALTON ? CLR_HALTON_PRIMES : CLR_SOBOL_DIMENSIONS;
  int dimension = 2;
  for (int r = 0; r < p->request_count; ++r) {
    clr_request_slot sl = slots[r];
    int elements = sl.array_size ? sl.array_size : 1;
    for (int j = 0; j < elements; ++j) {
      if (sl.skipped) { /* clr_v4_skip */
        if (dimension + sl.dims - 1 >= wrap) dimension = 2;
        dimension += sl.dims;
      } else if (r == p->film_request) {
        float8 u0, u1;
        clr_v4_global_pixel8(p, g, &u0, &u1);
        clr_store_pairs8(values, out, (size_t)sl.first_value, u0, u1);
      } else if (sl.dims == 1) {
        if (dimension >= wrap) dimension = 2;
        clr_store_lanes8(values, out, (size_t)(sl.first_value + j),
                         clr_v4_global_value8(p, g, dimension++));
      } else {
        if (dimension + 1 >= wrap) dimension = 2;
        clr_store_pairs8(values, out, (size_t)(sl.first_value + 2 * j),
                         clr_v4_global_value8(p, g, dimension),
                         clr_v4_global_value8(p, g, dimension + 1));
        dimension += 2;
      }
    }
  }
}

/* clr_v4_sample_vector for pbrt-v4's IndependentSampler, 8 batch items (one RNG stream per lane,
 * at its StartPixelSample position; lane j's values at values[out[j]]): every value is the
 * stream's next float, GetPixel2D a Get2D, a skipped request an advance. */
static inline void clr_v4_independent_vectors8(const clr_sampler_params *p,
                                               __global const clr_request_slot *slots,
                                               clr_pcg32x8 *state, __global float *values,
                                               const ulong *out) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  for (int k = 0; k < p->request_count; ++k) {
    clr_request_slot sl = slots[k];
    int elements = sl.array_size ? sl.array_size : 1;
    for (int j = 0; j < elements; ++j) {
      if (sl.skipped) {
        clr_pcg32x8_advance(rng, (ulong)sl.dims);
      } else if (sl.dims == 1 && k != p->film_request) {
        clr_store_lanes8(values, out, (size_t)(sl.first_value + j), clr_pcg32x8_float(rng));
      } else {
        float8 u0 = clr_pcg32x8_float(rng);
        float8 u1 = clr_pcg32x8_float(rng);
        clr_store_pairs8(values, out, (size_t)(sl.first_value + (k == p->film_request ? 0 : 2 * j)),
                         u0, u1);
      }
    }
  }
  *state = r;
}

/* The 8 lanes' items of pbrt-v4's StratifiedSampler: pixels and sample indices, and their streams
 * (for the jitter). */
typedef struct clr_v4_items8 {
  int px[CLR_V4_LANES], py[CLR_V4_LANES];
  int one_pixel; /* every lane's item is a sample of the same pixel */
  uint8 sample;
  clr_pcg32x8 rng;
} clr_v4_items8;

/* StratifiedSampler's stratum at `dimension` of every lane: PermutationElement(sample, spp,
 * Hash(pixel, dimension, seed)), the hashes lane by lane, or once where the lanes share a pixel. */
CLR_V4_INLINE uint8 clr_v4_strata8(const clr_sampler_params *p, const clr_v4_items8 *items,
                                   int dimension) {
  ulong salt = clr_v4_pack(dimension, (int)p->seed);
  if (items->one_pixel)
    return clr_v4_permutation_element8(
        items->sample, (uint)p->spp,
        (uint8)(uint)clr_v4_hash16(clr_v4_pack(items->px[0], items->py[0]), salt));
  uint hash[CLR_V4_LANES];
  for (int j = 0; j < CLR_V4_LANES; ++j)
    hash[j] = (uint)clr_v4_hash16(clr_v4_pack(items->px[j], items->py[j]), salt);
  return clr_v4_permutation_element8(items->sample, (uint)p->spp, vload8(0, hash));
}

CLR_V4_INLINE float8 clr_v4_jitter8(const clr_sampler_params *p, clr_pcg32x8 *rng) {
  return p->jitter ? clr_pcg32x8_float(rng) : (float8)0.5f;
}

/* clr_v4_sample_vector for pbrt-v4's StratifiedSampler, 8 batch items (lane j's values at
 * values[out[j]]): Get1D, Get2D (GetPixel2D too) and skips as clr_v4_get1d, clr_v4_get2d and
 * clr_v4_skip make them. */
static inline void clr_v4_stratified_vectors8(const clr_sampler_params *p,
                                              __global const clr_request_slot *slots,
                                              clr_v4_items8 *items, __global float *values,
                                              const ulong *out) {
  clr_pcg32x8 r = items->rng, *rng = &r; /* in registers, not behind the pointer */
  int dimension = 0;
  for (int k = 0; k < p->request_count; ++k) {
    clr_request_slot sl = slots[k];
    int elements = sl.array_size ? sl.array_size : 1;
    for (int j = 0; j < elements; ++j) {
      if (sl.skipped) {
        dimension += sl.dims;
        if (p->jitter) clr_pcg32x8_advance(rng, (ulong)sl.dims);
      } else if (sl.dims == 1 && k != p->film_request) {
        uint8 stratum = clr_v4_strata8(p, items, dimension++);
        float8 u = clr_v4_div8(convert_float8(stratum) + clr_v4_jitter8(p, rng), (uint)p->spp);
        clr_store_lanes8(values, out, (size_t)(sl.first_value + j), u);
      } else {
        uint8 stratum = clr_v4_strata8(p, items, dimension);
        dimension += 2;
        uint8 y = clr_v4_quotient8(stratum, (uint)p->x_samples);
        uint8 x = stratum - y * (uint)p->x_samples;
        float8 dx = clr_v4_jitter8(p, rng);
        float8 dy = clr_v4_jitter8(p, rng);
        clr_store_pairs8(values, out, (size_t)(sl.first_value + (k == p->film_request ? 0 : 2 * j)),
                         clr_v4_div8(convert_float8(x) + dx, (uint)p->x_samples),
                         clr_v4_div8(convert_float8(y) + dy, (uint)p->y_samples));
      }
    }
  }
}

#endif
