/* pbrt-v3's StratifiedSampler::StartPixel with its sampling.cpp helpers (StratifiedSample1D/2D,
 * Shuffle, LatinHypercube), bit-exact in values and RNG consumption (contract:
 * kernels/pixel_sampler_funcs.h). Streams nobody reads are skipped with the same draws. */
#ifndef CLR_STRATIFIED_FUNCS_H
#define CLR_STRATIFIED_FUNCS_H

#include "clr_platform.h"
#include "pcg32.h"
#include "random_funcs.h"
#include "sampler_types.h"

CLR_INLINE float clr_below_one(float v) {
  return v < CLR_ONE_MINUS_EPSILON ? v : CLR_ONE_MINUS_EPSILON;
}

/* StratifiedSample1D: buf[i] = min((i + delta) * inv_n, 1-eps), delta a draw or 0.5. */
CLR_INLINE void clr_stratified_sample_1d(CLR_GLOBAL float *buf, clr_i32 n, float inv_n,
                                         clr_i32 jitter, clr_pcg32 *rng) {
  for (clr_i32 i = 0; i < n; ++i) {
    float delta = jitter ? clr_pcg32_float(rng) : 0.5f;
    buf[i] = clr_below_one(((float)i + delta) * inv_n);
  }
}

/* StratifiedSample2D: cell (x, y) at buf[2 * (y * nx + x)], y outer, jx drawn before jy. */
CLR_INLINE void clr_stratified_sample_2d(CLR_GLOBAL float *buf, clr_i32 nx, clr_i32 ny,
                                         float inv_nx, float inv_ny, clr_i32 jitter,
                                         clr_pcg32 *rng) {
  for (clr_i32 y = 0; y < ny; ++y)
    for (clr_i32 x = 0; x < nx; ++x) {
      float jx = jitter ? clr_pcg32_float(rng) : 0.5f;
      float jy = jitter ? clr_pcg32_float(rng) : 0.5f;
      clr_i32 i = 2 * (y * nx + x);
      buf[i] = clr_below_one(((float)x + jx) * inv_nx);
      buf[i + 1] = clr_below_one(((float)y + jy) * inv_ny);
    }
}

/* Shuffle of `count` items of `dims` floats: item i swaps with i + UniformUInt32(count - i). */
CLR_INLINE void clr_shuffle(CLR_GLOBAL float *buf, clr_i32 count, clr_i32 dims, clr_pcg32 *rng) {
  for (clr_i32 i = 0; i < count; ++i) {
    clr_i32 other = i + (clr_i32)clr_pcg32_bounded(rng, (clr_u32)(count - i));
    for (clr_i32 c = 0; c < dims; ++c) {
      float t = buf[dims * i + c];
      buf[dims * i + c] = buf[dims * other + c];
      buf[dims * other + c] = t;
    }
  }
}

/* The draws of a Shuffle of `count` items, without the items (rejection makes them data-dependent). */
CLR_INLINE void clr_shuffle_draws(clr_i32 count, clr_pcg32 *rng) {
  for (clr_i32 i = 0; i < count; ++i) clr_pcg32_bounded(rng, (clr_u32)(count - i));
}

/* LatinHypercube(n, 2): point i = ((i + u) * inv_n, (i + u') * inv_n), then each coordinate
 * permuted separately (x first). */
CLR_INLINE void clr_latin_hypercube_2d(CLR_GLOBAL float *buf, clr_i32 n, float inv_n,
                                       clr_pcg32 *rng) {
  for (clr_i32 i = 0; i < 2 * n; ++i)
    buf[i] = clr_below_one(((float)(i >> 1) + clr_pcg32_float(rng)) * inv_n);
  for (clr_i32 c = 0; c < 2; ++c)
    for (clr_i32 j = 0; j < n; ++j) {
      clr_i32 other = j + (clr_i32)clr_pcg32_bounded(rng, (clr_u32)(n - j));
      float t = buf[2 * j + c];
      buf[2 * j + c] = buf[2 * other + c];
      buf[2 * other + c] = t;
    }
}

/* The draws of LatinHypercube(n, 2) without the points. */
CLR_INLINE void clr_latin_hypercube_2d_draws(clr_i32 n, clr_pcg32 *rng) {
  clr_pcg32_advance(rng, 2u * (clr_u64)n);
  clr_shuffle_draws(n, rng);
  clr_shuffle_draws(n, rng);
}

/* Copies a single-value stream (buf[s * dims + c] for every sample s) to the slots it feeds. */
CLR_INLINE void clr_stratified_store_stream(const clr_sampler_params *p,
                                            CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                            clr_i32 source, CLR_GLOBAL const float *buf,
                                            CLR_GLOBAL float *out_pixel) {
  for (clr_i32 k = 0; k < p->request_count; ++k) {
    if (!clr_slot_stores(&slots[k], dims, 0, source)) continue;
    for (clr_i32 s = 0; s < p->sample_count; ++s)
      for (clr_i32 c = 0; c < dims; ++c)
        out_pixel[(clr_i64)s * p->values_per_sample + slots[k].first_value + c] =
            buf[(p->first_sample + s) * dims + c];
  }
}

