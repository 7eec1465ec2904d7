/* The wave tests' inputs: a 64-bit LCG from a seed the including test defines, and random unit
 * vectors from it (rejection in the unit ball). */
#ifndef CLR_WAVE_TEST_RANDOM_H
#define CLR_WAVE_TEST_RANDOM_H

#include <stdint.h>
#include "lambertian.h"

#ifndef WAVE_TEST_SEED
#error "define WAVE_TEST_SEED before including wave_test_random.h"
#endif

static uint64_t rng_state = WAVE_TEST_SEED;

static float uniform(void) { /* [0, 1) */
  rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (float)(rng_state >> 40) * 0x1p-24f;
}

static void random_unit(float v[3]) {
  float l2;
  do {
    for (int a = 0; a < 3; ++a) v[a] = 2.0f * uniform() - 1.0f;
    l2 = rs_dot(v, v);
  } while (!(l2 > 1e-4f) || l2 > 1.0f);
  rs_normalize(v);
}

#endif
