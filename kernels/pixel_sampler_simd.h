/* Device-only, 8 pixels per work-item (CLR_SEEDING_TYPE_PIXEL): the pixel samplers (stratified,
 * random, 02sequence, maxmindist) with one PCG32 stream per lane in OpenCL vector types. Every
 * lane runs the same sequence of operations as clr_pixel_sampler_pixel (stratified_funcs.h,
 * random_funcs.h, zerotwo_funcs.h, maxmin_funcs.h), which the host reference runs: same draws in
 * the same order, same float operations, so the same bits.
 * Lanes differ only where UniformUInt32 rejects a draw: those lanes alone draw again.
 *
 * Scratch: each work-item owns p->scratch_floats rows of 8 floats; row r holds float r of every
 * lane's scratch (lane j in column j), so that rows are vectors. */
#ifndef CLR_PIXEL_SAMPLER_SIMD_H
#define CLR_PIXEL_SAMPLER_SIMD_H

#include "pixel_sampler_funcs.h"
#include "lane_math.h"
#include "lane_store.h"
#include "pcg32_lanes.h"

#define CLR_PIXEL_LANES 8

/* A draw per lane, redrawn in the lanes where it is below `threshold` (UniformUInt32's rejection;
 * only the rejecting lanes draw again). */
CLR_LANE_INLINE uint8 clr_pcg32x8_accepted(clr_pcg32x8 *r, uint threshold) {
  uint8 v = clr_pcg32x8_next(r);
  int8 rejected = v < threshold;
  while (threshold != 0u && clr_any8(rejected)) {
    uint8 w = clr_pcg32x8_next_masked(r, rejected);
    v = select(v, w, rejected);
    rejected = rejected & (v < threshold);
  }
  return v;
}

/* clr_pcg32_bounded(b) in every lane: v % b by Granlund-Montgomery multiplication (exact for
 * every 32-bit v; no vector division). bounded[b - 1] = (threshold (-b) % b, magic, shift1,
 * shift2) from the host. */
CLR_LANE_INLINE uint8 clr_pcg32x8_bounded(clr_pcg32x8 *r, uint b, __global const uint4 *bounded) {
  uint4 k = bounded[b - 1u];
  uint8 v = clr_pcg32x8_accepted(r, k.x);
  uint8 t = clr_mul_hi8(v, k.y);
  uint8 q = (t + ((v - t) >> k.z)) >> k.w;
  return v - q * b;
}

/* UniformUInt32's rejection threshold for the bound b. */
CLR_LANE_INLINE uint clr_bounded_threshold(uint b) { return (0u - b) % b; }

/* clr_pcg32_bounded(b) for a b known when compiled (an unrolled loop's): the compiler folds the
 * threshold and the remainder (a mask for powers of two, no test where the threshold is 0). */
CLR_LANE_INLINE uint8 clr_pcg32x8_bounded_const(clr_pcg32x8 *r, uint b) {
  return clr_pcg32x8_accepted(r, clr_bounded_threshold(b)) % b;
}

/* Scratch rows: float c of item i (of `dims` floats) is row i * dims + c. */
CLR_LANE_INLINE uint8 clr_scratch_rows8(uint8 item, int dims, int c) {
  return (item * (uint)dims + (uint)c) * CLR_PIXEL_LANES + (uint8)(0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u);
}

CLR_LANE_INLINE float8 clr_gather8(__global const float *scratch, uint8 at) {
  return (float8)(scratch[at.s0], scratch[at.s1], scratch[at.s2], scratch[at.s3], scratch[at.s4],
                  scratch[at.s5], scratch[at.s6], scratch[at.s7]);
}

CLR_LANE_INLINE void clr_scatter8(__global float *scratch, uint8 at, float8 v) {
  scratch[at.s0] = v.s0;
  scratch[at.s1] = v.s1;
  scratch[at.s2] = v.s2;
  scratch[at.s3] = v.s3;
  scratch[at.s4] = v.s4;
  scratch[at.s5] = v.s5;
  scratch[at.s6] = v.s6;
  scratch[at.s7] = v.s7;
}

