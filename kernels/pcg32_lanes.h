/* 8 PCG32 generators in OpenCL vector types (the SIMD-shaped sampler kernels, one stream per
 * lane; OpenCL C only): each lane runs clr_pcg32_next's operations (pcg32.h), so the same bits. */
#ifndef CLR_PCG32_LANES_H
#define CLR_PCG32_LANES_H

#include "pcg32.h"

/* Small hot functions stay in registers only when inlined. */
#ifndef CLR_LANE_INLINE
#define CLR_LANE_INLINE static inline __attribute__((always_inline))
#endif

/* 8 PCG32 generators, 64-bit state in two halves of 4 lanes (AVX2-sized vectors). */
typedef struct clr_pcg32x8 {
  ulong4 state_lo, state_hi, inc_lo, inc_hi;
} clr_pcg32x8;

CLR_LANE_INLINE float8 clr_below_one_x8(float8 f) {
  return select((float8)CLR_ONE_MINUS_EPSILON, f, f < CLR_ONE_MINUS_EPSILON);
}

/* PCG32's XSH-RR output of 4 old states in the low halves of 64-bit lanes: the 32-bit xorshifted
 * value doubled into both halves, so that a 64-bit right shift by rot leaves the right rotation
 * in the low half. */
CLR_LANE_INLINE ulong4 clr_pcg32x4_output(ulong4 s) {
  uint8 xorshifted = as_uint8(((s >> (ulong)18) ^ s) >> (ulong)27);
  return as_ulong4(xorshifted.s00224466) >> (s >> (ulong)59);
}

/* PCG32's XSH-RR output of the old states (clr_pcg32_next). */
CLR_LANE_INLINE uint8 clr_pcg32x8_output(ulong4 lo, ulong4 hi) {
  return (uint8)(as_uint8(clr_pcg32x4_output(lo)).s0246, as_uint8(clr_pcg32x4_output(hi)).s0246);
}

/* s * CLR_PCG32_MULT + inc: the cross products' sum (mod 2^32) by one 32-bit multiply of both
 * halves, the low product as one 32x32->64 multiply. */
CLR_LANE_INLINE ulong4 clr_pcg32x4_step(ulong4 s, ulong4 inc) {
  const uint mult_lo = (uint)CLR_PCG32_MULT, mult_hi = (uint)(CLR_PCG32_MULT >> 32);
  uint8 products =
      as_uint8(s) * (uint8)(mult_hi, mult_lo, mult_hi, mult_lo, mult_hi, mult_lo, mult_hi, mult_lo);
  uint8 cross = products + products.s10325476;
  return (s & 0xFFFFFFFFul) * (ulong)mult_lo + (as_ulong4(cross) << 32ul) + inc;
}

CLR_LANE_INLINE uint8 clr_pcg32x8_next(clr_pcg32x8 *r) {
  ulong4 lo = r->state_lo, hi = r->state_hi;
  r->state_lo = clr_pcg32x4_step(lo, r->inc_lo);
  r->state_hi = clr_pcg32x4_step(hi, r->inc_hi);
  return clr_pcg32x8_output(lo, hi);
}

/* Draws only in the lanes of `mask` (others keep their state; their result is meaningless). */
CLR_LANE_INLINE uint8 clr_pcg32x8_next_masked(clr_pcg32x8 *r, int8 mask) {
  ulong4 lo = r->state_lo, hi = r->state_hi;
  r->state_lo = select(lo, clr_pcg32x4_step(lo, r->inc_lo), convert_long4(mask.lo));
  r->state_hi = select(hi, clr_pcg32x4_step(hi, r->inc_hi), convert_long4(mask.hi));
  return clr_pcg32x8_output(lo, hi);
}

CLR_LANE_INLINE float8 clr_pcg32x8_float(clr_pcg32x8 *r) {
  return clr_below_one_x8(convert_float8(clr_pcg32x8_next(r)) * 0x1p-32f);
}

/* clr_pcg32_advance by the same delta in every lane. Its increment term is linear in inc, so it
 * is formed once for inc = 1 and multiplied by each lane's inc. */
CLR_LANE_INLINE void clr_pcg32x8_advance(clr_pcg32x8 *r, ulong delta) {
  clr_u64 mult, plus;
  clr_pcg32_advance_terms(delta, 1u, &mult, &plus);
  r->state_lo = mult * r->state_lo + plus * r->inc_lo;
  r->state_hi = mult * r->state_hi + plus * r->inc_hi;
}

#endif
