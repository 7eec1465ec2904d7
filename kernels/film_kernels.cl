/* Film accumulation: a gather over samples binned by the host by their first reached pixel
 * (y0, x0) (stable, batch order inside a bin). A work-item owns a run of T (the accumulation
 * tile size) pixels of one row, in private sums. Bin row by bin row (ascending y0) it walks the
 * samples of the bins x0 in [run_x0 - K + 1, run_x1 - 1] (one contiguous range of the binned
 * samples per bin row) in their binned order and adds each one to the run's pixels it reaches:
 * every pixel sees its samples in the canonical order of film.h, whatever T, the work-group size
 * or the device. No two work-items write one address, no atomics. */
#include "film_funcs.h"

#define CLR_FILM_RUN_MAX 64 /* largest accumulation tile size */

/* params: film (tile_size = T); filt: filter; grid: the chunk's bins and output region; table:
 * pbrt 16x16 filter table; binned: CLR_FILM_BINNED_FLOATS per sample in bin order;
 * starts[b]..starts[b+1]: bin b's range (bins_x * bins_y + 1 entries); sums: CLR_FILM_SUM_FLOATS
 * per pixel of the output region, row-major. Global size: (runs per row rounded up to the
 * work-group size, out_h). */
__kernel void clr_film_gather(clr_film_params fp, clr_filter_params filt, clr_film_grid grid,
                              __global const float *table, __global const float *binned,
                              __global const uint *starts, __global float *sums) {
  const int out_x1 = grid.out_x0 + grid.out_w;
  const int run_x0 = grid.out_x0 + (int)get_global_id(0) * fp.tile_size;
  if (run_x0 >= out_x1) return;
  const int run_x1 = min(run_x0 + fp.tile_size, out_x1); /* exclusive */
  const int py = grid.out_y0 + (int)get_global_id(1);
  float acc[CLR_FILM_RUN_MAX * CLR_FILM_SUM_FLOATS];
  for (int i = 0; i < (run_x1 - run_x0) * CLR_FILM_SUM_FLOATS; ++i) acc[i] = 0.0f;
  /* Bin columns whose samples can reach the run, clipped to the grid. */
  const int cx0 = max(run_x0 - grid.reach_x + 1 - grid.bin_x0, 0);
  const int cx1 = min(run_x1 - 1 - grid.bin_x0, grid.bins_x - 1);
  for (int j = 0; j < grid.reach_y; ++j) {
    const int row = py - grid.reach_y + 1 + j - grid.bin_y0;
    if (row < 0 || row >= grid.bins_y || cx0 > cx1) continue;
    const uint end = starts[row * grid.bins_x + cx1 + 1];
    for (uint i = starts[row * grid.bins_x + cx0]; i < end; ++i) {
      __global const float *s = binned + (size_t)i * CLR_FILM_BINNED_FLOATS;
      const float dx = s[0], dy = s[1];
      if (py > clr_film_last_pixel(dy, filt.radius_y)) continue;
      const int x0 = max(clr_film_first_pixel(dx, filt.radius_x), run_x0);
      const int x1 = min(clr_film_last_pixel(dx, filt.radius_x), run_x1 - 1);
      for (int x = x0; x <= x1; ++x)
        clr_film_add(s[2], s[3], s[4], s[5], clr_film_filter_weight(&filt, table, dx, dy, x, py),
                     acc + (x - run_x0) * CLR_FILM_SUM_FLOATS);
    }
  }
  __global float *out = sums + ((size_t)get_global_id(1) * (size_t)grid.out_w +
                                (size_t)(run_x0 - grid.out_x0)) * CLR_FILM_SUM_FLOATS;
  for (int i = 0; i < (run_x1 - run_x0) * CLR_FILM_SUM_FLOATS; ++i) out[i] = acc[i];
}
