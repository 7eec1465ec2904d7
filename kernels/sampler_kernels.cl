/* Sample-vector generation kernels for every sampler family; the same math runs on the host as
 * the reference. Built per sampler with -DCLR_SAMPLER_TYPE=n (only that family's kernels) and the
 * family's specialisation defines (see host/lib/sampling/sampler_device.c).
 *
 * Two shapes (include/clrender/kernels.h): by default the SIMD kernels (8 items or pixels per
 * work-item in vector types, for PoCL's CPU devices); with -DCLR_KERNELS_PORTABLE the portable
 * ones (one work-item per sample vector or pixel, the scalar functions the host reference runs,
 * no vector types). The pbrt-v3-seeded pixel samplers replay a tile sequentially in both. */
#include "sampler_types.h"
#include "global_sampler_funcs.h"
#include "pixel_sampler_funcs.h"
#include "pbrt_v4_sampler_funcs.h"
#include "lane_math.h"
#include "lane_store.h" /* here: the embedder inlines each header once, at its first include */
#include "pcg32_lanes.h"

#ifdef CLR_SAMPLER_V4
/* The table arguments every pbrt-v4 kernel takes, in this order (CLR_V4_TABLES gathers them). */
#define CLR_V4_TABLE_ARGS                                                                          \
  __global const uint *restrict sobol32, __global const uint *restrict sobol_groups,               \
      __global const ulong *restrict vdc, __global const ulong *restrict vdc_inv,                  \
      __global const clr_halton_prime *restrict primes, __global const float *restrict pmj_pixels, \
      __global const ushort *restrict digit_perms, __global const uint *restrict digit_offsets,    \
      int digit_dims

/* The tables of the pbrt-v4 kernels' arguments; pmj02bn's point sets follow its pixel table. (An
 * out-parameter: a returned struct becomes a noalias sret argument, whose inlining Oclgrind
 * cannot run.) */
CLR_INLINE void clr_v4_kernel_tables(const clr_sampler_params *p, __global const uint *sobol32,
                                     __global const uint *sobol_groups, __global const ulong *vdc,
                                     __global const ulong *vdc_inv,
                                     __global const clr_halton_prime *primes,
                                     __global const float *pmj_pixels,
                                     __global const ushort *digit_perms,
                                     __global const uint *digit_offsets, int digit_dims,
                                     clr_v4_tables *t) {
  t->sobol32 = sobol32;
  t->sobol_groups = sobol_groups;
  t->vdc = vdc;
  t->vdc_inv = vdc_inv;
  t->primes = primes;
  t->pmj_pixels = pmj_pixels;
  t->pmj_sets = pmj_pixels + clr_v4_pmj02_pixel_floats(p);
  t->digit_perms = digit_perms;
  t->digit_offsets = digit_offsets;
  t->digit_dims = digit_dims;
}

/* clr_v4_tables t from a kernel's CLR_V4_TABLE_ARGS. */
#define CLR_V4_TABLES(p, t)                                                                        \
  clr_v4_kernel_tables(&(p), sobol32, sobol_groups, vdc, vdc_inv, primes, pmj_pixels, digit_perms, \
                       digit_offsets, digit_dims, &(t))

/* pbrt-v4's samplers (built with -DCLR_SAMPLER_V4 -DCLR_SAMPLER_TYPE=-1): one work-item per batch
 * item, the host reference's scalar functions, on SIMD and portable contexts alike (SIMD
 * contexts run zsobol and paddedsobol in clr_v4_generate_pixels8, below). sobol32: the Sobol'
 * matrices as columns; sobol_groups: as 3-bit group tables (read by clr_v4_generate8's sobol
 * only; NULL for the other samplers). */
__kernel void clr_v4_generate(clr_sampler_params p, __global const clr_request_slot *restrict slots,
                              CLR_V4_TABLE_ARGS, __global float *restrict values, int item_count) {
  const int item = (int)get_global_id(0);
  if (item >= item_count) return;
  clr_v4_tables t;
  CLR_V4_TABLES(p, t);
  clr_v4_sample_vector(&p, slots, &t, item, values + (size_t)item * (size_t)p.values_per_sample);
}

/* zsobol, paddedsobol and pmj02bn: one work-item per batch pixel, all of its samples (clr_v4_pixel_vectors:
 * each (pixel, dimension) part once). Same arguments as clr_v4_generate; pixel_count pixels. */
