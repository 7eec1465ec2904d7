/* Film accumulation in two kernels over samples binned by the host by their first reached pixel
 * (y0, x0) (stable, batch order inside a bin).
 * clr_film_weigh: per binned sample, once, L * w and the separable filter factors of every pixel
 * it can reach (reach_x along x, reach_y along y).
 * clr_film_gather: a work-item owns a run of T (the accumulation tile size) pixels of one row, in
 * private sums. Bin row by bin row (ascending y0) it walks the samples of the bins x0 in
 * [run_x0 - K + 1, run_x1 - 1] (one contiguous range per bin row) in their binned order and adds
 * each one to the K pixels x0 .. x0 + K - 1 with fixed trip counts (factors past the sample's
 * reach are 0 and add zeros; pixels outside the run land in padding): every pixel sees its
 * samples in the canonical order of film.h, whatever T, the work-group size or the device. No two
 * work-items write one address, no atomics. */
#include "film_funcs.h"

#define CLR_FILM_RUN_MAX 64 /* largest accumulation tile size */
#define CLR_FILM_ACC_MAX (CLR_FILM_RUN_MAX + 2 * (CLR_FILM_REACH_MAX - 1))

/* factors: 2 x 16 table factors (table mode); binned: CLR_FILM_BINNED_FLOATS per sample;
 * weighed: grid.weighed_floats per sample. Global size: count (rounded up). */
__kernel void clr_film_weigh(clr_filter_params filt, clr_film_grid grid,
                             __global const float *factors, __global const float *binned,
                             uint count, __global float *weighed) {
  const size_t i = get_global_id(0);
  if (i >= count) return;
  __global const float *s = binned + i * CLR_FILM_BINNED_FLOATS;
  __global float *o = weighed + i * (size_t)grid.weighed_floats;
  const float dx = s[0], dy = s[1], w = s[5];
  const int x0 = clr_film_first_pixel(dx, filt.radius_x);
  const int y0 = clr_film_first_pixel(dy, filt.radius_y);
  const int nx = clr_film_last_pixel(dx, filt.radius_x) - x0;
  const int ny = clr_film_last_pixel(dy, filt.radius_y) - y0;
  o[0] = s[2] * w;
  o[1] = s[3] * w;
  o[2] = s[4] * w;
  o[3] = 1.0f;
  o[4] = as_float(x0);
  o[5] = as_float(y0);
  __global float *wx = o + CLR_FILM_WEIGHED_HEAD, *wy = wx + grid.reach_x;
  for (int k = 0; k < grid.reach_x; ++k)
    wx[k] = k <= nx ? clr_film_filter_factor(&filt, factors, 0, dx, x0 + k) : 0.0f;
  for (int k = 0; k < grid.reach_y; ++k)
    wy[k] = k <= ny ? clr_film_filter_factor(&filt, factors, 1, dy, y0 + k) : 0.0f;
}

/* Adds a weighed sample at acc (its pixel x0) with y-factor fy: kx fixed-count updates. */
static inline void clr_film_add_row(__global const float *s, float fy, int kx, float4 *acc) {
  const float4 c = vload4(0, s);
  __global const float *wx = s + CLR_FILM_WEIGHED_HEAD;
  for (int k = 0; k < kx; ++k) acc[k] += c * clr_film_weight(wx[k], fy);
}

/* params: film (tile_size = T); grid: the chunk's bins and output region; weighed: the weighed
 * samples in bin order; starts[b]..starts[b+1]: bin b's range (bins_x * bins_y + 1 entries);
 * sums: CLR_FILM_SUM_FLOATS per pixel of the output region, row-major. Global size: (runs per
 * row rounded up to the work-group size, out_h). */
