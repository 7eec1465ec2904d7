/* pbrt-v3's SobolSampler math, bit for bit: (pixel, sample number) -> global Sobol index
 * (SobolIntervalToIndex), unscrambled SobolSampleFloat, and SampleDimension's remap of the
 * first two dimensions into the pixel. Tables: host/lib/sobol_tables.h.
 *
 * Differences from pbrt-v3, all outside its valid inputs:
 *  - log2 resolution m == 0 (1x1 sample bounds): the index is the sample number (pbrt-v3
 *    returns 0 for every sample, a bug fixed in pbrt-v4).
 *  - dimension >= CLR_SOBOL_DIMENSIONS (or < 0): pbrt-v3 aborts; this returns
 *    clr_hash_float(clr_mix64(index) ^ dim), uniform in [0,1), different per dimension.
 *  - only index bits 0..51 exist (52 matrix columns): a pixel holds at most
 *    clr_sobol_max_samples(m) = 2^(52-2m) samples; higher sample-number bits and pixel
 *    coordinates outside [0, 2^m) are masked off instead of reading past the tables. */
#ifndef CLR_SOBOL_FUNCS_H
#define CLR_SOBOL_FUNCS_H

#include "clr_platform.h"
#include "pcg32.h"
#include "sampler_types.h"

/* Largest log2 resolution the VdC tables cover: pbrt-v3 ships VdCSobolMatricesInv for m = 1 .. 26
 * and VdCSobolMatrices for m = 1 .. 25 (at m = 26 a pixel holds one sample, so its row is 0). */
#define CLR_SOBOL_MAX_LOG2_RESOLUTION 26
/* Index bits the generator matrices cover. */
#define CLR_SOBOL_INDEX_BITS 52

/* Position of the lowest set bit of x != 0 (OpenCL 1.2 has clz but no ctz). */
CLR_INLINE clr_u32 clr_sobol_ctz32(clr_u32 x) { return 31u - clr_clz32(x & (0u - x)); }

/* XOR of cols[c] over the set bits c of `bits`. */
CLR_INLINE clr_u32 clr_sobol_xor_columns32(clr_u32 bits, CLR_GLOBAL const clr_u32 *cols) {
  clr_u32 v = 0u;
  for (; bits != 0u; bits &= bits - 1u) v ^= cols[clr_sobol_ctz32(bits)];
  return v;
}

CLR_INLINE clr_u64 clr_sobol_xor_columns64(clr_u64 bits, CLR_GLOBAL const clr_u64 *cols) {
  clr_u64 v = 0u;
  for (clr_u32 lo = (clr_u32)bits; lo != 0u; lo &= lo - 1u) v ^= cols[clr_sobol_ctz32(lo)];
  for (clr_u32 hi = (clr_u32)(bits >> 32); hi != 0u; hi &= hi - 1u)
    v ^= cols[32u + clr_sobol_ctz32(hi)];
  return v;
}

/* SobolIntervalToIndex: global index of the `frame`-th sample of pixel (px, py) (relative to the
 * sample bounds' pMin) at resolution 2^m. vdc / vdc_inv: the flattened [26][52] tables. */
CLR_INLINE clr_u64 clr_sobol_interval_to_index(clr_u32 m, clr_u64 frame, clr_i32 px, clr_i32 py,
                                               CLR_GLOBAL const clr_u64 *vdc,
                                               CLR_GLOBAL const clr_u64 *vdc_inv) {
  if (m == 0u) return frame;
  if (m > CLR_SOBOL_MAX_LOG2_RESOLUTION) m = CLR_SOBOL_MAX_LOG2_RESOLUTION; /* host rejects */
  clr_u32 m2 = m << 1;
  clr_u32 row = (m - 1u) * CLR_SOBOL_MATRIX_SIZE;
  clr_u64 index = frame << m2;
  /* Pixel bits the frame's index bits 2m.. would move the point by. */
  clr_u64 frame_bits = frame & ((((clr_u64)1) << (CLR_SOBOL_INDEX_BITS - m2)) - 1u);
  clr_u64 delta = clr_sobol_xor_columns64(frame_bits, vdc + row);
  clr_u64 pixel_mask = (((clr_u64)1) << m) - 1u;
  clr_u64 b =
      ((((clr_u64)(clr_u32)px & pixel_mask) << m) | ((clr_u64)(clr_u32)py & pixel_mask)) ^ delta;
  /* Low 2m index bits that move the point into the pixel. */
  return index ^ clr_sobol_xor_columns64(b, vdc_inv + row);
}

