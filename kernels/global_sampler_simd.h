/* Device-only, 8 items per work-item: the global samplers (halton, sobol) in OpenCL vector types,
 * so that the code is SIMD whatever the runtime's work-item vectoriser does. Every function
 * mirrors a scalar one of sobol_funcs.h / halton_funcs.h step for step (the host reference
 * runs those): same integer operations, same float operations in the same order, so the bits
 * are the same.
 *
 * Only for launches whose global indices are all below 2^32 (CLR_INDEX32): lanes are 32-bit, and
 * 64-bit products are formed in halves of 4 lanes (8 x 64 bits would not fit the AVX2 ABI).
 *
 * Build defines (host/lib/sampler_device.c):
 *   CLR_INDEX32            every global index of the launch is below 2^32;
 *   CLR_HALTON_INDEX32     halton: with CLR_INDEX32.
 * Sobol's log2 resolution m and frame bits (sample numbers below 2^frame bits, 2m + frame bits
 * <= 32) are arguments, not defines: one program serves every resolution and sample count.
 * Halton plan entries carry in `shape` the chunks that cover the dimension's largest argument and
 * (bit 8) whether its reversed digits fit 32 bits (host/lib/sampler_device.c). */
#ifndef CLR_GLOBAL_SAMPLER_SIMD_H
#define CLR_GLOBAL_SAMPLER_SIMD_H

#include "global_sampler_funcs.h"
#include "lane_math.h"

#define CLR_LANES 8

#define CLR_SIMD_INLINE static inline __attribute__((always_inline))

/* (a * m) >> shift per lane for a < 2^31 and shift >= 31: mul_hi(2a, m) >> (shift - 31). */
CLR_SIMD_INLINE uint8 clr_mul_shift8(uint8 a, uint m, uint shift) {
  return clr_mul_hi8(a << 1u, m) >> (shift - 31u);
}

CLR_SIMD_INLINE float8 clr_below_one8(float8 f) {
  return select((float8)CLR_ONE_MINUS_EPSILON, f, f < CLR_ONE_MINUS_EPSILON);
}

/* The batch items of this work-item (8 consecutive ones; past the end the last one repeats, so
 * that padding lanes write the same value to the same place) and their pixels and samples. */
typedef struct clr_items8 {
  uint8 item, sample;
  int8 px, py;
  int one_pixel; /* every lane in one pixel (the items do not decrease: first and last lanes) */
} clr_items8;

static inline clr_items8 clr_items_of_work_item(const clr_sampler_params *p,
                                                const clr_item_divisors *d, int item_count) {
  clr_items8 it;
  uint first = (uint)get_global_id(0) * CLR_LANES;
  /* min with a vector on both sides: Oclgrind mis-evaluates min(uint8, uint). */
  it.item = min(first + (uint8)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u), (uint8)((uint)item_count - 1u));
  uint8 pixel = clr_mul_shift8(it.item, d->sample_magic, d->sample_shift); /* divisors */
  uint8 row = clr_mul_shift8(pixel, d->width_magic, d->width_shift);
  it.sample = (uint)p->first_sample + it.item - pixel * (uint)p->sample_count;
  it.px = p->batch_x0 + as_int8(pixel - row * (uint)p->batch_width);
  it.py = p->batch_y0 + as_int8(row);
  it.one_pixel = pixel.s7 == pixel.s0;
  return it;
}

/* Writes lane j's value to out[j * stride]. */
CLR_SIMD_INLINE void clr_store_rows8(__global float *out, size_t stride, float8 v) {
  out[0] = v.s0;
  out[stride] = v.s1;
  out[2 * stride] = v.s2;
  out[3 * stride] = v.s3;
  out[4 * stride] = v.s4;
  out[5 * stride] = v.s5;
  out[6 * stride] = v.s6;
  out[7 * stride] = v.s7;
}

/* Writes lane j's value to values[item_j * values_per_sample + value]. */
CLR_SIMD_INLINE void clr_store8(__global float *values, uint8 item, int values_per_sample,
                                int value, float8 v) {
  size_t stride = (size_t)values_per_sample, at = (size_t)value;
  values[(size_t)item.s0 * stride + at] = v.s0;
  values[(size_t)item.s1 * stride + at] = v.s1;
  values[(size_t)item.s2 * stride + at] = v.s2;
  values[(size_t)item.s3 * stride + at] = v.s3;
  values[(size_t)item.s4 * stride + at] = v.s4;
  values[(size_t)item.s5 * stride + at] = v.s5;
  values[(size_t)item.s6 * stride + at] = v.s6;
  values[(size_t)item.s7 * stride + at] = v.s7;
}