/* clr_shuffle of `count` items of `dims` floats in scratch. */
static inline void clr_shuffle8(__global float *buf, int count, int dims, clr_pcg32x8 *state,
                                __global const uint4 *bounded) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  for (int i = 0; i < count; ++i) {
    uint8 other = (uint)i + clr_pcg32x8_bounded(rng, (uint)(count - i), bounded);
    for (int c = 0; c < dims; ++c) {
      uint8 at = clr_scratch_rows8(other, dims, c);
      float8 t = vload8(i * dims + c, buf);
      vstore8(clr_gather8(buf, at), i * dims + c, buf);
      clr_scatter8(buf, at, t);
    }
  }
  *state = r;
}

/* Items of a shuffle of at most 16 items live as a permutation in registers: nibble s of lane j
 * is the item at position s (the scratch rows stay where clr_stratified_sample_*8 put them). */
#define CLR_PERM_MAX_ITEMS 16

/* The identity permutation 0xFEDCBA9876543210 (positions past count are never touched). */
#define CLR_PERM_IDENTITY 0xFEDCBA9876543210ul

/* The lanes' permutations as two 4-lane halves, always by pointer: 512-bit vectors as values
 * (ulong8 arguments, convert_ulong8) draw -Wpsabi warnings from PoCL's AVX2 build. */
typedef struct clr_perm8 {
  ulong4 lo, hi;
} clr_perm8;

/* Swaps position i (the same in every lane) with position other >= i of each lane. */
CLR_LANE_INLINE ulong4 clr_perm_swap4(ulong4 perm, ulong at_i, uint4 other) {
  ulong4 at_other = convert_ulong4(other) << 2ul;
  ulong4 x = ((perm >> at_i) ^ (perm >> at_other)) & 15ul;
  return perm ^ ((x << at_i) | (x << at_other));
}

CLR_LANE_INLINE void clr_perm_swap8(clr_perm8 *perm, int i, uint8 other) {
  ulong at_i = 4ul * (ulong)i;
  perm->lo = clr_perm_swap4(perm->lo, at_i, other.lo);
  perm->hi = clr_perm_swap4(perm->hi, at_i, other.hi);
}

/* clr_shuffle of `count` <= 16 items into *perm: the same swaps, made on the permutation's
 * nibbles; 16 items (4x4 strata, 16 samples) unrolled, so that every bound is a constant. */
static inline void clr_shuffle_perm8(int count, clr_pcg32x8 *state, __global const uint4 *bounded,
                                     clr_perm8 *perm) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  clr_perm8 p;
  p.lo = p.hi = (ulong4)CLR_PERM_IDENTITY;
  if (count == CLR_PERM_MAX_ITEMS) {
#pragma unroll
    for (int i = 0; i < CLR_PERM_MAX_ITEMS; ++i)
      clr_perm_swap8(&p, i,
                     (uint)i + clr_pcg32x8_bounded_const(rng, (uint)(CLR_PERM_MAX_ITEMS - i)));
  } else {
    for (int i = 0; i < count; ++i)
      clr_perm_swap8(&p, i, (uint)i + clr_pcg32x8_bounded(rng, (uint)(count - i), bounded));
  }
  *state = r;
  *perm = p;
}

/* Nibble s of every lane: the item at position s. */
CLR_LANE_INLINE uint8 clr_nibbles8(const clr_perm8 *perm, int s) {
  ulong at = 4ul * (ulong)s;
  return (uint8)(convert_uint4((perm->lo >> at) & 15ul), convert_uint4((perm->hi >> at) & 15ul));
}

/* Float c of the item at position s, read through the permutation. */
CLR_LANE_INLINE float8 clr_perm_load8(__global const float *buf, const clr_perm8 *perm, int s,
                                      int dims, int c) {
  return clr_gather8(buf, clr_scratch_rows8(clr_nibbles8(perm, s), dims, c));
}

/* The draws of clr_shuffle8 of `count` items (16 unrolled: no remainders, and no output where
 * the threshold is 0). */
static inline void clr_shuffle_draws8(int count, clr_pcg32x8 *state,
                                      __global const uint4 *bounded) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  if (count == CLR_PERM_MAX_ITEMS) {
#pragma unroll
    for (int i = 0; i < CLR_PERM_MAX_ITEMS; ++i)
      clr_pcg32x8_accepted(rng, clr_bounded_threshold((uint)(CLR_PERM_MAX_ITEMS - i)));
  } else {
    for (int i = 0; i < count; ++i) clr_pcg32x8_accepted(rng, bounded[count - i - 1].x);
  }
  *state = r;
}

