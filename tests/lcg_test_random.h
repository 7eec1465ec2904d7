/* The tests' 32-bit LCG (Numerical Recipes' constants) on a state the test keeps: each call steps
 * it once and returns its top 24 bits as a float or double in [0, 1). */
#ifndef CLR_LCG_TEST_RANDOM_H
#define CLR_LCG_TEST_RANDOM_H

#include <stdint.h>

static inline float lcg_float(uint32_t *s) {
  *s = *s * 1664525u + 1013904223u;
  return (float)(*s >> 8) / 16777216.0f;
}

static inline double lcg_double(uint32_t *s) {
  *s = *s * 1664525u + 1013904223u;
  return (*s >> 8) / 16777216.0;
}

#endif
