/* pbrt-v4's samplers (samplers.h), bit for bit on the host and on any OpenCL 1.2 device:
 * IndependentSampler, StratifiedSampler, HaltonSampler, SobolSampler, PaddedSobolSampler and
 * ZSobolSampler; PMJ02BNSampler's structure with point sets of our own (clr_pmj02_point). Each is stateless given (pixel, sample index, dimension): StartPixelSample, then
 * GetPixel2D for the layout's first request and Get1D/Get2D for every other value (an array of n
 * is n calls). Tables: the Sobol' matrices (sobol_tables.h) and the Halton prime records
 * (halton_tables.h: base and (float)1 / base). */
#ifndef CLR_PBRT_V4_SAMPLER_FUNCS_H
#define CLR_PBRT_V4_SAMPLER_FUNCS_H

#include "clr_platform.h"
#include "halton_funcs.h"
#include "pbrt_v4_hash_funcs.h"
#include "pcg32.h"
#include "sampler_types.h"
#include "sobol_funcs.h"

/* The tables a pbrt-v4 sampler reads (unused ones may be NULL). */
typedef struct clr_v4_tables {
  CLR_GLOBAL const clr_u32 *sobol32;
  CLR_GLOBAL const clr_u64 *vdc, *vdc_inv;
  CLR_GLOBAL const clr_halton_prime *primes;
  CLR_GLOBAL const float *pmj_pixels; /* pmj02bn: (x, y) of GetPixel2D per tile pixel, sample */
  CLR_GLOBAL const float *pmj_sets;   /* pmj02bn: (x, y) of point i < spp of each point set */
  /* halton with permuted digits: DigitPermutation of dimension d < digit_dims (base b) at
   * digit_perms[digit_offsets[d] + digit index * b + digit] (clr_v4_digit_permutation); past
   * them, or with no tables (digit_dims 0), computed per digit */
  CLR_GLOBAL const clr_u16 *digit_perms;
  CLR_GLOBAL const clr_u32 *digit_offsets;
  clr_i32 digit_dims;
  /* sobol's matrices as 3-bit group tables (clr_sobol_group_bits8; the SIMD kernels only), or
   * NULL: the columns */
  CLR_GLOBAL const clr_u32 *sobol_groups;
} clr_v4_tables;

/* Floats of pmj02bn's GetPixel2D table; its point-set table (clr_v4_pmj02_set_point) follows. */
CLR_INLINE clr_u64 clr_v4_pmj02_pixel_floats(const clr_sampler_params *p) {
  return 2u * (clr_u64)p->pmj_tile * (clr_u64)p->pmj_tile * (clr_u64)p->spp;
}

/* A sampler between StartPixelSample and the next one. */
typedef struct clr_v4_state {
  clr_i32 px, py, sample, dimension;
  clr_u64 index; /* halton: haltonIndex; sobol: sobolIndex; zsobol: mortonIndex */
  clr_pcg32 rng; /* independent, stratified */
} clr_v4_state;

/* RNG::SetSequence(Hash(p, seed)) then Advance(sampleIndex * 65536 + dimension). */
CLR_INLINE void clr_v4_pixel_rng(clr_i32 px, clr_i32 py, clr_u32 seed, clr_i32 sample,
                                 clr_pcg32 *out) {
  clr_u64 sequence = clr_v4_hash12(clr_v4_pack(px, py), seed);
  clr_pcg32 r;
  r.state = 0u;
  r.inc = (sequence << 1u) | 1u;
  clr_pcg32_next(&r);
  r.state += clr_v4_mix_bits(sequence);
  clr_pcg32_next(&r);
  clr_pcg32_advance(&r, (clr_u64)(clr_u32)sample * 65536u);
  *out = r;
}

/* SobolSample's unscrambled bits: the generator matrix of `dim` times index a (linear over GF(2):
 * the bits of a ^ b are those of a xor those of b). */
CLR_INLINE clr_u32 clr_v4_sobol_bits(clr_u64 a, clr_i32 dim, CLR_GLOBAL const clr_u32 *sobol32) {
  CLR_GLOBAL const clr_u32 *cols = sobol32 + (clr_u32)dim * CLR_SOBOL_MATRIX_SIZE;
  clr_u32 high = (clr_u32)(a >> 32) & ((1u << (CLR_SOBOL_INDEX_BITS - 32)) - 1u);
  return clr_sobol_xor_columns32((clr_u32)a, cols) ^ clr_sobol_xor_columns32(high, cols + 32);
}

/* SobolSample's value from its unscrambled bits v. */
CLR_INLINE float clr_v4_sobol_finish(clr_u32 v, clr_i32 randomization, clr_u32 hash) {
  v = clr_v4_scramble(v, randomization, hash);
  return clr_v4_below_one((float)v * 0x1p-32f);
}

/* SobolSample(a, dimension, randomizer). */
CLR_INLINE float clr_v4_sobol_sample(clr_u64 a, clr_i32 dim, clr_i32 randomization, clr_u32 hash,
                                     CLR_GLOBAL const clr_u32 *sobol32) {
  return clr_v4_sobol_finish(clr_v4_sobol_bits(a, dim, sobol32), randomization, hash);
}