/* clr_stratified_sample_1d into scratch rows 0..n-1. */
static inline void clr_stratified_sample_1d8(__global float *buf, int n, float inv_n, int jitter,
                                             clr_pcg32x8 *state) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  for (int i = 0; i < n; ++i) {
    float8 delta = jitter ? clr_pcg32x8_float(rng) : (float8)0.5f;
    vstore8(clr_below_one_x8(((float)i + delta) * inv_n), i, buf);
  }
  *state = r;
}

/* clr_stratified_sample_2d into scratch rows 0..2n-1. */
static inline void clr_stratified_sample_2d8(__global float *buf, int nx, int ny, float inv_nx,
                                             float inv_ny, int jitter, clr_pcg32x8 *state) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      float8 jx = jitter ? clr_pcg32x8_float(rng) : (float8)0.5f;
      float8 jy = jitter ? clr_pcg32x8_float(rng) : (float8)0.5f;
      int i = 2 * (y * nx + x);
      vstore8(clr_below_one_x8(((float)x + jx) * inv_nx), i, buf);
      vstore8(clr_below_one_x8(((float)y + jy) * inv_ny), i + 1, buf);
    }
  *state = r;
}

/* clr_latin_hypercube_2d into scratch rows 0..2n-1. */
static inline void clr_latin_hypercube_2d8(__global float *buf, int n, float inv_n,
                                           clr_pcg32x8 *state, __global const uint4 *bounded) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  for (int i = 0; i < 2 * n; ++i)
    vstore8(clr_below_one_x8(((float)(i >> 1) + clr_pcg32x8_float(rng)) * inv_n), i, buf);
  for (int c = 0; c < 2; ++c)
    for (int j = 0; j < n; ++j) {
      uint8 other = (uint)j + clr_pcg32x8_bounded(rng, (uint)(n - j), bounded);
      uint8 at = clr_scratch_rows8(other, 2, c);
      float8 t = vload8(2 * j + c, buf);
      vstore8(clr_gather8(buf, at), 2 * j + c, buf);
      clr_scatter8(buf, at, t);
    }
  *state = r;
}

static inline void clr_latin_hypercube_2d_draws8(int n, clr_pcg32x8 *rng,
                                                 __global const uint4 *bounded) {
  clr_pcg32x8_advance(rng, 2u * (ulong)n);
  clr_shuffle_draws8(n, rng, bounded);
  clr_shuffle_draws8(n, rng, bounded);
}

/* Shuffles the n points of stream d (dims floats each, scratch rows 0..n * dims - 1) as
 * clr_shuffle does, then stores them from scratch to every slot the stream feeds. */
CLR_LANE_INLINE void clr_stream_shuffle_store8(const clr_sampler_params *p,
                                               __global const clr_request_slot *slots, int dims,
                                               int d, int n, clr_pcg32x8 *rng,
                                               __global float *values, const ulong *out,
                                               __global float *buf, __global const uint4 *bounded) {
  int in_registers = n <= CLR_PERM_MAX_ITEMS;
  clr_perm8 perm;
  perm.lo = perm.hi = (ulong4)CLR_PERM_IDENTITY;
  if (in_registers)
    clr_shuffle_perm8(n, rng, bounded, &perm);
  else
    clr_shuffle8(buf, n, dims, rng, bounded);
  for (int k = 0; k < p->request_count; ++k) {
    if (!clr_slot_stores(&slots[k], dims, 0, d)) continue;
    if (in_registers && dims == 2) {
      for (int s = 0; s < p->sample_count; ++s) {
        uint8 at = clr_scratch_rows8(clr_nibbles8(&perm, p->first_sample + s), 2, 0);
        clr_store_pairs8(values, out,
                         (size_t)s * (size_t)p->values_per_sample + (size_t)slots[k].first_value,
                         clr_gather8(buf, at), clr_gather8(buf, at + (uint)CLR_PIXEL_LANES));
      }
      continue;
    }
    for (int s = 0; s < p->sample_count; ++s)
      for (int c = 0; c < dims; ++c) {
        int at = p->first_sample + s;
        float8 v =
            in_registers ? clr_perm_load8(buf, &perm, at, dims, c) : vload8(at * dims + c, buf);
        clr_store_lanes8(
            values, out,
            (size_t)s * (size_t)p->values_per_sample + (size_t)(slots[k].first_value + c), v);
      }
  }
}

