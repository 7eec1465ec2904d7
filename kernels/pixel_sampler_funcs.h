/* Drivers of pbrt-v3's pixel samplers (stratified, random, (0,2)-sequence, maxmindist): RNG seeding per render tile or per
 * pixel, and the sample values of a batch of pixels.
 *
 * CONTRACT between the host (fills clr_sampler_params p and clr_request_slot slots[]) and these
 * functions:
 *
 * Params:
 *   type        CLR_SAMPLER_TYPE_STRATIFIED, CLR_SAMPLER_TYPE_RANDOM, CLR_SAMPLER_TYPE_ZEROTWO or
 *               CLR_SAMPLER_TYPE_MAXMINDIST (maxmin_matrix: its generator matrix).
 *   spp         samples per pixel; stratified: x_samples * y_samples; zerotwo, maxmindist: a
 *               power of two.
 *   x_samples, y_samples, jitter, dimensions: stratified only (pbrt's xsamples, ysamples, jitter,
 *               dimensions); dimensions = number of 1D streams = number of 2D streams (also zerotwo, maxmindist).
 *   inv_x_samples, inv_y_samples, inv_spp: 1.0f / n rounded to float on the host.
 *   seeding     CLR_SEEDING_TYPE_PBRT_V3 (clr_pixel_sampler_tile) or CLR_SEEDING_TYPE_PIXEL
 *               (clr_pixel_sampler_pixel). seed: used only by the per-pixel seeding; in pbrt-v3
 *               mode the stream is SetSequence(tile index), as pbrt-v3's Clone(tileIndex) does.
 *   tiles_x     ceil((sample_x1 - sample_x0) / 16); sample_* the film's sample bounds, pixel_* its
 *               (cropped) pixel bounds, both half-open.
 *   batch_x0, batch_y0, batch_width, batch_height: the rect of pixels whose values are written.
 *   first_sample, sample_count: the samples [first_sample, first_sample + sample_count) of each
 *               pixel that are written (0 <= first_sample, first_sample + sample_count <= spp).
 *   values_per_sample: floats per sample vector; request_count: number of slots.
 *   fallback_draws_per_sample: RNG draws pbrt-v3 makes while rendering one sample, i.e. the sum
 *               of dims over the single-value slots whose source is -1.
 *   scratch_floats: floats of scratch per work-item, at least clr_pixel_sampler_scratch_need():
 *               stratified 2 * max(spp, largest array size), zerotwo and maxmindist 2 * spp * max(1, largest
 *               array size), random 0.
 *
 * Slots (in any order), one per request of the sample vector:
 *   dims 1 or 2; first_value: offset of its first float in a sample vector.
 *   array_size 0 (a single value, pbrt's Get1D/Get2D):
 *     source = k >= 0: the value of the k-th 1D stream (dims 1) or the k-th 2D stream (dims 2),
 *       k < dimensions (stratified, zerotwo, maxmindist: PixelSampler's current1DDimension/current2DDimension);
 *     source = -1: an RNG draw (the others past `dimensions`; random: always). rng_offset is the
 *       index of its draw among the fallback_draws_per_sample draws of one sample, in pbrt-v3's
 *       call order; a 2D value takes draws rng_offset (x) and rng_offset + 1 (y). pbrt-v3 writes
 *       Point2f(rng.UniformFloat(), rng.UniformFloat()), whose argument order C++ leaves
 *       unspecified; we define it left to right (x first), as RandomSampler's braced {x, y}.
 *   array_size n >= 1 (pbrt's Get1DArray/Get2DArray): source = index among the 1D arrays (dims 1)
 *     or among the 2D arrays (dims 2), in request order: the arrays of each kind are numbered
 *     0.. without gaps, and generated in that order. inv_array_size = 1.0f / n from the host.
 *     Element j's values lie at first_value + j * dims + c.
 *   skipped 1 (CLR_SAMPLE_REQUEST_SKIPPED): the slot feeds its stream, array or RNG draws as any
 *     other (source, rng_offset, array_size count as above), but nothing is stored for it.
 *
 * Output: sample s (first_sample <= s < first_sample + sample_count) of a pixel lies at
 *   out_pixel[(s - first_sample) * values_per_sample + ...]; per batch, the pixel (px, py) starts at
 *   out_batch[((py - batch_y0) * batch_width + (px - batch_x0)) * sample_count * values_per_sample].
 *   Floats of a sample vector that no slot covers are left untouched. Values lie in [0, 1).
 *
 * RNG order per pixel (pbrt-v3): StartPixel draws (see stratified_funcs.h / random_funcs.h), then,
 * for a pixel inside the pixel bounds, spp * fallback_draws_per_sample draws, sample after sample.
 */
#ifndef CLR_PIXEL_SAMPLER_FUNCS_H
#define CLR_PIXEL_SAMPLER_FUNCS_H

#include "clr_platform.h"
#include "pcg32.h"
#include "random_funcs.h"
#include "sampler_types.h"
#include "stratified_funcs.h"
#include "zerotwo_funcs.h"
#include "maxmin_funcs.h"

/* Scratch floats one work-item needs (see the contract). */
CLR_INLINE clr_i32 clr_pixel_sampler_scratch_need(const clr_sampler_params *p,
                                                  CLR_GLOBAL const clr_request_slot *slots) {
  clr_i32 n = clr_slots_max_array_size(p, slots);
  if (p->type == CLR_SAMPLER_TYPE_ZEROTWO || p->type == CLR_SAMPLER_TYPE_MAXMINDIST)
    return 2 * p->spp * (n > 1 ? n : 1);
  if (p->type != CLR_SAMPLER_TYPE_STRATIFIED) return 0;
  return 2 * (p->spp > n ? p->spp : n);
}

