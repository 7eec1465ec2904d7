/* One allocation holding a wave's structure-of-arrays columns. */
#ifndef CLR_WAVE_BLOCK_H
#define CLR_WAVE_BLOCK_H

#include <stddef.h>
#include <stdint.h>

/* A block of `columns` columns of at least n 4-byte entries each, every column 64-byte aligned
 * and an odd number of cache lines after the previous one (at a power-of-two stride the columns'
 * k-th entries would share one or two first-level cache sets). Column c starts at block + c *
 * *stride. NULL when out of memory; free() releases it. */
float *clr_wave_block_alloc(int32_t n, int columns, size_t *stride);

#endif
