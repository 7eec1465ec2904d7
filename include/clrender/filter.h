/* TEMPORARY stand-in for the filter helper's public header (film branch only; replaced at merge).
 * Holds exactly the contract the film code relies on. */
#ifndef CLRENDER_FILTER_H
#define CLRENDER_FILTER_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum clr_filter_type { CLR_FILTER_BOX = 0, CLR_FILTER_TRIANGLE = 1 } clr_filter_type;

/* Defined in kernels/filter_types.h. */
typedef struct clr_filter_params clr_filter_params;

typedef struct clr_filter_desc {
  size_t struct_size;
  clr_filter_type type;
  float radius[2];
  float alpha, b, c, tau;
  int32_t use_table;
} clr_filter_desc;

void clr_filter_desc_init(clr_filter_desc *desc, clr_filter_type type);
clr_result clr_filter_params_make(const clr_filter_desc *desc, clr_filter_params *params);
clr_result clr_filter_make_table(const clr_filter_params *params, float table[256]);

#ifdef __cplusplus
}
#endif
#endif
