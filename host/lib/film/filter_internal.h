/* Filters inside the library: the kernels' parameter block (kernels/filter_types.h) made from a
 * public clr_filter_desc, its pbrt-v3 table and host evaluation. */
#ifndef CLR_FILTER_INTERNAL_H
#define CLR_FILTER_INTERNAL_H

#include "clrender/filter.h"
#include "filter_types.h"

/* Validates `desc` (errors as clr_filter_check) and fills the kernels' parameter block (1/radius,
 * 1/tau and the gaussian's e^(-alpha r^2) precomputed). *out is written only on success. */
clr_result clr_filter_params_make(const clr_filter_desc *desc, clr_filter_params *out);

/* pbrt-v3's 16x16 table for `params`, bit-identical to the device's. */
clr_result clr_filter_params_table(const clr_filter_params *params,
                                   float table[CLR_FILTER_TABLE_ENTRIES]);

/* Host evaluation with the kernels' code: clr_filter_eval (table mode when params->use_table,
 * reading `table`, or computing the entry itself when table is NULL). 0 for a NULL params. */
float clr_filter_params_evaluate(const clr_filter_params *params, const float *table, float x,
                                 float y);

#endif