__kernel void clr_film_gather(clr_film_params fp, clr_film_grid grid, __global const float *weighed,
                              __global const uint *starts, __global float *sums) {
  const int out_x1 = grid.out_x0 + grid.out_w;
  const int run_x0 = grid.out_x0 + (int)get_global_id(0) * fp.tile_size;
  if (run_x0 >= out_x1) return;
  const int run_x1 = min(run_x0 + fp.tile_size, out_x1); /* exclusive */
  const int py = grid.out_y0 + (int)get_global_id(1);
  const int kx = grid.reach_x, ky = grid.reach_y, stride = grid.weighed_floats;
  /* acc[i] is pixel run_x0 - (kx - 1) + i */
  float4 acc[CLR_FILM_ACC_MAX];
  const int acc_n = (run_x1 - run_x0) + 2 * (kx - 1);
  for (int i = 0; i < acc_n; ++i) acc[i] = (float4)(0.0f);
  /* Bin columns whose samples can reach the run, clipped to the grid. */
  const int cx0 = max(run_x0 - kx + 1 - grid.bin_x0, 0);
  const int cx1 = min(run_x1 - 1 - grid.bin_x0, grid.bins_x - 1);
  for (int j = 0; j < ky; ++j) {
    const int row = py - ky + 1 + j - grid.bin_y0;
    if (row < 0 || row >= grid.bins_y || cx0 > cx1) continue;
    const int fy_at = CLR_FILM_WEIGHED_HEAD + kx + (ky - 1 - j); /* this row's py - y0 */
    const uint end = starts[row * grid.bins_x + cx1 + 1];
    for (uint i = starts[row * grid.bins_x + cx0]; i < end; ++i) {
      __global const float *s = weighed + (size_t)i * (size_t)stride;
      const int at = as_int(s[4]) - run_x0 + kx - 1;
      clr_film_add_row(s, s[fy_at], kx, acc + at);
    }
  }
  __global float *out =
      sums + ((size_t)get_global_id(1) * (size_t)grid.out_w + (size_t)(run_x0 - grid.out_x0)) *
                 CLR_FILM_SUM_FLOATS;
  for (int i = 0; i < run_x1 - run_x0; ++i) vstore4(acc[i + kx - 1], i, out);
}

/* The portable shape's gather (GPU-shaped): one work-item per output pixel with one float4 of
 * private sums, in 2D work-groups of a warp or more. Bin row by bin row (ascending y0) it walks
 * the samples of the bins x0 in [px - K + 1, px] in their binned order and adds each one's
 * contribution to this pixel: the same additions in the same order as clr_film_gather makes for
 * this pixel (its other additions there are zeros or go to other pixels), so the same bits.
 * Neighbouring work-items read the same samples (cache broadcast); no atomics, no local memory.
 * Global size: (out_w, out_h), each rounded up to the work-group. */
__kernel void clr_film_gather_pixels(clr_film_grid grid, __global const float *weighed,
                                     __global const uint *starts, __global float *sums) {
  const int ox = (int)get_global_id(0), oy = (int)get_global_id(1);
  if (ox >= grid.out_w || oy >= grid.out_h) return;
  const int px = grid.out_x0 + ox, py = grid.out_y0 + oy;
  const int kx = grid.reach_x, ky = grid.reach_y, stride = grid.weighed_floats;
  float4 acc = (float4)(0.0f);
  const int cx0 = max(px - kx + 1 - grid.bin_x0, 0);
  const int cx1 = min(px - grid.bin_x0, grid.bins_x - 1);
  for (int j = 0; j < ky; ++j) {
    const int row = py - ky + 1 + j - grid.bin_y0;
    if (row < 0 || row >= grid.bins_y || cx0 > cx1) continue;
    const int fy_at = CLR_FILM_WEIGHED_HEAD + kx + (ky - 1 - j); /* this row's py - y0 */
    const uint end = starts[row * grid.bins_x + cx1 + 1];
    for (uint i = starts[row * grid.bins_x + cx0]; i < end; ++i) {
      __global const float *s = weighed + (size_t)i * (size_t)stride;
      const int k = px - as_int(s[4]); /* px - x0, in [0, K) */
      acc += vload4(0, s) * clr_film_weight(s[CLR_FILM_WEIGHED_HEAD + k], s[fy_at]);
    }
  }
  vstore4(acc, (size_t)oy * (size_t)grid.out_w + (size_t)ox, sums);
}

/* The SIMD shape, for chunks whose reach is at most CLR_FILM_LANES pixels along both axes. */
#include "filter_simd.h"

/* clr_film_weigh in 8 lanes: the weighed sample of film_types.h (CLR_FILM_WEIGHED8_FLOATS). A
 * factor lane holds clr_film_filter_factor at its pixel where the sample reaches the pixel (k =
 * pixel - first pixel in [0, last - first]), else 0: clr_film_weigh's values, positioned. */