/* clr_stratified_streams: a used stream's points go straight from scratch to every slot fed. */
static inline void clr_stratified_streams8(const clr_sampler_params *p,
                                           __global const clr_request_slot *slots, int dims,
                                           clr_pcg32x8 *rng, __global float *values,
                                           const ulong *out, __global float *buf,
                                           __global const uint4 *bounded) {
  int n = p->x_samples * p->y_samples;
  for (int d = 0; d < p->dimensions; ++d) {
    if (!clr_slots_use(p, slots, dims, 0, d)) {
      if (p->jitter) clr_pcg32x8_advance(rng, (ulong)n * (ulong)dims);
      clr_shuffle_draws8(n, rng, bounded);
      continue;
    }
    if (dims == 1)
      clr_stratified_sample_1d8(buf, n, p->inv_spp, p->jitter, rng);
    else
      clr_stratified_sample_2d8(buf, p->x_samples, p->y_samples, p->inv_x_samples, p->inv_y_samples,
                                p->jitter, rng);
    clr_stream_shuffle_store8(p, slots, dims, d, n, rng, values, out, buf, bounded);
  }
}

/* clr_stratified_arrays. */
static inline void clr_stratified_arrays8(const clr_sampler_params *p,
                                          __global const clr_request_slot *slots, int dims,
                                          clr_pcg32x8 *rng, __global float *values,
                                          const ulong *out, __global float *buf,
                                          __global const uint4 *bounded) {
  int arrays = clr_slots_array_count(p, slots, dims);
  for (int a = 0; a < arrays; ++a) {
    int size = clr_slots_array_size(p, slots, dims, a);
    float inv_size = clr_slots_inv_array_size(p, slots, dims, a);
    int used = clr_slots_use(p, slots, dims, 1, a);
    for (int j = 0; j < p->spp; ++j) {
      int s = j - p->first_sample;
      if (used && s >= 0 && s < p->sample_count) {
        if (dims == 1) {
          clr_stratified_sample_1d8(buf, size, inv_size, p->jitter, rng);
          clr_shuffle8(buf, size, 1, rng, bounded);
        } else {
          clr_latin_hypercube_2d8(buf, size, inv_size, rng, bounded);
        }
        for (int k = 0; k < p->request_count; ++k) {
          if (!clr_slot_stores(&slots[k], dims, 1, a)) continue;
          size_t at = (size_t)s * (size_t)p->values_per_sample + (size_t)slots[k].first_value;
          for (int v = 0; v < size * dims; ++v)
            clr_store_lanes8(values, out, at + (size_t)v, vload8(v, buf));
        }
      } else if (dims == 1) {
        if (p->jitter) clr_pcg32x8_advance(rng, (ulong)size);
        clr_shuffle_draws8(size, rng, bounded);
      } else {
        clr_latin_hypercube_2d_draws8(size, rng, bounded);
      }
    }
  }
}

/* clr_zerotwo_generate's points without its shuffles: the scramble draws, then GrayCodeSample
 * of `total` points into scratch rows (dims floats each). Lanes differ only by their scrambles. */
static inline void clr_zerotwo_points8(__global float *buf, int dims, int total,
                                       clr_pcg32x8 *state) {
  clr_pcg32x8 r = *state, *rng = &r; /* in registers, not behind the pointer */
  uint8 v0 = clr_pcg32x8_next(rng);
  uint8 v1 = dims == 2 ? clr_pcg32x8_next(rng) : (uint8)0u;
  *state = r;
  uint c1[32];
  c1[0] = 0x80000000u;
  for (int k = 1; k < 32; ++k) c1[k] = c1[k - 1] ^ (c1[k - 1] >> 1u);
  for (int i = 0; i < total; ++i) {
    int k = clr_ctz32((uint)i + 1u);
    vstore8(convert_float8(v0) * 0x1p-32f, dims * i, buf);
    if (dims == 2) {
      vstore8(convert_float8(v1) * 0x1p-32f, 2 * i + 1, buf);
      v1 ^= c1[k];
    }
    v0 ^= 0x80000000u >> (uint)k;
  }
}