__kernel void clr_v4_generate_pixels(clr_sampler_params p,
                                     __global const clr_request_slot *restrict slots,
                                     CLR_V4_TABLE_ARGS, __global float *restrict values,
                                     int pixel_count) {
  const int pixel = (int)get_global_id(0);
  if (pixel >= pixel_count) return;
  clr_v4_tables t;
  CLR_V4_TABLES(p, t);
  clr_v4_pixel_vectors(
      &p, slots, &t, pixel,
      values + (size_t)pixel * (size_t)p.sample_count * (size_t)p.values_per_sample);
}

#ifndef CLR_KERNELS_PORTABLE
#include "pbrt_v4_sampler_simd.h"

/* pbrt-v4's sobol, halton, independent and stratified on SIMD contexts: one work-item per 8 batch
 * items (past the end the last item repeats), one per lane. Same arguments as clr_v4_generate.
 * Halton runs in lanes with permuted digits (its default) when every index is below 2^32 and
 * halton_exponent[1] >= 1 (clr_v4_global_vectors8), else lane by lane. */
__kernel void clr_v4_generate8(clr_sampler_params p,
                               __global const clr_request_slot *restrict slots, CLR_V4_TABLE_ARGS,
                               __global float *restrict values, int item_count) {
  size_t group = get_global_id(0);
  ulong out[CLR_V4_LANES], index[CLR_V4_LANES], inc[CLR_V4_LANES];
  clr_v4_items8 items;
  int sobol = p.v4_sampler == CLR_V4_SOBOL, halton = p.v4_sampler == CLR_V4_HALTON;
  /* A pixel's next sample starts 65536 draws on: that jump's terms (plus for increment 1; the
   * jump adds inc times it, as the terms are linear in inc). */
  ulong jump_mult = 0ul, jump_plus = 0ul, index_high = 0ul;
  if (!sobol && !halton) clr_pcg32_advance_terms(65536ul, 1ul, &jump_mult, &jump_plus);
  /* sobol's indices in lanes where they fit 32 bits: the sample numbers' bits and 2m */
  int frame_bits = clr_v4_sample_number_bits(&p);
  int sobol_lanes = sobol && frame_bits + 2 * p.sobol_log2_resolution <= 32;
  clr_v4_lane_items8 l;
  clr_v4_walk_items8(&p, group, item_count, &l);
  for (int j = 0; j < CLR_V4_LANES; ++j) {
    int x = l.x[j], y = l.y[j], sample = l.sample[j];
    out[j] = (ulong)l.item[j] * (ulong)p.values_per_sample;
    if (halton) { /* a pixel's next sample: the stride on */
      index[j] = l.next_in_pixel[j] ? index[j - 1] + (ulong)(uint)p.halton_stride
                                    : clr_v4_halton_index(&p, x, y, sample);
      index_high |= index[j] >> 32u;
    } else if (sobol) {
      if (!sobol_lanes)
        index[j] = clr_sobol_interval_to_index((uint)p.sobol_log2_resolution, (ulong)sample, x, y,
                                               vdc, vdc_inv);
    } else if (l.next_in_pixel[j]) { /* the last lane's, jumped */
      index[j] = jump_mult * index[j - 1] + inc[j - 1] * jump_plus;
      inc[j] = inc[j - 1];
    } else { /* independent, stratified: index holds the stream's state */
      clr_pcg32 r;
      clr_v4_pixel_rng(x, y, p.seed, sample, &r);
      index[j] = r.state;
      inc[j] = r.inc;
    }
    items.px[j] = x;
    items.py[j] = y;
  }
  uint8 samples = as_uint8(vload8(0, l.sample));
  if (halton) {
    clr_v4_tables t;
    CLR_V4_TABLES(p, t);
    if (index_high == 0ul && p.randomization == CLR_RANDOMIZE_TYPE_PERMUTEDIGITS &&
        p.halton_exponent[1] >= 1) {
      clr_v4_global_lanes g;
      g.halton = &t;
      g.halton_index = (uint8)(convert_uint4(vload4(0, index)), convert_uint4(vload4(1, index)));
      clr_v4_global_vectors8(&p, slots, &g, values, out);
    } else {
      for (int j = 0; j < CLR_V4_LANES; ++j)
        clr_v4_sample_vector(&p, slots, &t, (int)l.item[j], values + out[j]);
    }
    return;
  }
  if (sobol) {
    clr_v4_u64x8 lanes;
    if (sobol_lanes) {
      uint8 index32 = clr_sobol_index8(p.sobol_log2_resolution, frame_bits, samples, vload8(0, l.x),
                                       vload8(0, l.y), vdc, vdc_inv);
      lanes.lo = convert_ulong4(index32.lo);
      lanes.hi = convert_ulong4(index32.hi);
    } else {
      lanes.lo = vload4(0, index);
      lanes.hi = vload4(1, index);
    }
    clr_v4_global_lanes g;
    clr_v4_sobol_lanes_init(&g.sobol, sobol32, sobol_groups, &lanes);
    g.px = convert_float8(vload8(0, l.x));
    g.py = convert_float8(vload8(0, l.y));
    clr_v4_global_vectors8(&p, slots, &g, values, out);
    return;
  }
  items.rng.state_lo = vload4(0, index);
  items.rng.state_hi = vload4(1, index);
  items.rng.inc_lo = vload4(0, inc);
  items.rng.inc_hi = vload4(1, inc);
  items.sample = samples;
  /* the lanes' items are consecutive: the first and last in one pixel, all in it */
  items.one_pixel =
      items.px[0] == items.px[CLR_V4_LANES - 1] && items.py[0] == items.py[CLR_V4_LANES - 1];
  if (p.v4_sampler == CLR_V4_STRATIFIED)
    clr_v4_stratified_vectors8(&p, slots, &items, values, out);
  else
    clr_v4_independent_vectors8(&p, slots, &items.rng, values, out);
}

