/* PCG32 exactly as pbrt-v3's RNG (core/rng.h): same constants, SetSequence, XSH-RR output,
 * UniformUInt32 with rejection, UniformFloat clamped below one, and Advance. */
#ifndef CLR_PCG32_H
#define CLR_PCG32_H

#include "clr_platform.h"

#define CLR_PCG32_DEFAULT_STATE 0x853c49e6748fea9bUL
#define CLR_PCG32_DEFAULT_STREAM 0xda3e39cb94b95bdbUL
#define CLR_PCG32_MULT 0x5851f42d4c957f2dUL

typedef struct clr_pcg32 {
  clr_u64 state, inc;
} clr_pcg32;

/* pbrt-v3's default-constructed RNG. */
CLR_INLINE clr_pcg32 clr_pcg32_default(void) {
  clr_pcg32 r;
  r.state = CLR_PCG32_DEFAULT_STATE;
  r.inc = CLR_PCG32_DEFAULT_STREAM;
  return r;
}

CLR_INLINE clr_u32 clr_pcg32_next(clr_pcg32 *r) {
  clr_u64 old = r->state;
  r->state = old * CLR_PCG32_MULT + r->inc;
  clr_u32 xorshifted = (clr_u32)(((old >> 18u) ^ old) >> 27u);
  clr_u32 rot = (clr_u32)(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
}

/* RNG::SetSequence(initseq) with pbrt-v3's fixed initial state. */
CLR_INLINE clr_pcg32 clr_pcg32_sequence(clr_u64 initseq) {
  clr_pcg32 r;
  r.state = 0u;
  r.inc = (initseq << 1u) | 1u;
  clr_pcg32_next(&r);
  r.state += CLR_PCG32_DEFAULT_STATE;
  clr_pcg32_next(&r);
  return r;
}

/* RNG::UniformUInt32(b): uniform in [0, b), rejecting r < (-b mod b). b must be > 0. */
CLR_INLINE clr_u32 clr_pcg32_bounded(clr_pcg32 *r, clr_u32 b) {
  clr_u32 threshold = (~b + 1u) % b;
  for (;;) {
    clr_u32 v = clr_pcg32_next(r);
    if (v >= threshold) return v % b;
  }
}

/* RNG::UniformFloat(): min(u32 * 2^-32, OneMinusEpsilon). */
CLR_INLINE float clr_pcg32_float(clr_pcg32 *r) {
  float f = (float)clr_pcg32_next(r) * 0x1p-32f;
  return f < CLR_ONE_MINUS_EPSILON ? f : CLR_ONE_MINUS_EPSILON;
}

/* RNG::Advance(delta)'s jump for increment inc, in O(log delta): `delta` draws ahead the state is
 * mult * state + plus. */
CLR_INLINE void clr_pcg32_advance_terms(clr_u64 delta, clr_u64 inc, clr_u64 *mult, clr_u64 *plus) {
  clr_u64 cur_mult = CLR_PCG32_MULT, cur_plus = inc, acc_mult = 1u, acc_plus = 0u;
  while (delta > 0) {
    if (delta & 1u) {
      acc_mult *= cur_mult;
      acc_plus = acc_plus * cur_mult + cur_plus;
    }
    cur_plus = (cur_mult + 1u) * cur_plus;
    cur_mult *= cur_mult;
    delta >>= 1u;
  }
  *mult = acc_mult;
  *plus = acc_plus;
}

/* RNG::Advance(delta): jump `delta` draws ahead. */
CLR_INLINE void clr_pcg32_advance(clr_pcg32 *r, clr_u64 delta) {
  clr_u64 mult, plus;
  clr_pcg32_advance_terms(delta, r->inc, &mult, &plus);
  r->state = mult * r->state + plus;
}

/* A well-mixed 64-bit hash (splitmix64 finaliser), for per-pixel streams and fallbacks. */
CLR_INLINE clr_u64 clr_mix64(clr_u64 x) {
  x ^= x >> 30u;
  x *= 0xbf58476d1ce4e5b9UL;
  x ^= x >> 27u;
  x *= 0x94d049bb133111ebUL;
  x ^= x >> 31u;
  return x;
}

/* Uniform float in [0,1) from a hash of `key`: the documented value past a sampler's tables. */
CLR_INLINE float clr_hash_float(clr_u64 key) {
  clr_u32 bits = (clr_u32)(clr_mix64(key) >> 40u); /* 24 bits: exact in float */
  return (float)bits * 0x1p-24f;
}

#endif