/* clr_zerotwo_streams: VanDerCorput(1, spp) / Sobol2D(1, spp) per stream; the Shuffles of one
 * point inside each sample are one draw each. */
static inline void clr_zerotwo_streams8(const clr_sampler_params *p,
                                        __global const clr_request_slot *slots, int dims, int first,
                                        clr_pcg32x8 *rng, __global float *values, const ulong *out,
                                        __global float *buf, __global const uint4 *bounded) {
  for (int d = first; d < p->dimensions; ++d) {
    if (!clr_slots_use(p, slots, dims, 0, d)) {
      clr_pcg32x8_advance(rng, (ulong)dims + (ulong)p->spp);
      clr_shuffle_draws8(p->spp, rng, bounded);
      continue;
    }
    clr_zerotwo_points8(buf, dims, p->spp, rng);
    clr_pcg32x8_advance(rng, (ulong)p->spp);
    clr_stream_shuffle_store8(p, slots, dims, d, p->spp, rng, values, out, buf, bounded);
  }
}

/* clr_zerotwo_arrays: VanDerCorput(size, spp) / Sobol2D(size, spp) per array. */
static inline void clr_zerotwo_arrays8(const clr_sampler_params *p,
                                       __global const clr_request_slot *slots, int dims,
                                       clr_pcg32x8 *rng, __global float *values, const ulong *out,
                                       __global float *buf, __global const uint4 *bounded) {
  int arrays = clr_slots_array_count(p, slots, dims);
  for (int a = 0; a < arrays; ++a) {
    int size = clr_slots_array_size(p, slots, dims, a), floats = size * dims;
    if (!clr_slots_use(p, slots, dims, 1, a)) {
      clr_pcg32x8_advance(rng, (ulong)dims);
      for (int j = 0; j < p->spp; ++j) clr_shuffle_draws8(size, rng, bounded);
      clr_shuffle_draws8(p->spp, rng, bounded);
      continue;
    }
    clr_zerotwo_points8(buf, dims, size * p->spp, rng);
    for (int j = 0; j < p->spp; ++j)
      clr_shuffle8(buf + (size_t)j * (size_t)floats * CLR_PIXEL_LANES, size, dims, rng, bounded);
    clr_shuffle8(buf, p->spp, floats, rng, bounded);
    for (int k = 0; k < p->request_count; ++k) {
      if (!clr_slot_stores(&slots[k], dims, 1, a)) continue;
      for (int s = 0; s < p->sample_count; ++s) {
        size_t at = (size_t)s * (size_t)p->values_per_sample + (size_t)slots[k].first_value;
        int row = (p->first_sample + s) * floats;
        for (int v = 0; v < floats; ++v)
          clr_store_lanes8(values, out, at + (size_t)v, vload8(row + v, buf));
      }
    }
  }
}

/* clr_maxmin_start_pixel's first 2D stream (the same points in every lane, shuffled per lane);
 * returns the first 2D stream left to the (0,2)-sequence. */
static inline int clr_maxmin_first_stream8(const clr_sampler_params *p,
                                           __global const clr_request_slot *slots, clr_pcg32x8 *rng,
                                           __global float *values, const ulong *out,
                                           __global float *buf, __global const uint4 *bounded) {
  if (p->dimensions < 1) return 0;
  if (!clr_slots_use(p, slots, 2, 0, 0)) {
    clr_shuffle_draws8(p->spp, rng, bounded);
    return 1;
  }
  for (int i = 0; i < p->spp; ++i) {
    vstore8((float8)((float)i * p->inv_spp), 2 * i, buf);
    vstore8((float8)((float)clr_maxmin_generate(p->maxmin_matrix, (uint)i) * 0x1p-32f), 2 * i + 1,
            buf);
  }
  clr_stream_shuffle_store8(p, slots, 2, 0, p->spp, rng, values, out, buf, bounded);
  return 1;
}