/* Sample numbers s * scale + offset of an index slot. */
static inline uint8 clr_sample_numbers8(uint8 sample, clr_index_plan ip) {
  return sample * (uint)ip.scale + (uint)ip.offset;
}

#if CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_SOBOL && defined(CLR_INDEX32)
/* clr_sobol_sample_float for a table dimension, from its 3-bit group tables `groups`
 * (clr_sobol_group_bits8), the index's `bits` <= 32 (uniform). */
CLR_SIMD_INLINE float8 clr_sobol_float8(uint8 index, __global const uint *groups, int bits) {
  return clr_below_one8(convert_float8(clr_sobol_group_bits8(index, groups, bits)) * 0x1p-32f);
}

/* clr_sobol_sampler_value: dims 0 and 1 become the offset inside the pixel; dims past the
 * tables the hash of clr_sobol_fallback_float. */
CLR_SIMD_INLINE float8 clr_sobol_value8(const clr_sampler_params *p, __global const uint *groups,
                                        uint8 index, int dim, int8 px, int8 py) {
  if ((uint)dim >= CLR_SOBOL_DIMENSIONS) {
    uint lanes[CLR_LANES];
    float out[CLR_LANES];
    vstore8(index, 0, lanes);
    for (int j = 0; j < CLR_LANES; ++j) out[j] = clr_sobol_fallback_float((ulong)lanes[j], dim);
    return vload8(0, out);
  }
  float8 s = clr_sobol_float8(index, groups + (uint)dim * CLR_SOBOL_GROUP_TABLE,
                              2 * p->sobol_log2_resolution + p->sobol_frame_bits);
  if (dim > 1) return s;
  float pmin = (float)(dim == 0 ? p->sample_x0 : p->sample_y0);
  float8 pixel = convert_float8(dim == 0 ? px : py);
  s = s * p->sobol_resolution + pmin;
  s = s - pixel;
  s = select(s, (float8)0.0f, s < 0.0f);
  return select(s, (float8)CLR_ONE_MINUS_EPSILON, s > CLR_ONE_MINUS_EPSILON);
}
#endif

#if CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_HALTON && defined(CLR_INDEX32)
CLR_SIMD_INLINE uint8 clr_gather_u32(__global const uint *t, uint8 i) {
  return (uint8)(t[i.s0], t[i.s1], t[i.s2], t[i.s3], t[i.s4], t[i.s5], t[i.s6], t[i.s7]);
}

CLR_SIMD_INLINE float8 clr_gather_f32(__global const float *t, uint8 i) {
  return (float8)(t[i.s0], t[i.s1], t[i.s2], t[i.s3], t[i.s4], t[i.s5], t[i.s6], t[i.s7]);
}

/* v / 3^n (clr_halton_div_pow3). */
static inline uint8 clr_halton_div_pow3x8(uint8 v, int n) {
  CLR_UNROLL
  for (int i = 0; i < 5; ++i)
    if (i < n) v = v / 3u;
  return v;
}

/* The lowest chunk of each lane's a (clr_scrambled_radical_inverse32's loop body): its digits
 * permuted and reversed (`value`), base^(their count) (`scale`), their count, and a / chunk_base. */
CLR_SIMD_INLINE uint8 clr_halton_chunk8(__global const clr_halton_prime *pr,
                                        __global const ushort *perms, uint8 a, uint8 *value,
                                        uint8 *scale, uint8 *count) {
  uint base = pr->base, base2 = base * base, base4 = base2 * base2;
  uint tail_shift = pr->tail_shift;
  uint8 t = clr_mul_hi8(a, pr->chunk_magic); /* clr_halton_mulhi32 */
  uint8 next = (t + ((a - t) >> 1u)) >> pr->chunk_shift;
  uint8 d = a - next * pr->chunk_base;
  int8 top = next == 0u;
  uint8 entry =
      clr_gather_u16(perms, select((uint8)pr->chunk_offset, (uint8)pr->tail_offset, top) + d);
  *count = select((uint8)pr->chunk_digits, (entry >> tail_shift) + 1u, top);
  *value = entry & ((1u << tail_shift) - 1u);
  *scale = select((uint8)1u, (uint8)base, (*count & 1u) != 0u) *
           select((uint8)1u, (uint8)base2, (*count & 2u) != 0u) *
           select((uint8)1u, (uint8)base4, (*count & 4u) != 0u);
  return next;
}

