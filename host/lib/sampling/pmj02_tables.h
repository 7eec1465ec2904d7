/* pmj02bn's GetPixel2D and point-set tables, built per sampler as pbrt-v4's PMJ02BNSampler constructor does. */
#ifndef CLR_PMJ02_TABLES_H
#define CLR_PMJ02_TABLES_H

#include <stdint.h>

/* pbrt-v4's pixelTileSize for spp (1..CLR_PMJ02_POINTS): 2^(8 - Log4Int(RoundUpPow4(spp))). */
int32_t clr_pmj02_tile_size(int32_t spp);
/* (x, y) pairs, tile * tile * spp of them: the first CLR_PMJ02_POINTS points of set 0 sorted into
 * the tile's pixels (the first spp in each, in sequence order), as offsets inside the pixel; then
 * CLR_PMJ02_SETS * spp more: the first spp points of each point set (clr_v4_pmj02_set_point).
 * Returns NULL when out of memory; free() it. */
float *clr_pmj02_pixel_table(int32_t spp, int32_t tile);

#endif
