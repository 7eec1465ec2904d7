/* Film accumulation: one work-group per accumulation tile. The group loads the tile's samples
 * (binned by the host, in batch order) into local memory chunk by chunk; each work-item owns
 * pixels of the tile and sums their contributions in private registers in batch order. No two
 * work-items write one address, no atomics: every pixel's sums are the same float operations in
 * the same order whatever the tile size or work-group size, and the same as the host reference. */
#include "film_funcs.h"

/* params: film and filter; table: pbrt 16x16 filter table; samples: CLR_FILM_SAMPLE_FLOATS each;
 * tiles[g]: tile index of group g; starts[g]..starts[g+1]: its range in `order` (sample indices);
 * sums: per group, T*T pixels (row-major in the tile) x CLR_FILM_SUM_FLOATS. */
__kernel void clr_film_accumulate_tiles(clr_film_params fp, clr_filter_params filt,
                                        __global const float *table,
                                        __global const float *samples,
                                        __global const uint *tiles,
                                        __global const uint *starts,
                                        __global const uint *order,
                                        __global float *sums) {
  __local clr_film_prepared cache[CLR_FILM_GROUP_MAX];
  const uint group = get_group_id(0);
  const uint lid = get_local_id(0);
  const uint gsize = get_local_size(0);
  const int T = fp.tile_size;
  const uint tile = tiles[group];
  const int tile_x0 = fp.pixel_x0 + (int)(tile % (uint)fp.tiles_x) * T;
  const int tile_y0 = fp.pixel_y0 + (int)(tile / (uint)fp.tiles_x) * T;
  const uint first = starts[group];
  const uint count = starts[group + 1] - first;
  const uint pixels = (uint)(T * T);
  __global float *out = sums + (size_t)group * pixels * CLR_FILM_SUM_FLOATS;

  for (uint pass = 0; pass < pixels; pass += gsize) {
    const uint p = pass + lid;
    const int px = tile_x0 + (int)(p % (uint)T);
    const int py = tile_y0 + (int)(p / (uint)T);
    float acc[CLR_FILM_SUM_FLOATS] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (uint chunk = 0; chunk < count; chunk += gsize) {
      barrier(CLK_LOCAL_MEM_FENCE);
      if (chunk + lid < count) {
        __global const float *s = samples + (size_t)order[first + chunk + lid] * CLR_FILM_SAMPLE_FLOATS;
        clr_film_prepared prep;
        clr_film_prepare(&fp, &filt, s[0], s[1], s[2], s[3], s[4], s[5], &prep);
        cache[lid] = prep;
      }
      barrier(CLK_LOCAL_MEM_FENCE);
      const uint n = min(gsize, count - chunk);
      for (uint j = 0; j < n; ++j) {
        clr_film_prepared s = cache[j];
        clr_film_accumulate(&filt, table, &s, px, py, acc);
      }
    }
    if (p < pixels)
      for (int c = 0; c < CLR_FILM_SUM_FLOATS; ++c) out[(size_t)p * CLR_FILM_SUM_FLOATS + c] = acc[c];
  }
}