/* RadicalInverse(baseIndex, a). */
CLR_INLINE float clr_v4_radical_inverse(CLR_GLOBAL const clr_halton_prime *pr, clr_u64 a) {
  clr_u64 base = pr->base, limit = 0xffffffffffffffffUL / base - base, reversed = 0u;
  float inv_base = pr->inv_base, inv_m = 1.0f;
  while (a != 0u && reversed < limit) {
    clr_u64 next = a / base;
    reversed = reversed * base + (a - next * base);
    inv_m *= inv_base;
    a = next;
  }
  return clr_v4_below_one((float)reversed * inv_m);
}

/* DigitPermutation(base, seed)'s entry for `digit` of digit `digit_index`. */
CLR_INLINE clr_u32 clr_v4_digit_permutation(clr_u32 base, clr_i32 digit_index, clr_u32 digit,
                                            clr_u32 seed) {
  clr_u32 dseed = (clr_u32)clr_v4_hash12(clr_v4_pack((clr_i32)base, digit_index), seed);
  return clr_v4_permutation_element(digit, base, dseed);
}

/* The digits ScrambledRadicalInverse permutes in base pr->base (pbrt-v4's nDigits): at most. */
CLR_INLINE clr_i32 clr_v4_scrambled_digits(CLR_GLOBAL const clr_halton_prime *pr) {
  float inv_base = pr->inv_base, inv_m = 1.0f, top = (float)(pr->base - 1u);
  clr_i32 digits = 0;
  while (1.0f - top * inv_m < 1.0f) {
    inv_m *= inv_base;
    ++digits;
  }
  return digits;
}

/* ScrambledRadicalInverse with DigitPermutation(base, seed): digit i's permutation is
 * PermutationElement(digit, base, Hash(base, i, seed)), read from `perms` (clr_v4_tables) or,
 * where perms is NULL, computed. */
CLR_INLINE float clr_v4_scrambled_radical_inverse(CLR_GLOBAL const clr_halton_prime *pr, clr_u64 a,
                                                  clr_u32 seed, CLR_GLOBAL const clr_u16 *perms) {
  clr_u64 base = pr->base, limit = 0xffffffffffffffffUL / base - base, reversed = 0u;
  float inv_base = pr->inv_base, inv_m = 1.0f, top = (float)(pr->base - 1u);
  clr_i32 digit_index = 0;
  while (1.0f - top * inv_m < 1.0f && reversed < limit) {
    clr_u64 next =
        (a >> 32u) ? a / base : (clr_u64)clr_halton_div32((clr_u32)a, pr->div_magic, pr->div_shift);
    clr_u32 digit = (clr_u32)(a - next * base);
    clr_u32 element = perms ? (clr_u32)perms[(clr_u32)digit_index * pr->base + digit]
                            : clr_v4_digit_permutation(pr->base, digit_index, digit, seed);
    reversed = reversed * base + element;
    inv_m *= inv_base;
    ++digit_index;
    a = next;
  }
  return clr_v4_below_one(inv_m * (float)reversed);
}

/* OwenScrambledRadicalInverse(baseIndex, a, hash). */
CLR_INLINE float clr_v4_owen_radical_inverse(CLR_GLOBAL const clr_halton_prime *pr, clr_u64 a,
                                             clr_u32 hash) {
  clr_u64 base = pr->base, limit = 0xffffffffffffffffUL / base - base, reversed = 0u;
  float inv_base = pr->inv_base, inv_m = 1.0f;
  while (1.0f - inv_m < 1.0f && reversed < limit) {
    clr_u64 next = a / base;
    clr_u32 digit = (clr_u32)(a - next * base);
    clr_u32 digit_hash = (clr_u32)clr_v4_mix_bits((clr_u64)hash ^ reversed);
    reversed = reversed * base + clr_v4_permutation_element(digit, pr->base, digit_hash);
    inv_m *= inv_base;
    a = next;
  }
  return clr_v4_below_one(inv_m * (float)reversed);
}

/* pbrt's Mod(a, b) for b > 0: the remainder in [0, b). */
CLR_INLINE clr_i32 clr_v4_mod(clr_i32 a, clr_i32 b) {
  clr_i32 r = a - (a / b) * b;
  return r < 0 ? r + b : r;
}

/* InverseRadicalInverse(inverse, base, nDigits). */
CLR_INLINE clr_u64 clr_v4_inverse_radical_inverse(clr_u64 inverse, clr_u64 base, clr_i32 digits) {
  clr_u64 index = 0u;
  for (clr_i32 i = 0; i < digits; ++i) {
    clr_u64 digit = inverse % base;
    inverse /= base;
    index = index * base + digit;
  }
  return index;
}

/* HaltonSampler::StartPixelSample's haltonIndex (halton_* from the full resolution). */
CLR_INLINE clr_u64 clr_v4_halton_index(const clr_sampler_params *p, clr_i32 px, clr_i32 py,
                                       clr_i32 sample) {
  clr_u64 index = 0u, stride = (clr_u64)p->halton_stride;
  if (stride > 1u) {
    clr_i32 pm[2] = {clr_v4_mod(px, CLR_HALTON_MAX_RESOLUTION),
                     clr_v4_mod(py, CLR_HALTON_MAX_RESOLUTION)};
    for (int i = 0; i < 2; ++i) {
      clr_u64 offset =
          clr_v4_inverse_radical_inverse((clr_u64)pm[i], i == 0 ? 2u : 3u, p->halton_exponent[i]);
      index += offset * (stride / (clr_u64)p->halton_scale[i]) * p->halton_mult_inverse[i];
    }
    index %= stride;
  }
  return index + (clr_u64)sample * stride;
}

