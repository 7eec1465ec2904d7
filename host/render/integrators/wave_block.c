#include "wave_block.h"
#include <stdlib.h>

float *clr_wave_block_alloc(int32_t n, int columns, size_t *stride) {
  size_t entries = (size_t)(n > 0 ? n : 1);
  size_t s = entries + 15 - (entries + 15) % 16; /* whole 64-byte lines */
  if (s % 32 == 0) s += 16;                      /* an odd number of lines */
  *stride = s;
  return aligned_alloc(64, s * (size_t)columns * sizeof(float));
}
