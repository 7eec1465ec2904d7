/* pbrt-v3's ZeroTwoSequenceSampler::StartPixel with its lowdiscrepancy.h helpers (VanDerCorput,
 * Sobol2D, GrayCodeSample, Shuffle), bit-exact in values and RNG consumption (contract:
 * kernels/pixel_sampler_funcs.h). Streams and arrays nobody reads are skipped with the same draws.
 *
 * As in pbrt-v3, GrayCodeSample does not clamp: a scrambled value v >= 2^32 - 128 rounds to
 * exactly 1.0f (probability 2^-25 per value). */
#ifndef CLR_ZEROTWO_FUNCS_H
#define CLR_ZEROTWO_FUNCS_H

#include "clr_platform.h"
#include "pcg32.h"
#include "random_funcs.h"
#include "sampler_types.h"
#include "stratified_funcs.h"

/* CountTrailingZeros(v), v != 0. */
CLR_INLINE clr_i32 clr_ctz32(clr_u32 v) {
  clr_i32 z = 0;
  while (!(v & 1u)) {
    v >>= 1u;
    ++z;
  }
  return z;
}

/* Shuffle draws of pbrt-v3's VanDerCorput/Sobol2D after GrayCodeSample, without the data: one
 * Shuffle of `per` items per pixel sample, then one of the `spp` groups. */
CLR_INLINE void clr_zerotwo_shuffle_draws(clr_i32 per, clr_i32 spp, clr_pcg32 *rng) {
  for (clr_i32 i = 0; i < spp; ++i) clr_shuffle_draws(per, rng);
  clr_shuffle_draws(spp, rng);
}

/* VanDerCorput(per, spp, buf, rng) (dims 1) or Sobol2D(per, spp, buf, rng) (dims 2):
 * scramble draw(s), GrayCodeSample of per * spp points, Shuffle inside each pixel sample's group
 * of `per` points, Shuffle of the spp groups. buf: per * spp * dims floats. */
CLR_INLINE void clr_zerotwo_generate(CLR_GLOBAL float *buf, clr_i32 dims, clr_i32 per, clr_i32 spp,
                                     clr_pcg32 *rng) {
  clr_u32 v0 = clr_pcg32_next(rng);
  clr_u32 v1 = dims == 2 ? clr_pcg32_next(rng) : 0u;
  clr_u32 c1[32];
  c1[0] = 0x80000000u;
  for (clr_i32 k = 1; k < 32; ++k) c1[k] = c1[k - 1] ^ (c1[k - 1] >> 1u);
  clr_u32 total = (clr_u32)per * (clr_u32)spp;
  for (clr_u32 i = 0; i < total; ++i) {
    clr_i32 k = clr_ctz32(i + 1u);
    if (dims == 1) {
      buf[i] = (float)v0 * 0x1p-32f;
    } else {
      buf[2u * i] = (float)v0 * 0x1p-32f;
      buf[2u * i + 1u] = (float)v1 * 0x1p-32f;
      v1 ^= c1[k];
    }
    v0 ^= 0x80000000u >> (clr_u32)k;
  }
  for (clr_i32 i = 0; i < spp; ++i) clr_shuffle(buf + (clr_i64)i * per * dims, per, dims, rng);
  clr_shuffle(buf, spp, per * dims, rng);
}

/* The draws of clr_zerotwo_generate without the points. */
CLR_INLINE void clr_zerotwo_generate_draws(clr_i32 dims, clr_i32 per, clr_i32 spp, clr_pcg32 *rng) {
  clr_pcg32_advance(rng, (clr_u64)dims);
  clr_zerotwo_shuffle_draws(per, spp, rng);
}

/* The single-value streams first..dimensions-1 of one kind: VanDerCorput(1, spp) /
 * Sobol2D(1, spp). */
CLR_INLINE void clr_zerotwo_streams(const clr_sampler_params *p,
                                    CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                    clr_i32 first, clr_pcg32 *rng, CLR_GLOBAL float *out_pixel,
                                    CLR_GLOBAL float *scratch) {
  for (clr_i32 d = first; d < p->dimensions; ++d) {
    if (out_pixel && clr_slots_use(p, slots, dims, 0, d)) {
      clr_zerotwo_generate(scratch, dims, 1, p->spp, rng);
      clr_stratified_store_stream(p, slots, dims, d, scratch, out_pixel);
    } else {
      clr_zerotwo_generate_draws(dims, 1, p->spp, rng);
    }
  }
}

/* The arrays of one kind: VanDerCorput(size, spp) / Sobol2D(size, spp) per array; sample j's
 * elements are buf[j * size * dims ...]. */
CLR_INLINE void clr_zerotwo_arrays(const clr_sampler_params *p,
                                   CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                   clr_pcg32 *rng, CLR_GLOBAL float *out_pixel,
                                   CLR_GLOBAL float *scratch) {
  clr_i32 arrays = clr_slots_array_count(p, slots, dims);
  for (clr_i32 a = 0; a < arrays; ++a) {
    clr_i32 size = clr_slots_array_size(p, slots, dims, a);
    if (out_pixel && clr_slots_use(p, slots, dims, 1, a)) {
      clr_zerotwo_generate(scratch, dims, size, p->spp, rng);
      for (clr_i32 s = 0; s < p->sample_count; ++s)
        clr_stratified_store_array(p, slots, dims, a, size,
                                   scratch + (clr_i64)(p->first_sample + s) * size * dims,
                                   out_pixel + (clr_i64)s * p->values_per_sample);
    } else {
      clr_zerotwo_generate_draws(dims, size, p->spp, rng);
    }
  }
}

/* ZeroTwoSequenceSampler::StartPixel: 1D streams, 2D streams, 1D arrays, 2D arrays, then the RNG
 * fallback values. scratch: 2 * spp * max(1, largest array size) floats. */
CLR_INLINE void clr_zerotwo_start_pixel(const clr_sampler_params *p,
                                        CLR_GLOBAL const clr_request_slot *slots, clr_pcg32 *rng,
                                        CLR_GLOBAL float *out_pixel, CLR_GLOBAL float *scratch) {
  clr_zerotwo_streams(p, slots, 1, 0, rng, out_pixel, scratch);
  clr_zerotwo_streams(p, slots, 2, 0, rng, out_pixel, scratch);
  clr_zerotwo_arrays(p, slots, 1, rng, out_pixel, scratch);
  clr_zerotwo_arrays(p, slots, 2, rng, out_pixel, scratch);
  if (out_pixel) clr_pixel_store_fallbacks(p, slots, rng, out_pixel);
}

#endif