/* ZeroTwoSequenceSampler's and MaxMinDistSampler's StartPixel without the fallback values. */
static inline void clr_zerotwo_start_pixel8(const clr_sampler_params *p,
                                            __global const clr_request_slot *slots,
                                            clr_pcg32x8 *rng, __global float *values,
                                            const ulong *out, __global float *buf,
                                            __global const uint4 *bounded) {
  int first2d = p->type == CLR_SAMPLER_TYPE_MAXMINDIST
                    ? clr_maxmin_first_stream8(p, slots, rng, values, out, buf, bounded)
                    : 0;
  clr_zerotwo_streams8(p, slots, 1, 0, rng, values, out, buf, bounded);
  clr_zerotwo_streams8(p, slots, 2, first2d, rng, values, out, buf, bounded);
  clr_zerotwo_arrays8(p, slots, 1, rng, values, out, buf, bounded);
  clr_zerotwo_arrays8(p, slots, 2, rng, values, out, buf, bounded);
}

/* clr_pixel_store_fallbacks: the single values past the streams, drawn in order (their
 * rng_offsets number the fallback_draws_per_sample draws of a sample in slot order). */
static inline void clr_pixel_store_fallbacks8(const clr_sampler_params *p,
                                              __global const clr_request_slot *slots,
                                              clr_pcg32x8 rng, __global float *values,
                                              const ulong *out) {
  if (p->fallback_draws_per_sample == 0) return;
  clr_pcg32x8_advance(&rng, (ulong)p->first_sample * (ulong)p->fallback_draws_per_sample);
  for (int s = 0; s < p->sample_count; ++s) {
    size_t sample = (size_t)s * (size_t)p->values_per_sample;
    for (int k = 0; k < p->request_count; ++k) {
      if (slots[k].array_size != 0 || slots[k].source >= 0) continue;
      if (slots[k].skipped) { /* its draws, not its values */
        clr_pcg32x8_advance(&rng, (ulong)slots[k].dims);
        continue;
      }
      for (int c = 0; c < slots[k].dims; ++c)
        clr_store_lanes8(values, out, sample + (size_t)(slots[k].first_value + c),
                         clr_pcg32x8_float(&rng));
    }
  }
}

/* clr_random_array. */
static inline void clr_random_array8(const clr_sampler_params *p,
                                     __global const clr_request_slot *slots, int dims, int source,
                                     clr_pcg32x8 *rng, __global float *values, const ulong *out) {
  int size = clr_slots_array_size(p, slots, dims, source);
  ulong draws_per_sample = (ulong)size * (ulong)dims;
  for (int k = 0; k < p->request_count; ++k) {
    if (!clr_slot_stores(&slots[k], dims, 1, source)) continue;
    clr_pcg32x8 r = *rng;
    clr_pcg32x8_advance(&r, (ulong)p->first_sample * draws_per_sample);
    for (int s = 0; s < p->sample_count; ++s) {
      size_t at = (size_t)s * (size_t)p->values_per_sample + (size_t)slots[k].first_value;
      for (int v = 0; v < size * dims; ++v)
        clr_store_lanes8(values, out, at + (size_t)v, clr_pcg32x8_float(&r));
    }
  }
  clr_pcg32x8_advance(rng, (ulong)p->spp * draws_per_sample);
}

/* StartPixel of p->type for the 8 lanes, then the fallback values. */
static inline void clr_pixel_sampler_start_pixel8(const clr_sampler_params *p,
                                                  __global const clr_request_slot *slots,
                                                  clr_pcg32x8 *rng, __global float *values,
                                                  const ulong *out, __global float *buf,
                                                  __global const uint4 *bounded) {
  if (p->type == CLR_SAMPLER_TYPE_STRATIFIED) {
    clr_stratified_streams8(p, slots, 1, rng, values, out, buf, bounded);
    clr_stratified_streams8(p, slots, 2, rng, values, out, buf, bounded);
    clr_stratified_arrays8(p, slots, 1, rng, values, out, buf, bounded);
    clr_stratified_arrays8(p, slots, 2, rng, values, out, buf, bounded);
  } else if (p->type == CLR_SAMPLER_TYPE_ZEROTWO || p->type == CLR_SAMPLER_TYPE_MAXMINDIST) {
    clr_zerotwo_start_pixel8(p, slots, rng, values, out, buf, bounded);
  } else {
    for (int dims = 1; dims <= 2; ++dims) {
      int arrays = clr_slots_array_count(p, slots, dims);
      for (int a = 0; a < arrays; ++a) clr_random_array8(p, slots, dims, a, rng, values, out);
    }
  }
  clr_pixel_store_fallbacks8(p, slots, *rng, values, out);
}

#endif