/* zsobol, paddedsobol and pmj02bn on SIMD contexts: one work-item per 8 batch pixels (past the
 * end the last pixel repeats), one pixel per lane. Same arguments as clr_v4_generate_pixels. */
__kernel void clr_v4_generate_pixels8(clr_sampler_params p,
                                      __global const clr_request_slot *restrict slots,
                                      CLR_V4_TABLE_ARGS, __global float *restrict values,
                                      int pixel_count) {
  clr_v4_tables t;
  CLR_V4_TABLES(p, t);
  size_t group = get_global_id(0);
  size_t per_pixel = (size_t)p.sample_count * (size_t)p.values_per_sample;
  ulong out[CLR_V4_LANES], morton[CLR_V4_LANES];
  clr_v4_lanes8 lanes;
  for (int j = 0; j < CLR_V4_LANES; ++j) {
    uint pixel = min((uint)(group * CLR_V4_LANES) + (uint)j, (uint)pixel_count - 1u);
    int row = (int)(pixel / (uint)p.batch_width);
    out[j] = (ulong)pixel * per_pixel;
    lanes.px[j] = p.batch_x0 + (int)pixel - row * p.batch_width;
    lanes.py[j] = p.batch_y0 + row;
    morton[j] =
        p.v4_sampler == CLR_V4_ZSOBOL    ? clr_v4_zsobol_pixel_morton(&p, lanes.px[j], lanes.py[j])
        : p.v4_sampler == CLR_V4_PMJ02BN ? clr_v4_blue_noise_morton(lanes.px[j], lanes.py[j])
                                         : 0ul;
  }
  lanes.morton.lo = vload4(0, morton);
  lanes.morton.hi = vload4(1, morton);
  clr_v4_pixels8(&p, slots, &t, &lanes, values, out);
}
#endif
#endif

#ifndef CLR_SAMPLER_TYPE
#define CLR_SAMPLER_TYPE CLR_SAMPLER_TYPE_SOBOL
#endif

#if (CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_SOBOL || CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_HALTON) && \
    defined(CLR_KERNELS_PORTABLE)
/* One work-item per batch item: its sample vector and global index. sobol32: the generator
 * matrices as columns (sobol); vdc, vdc_inv: the VdC tables (sobol); primes, perms: the halton
 * records and permutations. The other family's tables are unused (may be NULL). */
__kernel void clr_global_generate_portable(
    clr_sampler_params p, __global const clr_request_slot *restrict slots,
    __global const uint *restrict sobol32, __global const ulong *restrict vdc,
    __global const ulong *restrict vdc_inv, __global const clr_halton_prime *restrict primes,
    __global const ushort *restrict perms, __global float *restrict values,
    __global ulong *restrict indices_out, int write_indices, int item_count) {
  const int item = (int)get_global_id(0);
  if (item >= item_count) return;
  ulong index = 0;
  clr_global_sample_vector(&p, slots, sobol32, vdc, vdc_inv, primes, perms, item,
                           values + (size_t)item * (size_t)p.values_per_sample, &index);
  if (write_indices) indices_out[item] = index;
}
#elif CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_SOBOL || CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_HALTON
#include "global_sampler_simd.h"