/* Value past the tables: a hash of (index, dim), uniform in [0,1). */
CLR_INLINE float clr_sobol_fallback_float(clr_u64 index, clr_i32 dim) {
  return clr_hash_float(clr_mix64(index) ^ (clr_u64)(clr_u32)dim);
}

/* SobolSampleFloat(index, dim) with no scramble: min(v * 2^-32, OneMinusEpsilon), v = XOR of
 * dimension dim's matrix columns over the set bits of index. */
CLR_INLINE float clr_sobol_sample_float(clr_u64 index, clr_i32 dim,
                                        CLR_GLOBAL const clr_u32 *matrices32) {
  if ((clr_u32)dim >= CLR_SOBOL_DIMENSIONS) return clr_sobol_fallback_float(index, dim);
  CLR_GLOBAL const clr_u32 *cols = matrices32 + (clr_u32)dim * CLR_SOBOL_MATRIX_SIZE;
  clr_u32 high = (clr_u32)(index >> 32) & ((1u << (CLR_SOBOL_INDEX_BITS - 32)) - 1u);
  clr_u32 v =
      clr_sobol_xor_columns32((clr_u32)index, cols) ^ clr_sobol_xor_columns32(high, cols + 32);
  float f = (float)v * 0x1p-32f;
  return f < CLR_ONE_MINUS_EPSILON ? f : CLR_ONE_MINUS_EPSILON;
}

/* SobolSampler::GetIndexForSample for absolute pixel (px, py): once per sample. */
CLR_INLINE clr_u64 clr_sobol_sampler_index(const clr_sampler_params *p,
                                           CLR_GLOBAL const clr_u64 *vdc,
                                           CLR_GLOBAL const clr_u64 *vdc_inv, clr_i32 px,
                                           clr_i32 py, clr_i64 sample_number) {
  return clr_sobol_interval_to_index((clr_u32)p->sobol_log2_resolution, (clr_u64)sample_number,
                                     px - p->sample_x0, py - p->sample_y0, vdc, vdc_inv);
}

/* SobolSampler::SampleDimension: dimensions 0 and 1 become the offset inside pixel (px, py). */
CLR_INLINE float clr_sobol_sampler_value(const clr_sampler_params *p,
                                         CLR_GLOBAL const clr_u32 *matrices32, clr_u64 index,
                                         clr_i32 dim, clr_i32 px, clr_i32 py) {
  float s = clr_sobol_sample_float(index, dim, matrices32);
  if (dim == 0 || dim == 1) {
    float pmin = (float)(dim == 0 ? p->sample_x0 : p->sample_y0);
    float pixel = (float)(dim == 0 ? px : py);
    s = s * p->sobol_resolution + pmin;
    s = s - pixel;
    s = s < 0.0f ? 0.0f : (s > CLR_ONE_MINUS_EPSILON ? CLR_ONE_MINUS_EPSILON : s);
  }
  return s;
}

#ifndef __OPENCL_C_VERSION__
/* Host: SobolSampler's resolution = RoundUpPow2(max(width, height)) of the sample bounds and its
 * log2. Empty bounds count as 1x1. The caller must reject sobol_log2_resolution >
 * CLR_SOBOL_MAX_LOG2_RESOLUTION (bounds wider than 2^26) and more than
 * clr_sobol_max_samples(sobol_log2_resolution) samples per pixel. */
static inline void clr_sobol_setup(clr_sampler_params *p) {
  int64_t w = (int64_t)p->sample_x1 - p->sample_x0, h = (int64_t)p->sample_y1 - p->sample_y0;
  int64_t extent = w > h ? w : h;
  uint64_t resolution = 1u;
  int log2_resolution = 0;
  while ((int64_t)resolution < extent) {
    resolution <<= 1;
    ++log2_resolution;
  }
  p->sobol_log2_resolution = log2_resolution;
  p->sobol_resolution = (float)resolution;
}

/* Samples a pixel can hold at log2 resolution m: index = sample << 2m must stay below 2^52
 * (0 past CLR_SOBOL_MAX_LOG2_RESOLUTION). */
static inline int64_t clr_sobol_max_samples(int32_t log2_resolution) {
  if (log2_resolution < 0 || log2_resolution > CLR_SOBOL_MAX_LOG2_RESOLUTION) return 0;
  return (int64_t)1 << (CLR_SOBOL_INDEX_BITS - 2 * log2_resolution);
}
#endif

#endif
