/* pbrt-v3's Halton tables (first 1000 primes, their scrambling digit permutations) and the
 * HaltonSampler constructor's scales, built on the host. */
#ifndef CLR_HALTON_TABLES_H
#define CLR_HALTON_TABLES_H

#include <stddef.h>
#include <stdint.h>
/* GCC does not know clr_platform.h's "#pragma STDC FP_CONTRACT" (-ffp-contract=off does the job). */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunknown-pragmas"
#include "halton_funcs.h"
#pragma GCC diagnostic pop

/* Sum of the first CLR_HALTON_PRIMES primes: entries of pbrt-v3's permutation table. */
#define CLR_HALTON_PERMUTATION_COUNT 3682913u
/* All entries of clr_halton_permutations(): pbrt-v3's permutations, the identity permutation of
 * the unscrambled base-3 record, then the chunk and tail tables of the bases below 128. */
#define CLR_HALTON_TABLE_ENTRIES 3965994u

/* The entries of every table set beyond its permutations: the identity permutation of the
 * unscrambled base-3 record, then the chunk and tail tables of the bases below 128. */
#define CLR_HALTON_CHUNK_ENTRIES (CLR_HALTON_TABLE_ENTRIES - CLR_HALTON_PERMUTATION_COUNT)

/* A set of Halton tables covering the primes of dimensions [0, extent): their records, the
 * unscrambled base-3 record (CLR_HALTON_BASE3_RECORD) and a u16 table their offsets point into,
 * which starts with pbrt-v3's radicalInversePermutations of those primes (every permutation,
 * concatenated in prime order, from a default-constructed RNG: the same values as pbrt-v3's first
 * ones). Records of primes past the extent are zero. */
typedef struct clr_halton_tables {
  const clr_halton_prime *primes; /* CLR_HALTON_PRIME_RECORDS records */
  const clr_u16 *permutations;
  size_t entries;                            /* u16 entries of permutations */
  int extent;                                /* primes covered: 64, 256 or CLR_HALTON_PRIMES */
  const char *primes_key, *permutations_key; /* names of their shared device buffers */
} clr_halton_tables;

/* The smallest set covering dimensions [0, dimensions) (all CLR_HALTON_PRIMES past 256). Each set
 * is built once, on first use (thread-safe), never freed or changed afterwards. */
const clr_halton_tables *clr_halton_tables_covering(int dimensions);
/* Dimensions [0, n) a pbrt-v3 Halton request layout reads: n = max(source + dims) over slots. */
int clr_halton_layout_dimensions(const clr_request_slot *slots, int count);
/* The records of the set covering every prime (clr_halton_tables_covering(CLR_HALTON_PRIMES)). */
const clr_halton_prime *clr_halton_primes(void);
/* That set's u16 table; *count (may be NULL) receives CLR_HALTON_TABLE_ENTRIES. */
const clr_u16 *clr_halton_permutations(size_t *count);

/* A pair table (kernels/halton_funcs.h): B = base^digits lo entries, `tops` top entries. */
typedef struct clr_halton_pair_shape {
  clr_u32 digits, tops;
} clr_halton_pair_shape;
/* The pair table of record pr with the fewest entries for arguments below `limit` (digits 0:
 * none fits, see CLR_HALTON_PAIR_HEADER). */
clr_halton_pair_shape clr_halton_pair_shape_for(const clr_halton_prime *pr, uint64_t limit);
/* u16 entries of that table. */
size_t clr_halton_pair_entries(const clr_halton_prime *pr, clr_halton_pair_shape shape);
/* Writes the table into out (clr_halton_pair_entries entries); `pr` and `permutations` from one
 * clr_halton_tables set. */
void clr_halton_pair_table(const clr_halton_prime *pr, const clr_u16 *permutations,
                           clr_halton_pair_shape shape, clr_u16 *out);
/* u16 entries of the table's lane rows (0, none: B above CLR_HALTON_PAIR_MOST_ROW_CHUNK). */
size_t clr_halton_pair_row_entries(const clr_halton_prime *pr, clr_halton_pair_shape shape);
/* Writes the lane rows of `table` (written by clr_halton_pair_table, with its entries) right after
 * it and their offset into its header (layout: CLR_HALTON_PAIR_HEADER), for the 8 lanes of a
 * work-item whose arguments are a_0 + j * step with a nonzero top part. */
void clr_halton_pair_rows(const clr_halton_prime *pr, clr_halton_pair_shape shape, clr_u32 step,
                          clr_u16 *table);

/* Fills halton_scale, halton_exponent, halton_mult_inverse and halton_stride from the sample
 * bounds p->sample_x0..sample_y1 as pbrt-v3's HaltonSampler constructor (kMaxResolution 128). */
void clr_halton_setup(clr_sampler_params *p);

#endif