#if CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_SOBOL
/* Generator matrices: with CLR_INDEX32 as 3-bit group tables (CLR_SOBOL_GROUP_TABLE per
 * dimension), else as columns (CLR_SOBOL_MATRIX_SIZE per dimension). */
typedef __global const uint *clr_table0_t;
typedef __global const ulong *clr_table1_t, *clr_table2_t; /* VdC matrices and inverses */
#define clr_index8(number) \
  clr_sobol_index8(p.sobol_log2_resolution, p.sobol_frame_bits, number, rel_x, rel_y, t1, t2)
#define clr_value8(index, e) clr_sobol_value8(&p, t0, index, e.dim, it.px, it.py)
#define clr_index1(j, number) clr_sobol_sampler_index(&p, t1, t2, pxs[j], pys[j], (long)(number))
#define clr_value1(j, index, dim) clr_sobol_sampler_value(&p, t0, index, dim, pxs[j], pys[j])
#else
typedef __global const clr_halton_prime *clr_table0_t; /* one record per prime */
typedef __global const ushort *clr_table1_t;           /* permutations and chunk tables */
typedef __global const ushort *clr_table2_t;           /* pair tables (or NULL) */
#define clr_index8(number) clr_halton_index8(&p, it.px, it.py, number, it.one_pixel, &base3)
#define clr_value8(index, e)                                                             \
  clr_halton_value8(&p, t0, t1, e.pair_table >= 0 ? t2 + e.pair_table : 0, index, base3, \
                    stepped && e.index_slot == 0, e.dim, e.shape & 0xff, e.shape >> 8)
#define clr_index1(j, number) clr_halton_sampler_index(&p, pxs[j], pys[j], (long)(number))
#define clr_value1(j, index, dim) clr_halton_sampler_value(&p, t0, t1, index, dim)
#endif

/* One work-item per 8 batch items: their sample vectors in plan order (grouped by index slot, so
 * that each slot's index is computed once), and with write_indices their global indices. Without
 * CLR_INDEX32 lane by lane with the scalar functions. */
__kernel void clr_global_generate(clr_sampler_params p, clr_item_divisors d,
                                  __global const clr_value_plan *restrict plan,
                                  __global const clr_index_plan *restrict slots,
                                  clr_table0_t restrict t0, clr_table1_t restrict t1,
                                  clr_table2_t restrict t2, __global float *restrict values,
                                  __global ulong *restrict indices_out, int write_indices,
                                  int item_count) {
  clr_items8 it = clr_items_of_work_item(&p, &d, item_count);
  int8 rel_x = it.px - p.sample_x0, rel_y = it.py - p.sample_y0; /* from the sample bounds */
  (void)rel_x;                                                   /* used by sobol's index only */
  (void)rel_y;
  (void)t2;
#ifdef CLR_INDEX32
  uint8 base3 = (uint8)0u; /* halton: dimension 1's argument of the current index */
  (void)base3;
  uint8 index = clr_index8(clr_sample_numbers8(it.sample, slots[0]));
  if (write_indices) {
    uint lanes[CLR_LANES], items[CLR_LANES];
    vstore8(index, 0, lanes);
    vstore8(it.item, 0, items);
    for (int j = 0; j < CLR_LANES; ++j) indices_out[items[j]] = lanes[j];
  }
  int current = 0;
  /* Consecutive items (no repeated padding lane): lane j's value is j rows after lane 0's. */
  int consecutive = it.item.s7 == it.item.s0 + 7u;
  /* halton: consecutive samples of one pixel (the pair tables' lane rows apply to slot 0) */
  int stepped = consecutive && it.one_pixel;
  (void)stepped;
  size_t stride = (size_t)p.values_per_sample;
  __global float *rows = values + (size_t)it.item.s0 * stride;
  for (int k = 0; k < p.values_per_sample; ++k) {
    clr_value_plan e = plan[k];
    if (e.index_slot != current) {
      current = e.index_slot;
      index = clr_index8(clr_sample_numbers8(it.sample, slots[current]));
    }
    float8 v = clr_value8(index, e);
    if (consecutive)
      clr_store_rows8(rows + e.value, stride, v);
    else
      clr_store8(values, it.item, p.values_per_sample, e.value, v);
  }
#else
  uint items[CLR_LANES], samples[CLR_LANES];
  int pxs[CLR_LANES], pys[CLR_LANES];
  vstore8(it.item, 0, items);
  vstore8(it.sample, 0, samples);
  vstore8(it.px, 0, pxs);
  vstore8(it.py, 0, pys);
  for (int j = 0; j < CLR_LANES; ++j) {
    ulong index = clr_index1(j, samples[j]);
    if (write_indices) indices_out[items[j]] = index;
    int current = 0;
    for (int k = 0; k < p.values_per_sample; ++k) {
      clr_value_plan e = plan[k];
      if (e.index_slot != current) {
        current = e.index_slot;
        clr_index_plan ip = slots[current];
        index = clr_index1(j, (long)samples[j] * ip.scale + ip.offset);
      }
      values[(size_t)items[j] * (size_t)p.values_per_sample + (size_t)e.value] =
          clr_value1(j, index, e.dim);
    }
  }
#endif
}
#endif

