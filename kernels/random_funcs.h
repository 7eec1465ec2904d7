/* pbrt-v3's RandomSampler::StartPixel, plus the request-slot helpers and the RNG fallback values
 * that every pixel sampler shares (contract: kernels/pixel_sampler_funcs.h). */
#ifndef CLR_RANDOM_FUNCS_H
#define CLR_RANDOM_FUNCS_H

#include "clr_platform.h"
#include "pcg32.h"
#include "sampler_types.h"

/* Whether slot `s` is fed by the 1D/2D (dims) single stream or array (is_array) number `source`. */
CLR_INLINE int clr_slot_is(CLR_GLOBAL const clr_request_slot *s, clr_i32 dims, int is_array,
                           clr_i32 source) {
  return s->dims == dims && (s->array_size > 0) == is_array && s->source == source;
}

/* Whether slot `s` is fed by that stream or array and stores its values (not skipped). */
CLR_INLINE int clr_slot_stores(CLR_GLOBAL const clr_request_slot *s, clr_i32 dims, int is_array,
                               clr_i32 source) {
  return !s->skipped && clr_slot_is(s, dims, is_array, source);
}

/* Whether any slot stores the values of that stream or array. */
CLR_INLINE int clr_slots_use(const clr_sampler_params *p, CLR_GLOBAL const clr_request_slot *slots,
                             clr_i32 dims, int is_array, clr_i32 source) {
  for (clr_i32 k = 0; k < p->request_count; ++k)
    if (clr_slot_stores(&slots[k], dims, is_array, source)) return 1;
  return 0;
}

/* Number of 1D or 2D arrays the pixel sampler generates: one past the largest array source. */
CLR_INLINE clr_i32 clr_slots_array_count(const clr_sampler_params *p,
                                         CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims) {
  clr_i32 count = 0;
  for (clr_i32 k = 0; k < p->request_count; ++k)
    if (slots[k].dims == dims && slots[k].array_size > 0 && slots[k].source >= count)
      count = slots[k].source + 1;
  return count;
}

/* Size of 1D or 2D array number `source` (0 if no slot describes it: a contract violation). */
CLR_INLINE clr_i32 clr_slots_array_size(const clr_sampler_params *p,
                                        CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                        clr_i32 source) {
  for (clr_i32 k = 0; k < p->request_count; ++k)
    if (clr_slot_is(&slots[k], dims, 1, source)) return slots[k].array_size;
  return 0;
}

/* 1 / size of 1D or 2D array number `source`, rounded on the host (0 if no slot describes it);
 * the last slot describing it gives it. */
CLR_INLINE float clr_slots_inv_array_size(const clr_sampler_params *p,
                                          CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                          clr_i32 source) {
  float inv_size = 0.0f;
  for (clr_i32 k = 0; k < p->request_count; ++k)
    if (clr_slot_is(&slots[k], dims, 1, source)) inv_size = slots[k].inv_array_size;
  return inv_size;
}

/* Largest array size over all slots (0 without arrays). */
CLR_INLINE clr_i32 clr_slots_max_array_size(const clr_sampler_params *p,
                                            CLR_GLOBAL const clr_request_slot *slots) {
  clr_i32 m = 0;
  for (clr_i32 k = 0; k < p->request_count; ++k)
    if (slots[k].array_size > m) m = slots[k].array_size;
  return m;
}

/* Single values past the precomputed streams (source -1): each is RNG draw number
 * s * fallback_draws_per_sample + rng_offset (y: + 1) counted from `after_start`, the state right
 * after StartPixel, because pbrt-v3 draws them while rendering sample after sample. */
CLR_INLINE void clr_pixel_store_fallbacks(const clr_sampler_params *p,
                                          CLR_GLOBAL const clr_request_slot *slots,
                                          const clr_pcg32 *after_start,
                                          CLR_GLOBAL float *out_pixel) {
  clr_pcg32 sample_start = *after_start;
  clr_pcg32_advance(&sample_start,
                    (clr_u64)p->first_sample * (clr_u64)p->fallback_draws_per_sample);
  for (clr_i32 s = 0; s < p->sample_count; ++s) {
    CLR_GLOBAL float *out = out_pixel + (clr_i64)s * p->values_per_sample;
    for (clr_i32 k = 0; k < p->request_count; ++k) {
      if (slots[k].array_size != 0 || slots[k].source >= 0 || slots[k].skipped) continue;
      clr_pcg32 r = sample_start;
      clr_pcg32_advance(&r, (clr_u64)slots[k].rng_offset);
      for (clr_i32 c = 0; c < slots[k].dims; ++c)
        out[slots[k].first_value + c] = clr_pcg32_float(&r);
    }
    clr_pcg32_advance(&sample_start, (clr_u64)p->fallback_draws_per_sample);
  }
}

/* RandomSampler arrays: array number `source` holds spp * size elements of `dims` draws each,
 * sample-major; writes the elements of samples [first_sample, first_sample + sample_count) to
 * every slot fed by it and leaves *rng past the whole array. */
CLR_INLINE void clr_random_array(const clr_sampler_params *p,
                                 CLR_GLOBAL const clr_request_slot *slots, clr_i32 dims,
                                 clr_i32 source, clr_pcg32 *rng, CLR_GLOBAL float *out_pixel) {
  clr_i32 size = clr_slots_array_size(p, slots, dims, source);
  clr_u64 draws_per_sample = (clr_u64)size * (clr_u64)dims;
  for (clr_i32 k = 0; out_pixel && k < p->request_count; ++k) {
    if (!clr_slot_stores(&slots[k], dims, 1, source)) continue;
    clr_pcg32 r = *rng;
    clr_pcg32_advance(&r, (clr_u64)p->first_sample * draws_per_sample);
    for (clr_i32 s = 0; s < p->sample_count; ++s) {
      CLR_GLOBAL float *out = out_pixel + (clr_i64)s * p->values_per_sample + slots[k].first_value;
      for (clr_i32 v = 0; v < size * dims; ++v) out[v] = clr_pcg32_float(&r);
    }
  }
  clr_pcg32_advance(rng, (clr_u64)p->spp * draws_per_sample);
}

/* RandomSampler::StartPixel: all 1D arrays, then all 2D arrays (x drawn before y). Single values
 * are all RNG fallbacks. Needs no scratch. */
CLR_INLINE void clr_random_start_pixel(const clr_sampler_params *p,
                                       CLR_GLOBAL const clr_request_slot *slots, clr_pcg32 *rng,
                                       CLR_GLOBAL float *out_pixel, CLR_GLOBAL float *scratch) {
  (void)scratch;
  for (clr_i32 dims = 1; dims <= 2; ++dims) {
    clr_i32 arrays = clr_slots_array_count(p, slots, dims);
    for (clr_i32 a = 0; a < arrays; ++a) clr_random_array(p, slots, dims, a, rng, out_pixel);
  }
  if (out_pixel) clr_pixel_store_fallbacks(p, slots, rng, out_pixel);
}

#endif
