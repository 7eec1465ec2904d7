/* pbrt-v3's MaxMinDistSampler::StartPixel (samplers/maxmin.cpp), bit-exact in values and RNG
 * consumption (contract: kernels/pixel_sampler_funcs.h): the first 2D stream is
 * (i / spp, C * i) for the generator matrix C of the pixel's sample count, shuffled; every other
 * stream and array is the (0,2)-sequence's (zerotwo_funcs.h).
 *
 * The generator matrices are data: the (0,m,2)-nets of maximized minimum distance found by
 * T. Grünschloß, J. Hanika, R. Schwede and A. Keller, "(t, m, s)-Nets and Maximized Minimum
 * Distance", Monte Carlo and Quasi-Monte Carlo Methods 2006, Springer 2008, pp. 397-412, in the
 * bit-reversed column form pbrt-v3 stores as CMaxMinDist[17][32] (core/lowdiscrepancy.cpp).
 * Matrix m (for 2^m samples) has m non-zero columns, the rest are zero; only those columns are
 * kept, matrix m's at clr_maxmin_columns[m * (m - 1) / 2]. (pbrt-v3's matrix 1 is all zero but
 * for column 31, which indices below 2^31 never reach: 2 samples get second coordinates 0.) */
#ifndef CLR_MAXMIN_FUNCS_H
#define CLR_MAXMIN_FUNCS_H

#include "clr_platform.h"
#include "pcg32.h"
#include "random_funcs.h"
#include "sampler_types.h"
#include "stratified_funcs.h"
#include "zerotwo_funcs.h"

#define CLR_MAXMIN_MATRICES 17

#ifdef __OPENCL_C_VERSION__
__constant clr_u32 clr_maxmin_columns[136] = {
#else
static const clr_u32 clr_maxmin_columns[136] = {
#endif
    // clang-format off
    /* m =  1 */ 0x00000000u,
    /* m =  2 */ 0xc0000000u, 0x80000000u,
    /* m =  3 */ 0xa0000000u, 0x40000000u, 0x80000000u,
    /* m =  4 */ 0xc0000000u, 0x50000000u, 0x20000000u, 0x30000000u,
    /* m =  5 */ 0x88000000u, 0x58000000u, 0x20000000u, 0x40000000u, 0x80000000u,
    /* m =  6 */ 0xe0000000u, 0x60000000u, 0x28000000u, 0x10000000u, 0x18000000u, 0x04000000u,
    /* m =  7 */ 0x82000000u, 0x44000000u, 0x2c000000u, 0x10000000u, 0x20000000u, 0x40000000u,
                 0x80000000u,
    /* m =  8 */ 0x80000000u, 0x70000000u, 0x30000000u, 0x14000000u, 0x08000000u, 0x0c000000u,
                 0x02000000u, 0x01000000u,
    /* m =  9 */ 0xc0000000u, 0x41000000u, 0x22000000u, 0x16000000u, 0x08000000u, 0x10000000u,
                 0x20000000u, 0x40800000u, 0x80000000u,
    /* m = 10 */ 0x80000000u, 0x40000000u, 0x20000000u, 0x18000000u, 0x08000000u, 0x1c000000u,
                 0x1e000000u, 0x03000000u, 0x00800000u, 0x00400000u,
    /* m = 11 */ 0x80000000u, 0x60400000u, 0x20800000u, 0x11000000u, 0x0b000000u, 0x04000000u,
                 0x08000000u, 0x10000000u, 0x20000000u, 0x40000000u, 0x00200000u,
    /* m = 12 */ 0x80000000u, 0x40000000u, 0x20000000u, 0x1c000000u, 0x0c000000u, 0x05000000u,
                 0x02000000u, 0x03000000u, 0x00800000u, 0x00400000u, 0x00200000u, 0x00100000u,
    /* m = 13 */ 0x80000000u, 0x40000000u, 0x30200000u, 0x10400000u, 0x08800000u, 0x05800000u,
                 0x02000000u, 0x04000000u, 0x08000000u, 0x10000000u, 0x20000000u, 0x00100000u,
                 0x00080000u,
    /* m = 14 */ 0x80000000u, 0x40000000u, 0x20000000u, 0x10000000u, 0x0e000000u, 0x06000000u,
                 0x02800000u, 0x01000000u, 0x01800000u, 0x00400000u, 0x00200000u, 0x00100000u,
                 0x00080000u, 0x00040000u,
    /* m = 15 */ 0x80000000u, 0x40000000u, 0x20000000u, 0x18100000u, 0x08200000u, 0x04400000u,
                 0x02c00000u, 0x01000000u, 0x02000000u, 0x04000000u, 0x08000000u, 0x10000000u,
                 0x00080000u, 0x00040000u, 0x00020000u,
    /* m = 16 */ 0x80000000u, 0x40000000u, 0x20000000u, 0x10000000u, 0x08000000u, 0x07000000u,
                 0x03000000u, 0x01400000u, 0x00800000u, 0x00c00000u, 0x00200000u, 0x00100000u,
                 0x00080000u, 0x00040000u, 0x00020000u, 0x00010000u,
    // clang-format on
};

/* MultiplyGenerator(CMaxMinDist[m], a) for a < 2^31. */
CLR_INLINE clr_u32 clr_maxmin_generate(clr_i32 m, clr_u32 a) {
  clr_u32 v = 0u;
  clr_i32 first = m * (m - 1) / 2;
  for (clr_i32 i = 0; a != 0u && i < m; ++i, a >>= 1u)
    if (a & 1u) v ^= clr_maxmin_columns[first + i];
  return v;
}

/* MaxMinDistSampler::StartPixel: the first 2D stream (when dimensions >= 1) then the rest as
 * ZeroTwoSequenceSampler, then the RNG fallback values. p->maxmin_matrix: pbrt-v3's
 * Log2Int(pixelsamples as given), which for a pixelsamples that is no power of two is the
 * matrix of half the rounded-up spp, as in pbrt-v3. scratch: as zerotwo. */
CLR_INLINE void clr_maxmin_start_pixel(const clr_sampler_params *p,
                                       CLR_GLOBAL const clr_request_slot *slots, clr_pcg32 *rng,
                                       CLR_GLOBAL float *out_pixel, CLR_GLOBAL float *scratch) {
  clr_i32 first2d = p->dimensions > 0 ? 1 : 0;
  if (first2d) {
    if (out_pixel && clr_slots_use(p, slots, 2, 0, 0)) {
      for (clr_i32 i = 0; i < p->spp; ++i) {
        scratch[2 * i] = (float)i * p->inv_spp;
        scratch[2 * i + 1] = (float)clr_maxmin_generate(p->maxmin_matrix, (clr_u32)i) * 0x1p-32f;
      }
      clr_shuffle(scratch, p->spp, 2, rng);
      clr_stratified_store_stream(p, slots, 2, 0, scratch, out_pixel);
    } else {
      clr_shuffle_draws(p->spp, rng);
    }
  }
  clr_zerotwo_streams(p, slots, 1, 0, rng, out_pixel, scratch);
  clr_zerotwo_streams(p, slots, 2, first2d, rng, out_pixel, scratch);
  clr_zerotwo_arrays(p, slots, 1, rng, out_pixel, scratch);
  clr_zerotwo_arrays(p, slots, 2, rng, out_pixel, scratch);
  if (out_pixel) clr_pixel_store_fallbacks(p, slots, rng, out_pixel);
}

#endif