/* Copies one sample's array (buf: size elements of dims floats) to the slots it feeds. */
CLR_INLINE void clr_stratified_store_array(const clr_sampler_params *p,
                                           CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                           clr_i32 source, clr_i32 size,
                                           CLR_GLOBAL const float *buf,
                                           CLR_GLOBAL float *out_sample) {
  for (clr_i32 k = 0; k < p->request_count; ++k) {
    if (!clr_slot_stores(&slots[k], dims, 1, source)) continue;
    for (clr_i32 v = 0; v < size * dims; ++v) out_sample[slots[k].first_value + v] = buf[v];
  }
}

/* The `dimensions` single-value streams of one kind (1D: StratifiedSample1D over spp strata;
 * 2D: StratifiedSample2D over x_samples x y_samples), each followed by a Shuffle of its points. */
CLR_INLINE void clr_stratified_streams(const clr_sampler_params *p,
                                       CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                       clr_pcg32 *rng, CLR_GLOBAL float *out_pixel,
                                       CLR_GLOBAL float *scratch) {
  clr_i32 n = p->x_samples * p->y_samples;
  for (clr_i32 d = 0; d < p->dimensions; ++d) {
    if (out_pixel && clr_slots_use(p, slots, dims, 0, d)) {
      if (dims == 1)
        clr_stratified_sample_1d(scratch, n, p->inv_spp, p->jitter, rng);
      else
        clr_stratified_sample_2d(scratch, p->x_samples, p->y_samples, p->inv_x_samples,
                                 p->inv_y_samples, p->jitter, rng);
      clr_shuffle(scratch, n, dims, rng);
      clr_stratified_store_stream(p, slots, dims, d, scratch, out_pixel);
    } else {
      if (p->jitter) clr_pcg32_advance(rng, (clr_u64)n * (clr_u64)dims);
      clr_shuffle_draws(n, rng);
    }
  }
}

/* The arrays of one kind: per array, per sample j in [0, spp), 1D: StratifiedSample1D + Shuffle
 * of `size` values; 2D: LatinHypercube(size, 2). */
CLR_INLINE void clr_stratified_arrays(const clr_sampler_params *p,
                                      CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                      clr_pcg32 *rng, CLR_GLOBAL float *out_pixel,
                                      CLR_GLOBAL float *scratch) {
  clr_i32 arrays = clr_slots_array_count(p, slots, dims);
  for (clr_i32 a = 0; a < arrays; ++a) {
    clr_i32 size = clr_slots_array_size(p, slots, dims, a);
    float inv_size = clr_slots_inv_array_size(p, slots, dims, a);
    int used = out_pixel && clr_slots_use(p, slots, dims, 1, a);
    for (clr_i32 j = 0; j < p->spp; ++j) {
      clr_i32 s = j - p->first_sample;
      if (used && s >= 0 && s < p->sample_count) {
        if (dims == 1) {
          clr_stratified_sample_1d(scratch, size, inv_size, p->jitter, rng);
          clr_shuffle(scratch, size, 1, rng);
        } else {
          clr_latin_hypercube_2d(scratch, size, inv_size, rng);
        }
        clr_stratified_store_array(p, slots, dims, a, size, scratch,
                                   out_pixel + (clr_i64)s * p->values_per_sample);
      } else if (dims == 1) {
        if (p->jitter) clr_pcg32_advance(rng, (clr_u64)size);
        clr_shuffle_draws(size, rng);
      } else {
        clr_latin_hypercube_2d_draws(size, rng);
      }
    }
  }
}

/* StratifiedSampler::StartPixel: 1D streams, 2D streams, 1D arrays, 2D arrays, then the RNG
 * fallback values. scratch: 2 * max(spp, largest array size) floats. */
CLR_INLINE void clr_stratified_start_pixel(const clr_sampler_params *p,
                                           CLR_GLOBAL const clr_request_slot *slots, clr_pcg32 *rng,
                                           CLR_GLOBAL float *out_pixel, CLR_GLOBAL float *scratch) {
  clr_stratified_streams(p, slots, 1, rng, out_pixel, scratch);
  clr_stratified_streams(p, slots, 2, rng, out_pixel, scratch);
  clr_stratified_arrays(p, slots, 1, rng, out_pixel, scratch);
  clr_stratified_arrays(p, slots, 2, rng, out_pixel, scratch);
  if (out_pixel) clr_pixel_store_fallbacks(p, slots, rng, out_pixel);
}

#endif