/* HaltonSampler::SampleDimension. */
CLR_INLINE float clr_v4_halton_dimension(const clr_sampler_params *p, const clr_v4_tables *t,
                                         clr_u64 index, clr_i32 dim) {
  CLR_GLOBAL const clr_halton_prime *pr = t->primes + dim;
  if (p->randomization == CLR_RANDOMIZE_TYPE_PERMUTEDIGITS)
    return clr_v4_scrambled_radical_inverse(
        pr, index, p->seed, dim < t->digit_dims ? t->digit_perms + t->digit_offsets[dim] : 0);
  if (p->randomization == CLR_RANDOMIZE_TYPE_OWEN)
    return clr_v4_owen_radical_inverse(
        pr, index, (clr_u32)clr_v4_mix_bits((clr_u64)(clr_i64)(1 + (dim << 4))));
  return clr_v4_radical_inverse(pr, index);
}

/* SobolSampler::SampleDimension: the hash of (dimension, seed) seeds the randomizer. */
CLR_INLINE float clr_v4_sobol_dimension(const clr_sampler_params *p, const clr_v4_tables *t,
                                        clr_u64 index, clr_i32 dim) {
  clr_u32 hash = (clr_u32)clr_v4_hash8(clr_v4_pack(dim, (clr_i32)p->seed));
  return clr_v4_sobol_sample(index, dim, p->randomization, hash, t->sobol32);
}

/* The p-th of pbrt-v4's 24 permutations of 0..3, entries packed 2 bits each: the order in which
 * swapping entry k with entry k + c_k (k = 0, 1, 2) enumerates them, c_0 = p / 6,
 * c_1 = p / 2 % 3, c_2 = p % 2. Constant expressions: the compiler builds the table. */
#define CLR_V4_SWAP2(x, i, j)                           \
  (((x) & ~((3u << (2u * (i))) | (3u << (2u * (j))))) | \
   ((((x) >> (2u * (i))) & 3u) << (2u * (j))) | ((((x) >> (2u * (j))) & 3u) << (2u * (i))))
#define CLR_V4_PERM4(p)                                                                     \
  CLR_V4_SWAP2(CLR_V4_SWAP2(CLR_V4_SWAP2(0xe4u, 0u, (p) / 6u), 1u, 1u + (p) / 2u % 3u), 2u, \
               2u + (p) % 2u)
/* Permutations p .. p + 7, one byte each. */
#define CLR_V4_PERM4_BYTE(p, i) ((clr_u64)CLR_V4_PERM4((p) + (i)) << (8u * (i)))
#define CLR_V4_PERM4_WORD(p)                                                        \
  (CLR_V4_PERM4_BYTE(p, 0u) | CLR_V4_PERM4_BYTE(p, 1u) | CLR_V4_PERM4_BYTE(p, 2u) | \
   CLR_V4_PERM4_BYTE(p, 3u) | CLR_V4_PERM4_BYTE(p, 4u) | CLR_V4_PERM4_BYTE(p, 5u) | \
   CLR_V4_PERM4_BYTE(p, 6u) | CLR_V4_PERM4_BYTE(p, 7u))

/* Entry `digit` of permutation p < 24. */
CLR_INLINE clr_u32 clr_v4_permute4(clr_u32 p, clr_u32 digit) {
  clr_u64 word = p < 8u    ? CLR_V4_PERM4_WORD(0u)
                 : p < 16u ? CLR_V4_PERM4_WORD(8u)
                           : CLR_V4_PERM4_WORD(16u);
  clr_u32 packed = (clr_u32)(word >> (8u * (p & 7u))) & 0xffu;
  return (packed >> (2u * digit)) & 3u;
}

/* EncodeMorton2(x, y): x in the even bits, y in the odd ones. */
CLR_INLINE clr_u64 clr_v4_left_shift2(clr_u64 x) {
  x &= 0xffffffffu;
  x = (x ^ (x << 16u)) & 0x0000ffff0000ffffUL;
  x = (x ^ (x << 8u)) & 0x00ff00ff00ff00ffUL;
  x = (x ^ (x << 4u)) & 0x0f0f0f0f0f0f0f0fUL;
  x = (x ^ (x << 2u)) & 0x3333333333333333UL;
  x = (x ^ (x << 1u)) & 0x5555555555555555UL;
  return x;
}

/* ZSobolSampler's Morton index of sample 0 of pixel (px, py). */
CLR_INLINE clr_u64 clr_v4_zsobol_pixel_morton(const clr_sampler_params *p, clr_i32 px, clr_i32 py) {
  return (clr_v4_left_shift2((clr_u32)py) << 1u | clr_v4_left_shift2((clr_u32)px))
         << (clr_u32)p->zsobol_log2_spp;
}

/* ZSobolSampler::GetSampleIndex's permuted digits hi down to lo: each base-4 digit of the Morton
 * index permuted by a hash of the digits above it and the dimension (salt). */
CLR_INLINE clr_u64 clr_v4_zsobol_digits(clr_u64 morton, clr_u64 salt, clr_i32 odd, clr_i32 hi,
                                        clr_i32 lo) {
  clr_u64 index = 0u;
  for (clr_i32 i = hi; i >= lo; --i) {
    clr_u32 shift = (clr_u32)(2 * i - odd);
    clr_u32 digit = (clr_u32)(morton >> shift) & 3u;
    clr_u32 perm = (clr_u32)((clr_v4_mix_bits((morton >> (shift + 2u)) ^ salt) >> 24u) % 24u);
    index |= (clr_u64)clr_v4_permute4(perm, digit) << shift;
  }
  return index;
}