/* clr_scrambled_radical_inverse32 over `chunks` chunks (the scalar loop's later chunks see
 * a == 0 and change nothing). reversed32: the host knows every reversed value is below 2^32
 * (base^digits of the largest argument), so it is formed in 32 bits; else in 64. */
CLR_SIMD_INLINE float8 clr_scrambled_radical_inverse8(__global const clr_halton_prime *pr,
                                                      __global const ushort *perms, uint8 a,
                                                      int chunks, int reversed32) {
  uint8 value, scale, count, digits = (uint8)0u;
  float8 reversed;
  if (reversed32) {
    uint8 r = (uint8)0u;
    for (int chunk = 0; chunk < chunks; ++chunk) {
      uint8 next = clr_halton_chunk8(pr, perms, a, &value, &scale, &count);
      int8 active = a != 0u;
      r = select(r, r * scale + value, active);
      digits += select((uint8)0u, count, active);
      a = next;
    }
    reversed = convert_float8(r);
  } else {
    ulong4 r_lo = (ulong4)0u, r_hi = (ulong4)0u; /* lanes 0-3, 4-7 */
    for (int chunk = 0; chunk < chunks; ++chunk) {
      uint8 next = clr_halton_chunk8(pr, perms, a, &value, &scale, &count);
      int8 active = a != 0u;
      r_lo = select(r_lo, r_lo * convert_ulong4(scale.lo) + convert_ulong4(value.lo),
                    convert_long4(active.lo));
      r_hi = select(r_hi, r_hi * convert_ulong4(scale.hi) + convert_ulong4(value.hi),
                    convert_long4(active.hi));
      digits += select((uint8)0u, count, active);
      a = next;
    }
    reversed = (float8)(convert_float4(r_lo), convert_float4(r_hi));
  }
  float8 v = clr_gather_f32(pr->inv_base_pow, digits) * (reversed + pr->scramble_tail);
  return clr_below_one8(v);
}

/* The digit counts of a pair table without stored ones (CLR_HALTON_PAIR_DERIVED_COUNTS): c, the
 * significant base-b digits of hi (of a = lo where hi is 0), is how many of base^0..base^top (the
 * header's nonzero powers; hi < base^top) it reaches. *count: hi's digits, *digits: a's. */
CLR_SIMD_INLINE void clr_halton_pair_counts8(__global const ushort *pt, uint8 a, uint8 hi,
                                             uint8 *count, uint8 *digits) {
  int8 top = hi != 0u;
  uint8 x = select(a, hi, top), c = (uint8)0u;
  /* select, not c -= as_uint8(x >= p): Oclgrind evaluated that form wrongly */
  for (int k = 0; k < CLR_HALTON_PAIR_ROW && pt[8 + k] != 0u; ++k)
    c += select((uint8)0u, (uint8)1u, x >= (uint8)(uint)pt[8 + k]);
  *count = select((uint8)0u, c, top);
  *digits = c + select((uint8)0u, (uint8)(uint)pt[4], top);
}

/* clr_scrambled_radical_inverse32 for the arguments of a launch from the record's pair table
 * `pt` (CLR_HALTON_PAIR_HEADER in halton_funcs.h): a = hi * B + lo; lo's entry is its m digits
 * below a nonzero hi, else its significant ones; hi's entry its significant digits (none for 0).
 * The reversed digits are lo's * base^(hi's count) + hi's, below 2^31 (so a signed conversion
 * gives the same float); their count is at most 14, so invBaseN comes from two register tables.
 * Same integers, same float operations. */
