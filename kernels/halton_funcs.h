/* pbrt-v3's Halton sampler math (core/lowdiscrepancy, samplers/halton), bit-exact on the host and
 * on any OpenCL 1.2 device (no fp64, no division where the digits are taken from a table). */
#ifndef CLR_HALTON_FUNCS_H
#define CLR_HALTON_FUNCS_H

#include "clr_platform.h"
#include "sampler_types.h"
#include "pcg32.h"

/* One prime base of the scrambled dimensions (dimension d uses record d), filled on the host by
 * clr_halton_primes(). Dividing a 32-bit n by `base` needs no divide instruction:
 *   t = mulhi32(n, div_magic); n / base = (t + ((n - t) >> 1)) >> div_shift. */
typedef struct clr_halton_prime {
  clr_u32 base;
  clr_u32 perm_offset;  /* first entry of this base's digit permutation (pbrt-v3 PrimeSums) */
  float inv_base;       /* (float)1 / (float)base */
  float scramble_tail;  /* inv_base * perm[0] / (1 - inv_base), in float, pbrt-v3's order */
  clr_u32 div_magic;    /* floor(2^32 * (2^l - base) / base) + 1, l = ceil(log2(base)) */
  clr_u32 div_shift;    /* l - 1 */
} clr_halton_prime;

/* (float)1 / (float)3, written out so that devices never divide. */
#define CLR_HALTON_INV_3 0x1.555556p-2f

CLR_INLINE clr_u32 clr_halton_mulhi32(clr_u32 a, clr_u32 b) {
#if CLR_DEVICE
  return mul_hi(a, b);
#else
  return (clr_u32)(((clr_u64)a * b) >> 32u);
#endif
}

CLR_INLINE clr_u32 clr_halton_clz64(clr_u64 x) {
#if CLR_DEVICE
  return (clr_u32)clz(x);
#else
  return x ? (clr_u32)__builtin_clzll(x) : 64u;
#endif
}

/* n / base for any 32-bit n, with the magic constants of the base's clr_halton_prime. */
CLR_INLINE clr_u32 clr_halton_div32(clr_u32 n, clr_u32 magic, clr_u32 shift) {
  clr_u32 t = clr_halton_mulhi32(n, magic);
  return (t + ((n - t) >> 1u)) >> shift;
}

CLR_INLINE clr_u32 clr_reverse_bits32(clr_u32 n) {
  n = (n << 16u) | (n >> 16u);
  n = ((n & 0x00ff00ffu) << 8u) | ((n & 0xff00ff00u) >> 8u);
  n = ((n & 0x0f0f0f0fu) << 4u) | ((n & 0xf0f0f0f0u) >> 4u);
  n = ((n & 0x33333333u) << 2u) | ((n & 0xccccccccu) >> 2u);
  n = ((n & 0x55555555u) << 1u) | ((n & 0xaaaaaaaau) >> 1u);
  return n;
}

CLR_INLINE clr_u64 clr_reverse_bits64(clr_u64 n) {
  return ((clr_u64)clr_reverse_bits32((clr_u32)n) << 32u) | clr_reverse_bits32((clr_u32)(n >> 32u));
}

