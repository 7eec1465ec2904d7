/* pbrt-v3's Sobol tables, generated at build time from data/joe-kuo-sobol-1024.txt by
 * tools/gen_sobol_tables.c (build/generated/sobol_tables.c, compiled into the library). */
#ifndef CLR_SOBOL_TABLES_H
#define CLR_SOBOL_TABLES_H

#include <stdint.h>
#include "sobol_funcs.h"

/* Rows of the (pixel, sample number) -> index tables: one per log2 resolution m = 1 .. 26. */
#define CLR_SOBOL_VDC_MATRICES 26
_Static_assert(CLR_SOBOL_VDC_MATRICES == CLR_SOBOL_MAX_LOG2_RESOLUTION,
               "the kernels' resolution limit must match the generated tables");

/* pbrt-v3 SobolMatrices32: dimension d's 52 generator-matrix columns at [d * 52 + k], each the
 * Joe-Kuo direction number m_(k+1) as 32-bit fixed point (dimension 0: van der Corput). */
extern const uint32_t clr_sobol_matrices32[CLR_SOBOL_DIMENSIONS * CLR_SOBOL_MATRIX_SIZE];

/* pbrt-v3 VdCSobolMatrices[m-1][c]: the pixel bits ((x << m) | y, top m bits of dimensions 0
 * and 1) that index bit 2m + c sets; 52 - 2m columns used, the rest zero (row 26: pbrt-v3 has
 * no such row; it is all zero, a pixel at m = 26 holds one sample). */
extern const uint64_t clr_vdc_sobol_matrices[CLR_SOBOL_VDC_MATRICES][CLR_SOBOL_MATRIX_SIZE];

/* pbrt-v3 VdCSobolMatricesInv[m-1][c]: the low 2m index bits whose points differ from index 0's
 * by pixel bit c alone (GF(2) inverse of index bits 0 .. 2m-1); 2m columns used, rest zero. */
extern const uint64_t clr_vdc_sobol_matrices_inv[CLR_SOBOL_VDC_MATRICES][CLR_SOBOL_MATRIX_SIZE];

#endif