#if (CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_RANDOM ||      \
     CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_STRATIFIED ||  \
     CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_ZEROTWO ||     \
     CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_MAXMINDIST) && \
    defined(CLR_KERNELS_PORTABLE)
/* CLR_SEEDING_TYPE_PIXEL: one work-item per pixel of the batch, its own RNG stream and
 * p.scratch_floats of scratch. */
__kernel void clr_pixel_generate_portable(clr_sampler_params p,
                                          __global const clr_request_slot *restrict slots,
                                          __global float *restrict values,
                                          __global float *restrict scratch, int pixel_count) {
  const int pixel = (int)get_global_id(0);
  if (pixel >= pixel_count) return;
  const int row = pixel / p.batch_width;
  const size_t per_pixel = (size_t)p.sample_count * (size_t)p.values_per_sample;
  clr_pixel_sampler_pixel(&p, slots, p.batch_x0 + (pixel - row * p.batch_width), p.batch_y0 + row,
                          values + (size_t)pixel * per_pixel,
                          scratch + (size_t)pixel * (size_t)p.scratch_floats);
}
#elif CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_RANDOM ||   \
    CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_STRATIFIED || \
    CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_ZEROTWO ||    \
    CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_MAXMINDIST
#include "pixel_sampler_simd.h"

/* CLR_SEEDING_TYPE_PIXEL: one work-item per 8 pixels of the batch (past the end the last pixel
 * repeats), one lane and RNG stream per pixel. */
__kernel void clr_pixel_generate(clr_sampler_params p,
                                 __global const clr_request_slot *restrict slots,
                                 __global float *restrict values, __global float *restrict scratch,
                                 __global const uint4 *restrict bounded, int pixel_count) {
  size_t group = get_global_id(0);
  size_t per_pixel = (size_t)p.sample_count * (size_t)p.values_per_sample;
  ulong out[CLR_PIXEL_LANES], state[CLR_PIXEL_LANES], inc[CLR_PIXEL_LANES];
  for (int j = 0; j < CLR_PIXEL_LANES; ++j) {
    uint pixel = min((uint)(group * CLR_PIXEL_LANES) + (uint)j, (uint)pixel_count - 1u);
    int row = (int)(pixel / (uint)p.batch_width);
    clr_pcg32 r =
        clr_pixel_stream(&p, p.batch_x0 + (int)pixel - row * p.batch_width, p.batch_y0 + row);
    state[j] = r.state;
    inc[j] = r.inc;
    out[j] = (ulong)pixel * per_pixel;
  }
  clr_pcg32x8 rng;
  rng.state_lo = vload4(0, state);
  rng.state_hi = vload4(1, state);
  rng.inc_lo = vload4(0, inc);
  rng.inc_hi = vload4(1, inc);
  clr_pixel_sampler_start_pixel8(&p, slots, &rng, values, out,
                                 scratch + group * (size_t)p.scratch_floats * CLR_PIXEL_LANES,
                                 bounded);
}

#endif

#if CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_RANDOM ||     \
    CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_STRATIFIED || \
    CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_ZEROTWO ||    \
    CLR_SAMPLER_TYPE == CLR_SAMPLER_TYPE_MAXMINDIST
/* CLR_SEEDING_TYPE_PBRT_V3: one work-item per pbrt-v3 16x16 tile touching the batch. */
__kernel void clr_generate_tiles(clr_sampler_params p,
                                 __global const clr_request_slot *restrict slots,
                                 __global float *restrict values, __global float *restrict scratch,
                                 int tile_x0, int tile_y0, int tiles_wide, int tile_count) {
  int t = (int)get_global_id(0);
  if (t >= tile_count) return;
  clr_pixel_sampler_tile(&p, slots, tile_x0 + t % tiles_wide, tile_y0 + t / tiles_wide, values,
                         scratch + (size_t)t * (size_t)p.scratch_floats);
}
#endif
