/* pbrt-v4's hashing and randomization primitives (util/hash.h, util/math.h, util/lowdiscrepancy.h),
 * bit for bit on the host and on any OpenCL 1.2 device: MurmurHash64A of the little-endian bytes
 * of 32-bit arguments, MixBits, PermutationElement, the Sobol' scramblers and a correctly rounded
 * float division by an integer. */
#ifndef CLR_PBRT_V4_HASH_FUNCS_H
#define CLR_PBRT_V4_HASH_FUNCS_H

#include "clr_platform.h"
#include "halton_funcs.h"

#if defined(__OPENCL_C_VERSION__) && defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#define CLR_MURMUR_M 0xc6a4a7935bd1e995UL

/* Two 32-bit arguments as the 8 bytes pbrt-v4's Hash copies (little endian: a first). */
CLR_INLINE clr_u64 clr_v4_pack(clr_i32 a, clr_i32 b) {
  return (clr_u64)(clr_u32)a | ((clr_u64)(clr_u32)b << 32u);
}

CLR_INLINE clr_u64 clr_murmur_block(clr_u64 h, clr_u64 k) {
  k *= CLR_MURMUR_M;
  k ^= k >> 47u;
  k *= CLR_MURMUR_M;
  h ^= k;
  return h * CLR_MURMUR_M;
}

CLR_INLINE clr_u64 clr_murmur_final(clr_u64 h) {
  h ^= h >> 47u;
  h *= CLR_MURMUR_M;
  return h ^ (h >> 47u);
}

/* Hash(a, b): MurmurHash64A of 8 bytes, seed 0. */
CLR_INLINE clr_u64 clr_v4_hash8(clr_u64 w0) {
  return clr_murmur_final(clr_murmur_block(8u * CLR_MURMUR_M, w0));
}

/* Hash(a, b, c) of three 32-bit arguments (12 bytes). */
CLR_INLINE clr_u64 clr_v4_hash12(clr_u64 w0, clr_u32 tail) {
  clr_u64 h = clr_murmur_block(12u * CLR_MURMUR_M, w0);
  h ^= (clr_u64)tail;
  return clr_murmur_final(h * CLR_MURMUR_M);
}

/* Hash(a, b, c, d) of four 32-bit arguments (16 bytes). */
CLR_INLINE clr_u64 clr_v4_hash16(clr_u64 w0, clr_u64 w1) {
  return clr_murmur_final(clr_murmur_block(clr_murmur_block(16u * CLR_MURMUR_M, w0), w1));
}

/* MixBits on v (u64, or u64 lanes) in place; a macro so that scalar and lane code share it. */
#define CLR_V4_MIX_BITS(v)       \
  do {                           \
    (v) ^= (v) >> 31u;           \
    (v) *= 0x7fb5d329728ea185UL; \
    (v) ^= (v) >> 27u;           \
    (v) *= 0x81dadef4bc2dd44dUL; \
    (v) ^= (v) >> 33u;           \
  } while (0)

CLR_INLINE clr_u64 clr_v4_mix_bits(clr_u64 v) {
  CLR_V4_MIX_BITS(v);
  return v;
}

/* One step of PermutationElement's cycle walk: i (u32, or u32 lanes) hashed with p (of i's type
 * or a scalar) under the mask w (a scalar). A macro so that scalar and lane code share it. */
#define CLR_V4_PERMUTATION_STEP(i, p, w) \
  do {                                   \
    (i) ^= (p);                          \
    (i) *= 0xe170893du;                  \
    (i) ^= (p) >> 16u;                   \
    (i) ^= ((i) & (w)) >> 4u;            \
    (i) ^= (p) >> 8u;                    \
    (i) *= 0x0929eb3fu;                  \
    (i) ^= (p) >> 23u;                   \
    (i) ^= ((i) & (w)) >> 1u;            \
    (i) *= 1u | (p) >> 27u;              \
    (i) *= 0x6935fa69u;                  \
    (i) ^= ((i) & (w)) >> 11u;           \
    (i) *= 0x74dcb303u;                  \
    (i) ^= ((i) & (w)) >> 2u;            \
    (i) *= 0x9e501cc3u;                  \
    (i) ^= ((i) & (w)) >> 2u;            \
    (i) *= 0xc860a3dfu;                  \
    (i) &= (w);                          \
    (i) ^= (i) >> 5u;                    \
  } while (0)

/* The mask of PermutationElement's cycle walk for l items: l - 1 with every lower bit set. */
CLR_INLINE clr_u32 clr_v4_permutation_mask(clr_u32 l) {
  clr_u32 w = l - 1u;
  w |= w >> 1u;
  w |= w >> 2u;
  w |= w >> 4u;
  w |= w >> 8u;
  w |= w >> 16u;
  return w;
}