CLR_INLINE clr_u64 clr_v4_zsobol_salt(clr_i32 dimension) {
  return (clr_u64)(0x55555555u * (clr_u32)dimension);
}

/* The lowest digit whose bits and hash hold no bit of the sample index (log2 spp low bits). */
CLR_INLINE clr_i32 clr_v4_zsobol_pixel_digit(const clr_sampler_params *p) {
  return (p->zsobol_log2_spp + 1) / 2;
}

/* The digits of the pixel's Morton index: the same for every sample of the pixel. */
CLR_INLINE clr_u64 clr_v4_zsobol_pixel_part(const clr_sampler_params *p, clr_u64 morton,
                                            clr_u64 salt) {
  return clr_v4_zsobol_digits(morton, salt, p->zsobol_log2_spp & 1, p->zsobol_base4_digits - 1,
                              clr_v4_zsobol_pixel_digit(p));
}

/* The digits that hold sample bits, and the last binary digit flipped when spp is 2^odd. */
CLR_INLINE clr_u64 clr_v4_zsobol_sample_part(const clr_sampler_params *p, clr_u64 morton,
                                             clr_u64 salt) {
  clr_i32 odd = p->zsobol_log2_spp & 1;
  clr_u64 index = clr_v4_zsobol_digits(morton, salt, odd, clr_v4_zsobol_pixel_digit(p) - 1, odd);
  if (odd) index |= (morton & 1u) ^ (clr_v4_mix_bits((morton >> 1u) ^ salt) & 1u);
  return index;
}

/* ZSobolSampler::GetSampleIndex: the Morton index with each base-4 digit permuted by a hash of
 * the digits above it and the dimension (and the last binary digit flipped when spp is 2^odd). */
CLR_INLINE clr_u64 clr_v4_zsobol_index(const clr_sampler_params *p, clr_u64 morton,
                                       clr_i32 dimension) {
  clr_u64 salt = clr_v4_zsobol_salt(dimension);
  return clr_v4_zsobol_pixel_part(p, morton, salt) | clr_v4_zsobol_sample_part(p, morton, salt);
}

/* Point `index` of pmj02bn point set `set`: pbrt-v4's sets (pmj02bn, found by a randomized
 * search) are not reproducible, so each set is the Sobol' (0,2)-sequence (dimensions 0 and 1)
 * Owen-scrambled with a fixed seed per set and dimension: also a progressive (0,2)-sequence, whose
 * first 2^k points form a (0,k,2)-net. Fixed point, 32 bits per coordinate. */
CLR_INLINE clr_u32 clr_pmj02_point(clr_i32 set, clr_u32 index, clr_i32 c,
                                   CLR_GLOBAL const clr_u32 *sobol32) {
  clr_u32 v = clr_sobol_xor_columns32(index, sobol32 + (clr_u32)c * CLR_SOBOL_MATRIX_SIZE);
  return clr_v4_owen(v, (clr_u32)clr_v4_mix_bits(0x706d6a3032UL + (clr_u64)(2 * set + c)));
}

/* The Morton index of pixel p mod 256, BlueNoiseSample's digits. */
CLR_INLINE clr_u64 clr_v4_blue_noise_morton(clr_i32 px, clr_i32 py) {
  return clr_v4_left_shift2((clr_u32)py & 255u) << 1u | clr_v4_left_shift2((clr_u32)px & 255u);
}

CLR_INLINE clr_u64 clr_v4_blue_noise_salt(clr_i32 instance) {
  return (clr_u64)(clr_i64)(clr_i32)(0x55555555u * (clr_u32)instance);
}

/* BlueNoiseSample's permuted base-4 digits hi down to lo of a Morton index. */
CLR_INLINE clr_u32 clr_v4_blue_noise_digits(clr_u64 morton, clr_u64 salt, clr_i32 hi, clr_i32 lo) {
  clr_u32 index = 0u;
  for (clr_i32 i = hi; i >= lo; --i) {
    clr_u32 shift = (clr_u32)(2 * i);
    clr_u32 digit = (clr_u32)(morton >> shift) & 3u;
    clr_u32 perm = (clr_u32)(clr_v4_mix_bits((morton >> (shift + 2u)) ^ salt) >> 24u) % 24u;
    index |= clr_v4_permute4(perm, digit) << shift;
  }
  return index;
}

/* BlueNoiseSample(p, instance) of pbrt-v4's lowdiscrepancy.h (the pixel's Morton index with
 * hashed base-4 digit permutations, reversed), used where pbrt-v4's pmj02bn reads its blue-noise
 * textures (BlueNoise(instance, p), also found by search). */
CLR_INLINE float clr_v4_blue_noise_sample(clr_i32 px, clr_i32 py, clr_i32 instance) {
  clr_u32 index = clr_v4_blue_noise_digits(clr_v4_blue_noise_morton(px, py),
                                           clr_v4_blue_noise_salt(instance), 7, 0);
  return (float)clr_reverse_bits32(index) * 0x1p-32f;
}

/* Coordinate c of point `index` (< spp) of pmj02bn point set `set`: clr_pmj02_point as a float,
 * read from the sampler's table (built once on the host, clr_pmj02_set_table). */
CLR_INLINE float clr_v4_pmj02_set_point(const clr_sampler_params *p, const clr_v4_tables *t,
                                        clr_i32 set, clr_u32 index, clr_i32 c) {
  return t->pmj_sets[2u * ((clr_u32)set * (clr_u32)p->spp + index) + (clr_u32)c];
}

