/* The host's fast Halton values: pbrt-v3's HaltonSampler values from pair tables
 * (clr_halton_pair_value in kernels/halton_funcs.h), the same bits as clr_halton_sampler_value. */
#ifndef CLR_HALTON_HOST_H
#define CLR_HALTON_HOST_H

#include "halton_tables.h"

/* Pair tables of the records of dimensions [1, dimensions) for indices below index_limit, built
 * once and never changed (threads may read them together). Arguments at or past a record's
 * limit, and records without a table (none fits, or past the entry budget), take
 * clr_halton_sampler_value. */
typedef struct clr_halton_host_pairs {
  const clr_halton_tables *tables; /* covering dimensions [0, dimensions) */
  int dimensions;
  uint64_t index_limit;
  clr_u32 limit[CLR_HALTON_PRIME_RECORDS];  /* record's arguments below it use its table; 0: none */
  clr_u32 offset[CLR_HALTON_PRIME_RECORDS]; /* its table in entries */
  clr_u16 *entries;
  struct clr_halton_host_pairs *older; /* superseded sets, freed with this one */
} clr_halton_host_pairs;

/* NULL when out of memory. scale1: the sampler's halton_scale[1] (dimension 1's arguments are
 * index / scale1). */
clr_halton_host_pairs *clr_halton_host_pairs_create(int dimensions, uint64_t index_limit,
                                                    clr_u32 scale1);
/* Frees hp and every older set chained to it. */
void clr_halton_host_pairs_free(clr_halton_host_pairs *hp);

/* Items per block of clr_halton_host_values' callers (their indices on the stack). */
#define CLR_HALTON_HOST_BLOCK 256

/* out[i * stride] = clr_halton_sampler_value(p, hp's primes, hp's permutations, index[i], dim)
 * for i < n, dim below hp's dimensions (or past CLR_HALTON_PRIMES): one dimension's values, its
 * pair table read where the argument is below its limit. */
void clr_halton_host_values(const clr_halton_host_pairs *hp, const clr_sampler_params *p,
                            clr_i32 dim, const clr_u64 *index, clr_i32 n, float *out,
                            size_t stride);

/* clr_global_sample_vector of every item of p's batch into values (items' vectors one after the
 * other) and, when indices is not NULL, their indices; the slots' dimensions below hp's. */
void clr_halton_host_batch(const clr_halton_host_pairs *hp, const clr_sampler_params *p,
                           const clr_request_slot *slots, float *values, clr_u64 *indices);

#endif
