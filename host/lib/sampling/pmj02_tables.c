/* pmj02bn's GetPixel2D table (pbrt-v4 PMJ02BNSampler::PMJ02BNSampler) from its point set 0. */
#include "pmj02_tables.h"
#include <stdlib.h>
#include "pbrt_v4_sampler_funcs.h"
#include "sobol_tables.h"

static int32_t log4_int(int32_t v) {
  int32_t l = 0;
  while ((v >> (l + 1)) > 0) ++l;
  return l / 2;
}

int32_t clr_pmj02_tile_size(int32_t spp) {
  int32_t up = spp == 1 << (2 * log4_int(spp)) ? spp : 1 << (2 * (1 + log4_int(spp)));
  return 1 << (log4_int(CLR_PMJ02_POINTS) - log4_int(up));
}

float *clr_pmj02_pixel_table(int32_t spp, int32_t tile) {
  int32_t pixels = tile * tile, bits = log4_int(tile * tile); /* tile = 2^bits */
  size_t pixel_floats = 2 * (size_t)pixels * (size_t)spp;
  float *table = malloc(sizeof(float) * (pixel_floats + 2 * CLR_PMJ02_SETS * (size_t)spp));
  int32_t *stored = calloc((size_t)pixels, sizeof(int32_t));
  if (!table || !stored) {
    free(table);
    free(stored);
    return NULL;
  }
  for (uint32_t i = 0; i < CLR_PMJ02_POINTS; ++i) {
    uint32_t x = clr_pmj02_point(0, i, 0, clr_sobol_matrices32);
    uint32_t y = clr_pmj02_point(0, i, 1, clr_sobol_matrices32);
    /* p * tile: the pixel is the top `bits` bits, the offset the rest (exact in double) */
    int32_t pixel =
        (int32_t)(bits ? x >> (32 - bits) : 0) + (int32_t)(bits ? y >> (32 - bits) : 0) * tile;
    if (stored[pixel] == spp) continue;
    float *xy = table + 2 * ((size_t)pixel * (size_t)spp + (size_t)stored[pixel]++);
    xy[0] = (float)((double)(uint32_t)(x << bits) * 0x1p-32);
    xy[1] = (float)((double)(uint32_t)(y << bits) * 0x1p-32);
  }
  free(stored);
  float *sets = table + pixel_floats;
  for (int32_t set = 0; set < CLR_PMJ02_SETS; ++set)
    for (uint32_t i = 0; i < (uint32_t)spp; ++i)
      for (int32_t c = 0; c < 2; ++c)
        sets[2 * ((size_t)set * (size_t)spp + i) + (size_t)c] =
            (float)clr_pmj02_point(set, i, c, clr_sobol_matrices32) * 0x1p-32f;
  return table;
}