/* PMJ02BNSampler::Get2D's point: the sample index permuted past the sets by `hash`. */
CLR_INLINE clr_u32 clr_v4_pmj02_index2d(const clr_sampler_params *p, clr_i32 sample, clr_i32 set,
                                        clr_u64 hash) {
  if (set < CLR_PMJ02_SETS) return (clr_u32)sample;
  return clr_v4_permutation_element((clr_u32)sample, (clr_u32)p->spp, (clr_u32)hash);
}

/* Point value v (in [0, 1)) rotated toroidally by blue noise. */
CLR_INLINE float clr_v4_pmj02_rotate(float v, float noise) {
  v += noise;
  if (v >= 1.0f) v -= 1.0f;
  return clr_v4_below_one(v);
}

/* Hash(pixel, dimension, seed) of pmj02bn's Get1D and Get2D. */
CLR_INLINE clr_u64 clr_v4_pixel_dim_hash(const clr_sampler_params *p, clr_i32 px, clr_i32 py,
                                         clr_i32 dimension) {
  return clr_v4_hash16(clr_v4_pack(px, py), clr_v4_pack(dimension, (clr_i32)p->seed));
}

/* PMJ02BNSampler::Get2D: set dimension / 2 (the sample index permuted past the sets), rotated
 * toroidally by the pixel's blue noise. */
CLR_INLINE void clr_v4_pmj02_get2d(const clr_sampler_params *p, const clr_v4_tables *t,
                                   clr_v4_state *s, float *u) {
  clr_i32 set = s->dimension / 2;
  clr_u64 hash = set >= CLR_PMJ02_SETS ? clr_v4_pixel_dim_hash(p, s->px, s->py, s->dimension) : 0u;
  clr_u32 index = clr_v4_pmj02_index2d(p, s->sample, set, hash);
  for (clr_i32 c = 0; c < 2; ++c)
    u[c] = clr_v4_pmj02_rotate(clr_v4_pmj02_set_point(p, t, set % CLR_PMJ02_SETS, index, c),
                               clr_v4_blue_noise_sample(s->px, s->py, s->dimension + c));
  s->dimension += 2;
}

/* PMJ02BNSampler::Get1D's value: the permuted stratum plus blue noise delta, over spp. */
CLR_INLINE float clr_v4_pmj02_value1d(const clr_sampler_params *p, clr_i32 sample, clr_u64 hash,
                                      float delta) {
  clr_u32 index = clr_v4_permutation_element((clr_u32)sample, (clr_u32)p->spp, (clr_u32)hash);
  return clr_v4_below_one(clr_v4_div((float)index + delta, (clr_u32)p->spp));
}

/* PMJ02BNSampler::Get1D: the permuted stratum plus the pixel's blue noise. */
CLR_INLINE float clr_v4_pmj02_get1d(const clr_sampler_params *p, clr_v4_state *s) {
  float v = clr_v4_pmj02_value1d(p, s->sample, clr_v4_pixel_dim_hash(p, s->px, s->py, s->dimension),
                                 clr_v4_blue_noise_sample(s->px, s->py, s->dimension));
  ++s->dimension;
  return v;
}

/* Sampler::StartPixelSample(p, sampleIndex, 0) into *out (a struct returned by value is an sret
 * argument, whose inlining emits llvm.experimental.noalias.scope.decl: Oclgrind can't run it). */
CLR_INLINE void clr_v4_start(const clr_sampler_params *p, const clr_v4_tables *t, clr_i32 px,
                             clr_i32 py, clr_i32 sample, clr_v4_state *out) {
  clr_v4_state s;
  s.px = px;
  s.py = py;
  s.sample = sample;
  s.dimension = 0;
  s.index = 0u;
  s.rng.state = s.rng.inc = 0u;
  switch (p->v4_sampler) {
    case CLR_V4_INDEPENDENT:
    case CLR_V4_STRATIFIED:
      clr_v4_pixel_rng(px, py, p->seed, sample, &s.rng);
      break;
    case CLR_V4_HALTON:
      s.index = clr_v4_halton_index(p, px, py, sample);
      s.dimension = 2;
      break;
    case CLR_V4_SOBOL:
      s.index = clr_sobol_interval_to_index((clr_u32)p->sobol_log2_resolution, (clr_u64)sample, px,
                                            py, t->vdc, t->vdc_inv);
      s.dimension = 2;
      break;
    case CLR_V4_PMJ02BN:
      s.dimension = 2;
      break;
    case CLR_V4_ZSOBOL:
      s.index = clr_v4_zsobol_pixel_morton(p, px, py) | (clr_u64)(clr_u32)sample;
      break;
    default:
      break;
  }
  *out = s;
}

/* PermutationElement(sampleIndex, spp, Hash(pixel, dimension, seed)), and the hash. */
CLR_INLINE clr_u32 clr_v4_permuted_sample(const clr_sampler_params *p, const clr_v4_state *s,
                                          clr_u64 *hash) {
  *hash = clr_v4_hash16(clr_v4_pack(s->px, s->py), clr_v4_pack(s->dimension, (clr_i32)p->seed));
  return clr_v4_permutation_element((clr_u32)s->sample, (clr_u32)p->spp, (clr_u32)*hash);
}

