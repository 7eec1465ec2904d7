#include "v4_digit_tables.h"

#include <stdlib.h>
#include "halton_tables.h"
#include "pbrt_v4_sampler_funcs.h"

void clr_v4_digit_tables_free(clr_v4_digit_tables *t) {
  free(t->perms);
  t->perms = NULL;
  t->count = 0;
  t->dims = 0;
}

int clr_v4_digit_tables_make(clr_v4_digit_tables *t, uint32_t seed, int dims) {
  if (dims > CLR_HALTON_PRIMES) dims = CLR_HALTON_PRIMES;
  if (t->dims > 0 && t->seed == seed && t->dims >= dims) return 0;
  const clr_halton_prime *primes = clr_halton_primes();
  size_t count = 0;
  for (int d = 0; d < dims; ++d) count += (size_t)primes[d].v4_digits * primes[d].base;
  clr_v4_digit_tables_free(t);
  t->perms = malloc((count ? count : 1) * sizeof *t->perms);
  if (!t->perms) return -1;
  size_t at = 0;
  for (int d = 0; d < dims; ++d) {
    uint32_t base = primes[d].base;
    int digits = (int)primes[d].v4_digits;
    t->offsets[d] = (uint32_t)at;
    for (int i = 0; i < digits; ++i)
      for (uint32_t digit = 0; digit < base; ++digit)
        t->perms[at++] = (uint16_t)clr_v4_digit_permutation(base, i, digit, seed);
  }
  t->seed = seed;
  t->dims = dims;
  t->count = count;
  return 1;
}