/* v / 2^shift rounded to nearest, ties to even (shift in [0, 63]). */
CLR_INLINE clr_u64 clr_halton_round_shift(clr_u64 v, clr_u32 shift) {
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
CLR_INLINE float clr_radical_inverse_base2(clr_u64 a) {
  if ((a >> 32u) == 0u) /* at most 32 significant bits: the double is exact */
    return (float)clr_reverse_bits32((clr_u32)a) * 0x1p-32f;
  clr_u64 v = clr_reverse_bits64(a);
  clr_u32 bits = 64u - clr_halton_clz64(v);
  clr_u32 shift53 = bits > 53u ? bits - 53u : 0u;
  clr_u64 q53 = clr_halton_round_shift(v, shift53); /* the double is q53 * 2^shift53 */
  clr_u32 bits53 = bits > 53u ? 53u : bits;          /* q53 == 2^53 after a carry rounds exactly */
  clr_u32 shift24 = bits53 > 24u ? bits53 - 24u : 0u;
  clr_u32 q24 = (clr_u32)clr_halton_round_shift(q53, shift24); /* <= 2^24: exact in float */
  clr_u32 exponent = shift53 + shift24;                         /* value = q24 * 2^(exponent-64) */
  return (float)q24 * clr_as_float((127u + exponent - 64u) << 23u);
}

/* pbrt-v3 RadicalInverseSpecialized<base>(a) in float: digits accumulate in a u64, invBaseN is
 * the running float product of inv_base, result min((float)reversed * invBaseN, 1 - eps).
 * Digits of a >= 2^32 use 64-bit division, the rest 32-bit division (a constant divisor when
 * base is a literal and the call is inlined). */
CLR_INLINE float clr_radical_inverse(clr_u32 base, float inv_base, clr_u64 a) {
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

/* pbrt-v3 ScrambledRadicalInverseSpecialized(perm, a):
 *   min(invBaseN * ((float)reversed + scramble_tail), 1 - eps), digits d replaced by perm[d].
 * `pr` points to a private copy of the prime's record (copy it from the global table first);
 * `perms` is the whole permutation table (clr_halton_permutations()). */
CLR_INLINE float clr_scrambled_radical_inverse(const clr_halton_prime *pr,
                                               CLR_GLOBAL const clr_u16 *perms, clr_u64 a) {
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
}

/* pbrt-v3 InverseRadicalInverse<base>(inverse, nDigits): the index whose n_digits lowest base-b
 * digits, reversed, are the lowest digits of `inverse`. */
CLR_INLINE clr_u64 clr_inverse_radical_inverse(clr_u32 base, clr_u64 inverse, clr_i32 n_digits) {
  clr_u64 index = 0u;
  for (clr_i32 i = 0; i < n_digits; ++i) {
    clr_u64 next = inverse / base;
    index = index * base + (inverse - next * base);
    inverse = next;
  }
  return index;
}

/* Same for small values (pixel coordinates modulo 128), in 32 bits. */
CLR_INLINE clr_u32 clr_halton_inverse_digits32(clr_u32 base, clr_u32 inverse, clr_i32 n_digits) {
  clr_u32 index = 0u;
  for (clr_i32 i = 0; i < n_digits; ++i) {
    clr_u32 next = inverse / base;
    index = index * base + (inverse - next * base);
    inverse = next;
  }
  return index;
}

/* pbrt-v3 HaltonSampler::GetIndexForSample for the absolute pixel (px, py): the global index of
 * the pixel's sample `sample_number` (CRT over the base-2 and base-3 scales set up by
 * clr_halton_setup). Pixels are taken modulo 128 like pbrt-v3's Mod (p & 127 for negatives too). */
CLR_INLINE clr_u64 clr_halton_sampler_index(const clr_sampler_params *p, clr_i32 px, clr_i32 py,
                                            clr_i64 sample_number) {
  clr_u32 stride = (clr_u32)p->halton_stride;
  clr_u32 offset = 0u;
  if (stride > 1u) {
    clr_u32 mx = (clr_u32)px & (CLR_HALTON_MAX_RESOLUTION - 1u);
    clr_u32 my = (clr_u32)py & (CLR_HALTON_MAX_RESOLUTION - 1u);
    clr_u32 d0 = clr_halton_inverse_digits32(2u, mx, p->halton_exponent[0]);
    clr_u32 d1 = clr_halton_inverse_digits32(3u, my, p->halton_exponent[1]);
    /* stride / scale[0] == scale[1] and back; every term stays below 2^24. */
    offset = (d0 * (clr_u32)p->halton_scale[1] * p->halton_mult_inverse[0] +
              d1 * (clr_u32)p->halton_scale[0] * p->halton_mult_inverse[1]) % stride;
  }
  return (clr_u64)offset + (clr_u64)sample_number * (clr_u64)stride;
}

/* index / scale[1] (scale[1] = 3^exponent[1]). */
CLR_INLINE clr_u64 clr_halton_drop_base3_digits(const clr_sampler_params *p, clr_u64 index) {
  if ((index >> 32u) != 0u) return index / (clr_u64)(clr_u32)p->halton_scale[1];
  clr_u32 a = (clr_u32)index;
  for (clr_i32 i = 0; i < p->halton_exponent[1]; ++i) a /= 3u;
  return a;
}

/* pbrt-v3 HaltonSampler::SampleDimension(index, dim):
 *   dims 0, 1: 0.5 with sample_pixel_center; else Phi_2(index >> exponent[0]) and
 *              Phi_3(index / scale[1]), the offset inside the pixel (unscrambled);
 *   dims 2..999: ScrambledRadicalInverse with primes[dim] and its permutation.
 * Where pbrt-v3 aborts (dim >= 1000, or dim < 0) this returns a documented stand-in:
 *   clr_hash_float(clr_mix64(index) ^ (clr_u32)dim), uniform in [0, 1). */
CLR_INLINE float clr_halton_sampler_value(const clr_sampler_params *p,
                                          CLR_GLOBAL const clr_halton_prime *primes,
                                          CLR_GLOBAL const clr_u16 *perms, clr_u64 index,
                                          clr_i32 dim) {
  if (dim == 0 || dim == 1) {
    if (p->sample_pixel_center) return 0.5f;
    if (dim == 0) return clr_radical_inverse_base2(index >> (clr_u32)p->halton_exponent[0]);
    return clr_radical_inverse(3u, CLR_HALTON_INV_3, clr_halton_drop_base3_digits(p, index));
  }
  if ((clr_u32)dim >= CLR_HALTON_PRIMES)
    return clr_hash_float(clr_mix64(index) ^ (clr_u64)(clr_u32)dim);
  clr_halton_prime pr = primes[dim];
  return clr_scrambled_radical_inverse(&pr, perms, index);
}

#endif