CLR_SIMD_INLINE float8 clr_halton_pair8(__global const clr_halton_prime *pr,
                                        __global const ushort *pt, uint8 a, int stepped,
                                        int derived) {
  uint chunk = pt[0], magic = (uint)pt[1] | (uint)pt[2] << 16, count_shift = pt[5];
  uint rows = (uint)pt[6] | (uint)pt[7] << 16;
  /* a < 2^28 and shift >= 30: (a * magic) >> shift = mul_hi(a * 16, magic) >> (shift - 28) */
  uint8 hi = clr_mul_hi8(a << 4u, magic) >> (uint)(pt[3] - 28u);
  uint8 low;
  if (stepped && rows != 0u && hi.s0 != 0u) { /* a_j = a_0 + j * step, every hi nonzero */
    low = convert_uint8(vload8(0, pt + rows + (a.s0 - hi.s0 * chunk) * CLR_HALTON_PAIR_ROW));
  } else {
    uint8 lo = a - hi * chunk;
    uint8 low_table =
        select((uint8)CLR_HALTON_PAIR_HEADER, (uint8)(CLR_HALTON_PAIR_HEADER + chunk), hi == 0u);
    low = clr_gather_u16(pt, low_table + lo);
  }
  uint8 high = clr_gather_u16(pt + CLR_HALTON_PAIR_HEADER + chunk, hi);
  uint value_mask = (1u << count_shift) - 1u;
  uint8 count = high >> count_shift, digits8 = (low >> count_shift) + count;
  if (derived) clr_halton_pair_counts8(pt, a, hi, &count, &digits8);
  uint8 powers = convert_uint8(vload8(1, pt)); /* base^0..base^7 */
  uint8 reversed = (low & value_mask) * clr_permute8(powers, count) + (high & value_mask);
  int8 digits = as_int8(digits8);
  uint8 pow_lo = clr_permute8(as_uint8(vload8(0, pr->inv_base_pow)), as_uint8(digits));
  uint8 pow_hi = clr_permute8(as_uint8(vload8(1, pr->inv_base_pow)), as_uint8(digits));
  float8 inv_base_n = as_float8(select(pow_lo, pow_hi, digits > 7));
  return clr_below_one8(inv_base_n * (convert_float8(as_int8(reversed)) + pr->scramble_tail));
}

/* ceil(2^32 / 3^e), e = 0..5 (scale[1] = 3^e1, e1 <= 5). */
__constant ulong clr_pow3_reciprocals[6] = {0x100000000ul, 1431655766ul, 477218589ul,
                                            159072863ul,   53024288ul,   17674763ul};

/* n / 3^e for n < 2^16 and e <= 5: (n * ceil(2^32 / 3^e)) >> 32, exact since n times the
 * rounding error (below 3^e) times 3^e stays below 2^32; no division instruction. */
CLR_SIMD_INLINE uint clr_div_pow3_small(uint n, int e) {
  return (uint)(((ulong)n * clr_pow3_reciprocals[e]) >> 32);
}

/* clr_halton_sampler_index(p, px, py, 0), scalar, in fewer steps: the e0 <= 7 low bits of mx
 * reversed from two nibble reversals, y1 / 3^e1 (y1 = d1 * inverse < 3^2e1 <= 243^2) by
 * clr_div_pow3_small. */
CLR_SIMD_INLINE uint clr_halton_pixel_offset(const clr_sampler_params *p, int px, int py) {
  uint scale0 = (uint)p->halton_scale[0], scale1 = (uint)p->halton_scale[1];
  uint mx = (uint)px & (CLR_HALTON_MAX_RESOLUTION - 1u);
  uint my = (uint)py & (CLR_HALTON_MAX_RESOLUTION - 1u);
  uint reversed8 = clr_reverse_nibble(mx & 15u) << 4u | clr_reverse_nibble(mx >> 4u);
  uint d0 = reversed8 >> (8u - (uint)p->halton_exponent[0]);
  uint d1 = 0u;
  CLR_UNROLL
  for (int i = 0; i < 5; ++i) {
    uint next = my / 3u;
    d1 = i < p->halton_exponent[1] ? d1 * 3u + (my - next * 3u) : d1;
    my = next;
  }
  uint x0 = (d0 * p->halton_mult_inverse[0]) & (scale0 - 1u);
  uint y1 = d1 * p->halton_mult_inverse[1];
  uint offset =
      x0 * scale1 + (y1 - clr_div_pow3_small(y1, p->halton_exponent[1]) * scale1) * scale0;
  return offset >= (uint)p->halton_stride ? offset - (uint)p->halton_stride : offset;
}