CLR_FILTER_SIMD_INLINE float8 clr_film_factors8(const clr_filter_params *f,
                                                __global const float *factors, int axis, float d,
                                                int8 pixel, int8 k, int last_k) {
  float8 v = clr_filter_eval_1d8(f, axis, convert_float8(pixel) - d, factors);
  return select((float8)(0.0f), v, k >= 0 && k <= last_k);
}

/* factors: 2 x 16 table factors (table mode); binned: CLR_FILM_BINNED_FLOATS per sample;
 * weighed: CLR_FILM_WEIGHED8_FLOATS per sample. Global size: count (rounded up). */
__kernel void clr_film_weigh8(clr_filter_params filt, clr_film_grid grid,
                              __global const float *factors, __global const float *binned,
                              uint count, __global float *weighed) {
  const size_t i = get_global_id(0);
  if (i >= count) return;
  __global const float *s = binned + i * CLR_FILM_BINNED_FLOATS;
  __global float *o = weighed + i * CLR_FILM_WEIGHED8_FLOATS;
  const float dx = s[0], dy = s[1], w = s[5];
  const int x0 = clr_film_first_pixel(dx, filt.radius_x);
  const int y0 = clr_film_first_pixel(dy, filt.radius_y);
  const int nx = clr_film_last_pixel(dx, filt.radius_x) - x0;
  const int ny = clr_film_last_pixel(dy, filt.radius_y) - y0;
  /* x0 - out_x0 > -CLR_FILM_RUN_BIAS (the largest reach): the division rounds down */
  const int gx = grid.out_x0 + ((x0 - grid.out_x0 + CLR_FILM_RUN_BIAS) / CLR_FILM_LANES -
                                CLR_FILM_RUN_BIAS / CLR_FILM_LANES) *
                                   CLR_FILM_LANES;
  vstore4((float4)(s[2] * w, s[3] * w, s[4] * w, 1.0f), 0, o);
  vstore4((float4)(as_float(x0), as_float(y0), as_float(gx), 0.0f), 1, o);
  /* the x-factors from pixel x0 on, stored over zeros at their place among the 16 */
  vstore8((float8)(0.0f), 0, o + CLR_FILM_WEIGHED8_X);
  vstore8((float8)(0.0f), 1, o + CLR_FILM_WEIGHED8_X);
  if (grid.reach_x <= CLR_FILM_QUAD && grid.reach_y <= CLR_FILM_QUAD) {
    /* 4 x- and 4 y-factors in one vector; those past the reach are 0 (raise_reach in
     * film_accumulate.c) */
    const int8 k = (int8)(0, 1, 2, 3, 0, 1, 2, 3);
    const int8 pixel = (int8)((int4)(x0), (int4)(y0)) + k;
    const float8 d = convert_float8(pixel) - (float8)((float4)(dx), (float4)(dy));
    const float8 v = select((float8)(0.0f), clr_filter_eval_xy8(&filt, d, factors),
                            k <= (int8)((int4)(nx), (int4)(ny)));
    vstore4(v.lo, 0, o + CLR_FILM_WEIGHED8_X + (x0 - gx));
    vstore8((float8)(v.hi, (float4)(0.0f)), 0, o + CLR_FILM_WEIGHED8_Y);
    return;
  }
  const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7);
  vstore8(clr_film_factors8(&filt, factors, 0, dx, x0 + lane, lane, nx), 0,
          o + CLR_FILM_WEIGHED8_X + (x0 - gx));
  vstore8(clr_film_factors8(&filt, factors, 1, dy, y0 + lane, lane, ny), 0,
          o + CLR_FILM_WEIGHED8_Y);
}

/* Adds a weighed sample's positioned x-factors f times its y-factor fy to the sums of one row. */
#define CLR_FILM_ADD8(s, f, fy, r, g, b, w)             \
  do {                                                  \
    const float8 fw = clr_flush_subnormal8((f) * (fy)); \
    r += (s)[0] * fw;                                   \
    g += (s)[1] * fw;                                   \
    b += (s)[2] * fw;                                   \
    w += fw;                                            \
  } while (0)

#define CLR_FILM_STORE_LANE(out, r, g, b, w, j, c) \
  if (j < n) vstore4((float4)(r.c, g.c, b.c, w.c), j, out)

