/* Film accumulation: a gather over samples binned by the host by their first reached pixel
 * (y0, x0) (stable, batch order inside a bin). A work-item owns one pixel and adds, bin row by
 * bin row (ascending y0), the samples of the bins x0 in [px - K + 1, px] (one contiguous range
 * of the binned samples per bin row) that reach it, in their binned order: the canonical order
 * of film.h whatever the work-group size. No two work-items write one address, no atomics. */
#include "film_funcs.h"

/* params: film; filt: filter; table: pbrt 16x16 filter table; binned: CLR_FILM_BINNED_FLOATS per
 * sample in bin order; starts[b]..starts[b+1]: bin b's range (bins_x * bins_y + 1 entries);
 * sums: CLR_FILM_SUM_FLOATS per pixel of the grid's output region, row-major. Global size:
 * (out_w rounded up to the work-group size, out_h); local size (G, 1). */
__kernel void clr_film_gather(clr_film_params fp, clr_filter_params filt, clr_film_grid grid,
                              __global const float *table, __global const float *binned,
                              __global const uint *starts, __global float *sums) {
  const int px = grid.out_x0 + (int)get_global_id(0);
  const int py = grid.out_y0 + (int)get_global_id(1);
  const int kx = grid.reach_x, ky = grid.reach_y;
  /* Bin columns this pixel gathers: x0 in [px - K + 1, px], clipped to the grid. */
  const int cx0 = max(px - kx + 1 - grid.bin_x0, 0);
  const int cx1 = min(px - grid.bin_x0, grid.bins_x - 1);
  float acc[CLR_FILM_SUM_FLOATS] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int j = 0; j < ky; ++j) {
    const int row = py - ky + 1 + j - grid.bin_y0;
    if (row < 0 || row >= grid.bins_y || cx0 > cx1) continue;
    const uint end = starts[row * grid.bins_x + cx1 + 1];
    for (uint i = starts[row * grid.bins_x + cx0]; i < end; ++i) {
      __global const float *s = binned + (size_t)i * CLR_FILM_BINNED_FLOATS;
      const float dx = s[0], dy = s[1];
      /* Branch-free (random positions defeat branch prediction): a sample that does not reach
       * the pixel adds zeros, which leave the sums' bits unchanged. */
      const int reached = (px <= clr_film_last_pixel(dx, filt.radius_x)) &
                          (py <= clr_film_last_pixel(dy, filt.radius_y));
      const float fw = clr_film_filter_weight(&filt, table, dx, dy, px, py);
      clr_film_add(s[2], s[3], s[4], s[5], select(0.0f, fw, reached), acc);
    }
  }
  if (px < grid.out_x0 + grid.out_w) {
    __global float *out = sums + ((size_t)get_global_id(1) * (size_t)grid.out_w +
                                  (size_t)(px - grid.out_x0)) * CLR_FILM_SUM_FLOATS;
    for (int c = 0; c < CLR_FILM_SUM_FLOATS; ++c) out[c] = acc[c];
  }
}
