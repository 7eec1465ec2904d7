/* pbrt-v3's GlobalSampler (halton, sobol) for one sample vector: each value is the sampler's
 * SampleDimension at the global index of the pixel's sample (arrays: of sample s*n + j). */
#ifndef CLR_GLOBAL_SAMPLER_FUNCS_H
#define CLR_GLOBAL_SAMPLER_FUNCS_H

#include "sampler_types.h"
#include "sobol_funcs.h"
#include "halton_funcs.h"

CLR_INLINE clr_u64 clr_global_index(const clr_sampler_params *p, CLR_GLOBAL const clr_u64 *vdc,
                                    CLR_GLOBAL const clr_u64 *vdc_inv, clr_i32 px, clr_i32 py,
                                    clr_i64 sample_number) {
  if (p->type == CLR_SAMPLER_TYPE_SOBOL)
    return clr_sobol_sampler_index(p, vdc, vdc_inv, px, py, sample_number);
  return clr_halton_sampler_index(p, px, py, sample_number);
}

CLR_INLINE float clr_global_value(const clr_sampler_params *p, CLR_GLOBAL const clr_u32 *sobol32,
                                  CLR_GLOBAL const clr_halton_prime *primes,
                                  CLR_GLOBAL const clr_u16 *perms, clr_u64 index, clr_i32 dim,
                                  clr_i32 px, clr_i32 py) {
  if (p->type == CLR_SAMPLER_TYPE_SOBOL)
    return clr_sobol_sampler_value(p, sobol32, index, dim, px, py);
  return clr_halton_sampler_value(p, primes, perms, index, dim);
}

/* Writes the sample vector of batch item `item` (pixel-major, then sample) to `out` and its
 * global index to *index_out. Skipped slots are not computed (their dimensions are in `source`). */
CLR_INLINE void clr_global_sample_vector(
    const clr_sampler_params *p, CLR_GLOBAL const clr_request_slot *slots,
    CLR_GLOBAL const clr_u32 *sobol32, CLR_GLOBAL const clr_u64 *vdc,
    CLR_GLOBAL const clr_u64 *vdc_inv, CLR_GLOBAL const clr_halton_prime *primes,
    CLR_GLOBAL const clr_u16 *perms, clr_i32 item, CLR_GLOBAL float *out, clr_u64 *index_out) {
  clr_i32 pixel = item / p->sample_count;
  clr_i32 s = p->first_sample + (item - pixel * p->sample_count);
  clr_i32 px = p->batch_x0 + pixel % p->batch_width;
  clr_i32 py = p->batch_y0 + pixel / p->batch_width;
  clr_u64 index = clr_global_index(p, vdc, vdc_inv, px, py, (clr_i64)s);
  *index_out = index;
  for (clr_i32 r = 0; r < p->request_count; ++r) {
    clr_request_slot slot = slots[r];
    if (slot.skipped) continue;
    if (slot.array_size == 0) {
      for (clr_i32 c = 0; c < slot.dims; ++c)
        out[slot.first_value + c] =
            clr_global_value(p, sobol32, primes, perms, index, slot.source + c, px, py);
      continue;
    }
    for (clr_i32 j = 0; j < slot.array_size; ++j) {
      clr_i64 n = (clr_i64)s * slot.array_size + j;
      clr_u64 element_index = clr_global_index(p, vdc, vdc_inv, px, py, n);
      for (clr_i32 c = 0; c < slot.dims; ++c)
        out[slot.first_value + j * slot.dims + c] =
            clr_global_value(p, sobol32, primes, perms, element_index, slot.source + c, px, py);
    }
  }
}

/* ---- Device layout (kernels/global_sampler_simd.h): the values of a sample vector are made in
 * the order of a plan built on the host, grouped by index slot: slot 0 is the item's own sample,
 * the other slots the elements of arrays (sample numbers s * scale + offset). */

/* One value of the sample vector: its offset in the vector, its dimension, its index slot,
 * per-family shape bits (halton: chunks | reversed-fits-32-bits << 8; see global_sampler_simd.h)
 * and (halton) the offset of its pair table in the launch's pair tables, or -1. */
typedef struct clr_value_plan {
  clr_i32 value, dim, index_slot, shape, pair_table;
} clr_value_plan;

/* One index slot: the sample number of the item's sample s is s * scale + offset. */
typedef struct clr_index_plan {
  clr_i32 scale, offset;
} clr_index_plan;

/* Sobol generator matrices regrouped for the device: per dimension, CLR_SOBOL_GROUPS groups of 3
 * index bits, each a table of the 8 XORs of its columns (entry x: columns 3g + b over the bits b
 * of x; columns past the 52 count as 0). Built by the host from clr_sobol_matrices32. */
#define CLR_SOBOL_GROUPS ((CLR_SOBOL_MATRIX_SIZE + 2) / 3)
#define CLR_SOBOL_GROUP_ENTRIES 8
#define CLR_SOBOL_GROUP_TABLE (CLR_SOBOL_GROUPS * CLR_SOBOL_GROUP_ENTRIES)

/* Constants that divide item numbers (< 2^31) by one batch's sample count and width:
 * n / d = (n * magic) >> shift (udiv31_magic in host/lib/sampler_device.c). */
typedef struct clr_item_divisors {
  clr_u32 sample_magic, sample_shift, width_magic, width_shift;
} clr_item_divisors;

#endif