/* Stores the first n lanes of one row's sums at out (CLR_FILM_SUM_FLOATS per pixel). */
static inline void clr_film_store8(__global float *out, int n, float8 r, float8 g, float8 b,
                                   float8 w) {
  CLR_FILM_STORE_LANE(out, r, g, b, w, 0, s0);
  CLR_FILM_STORE_LANE(out, r, g, b, w, 1, s1);
  CLR_FILM_STORE_LANE(out, r, g, b, w, 2, s2);
  CLR_FILM_STORE_LANE(out, r, g, b, w, 3, s3);
  CLR_FILM_STORE_LANE(out, r, g, b, w, 4, s4);
  CLR_FILM_STORE_LANE(out, r, g, b, w, 5, s5);
  CLR_FILM_STORE_LANE(out, r, g, b, w, 6, s6);
  CLR_FILM_STORE_LANE(out, r, g, b, w, 7, s7);
}

/* One 8-pixel run's sums in two rows (lanes are pixels run_x0 .. run_x0 + 7). */
typedef struct clr_film_run8 {
  float8 r0, g0, b0, w0; /* row py0 */
  float8 r1, g1, b1, w1; /* row py0 + 1 */
} clr_film_run8;

/* clr_film_gather for a run of 8 pixels in two rows (py0, py0 + 1), the pixels in the lanes of
 * four float8 sums (r, g, b, weight) per row: bin row by bin row (ascending y0, from py0 - K + 1
 * to py0 + 1) it walks the samples of the bins x0 in [run_x0 - K + 1, run_x0 + 7] in their binned
 * order and adds each one's positioned x-factors (the half of its 16 that covers the run) times
 * its y-factor to each row the bin row can reach: every lane adds its pixel's contributions in
 * clr_film_gather's order (lanes the sample does not reach add zeros), so the same bits. oy: py0's
 * row in the output region; run_x1: the run's end (exclusive) in it. */
static inline clr_film_run8 clr_film_gather_run8(const clr_film_grid *grid,
                                                 __global const float *weighed,
                                                 __global const uint *starts, int run_x0,
                                                 int run_x1, int oy) {
  const int py = grid->out_y0 + oy, kx = grid->reach_x, ky = grid->reach_y;
  float8 r0 = (float8)(0.0f), g0 = r0, b0 = r0, w0 = r0, r1 = r0, g1 = r0, b1 = r0, w1 = r0;
  const int cx0 = max(run_x0 - kx + 1 - grid->bin_x0, 0);
  const int cx1 = min(run_x1 - 1 - grid->bin_x0, grid->bins_x - 1);
  for (int j = 0; j <= ky; ++j) { /* bin row y0 = py - ky + 1 + j */
    const int row = py - ky + 1 + j - grid->bin_y0;
    if (row < 0 || row >= grid->bins_y || cx0 > cx1) continue;
    /* rows py (py - y0 = ky - 1 - j) and py + 1 (ky - j) where in reach, and their y-factors */
    const int on0 = j<ky, on1 = j> 0 && oy + 1 < grid->out_h;
    const int fy0_at = CLR_FILM_WEIGHED8_Y + (on0 ? ky - 1 - j : 0);
    const int fy1_at = CLR_FILM_WEIGHED8_Y + (on1 ? ky - j : 0);
    const uint end = starts[row * grid->bins_x + cx1 + 1];
    for (uint i = starts[row * grid->bins_x + cx0]; i < end; ++i) {
      __global const float *s = weighed + (size_t)i * CLR_FILM_WEIGHED8_FLOATS;
      const int upper = as_int(s[6]) != run_x0; /* else its run is the previous one */
      const float8 f = vload8(upper, s + CLR_FILM_WEIGHED8_X);
      if (on0) CLR_FILM_ADD8(s, f, s[fy0_at], r0, g0, b0, w0);
      if (on1) CLR_FILM_ADD8(s, f, s[fy1_at], r1, g1, b1, w1);
    }
  }
  clr_film_run8 sums = {r0, g0, b0, w0, r1, g1, b1, w1};
  return sums;
}

/* clr_film_gather_run8 over the output region, into the chunk's float sums. Global size: (runs
 * per row rounded up to the work-group size, row pairs). */