/* PermutationElement(i, l, p): element i of a pseudo-random permutation of 0..l-1 (Kensler's
 * cycle-walking hash). */
CLR_INLINE clr_u32 clr_v4_permutation_element(clr_u32 i, clr_u32 l, clr_u32 p) {
  clr_u32 w = clr_v4_permutation_mask(l);
  do {
    CLR_V4_PERMUTATION_STEP(i, p, w);
  } while (i >= l);
  return (i + p) % l;
}

/* FastOwenScrambler's hash of the reversed bits v (u32, or u32 lanes) with seed, in place; a
 * macro so that scalar and lane code share it. */
#define CLR_V4_FAST_OWEN_HASH(v, seed) \
  do {                                 \
    (v) ^= (v)*0x3d20adeau;            \
    (v) += (seed);                     \
    (v) *= ((seed) >> 16u) | 1u;       \
    (v) ^= (v)*0x05526c56u;            \
    (v) ^= (v)*0x53a22864u;            \
  } while (0)

/* FastOwenScrambler(seed). */
CLR_INLINE clr_u32 clr_v4_fast_owen(clr_u32 v, clr_u32 seed) {
  v = clr_reverse_bits32(v);
  CLR_V4_FAST_OWEN_HASH(v, seed);
  return clr_reverse_bits32(v);
}

/* OwenScrambler(seed): bit 31 - b flips with a hash of the b bits above it. */
CLR_INLINE clr_u32 clr_v4_owen(clr_u32 v, clr_u32 seed) {
  if (seed & 1u) v ^= 1u << 31u;
  for (clr_u32 b = 1u; b < 32u; ++b) {
    clr_u32 mask = 0xffffffffu << (32u - b);
    if ((clr_u32)clr_v4_mix_bits((clr_u64)((v & mask) ^ seed)) & (1u << b)) v ^= 1u << (31u - b);
  }
  return v;
}

/* The randomizer of CLR_RANDOMIZE_TYPE_* applied to a 32-bit Sobol' value. */
CLR_INLINE clr_u32 clr_v4_scramble(clr_u32 v, clr_i32 randomization, clr_u32 hash) {
  if (randomization == CLR_RANDOMIZE_TYPE_PERMUTEDIGITS) return v ^ hash;
  if (randomization == CLR_RANDOMIZE_TYPE_FASTOWEN) return clr_v4_fast_owen(v, hash);
  if (randomization == CLR_RANDOMIZE_TYPE_OWEN) return clr_v4_owen(v, hash);
  return v;
}

CLR_INLINE float clr_v4_below_one(float f) {
  return f < CLR_ONE_MINUS_EPSILON ? f : CLR_ONE_MINUS_EPSILON;
}

/* a / (float)b rounded to nearest even, as IEEE division, for finite a >= 0, 1 <= b < 2^24 and a
 * normal quotient: OpenCL's float `/` may be off by 2.5 ulp, so the quotient is formed in
 * integers, or, on devices with fp64, in double (correctly rounded in OpenCL), whose rounding to
 * float is then the correctly rounded float quotient (53 >= 2 * 24 + 2 bits: no double rounding
 * error for a quotient of two floats). */
CLR_INLINE float clr_v4_div(float a, clr_u32 b) {
#if defined(__OPENCL_C_VERSION__) && defined(cl_khr_fp64)
  return (float)((double)a / (double)b);
#else
  clr_u32 bits = clr_as_uint(a);
  clr_i32 biased = (clr_i32)(bits >> 23u);
  if (a == 0.0f) return 0.0f;
  clr_u64 m = (clr_u64)(bits & 0x7fffffu);
  clr_i32 e = biased - 150; /* a = m * 2^e */
  if (biased == 0)
    e = -149;
  else
    m |= 0x800000u;
  clr_u64 n = m << 40u;
  clr_u64 q = n / (clr_u64)b;
  int sticky = n - q * (clr_u64)b != 0u;
  clr_i32 top = 63 - (clr_i32)clr_halton_clz64(q);
  clr_u32 shift = (clr_u32)(top - 23);
  clr_u64 mant = q >> shift;
  clr_u64 rest = q & ((((clr_u64)1) << shift) - 1u);
  clr_u64 halfway = ((clr_u64)1) << (shift - 1u);
  if (rest > halfway || (rest == halfway && (sticky || (mant & 1u)))) ++mant;
  if (mant == (((clr_u64)1) << 24u)) {
    mant >>= 1u;
    ++shift;
  }
  clr_i32 exponent = (clr_i32)shift + e - 40 + 23 + 127;
  return clr_as_float(((clr_u32)exponent << 23u) | ((clr_u32)mant & 0x7fffffu));
#endif
}

#endif