/* clr_halton_sampler_index for indices below 2^32, and in *base3 the argument of dimension 1,
 * index / scale1 (clr_halton_drop_base3_digits): with the lanes in one pixel (one_pixel), offset /
 * scale1 + number * scale0 (stride = scale0 * scale1). */
CLR_SIMD_INLINE uint8 clr_halton_index8(const clr_sampler_params *p, int8 px, int8 py, uint8 number,
                                        int one_pixel, uint8 *base3) {
  if (one_pixel) { /* (spp a multiple of 8): its offset once */
    uint offset = clr_halton_pixel_offset(p, px.s0, py.s0);
    /* offset < stride <= 128 * 243 */
    *base3 = clr_div_pow3_small(offset, p->halton_exponent[1]) + number * (uint)p->halton_scale[0];
    return offset + number * (uint)p->halton_stride;
  }
  uint scale0 = (uint)p->halton_scale[0], scale1 = (uint)p->halton_scale[1];
  uint stride = (uint)p->halton_stride;
  int exponent1 = p->halton_exponent[1];
  uint8 mx = as_uint8(px) & (CLR_HALTON_MAX_RESOLUTION - 1u);
  uint8 my = as_uint8(py) & (CLR_HALTON_MAX_RESOLUTION - 1u);
  uint8 d0 = (clr_reverse_bits32x8(mx) >> (31u - (uint)p->halton_exponent[0])) >> 1u;
  uint8 d1 = (uint8)0u;
  CLR_UNROLL
  for (int i = 0; i < 5; ++i) {
    uint8 next = my / 3u;
    if (i < exponent1) d1 = d1 * 3u + (my - next * 3u);
    my = next;
  }
  uint8 x0 = (d0 * (uint)p->halton_mult_inverse[0]) & (scale0 - 1u);
  uint8 y1 = d1 * (uint)p->halton_mult_inverse[1];
  uint8 x1 = y1 - clr_halton_div_pow3x8(y1, exponent1) * scale1;
  uint8 offset = x0 * scale1 + x1 * scale0;
  offset = select(offset, offset - stride, offset >= stride);
  uint8 index = offset + number * stride;
  *base3 = clr_halton_div_pow3x8(index, exponent1);
  return index;
}

/* clr_halton_sampler_value for indices below 2^32; pair: the dimension's pair table, or NULL;
 * stepped: the lanes are consecutive samples of one pixel and index is slot 0's (index_j = index_0
 * + j * stride, base3_j = base3_0 + j * scale[0]: the pair tables' lane rows apply). */
static inline float8 clr_halton_value8(const clr_sampler_params *p,
                                       __global const clr_halton_prime *primes,
                                       __global const ushort *perms, __global const ushort *pair,
                                       uint8 index, uint8 base3, int stepped, int dim, int chunks,
                                       int reversed32) {
  uint udim = (uint)dim;
  if (udim <= 1u && p->sample_pixel_center) return (float8)0.5f;
  if (udim == 0u)
    return convert_float8(clr_reverse_bits32x8(index >> (uint)p->halton_exponent[0])) * 0x1p-32f;
  if (udim < CLR_HALTON_PRIMES) {
    __global const clr_halton_prime *pr = primes + (udim == 1u ? CLR_HALTON_BASE3_RECORD : udim);
    uint8 a = udim == 1u ? base3 : index;
    if (pair) /* two inlined copies: tables with stored counts test nothing per value */
      return pair[5] == CLR_HALTON_PAIR_DERIVED_COUNTS ? clr_halton_pair8(pr, pair, a, stepped, 1)
                                                       : clr_halton_pair8(pr, pair, a, stepped, 0);
    return clr_scrambled_radical_inverse8(pr, perms, a, chunks, reversed32);
  }
  uint lanes[CLR_LANES];
  float out[CLR_LANES];
  vstore8(index, 0, lanes);
  for (int j = 0; j < CLR_LANES; ++j)
    out[j] = clr_hash_float(clr_mix64((ulong)lanes[j]) ^ (ulong)udim);
  return vload8(0, out);
}
#endif

#endif
