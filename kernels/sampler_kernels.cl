/* Sample-vector generation kernels for every sampler family; the same per-item functions run
 * on the host as the reference. */
#include "sampler_types.h"
#include "global_sampler_funcs.h"
#include "pixel_sampler_funcs.h"

/* One work-item per (pixel, sample) of the batch: halton, sobol. */
__kernel void clr_generate_global(__global const clr_sampler_params *params,
                                  __global const clr_request_slot *slots,
                                  __global const uint *sobol32, __global const ulong *vdc,
                                  __global const ulong *vdc_inv,
                                  __global const clr_halton_prime *primes,
                                  __global const ushort *perms, __global float *values,
                                  __global ulong *indices, int item_count) {
  int item = (int)get_global_id(0);
  if (item >= item_count) return;
  clr_sampler_params p = *params;
  clr_global_sample_vector(&p, slots, sobol32, vdc, vdc_inv, primes, perms, item,
                           values + (size_t)item * (size_t)p.values_per_sample, indices + item);
}

/* One work-item per pixel of the batch, each with its own RNG stream: random, stratified. */
__kernel void clr_generate_pixel(__global const clr_sampler_params *params,
                                 __global const clr_request_slot *slots, __global float *values,
                                 __global float *scratch, int pixel_count) {
  int pixel = (int)get_global_id(0);
  if (pixel >= pixel_count) return;
  clr_sampler_params p = *params;
  int px = p.batch_x0 + pixel % p.batch_width;
  int py = p.batch_y0 + pixel / p.batch_width;
  size_t per_pixel = (size_t)p.sample_count * (size_t)p.values_per_sample;
  clr_pixel_sampler_pixel(&p, slots, px, py, values + (size_t)pixel * per_pixel,
                          scratch + (size_t)pixel * (size_t)p.scratch_floats);
}

/* One work-item per pbrt-v3 16x16 tile touching the batch (pbrt-v3 seeding). */
__kernel void clr_generate_tiles(__global const clr_sampler_params *params,
                                 __global const clr_request_slot *slots, __global float *values,
                                 __global float *scratch, int tile_x0, int tile_y0,
                                 int tiles_wide, int tile_count) {
  int t = (int)get_global_id(0);
  if (t >= tile_count) return;
  clr_sampler_params p = *params;
  clr_pixel_sampler_tile(&p, slots, tile_x0 + t % tiles_wide, tile_y0 + t / tiles_wide, values,
                         scratch + (size_t)t * (size_t)p.scratch_floats);
}
