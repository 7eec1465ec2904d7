/* pbrt-v4's DigitPermutation tables for the halton sampler with permuted digits, built on the
 * host for the dimensions a launch reads, so that the kernels look each digit's permutation up
 * instead of hashing it (clr_v4_scrambled_radical_inverse; same values). */
#ifndef CLR_V4_DIGIT_TABLES_H
#define CLR_V4_DIGIT_TABLES_H

#include <stddef.h>
#include <stdint.h>
#include "halton_funcs.h"

typedef struct clr_v4_digit_tables {
  uint32_t seed;
  int dims;                            /* dimensions 0..dims-1 have tables; 0: none built */
  uint32_t offsets[CLR_HALTON_PRIMES]; /* dimension d's table starts at perms[offsets[d]] */
  uint16_t *perms;                     /* per dimension (base b): digits x b entries */
  size_t count;                        /* entries in perms */
} clr_v4_digit_tables;

/* Makes t hold the tables of dimensions 0..dims-1 (dims <= CLR_HALTON_PRIMES) for seed; a table
 * for the same seed and as many dimensions or more is kept. Returns 1 when t changed, 0 when it
 * was kept, -1 when out of memory (t then holds no tables). */
int clr_v4_digit_tables_make(clr_v4_digit_tables *t, uint32_t seed, int dims);
void clr_v4_digit_tables_free(clr_v4_digit_tables *t);

#endif
