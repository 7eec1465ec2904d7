/* TEMPORARY stand-in for the filter helper's host code (film branch only; replaced at merge):
 * box and triangle descriptions, parameters and pbrt-v3's 16x16 table. */
#include <math.h>
#include <string.h>
#include "clr_internal.h"
#include "filter_funcs.h"
#include "filter_stub.h"

void clr_filter_desc_init(clr_filter_desc *desc, clr_filter_type type) {
  if (!desc) return;
  memset(desc, 0, sizeof *desc);
  desc->struct_size = sizeof *desc;
  desc->type = type;
  float r = type == CLR_FILTER_BOX ? 0.5f : 2.0f;
  desc->radius[0] = desc->radius[1] = r;
  desc->alpha = 2.0f;
  desc->b = desc->c = 1.0f / 3.0f;
  desc->tau = 3.0f;
  desc->use_table = 1;
}

clr_result clr_filter_params_make(const clr_filter_desc *desc, clr_filter_params *params) {
  if (!desc || !params) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_filter_params_make: NULL");
  if ((int)desc->type != CLR_FILTER_TYPE_BOX && (int)desc->type != CLR_FILTER_TYPE_TRIANGLE)
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER, "stub filter: type %d", (int)desc->type);
  for (int i = 0; i < 2; ++i)
    if (!(desc->radius[i] > 0.0f) || isinf(desc->radius[i]))
      return clr_fail(NULL, CLR_ERROR_INVALID_RADIUS, "filter radius[%d] = %g", i,
                      (double)desc->radius[i]);
  memset(params, 0, sizeof *params);
  params->type = (clr_i32)desc->type;
  params->use_table = desc->use_table ? 1 : 0;
  params->radius_x = desc->radius[0];
  params->radius_y = desc->radius[1];
  params->inv_radius_x = 1.0f / desc->radius[0];
  params->inv_radius_y = 1.0f / desc->radius[1];
  return CLR_SUCCESS;
}

clr_result clr_filter_make_table(const clr_filter_params *params, float table[256]) {
  if (!params || !table) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_filter_make_table: NULL");
  for (int y = 0; y < CLR_FILTER_TABLE_SIZE; ++y)
    for (int x = 0; x < CLR_FILTER_TABLE_SIZE; ++x) {
      float px = ((float)x + 0.5f) * params->radius_x / (float)CLR_FILTER_TABLE_SIZE;
      float py = ((float)y + 0.5f) * params->radius_y / (float)CLR_FILTER_TABLE_SIZE;
      table[y * CLR_FILTER_TABLE_SIZE + x] = clr_filter_eval_exact(params, px, py);
    }
  return CLR_SUCCESS;
}
