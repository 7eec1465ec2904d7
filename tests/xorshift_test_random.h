/* The film tests' sample values: a 32-bit xorshift (13, 17, 5) that a test seeds by setting
 * rng_state (XORSHIFT_TEST_SEED, when the including test defines it, before any), and floats in
 * [0, 1) from its top 24 bits. */
#ifndef CLR_XORSHIFT_TEST_RANDOM_H
#define CLR_XORSHIFT_TEST_RANDOM_H

#include <stdint.h>

#ifndef XORSHIFT_TEST_SEED
#define XORSHIFT_TEST_SEED 0u
#endif

static uint32_t rng_state = XORSHIFT_TEST_SEED;

static float rnd(void) {
  rng_state ^= rng_state << 13;
  rng_state ^= rng_state >> 17;
  rng_state ^= rng_state << 5;
  return (float)(rng_state >> 8) * 0x1p-24f;
}

#endif