__kernel void clr_film_gather8(clr_film_grid grid, __global const float *weighed,
                               __global const uint *starts, __global float *sums) {
  const int run_x0 = grid.out_x0 + (int)get_global_id(0) * CLR_FILM_LANES;
  if (run_x0 >= grid.out_x0 + grid.out_w) return;
  const int n = min(CLR_FILM_LANES, grid.out_x0 + grid.out_w - run_x0); /* the run's pixels */
  const int oy = 2 * (int)get_global_id(1);
  const clr_film_run8 a = clr_film_gather_run8(&grid, weighed, starts, run_x0, run_x0 + n, oy);
  __global float *out = sums + ((size_t)oy * (size_t)grid.out_w + (size_t)(run_x0 - grid.out_x0)) *
                                   CLR_FILM_SUM_FLOATS;
  clr_film_store8(out, n, a.r0, a.g0, a.b0, a.w0);
  if (oy + 1 < grid.out_h)
    clr_film_store8(out + (size_t)grid.out_w * CLR_FILM_SUM_FLOATS, n, a.r1, a.g1, a.b1, a.w1);
}

#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable

/* Adds the first n lanes of one row's float sums into the film's double sums from pixel i on:
 * clr_film_add_block's additions, pixel by pixel. */
static inline void clr_film_add_doubles8(__global double *rgb_sum, __global double *weight_sum,
                                         size_t i, int n, float8 r, float8 g, float8 b, float8 w) {
  if (n == CLR_FILM_LANES) { /* whole runs: 24 rgb and 8 weight sums in 4-lane vectors */
    const float4 rgb[6] = {(float4)(r.s0, g.s0, b.s0, r.s1), (float4)(g.s1, b.s1, r.s2, g.s2),
                           (float4)(b.s2, r.s3, g.s3, b.s3), (float4)(r.s4, g.s4, b.s4, r.s5),
                           (float4)(g.s5, b.s5, r.s6, g.s6), (float4)(b.s6, r.s7, g.s7, b.s7)};
    __global double *at = rgb_sum + 3 * i;
    for (int k = 0; k < 6; ++k) vstore4(vload4(k, at) + convert_double4(rgb[k]), k, at);
    vstore4(vload4(0, weight_sum + i) + convert_double4(w.lo), 0, weight_sum + i);
    vstore4(vload4(1, weight_sum + i) + convert_double4(w.hi), 1, weight_sum + i);
    return;
  }
  float rs[CLR_FILM_LANES], gs[CLR_FILM_LANES], bs[CLR_FILM_LANES], ws[CLR_FILM_LANES];
  vstore8(r, 0, rs);
  vstore8(g, 0, gs);
  vstore8(b, 0, bs);
  vstore8(w, 0, ws);
  for (int k = 0; k < n; ++k) {
    rgb_sum[3 * (i + k)] += (double)rs[k];
    rgb_sum[3 * (i + k) + 1] += (double)gs[k];
    rgb_sum[3 * (i + k) + 2] += (double)bs[k];
    weight_sum[i + k] += (double)ws[k];
  }
}

/* clr_film_gather8 adding each run's sums straight into the film's double sums (rgb_sum: 3 per
 * pixel, weight_sum: 1, row-major over the pixel bounds of fp; the output region lies inside
 * them), for devices that share the host's memory: the same additions in the same order as the
 * host's add of the chunk's float sums, with no float sums buffer. */
__kernel void clr_film_gather8_add(clr_film_params fp, clr_film_grid grid,
                                   __global const float *weighed, __global const uint *starts,
                                   __global double *rgb_sum, __global double *weight_sum) {
  const int run_x0 = grid.out_x0 + (int)get_global_id(0) * CLR_FILM_LANES;
  if (run_x0 >= grid.out_x0 + grid.out_w) return;
  const int n = min(CLR_FILM_LANES, grid.out_x0 + grid.out_w - run_x0); /* the run's pixels */
  const int oy = 2 * (int)get_global_id(1);
  const clr_film_run8 a = clr_film_gather_run8(&grid, weighed, starts, run_x0, run_x0 + n, oy);
  const size_t width = (size_t)(fp.pixel_x1 - fp.pixel_x0);
  const size_t i =
      (size_t)(grid.out_y0 + oy - fp.pixel_y0) * width + (size_t)(run_x0 - fp.pixel_x0);
  clr_film_add_doubles8(rgb_sum, weight_sum, i, n, a.r0, a.g0, a.b0, a.w0);
  if (oy + 1 < grid.out_h)
    clr_film_add_doubles8(rgb_sum, weight_sum, i + width, n, a.r1, a.g1, a.b1, a.w1);
}
#endif