/* StartPixel of the sampler p->type; writes the pixel's values when out_pixel is non-null. */
CLR_INLINE void clr_pixel_sampler_start_pixel(const clr_sampler_params *p,
                                              CLR_GLOBAL const clr_request_slot *slots,
                                              clr_pcg32 *rng, CLR_GLOBAL float *out_pixel,
                                              CLR_GLOBAL float *scratch) {
  if (p->type == CLR_SAMPLER_TYPE_STRATIFIED)
    clr_stratified_start_pixel(p, slots, rng, out_pixel, scratch);
  else if (p->type == CLR_SAMPLER_TYPE_ZEROTWO)
    clr_zerotwo_start_pixel(p, slots, rng, out_pixel, scratch);
  else if (p->type == CLR_SAMPLER_TYPE_MAXMINDIST)
    clr_maxmin_start_pixel(p, slots, rng, out_pixel, scratch);
  else
    clr_random_start_pixel(p, slots, rng, out_pixel, scratch);
}

/* CLR_SEEDING_TYPE_PIXEL: the pixel's own PCG32 stream, from a hash of (px, py, seed); it does
 * not depend on tiles or batches. */
CLR_INLINE clr_pcg32 clr_pixel_stream(const clr_sampler_params *p, clr_i32 px, clr_i32 py) {
  clr_u64 position = ((clr_u64)(clr_u32)py << 32u) | (clr_u64)(clr_u32)px;
  return clr_pcg32_sequence(clr_mix64(clr_mix64(position) ^ (clr_u64)p->seed));
}

/* CLR_SEEDING_TYPE_PIXEL: the values of pixel (px, py) into out_pixel. */
CLR_INLINE void clr_pixel_sampler_pixel(const clr_sampler_params *p,
                                        CLR_GLOBAL const clr_request_slot *slots, clr_i32 px,
                                        clr_i32 py, CLR_GLOBAL float *out_pixel,
                                        CLR_GLOBAL float *scratch) {
  clr_pcg32 rng = clr_pixel_stream(p, px, py);
  clr_pixel_sampler_start_pixel(p, slots, &rng, out_pixel, scratch);
}

CLR_INLINE int clr_inside(clr_i32 x, clr_i32 y, clr_i32 x0, clr_i32 y0, clr_i32 x1, clr_i32 y1) {
  return x >= x0 && x < x1 && y >= y0 && y < y1;
}

/* CLR_SEEDING_TYPE_PBRT_V3: replays pbrt-v3's SamplerIntegrator::Render over 16x16 tile
 * (tile_x, tile_y) of the sample bounds: SetSequence(tile_y * tiles_x + tile_x), pixels row-major,
 * StartPixel for each, then the rendering draws of pixels inside the pixel bounds. Writes the
 * tile's pixels that lie in the batch rect and stops after the last of them. */
CLR_INLINE void clr_pixel_sampler_tile(const clr_sampler_params *p,
                                       CLR_GLOBAL const clr_request_slot *slots, clr_i32 tile_x,
                                       clr_i32 tile_y, CLR_GLOBAL float *out_batch,
                                       CLR_GLOBAL float *scratch) {
  clr_i32 x0 = p->sample_x0 + tile_x * CLR_PBRT_TILE_SIZE;
  clr_i32 y0 = p->sample_y0 + tile_y * CLR_PBRT_TILE_SIZE;
  clr_i32 x1 = x0 + CLR_PBRT_TILE_SIZE < p->sample_x1 ? x0 + CLR_PBRT_TILE_SIZE : p->sample_x1;
  clr_i32 y1 = y0 + CLR_PBRT_TILE_SIZE < p->sample_y1 ? y0 + CLR_PBRT_TILE_SIZE : p->sample_y1;
  clr_i32 bx1 = p->batch_x0 + p->batch_width, by1 = p->batch_y0 + p->batch_height;
  /* The tile's part of the batch rect; nothing to do when it is empty. */
  clr_i32 wx0 = x0 > p->batch_x0 ? x0 : p->batch_x0, wy0 = y0 > p->batch_y0 ? y0 : p->batch_y0;
  clr_i32 wx1 = x1 < bx1 ? x1 : bx1, wy1 = y1 < by1 ? y1 : by1;
  if (wx0 >= wx1 || wy0 >= wy1) return;
  clr_pcg32 rng = clr_pcg32_sequence((clr_u64)(tile_y * p->tiles_x + tile_x));
  clr_u64 render_draws = (clr_u64)p->spp * (clr_u64)p->fallback_draws_per_sample;
  clr_i64 pixel_floats = (clr_i64)p->sample_count * p->values_per_sample;
  for (clr_i32 py = y0; py < wy1; ++py)
    for (clr_i32 px = x0; px < x1; ++px) {
      CLR_GLOBAL float *out = 0;
      if (clr_inside(px, py, wx0, wy0, wx1, wy1))
        out = out_batch +
              ((clr_i64)(py - p->batch_y0) * p->batch_width + (px - p->batch_x0)) * pixel_floats;
      clr_pixel_sampler_start_pixel(p, slots, &rng, out, scratch);
      if (py == wy1 - 1 && px == wx1 - 1) return;
      if (clr_inside(px, py, p->pixel_x0, p->pixel_y0, p->pixel_x1, p->pixel_y1))
        clr_pcg32_advance(&rng, render_draws);
    }
}

#endif