CLR_INLINE float clr_v4_jitter(const clr_sampler_params *p, clr_v4_state *s) {
  return p->jitter ? clr_pcg32_float(&s->rng) : 0.5f;
}

/* Sampler::Get1D. */
CLR_INLINE float clr_v4_get1d(const clr_sampler_params *p, const clr_v4_tables *t,
                              clr_v4_state *s) {
  clr_u64 hash = 0u;
  switch (p->v4_sampler) {
    case CLR_V4_STRATIFIED: {
      clr_u32 stratum = clr_v4_permuted_sample(p, s, &hash);
      ++s->dimension;
      return clr_v4_div((float)stratum + clr_v4_jitter(p, s), (clr_u32)p->spp);
    }
    case CLR_V4_HALTON:
      if (s->dimension >= CLR_HALTON_PRIMES) s->dimension = 2;
      return clr_v4_halton_dimension(p, t, s->index, s->dimension++);
    case CLR_V4_SOBOL:
      if (s->dimension >= CLR_SOBOL_DIMENSIONS) s->dimension = 2;
      return clr_v4_sobol_dimension(p, t, s->index, s->dimension++);
    case CLR_V4_PADDEDSOBOL: {
      clr_u32 index = clr_v4_permuted_sample(p, s, &hash);
      ++s->dimension;
      return clr_v4_sobol_sample(index, 0, p->randomization, (clr_u32)(hash >> 32u), t->sobol32);
    }
    case CLR_V4_ZSOBOL: {
      clr_u64 index = clr_v4_zsobol_index(p, s->index, s->dimension);
      ++s->dimension;
      hash = clr_v4_hash8(clr_v4_pack(s->dimension, (clr_i32)p->seed));
      return clr_v4_sobol_sample(index, 0, p->randomization, (clr_u32)hash, t->sobol32);
    }
    case CLR_V4_PMJ02BN:
      return clr_v4_pmj02_get1d(p, s);
    default:
      return clr_pcg32_float(&s->rng);
  }
}

/* Sampler::Get2D into u[0], u[1]. */
CLR_INLINE void clr_v4_get2d(const clr_sampler_params *p, const clr_v4_tables *t, clr_v4_state *s,
                             float *u) {
  clr_u64 hash = 0u;
  switch (p->v4_sampler) {
    case CLR_V4_STRATIFIED: {
      clr_u32 stratum = clr_v4_permuted_sample(p, s, &hash);
      s->dimension += 2;
      clr_u32 x = stratum % (clr_u32)p->x_samples, y = stratum / (clr_u32)p->x_samples;
      float dx = clr_v4_jitter(p, s);
      float dy = clr_v4_jitter(p, s);
      u[0] = clr_v4_div((float)x + dx, (clr_u32)p->x_samples);
      u[1] = clr_v4_div((float)y + dy, (clr_u32)p->y_samples);
      return;
    }
    case CLR_V4_HALTON:
      if (s->dimension + 1 >= CLR_HALTON_PRIMES) s->dimension = 2;
      u[0] = clr_v4_halton_dimension(p, t, s->index, s->dimension);
      u[1] = clr_v4_halton_dimension(p, t, s->index, s->dimension + 1);
      s->dimension += 2;
      return;
    case CLR_V4_SOBOL:
      if (s->dimension + 1 >= CLR_SOBOL_DIMENSIONS) s->dimension = 2;
      u[0] = clr_v4_sobol_dimension(p, t, s->index, s->dimension);
      u[1] = clr_v4_sobol_dimension(p, t, s->index, s->dimension + 1);
      s->dimension += 2;
      return;
    case CLR_V4_PADDEDSOBOL: {
      clr_u32 index = clr_v4_permuted_sample(p, s, &hash);
      s->dimension += 2;
      u[0] = clr_v4_sobol_sample(index, 0, p->randomization, (clr_u32)hash, t->sobol32);
      u[1] = clr_v4_sobol_sample(index, 1, p->randomization, (clr_u32)(hash >> 32u), t->sobol32);
      return;
    }
    case CLR_V4_ZSOBOL: {
      clr_u64 index = clr_v4_zsobol_index(p, s->index, s->dimension);
      s->dimension += 2;
      hash = clr_v4_hash8(clr_v4_pack(s->dimension, (clr_i32)p->seed));
      u[0] = clr_v4_sobol_sample(index, 0, p->randomization, (clr_u32)hash, t->sobol32);
      u[1] = clr_v4_sobol_sample(index, 1, p->randomization, (clr_u32)(hash >> 32u), t->sobol32);
      return;
    }
    case CLR_V4_PMJ02BN:
      clr_v4_pmj02_get2d(p, t, s, u);
      return;
    default:
      u[0] = clr_pcg32_float(&s->rng);
      u[1] = clr_pcg32_float(&s->rng);
      return;
  }
}

/* SobolSampler::GetPixel2D's remap of an unscrambled value into the pixel. */
CLR_INLINE float clr_v4_sobol_pixel(const clr_sampler_params *p, float u, clr_i32 pixel) {
  float v = u * p->sobol_resolution - (float)pixel;
  return v < 0.0f ? 0.0f : (v > CLR_ONE_MINUS_EPSILON ? CLR_ONE_MINUS_EPSILON : v);
}

/* Sampler::GetPixel2D: Halton and Sobol read their unrandomized first two dimensions, the others
 * make a Get2D. */
CLR_INLINE void clr_v4_get_pixel2d(const clr_sampler_params *p, const clr_v4_tables *t,
                                   clr_v4_state *s, float *u) {
  if (p->v4_sampler == CLR_V4_HALTON) {
    u[0] = clr_v4_radical_inverse(t->primes, s->index >> (clr_u32)p->halton_exponent[0]);
    u[1] = clr_v4_radical_inverse(t->primes + 1, s->index / (clr_u64)p->halton_scale[1]);
  } else if (p->v4_sampler == CLR_V4_PMJ02BN) {
    clr_i32 x = clr_v4_mod(s->px, p->pmj_tile), y = clr_v4_mod(s->py, p->pmj_tile);
    CLR_GLOBAL const float *xy = t->pmj_pixels + 2 * ((x + y * p->pmj_tile) * p->spp + s->sample);
    u[0] = xy[0];
    u[1] = xy[1];
  } else if (p->v4_sampler == CLR_V4_SOBOL) {
    u[0] = clr_v4_sobol_pixel(p, clr_v4_sobol_sample(s->index, 0, 0, 0u, t->sobol32), s->px);
    u[1] = clr_v4_sobol_pixel(p, clr_v4_sobol_sample(s->index, 1, 0, 0u, t->sobol32), s->py);
  } else {
    clr_v4_get2d(p, t, s, u);
  }
}

/* A skipped Get1D (dims 1) or Get2D: the state moves on as the call would move it, no value. */
CLR_INLINE void clr_v4_skip(const clr_sampler_params *p, clr_v4_state *s, clr_i32 dims) {
  if (p->v4_sampler == CLR_V4_INDEPENDENT) {
    clr_pcg32_advance(&s->rng, (clr_u64)dims);
    return;
  }
  if ((p->v4_sampler == CLR_V4_HALTON && s->dimension + dims - 1 >= CLR_HALTON_PRIMES) ||
      (p->v4_sampler == CLR_V4_SOBOL && s->dimension + dims - 1 >= CLR_SOBOL_DIMENSIONS))
    s->dimension = 2;
  s->dimension += dims;
  if (p->v4_sampler == CLR_V4_STRATIFIED && p->jitter) clr_pcg32_advance(&s->rng, (clr_u64)dims);
}

/* Sample vector of batch item `item` (pixel-major, then sample): request p->film_request is
 * GetPixel2D, every other value Get1D/Get2D in layout order (skipped slots: clr_v4_skip). */
CLR_INLINE void clr_v4_sample_vector(const clr_sampler_params *p,
                                     CLR_GLOBAL const clr_request_slot *slots,
                                     const clr_v4_tables *t, clr_i32 item, CLR_GLOBAL float *out) {
  clr_i32 pixel = item / p->sample_count;
  clr_i32 row = pixel / p->batch_width;
  clr_v4_state s;
  clr_v4_start(p, t, p->batch_x0 + pixel - row * p->batch_width, p->batch_y0 + row,
               p->first_sample + item % p->sample_count, &s);
  float u[2];
  for (clr_i32 r = 0; r < p->request_count; ++r) {
    clr_request_slot sl = slots[r];
    clr_i32 elements = sl.array_size ? sl.array_size : 1;
    CLR_GLOBAL float *v = out + sl.first_value;
    for (clr_i32 j = 0; j < elements; ++j) {
      if (sl.skipped) {
        clr_v4_skip(p, &s, sl.dims);
      } else if (r == p->film_request) {
        clr_v4_get_pixel2d(p, t, &s, u);
        v[0] = u[0];
        v[1] = u[1];
      } else if (sl.dims == 1) {
        v[j] = clr_v4_get1d(p, t, &s);
      } else {
        clr_v4_get2d(p, t, &s, u);
        v[2 * j] = u[0];
        v[2 * j + 1] = u[1];
      }
    }
  }
}

/* The part of a zsobol, paddedsobol or pmj02bn value that depends only on (pixel, dimension),
 * computed once
 * for every sample of the pixel (clr_v4_pixel_vectors). */
typedef struct clr_v4_pixel_dim {
  clr_u32 bits[2]; /* zsobol: Sobol' bits (dimensions 0, 1) of the permuted pixel digits */
  clr_u64
      hash; /* zsobol: the scrambler's hash; paddedsobol, pmj02bn: Hash(pixel, dimension, seed) */
  float noise[2]; /* pmj02bn: blue noise of dimension and dimension + 1 */
} clr_v4_pixel_dim;

/* The (pixel, dimension) part of Get1D (dims 1) or Get2D (dims 2) at `dimension`. */
CLR_INLINE void clr_v4_pixel_dim_part(const clr_sampler_params *p, const clr_v4_tables *t,
                                      clr_i32 px, clr_i32 py, clr_u64 morton, clr_i32 dimension,
                                      clr_i32 dims, clr_v4_pixel_dim *out) {
  out->bits[0] = out->bits[1] = 0u;
  if (p->v4_sampler == CLR_V4_ZSOBOL) {
    clr_u64 high = clr_v4_zsobol_pixel_part(p, morton, clr_v4_zsobol_salt(dimension));
    out->bits[0] = clr_v4_sobol_bits(high, 0, t->sobol32);
    out->bits[1] = dims == 2 ? clr_v4_sobol_bits(high, 1, t->sobol32) : 0u;
    out->hash = clr_v4_hash8(clr_v4_pack(dimension + dims, (clr_i32)p->seed));
    return;
  }
  if (p->v4_sampler == CLR_V4_PADDEDSOBOL) {
    out->hash = clr_v4_pixel_dim_hash(p, px, py, dimension);
    return;
  }
  out->hash = dims == 1 || dimension / 2 >= CLR_PMJ02_SETS
                  ? clr_v4_pixel_dim_hash(p, px, py, dimension)
                  : 0u;
  out->noise[0] = clr_v4_blue_noise_sample(px, py, dimension);
  out->noise[1] = dims == 2 ? clr_v4_blue_noise_sample(px, py, dimension + 1) : 0.0f;
}

/* zsobol's, paddedsobol's or pmj02bn's Get1D (dims 1) or Get2D for `sample` of the pixel at `dimension`. */
CLR_INLINE void clr_v4_pixel_dim_value(const clr_sampler_params *p, const clr_v4_tables *t,
                                       const clr_v4_pixel_dim *d, clr_u64 morton, clr_i32 dimension,
                                       clr_i32 dims, clr_i32 sample, float *u) {
  if (p->v4_sampler == CLR_V4_ZSOBOL) {
    clr_u64 low =
        clr_v4_zsobol_sample_part(p, morton | (clr_u32)sample, clr_v4_zsobol_salt(dimension));
    u[0] = clr_v4_sobol_finish(d->bits[0] ^ clr_v4_sobol_bits(low, 0, t->sobol32), p->randomization,
                               (clr_u32)d->hash);
    if (dims == 2)
      u[1] = clr_v4_sobol_finish(d->bits[1] ^ clr_v4_sobol_bits(low, 1, t->sobol32),
                                 p->randomization, (clr_u32)(d->hash >> 32u));
    return;
  }
  if (p->v4_sampler == CLR_V4_PADDEDSOBOL) {
    clr_u32 index = clr_v4_permutation_element((clr_u32)sample, (clr_u32)p->spp, (clr_u32)d->hash);
    u[0] = clr_v4_sobol_sample(index, 0, p->randomization,
                               (clr_u32)(dims == 1 ? d->hash >> 32u : d->hash), t->sobol32);
    if (dims == 2)
      u[1] = clr_v4_sobol_sample(index, 1, p->randomization, (clr_u32)(d->hash >> 32u), t->sobol32);
    return;
  }
  if (dims == 1) {
    u[0] = clr_v4_pmj02_value1d(p, sample, d->hash, d->noise[0]);
    return;
  }
  clr_i32 set = dimension / 2;
  clr_u32 index = clr_v4_pmj02_index2d(p, sample, set, d->hash);
  for (clr_i32 c = 0; c < 2; ++c)
    u[c] = clr_v4_pmj02_rotate(clr_v4_pmj02_set_point(p, t, set % CLR_PMJ02_SETS, index, c),
                               d->noise[c]);
}

/* zsobol, paddedsobol and pmj02bn: the sample vectors of every sample of batch pixel `pixel` (out: its first
 * one), the same values as clr_v4_sample_vector: the layout is walked once, each Get1D/Get2D's
 * (pixel, dimension) part computed once and each sample's part per sample. */
CLR_INLINE void clr_v4_pixel_vectors(const clr_sampler_params *p,
                                     CLR_GLOBAL const clr_request_slot *slots,
                                     const clr_v4_tables *t, clr_i32 pixel, CLR_GLOBAL float *out) {
  clr_i32 row = pixel / p->batch_width;
  clr_i32 px = p->batch_x0 + pixel - row * p->batch_width, py = p->batch_y0 + row;
  clr_u64 morton = p->v4_sampler == CLR_V4_ZSOBOL ? clr_v4_zsobol_pixel_morton(p, px, py) : 0u;
  clr_i32 dimension = p->v4_sampler == CLR_V4_PMJ02BN ? 2 : 0;
  clr_i32 stride = p->values_per_sample;
  for (clr_i32 r = 0; r < p->request_count; ++r) {
    clr_request_slot sl = slots[r];
    clr_i32 elements = sl.array_size ? sl.array_size : 1;
    if (sl.skipped) { /* never the film offset: its dimensions only */
      dimension += elements * sl.dims;
      continue;
    }
    for (clr_i32 j = 0; j < elements; ++j) {
      CLR_GLOBAL float *v = out + sl.first_value + (sl.dims == 2 ? 2 * j : j);
      float u[2];
      if (r == p->film_request && p->v4_sampler == CLR_V4_PMJ02BN) {
        clr_i32 x = clr_v4_mod(px, p->pmj_tile), y = clr_v4_mod(py, p->pmj_tile);
        CLR_GLOBAL const float *xy = t->pmj_pixels + 2 * ((x + y * p->pmj_tile) * p->spp);
        for (clr_i32 k = 0; k < p->sample_count; ++k) {
          v[(size_t)k * (size_t)stride] = xy[2 * (p->first_sample + k)];
          v[(size_t)k * (size_t)stride + 1u] = xy[2 * (p->first_sample + k) + 1];
        }
        continue;
      }
      clr_i32 dims = r == p->film_request ? 2 : sl.dims;
      clr_v4_pixel_dim d;
      clr_v4_pixel_dim_part(p, t, px, py, morton, dimension, dims, &d);
      for (clr_i32 k = 0; k < p->sample_count; ++k) {
        clr_v4_pixel_dim_value(p, t, &d, morton, dimension, dims, p->first_sample + k, u);
        v[(size_t)k * (size_t)stride] = u[0];
        if (dims == 2) v[(size_t)k * (size_t)stride + 1u] = u[1];
      }
      dimension += dims;
    }
  }
}

#endif
