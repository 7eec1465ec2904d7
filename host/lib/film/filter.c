/* Reconstruction filter descriptions: pbrt-v3 defaults, names, validation, the 16x16 table. */
#include <math.h>
#include <string.h>
#include "clr_internal.h"
#include "filter_funcs.h"
#include "filter_internal.h"

_Static_assert(sizeof(clr_filter_params) % 16 == 0, "clr_filter_params must be 16-byte sized");
_Static_assert(CLR_FILTER_TABLE_SIZE *CLR_FILTER_TABLE_SIZE == CLR_FILTER_TABLE_ENTRIES,
               "table size mismatch");
_Static_assert(CLR_FILTER_BOX == CLR_FILTER_TYPE_BOX &&
                   CLR_FILTER_TRIANGLE == CLR_FILTER_TYPE_TRIANGLE &&
                   CLR_FILTER_GAUSSIAN == CLR_FILTER_TYPE_GAUSSIAN &&
                   CLR_FILTER_MITCHELL == CLR_FILTER_TYPE_MITCHELL &&
                   CLR_FILTER_SINC == CLR_FILTER_TYPE_SINC &&
                   CLR_FILTER_BLACKMANHARRIS == CLR_FILTER_TYPE_BLACKMANHARRIS &&
                   CLR_FILTER_CATMULLROM == CLR_FILTER_TYPE_CATMULLROM,
               "public and kernel filter types differ");

static const char *const filter_names[CLR_FILTER_TYPE_COUNT] = {
    "box", "triangle", "gaussian", "mitchell", "sinc", "blackmanharris", "catmullrom"};

/* Default radius (xwidth = ywidth) per type. */
static const float default_radius[CLR_FILTER_TYPE_COUNT] = {0.5f, 2.0f, 2.0f, 2.0f,
                                                            4.0f, 2.0f, 2.0f};

static int valid_type(int type) { return type >= 0 && type < CLR_FILTER_TYPE_COUNT; }

void clr_filter_desc_init(clr_filter_desc *desc, clr_filter_type type) {
  if (!desc) return;
  memset(desc, 0, sizeof *desc);
  desc->struct_size = sizeof *desc;
  desc->type = type;
  float radius = valid_type((int)type) ? default_radius[type] : default_radius[CLR_FILTER_BOX];
  desc->radius[0] = desc->radius[1] = radius;
  desc->alpha = 2.0f;
  desc->b = desc->c = 1.0f / 3.0f;
  if (type == CLR_FILTER_CATMULLROM) {
    desc->b = 0.0f;
    desc->c = 0.5f;
  }
  desc->tau = 3.0f;
  desc->use_table = 0;
}

clr_result clr_filter_type_from_name(const char *name, clr_filter_type *type) {
  if (!name || !type)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_filter_type_from_name: %s is NULL",
                    name ? "type" : "name");
  for (int i = 0; i < CLR_FILTER_TYPE_COUNT; ++i) {
    if (strcmp(name, filter_names[i]) == 0) {
      *type = (clr_filter_type)i;
      return CLR_SUCCESS;
    }
  }
  return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                  "clr_filter_type_from_name: unknown filter \"%.200s\" (expected box, triangle, "
                  "gaussian, mitchell, sinc, blackmanharris or catmullrom)",
                  name);
}

const char *clr_filter_type_name(clr_filter_type type) {
  return valid_type((int)type) ? filter_names[type] : "unknown";
}

static clr_result check_radius(float radius, int axis) {
  if (!(radius >= CLR_FILTER_MIN_RADIUS && radius <= CLR_FILTER_MAX_RADIUS))
    return clr_fail(NULL, CLR_ERROR_INVALID_RADIUS,
                    "clr_filter_params_make: radius[%d] (%cwidth) is %g; it must be finite and in "
                    "[%g, %g]",
                    axis, axis ? 'y' : 'x', (double)radius, (double)CLR_FILTER_MIN_RADIUS,
                    (double)CLR_FILTER_MAX_RADIUS);
  return CLR_SUCCESS;
}

static clr_result check_mitchell(float b, float c) {
  if (!(fabsf(b) <= CLR_FILTER_MAX_BC))
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                    "clr_filter_params_make: mitchell B is %g; it must be finite with |B| <= %g",
                    (double)b, (double)CLR_FILTER_MAX_BC);
  if (!(fabsf(c) <= CLR_FILTER_MAX_BC))
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                    "clr_filter_params_make: mitchell C is %g; it must be finite with |C| <= %g",
                    (double)c, (double)CLR_FILTER_MAX_BC);
  return CLR_SUCCESS;
}

/* Gaussian: alpha > 0 and finite, and the filter must not vanish at its center. */
static clr_result fill_gaussian(float alpha, clr_filter_params *p) {
  if (!(alpha > 0.0f && isfinite(alpha)))
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                    "clr_filter_params_make: gaussian alpha is %g; it must be positive and finite",
                    (double)alpha);
  p->alpha = alpha;
  p->exp_x = clr_exp_portable(-(alpha * (p->radius_x * p->radius_x)));
  p->exp_y = clr_exp_portable(-(alpha * (p->radius_y * p->radius_y)));
  if (!(1.0f - p->exp_x > 0.0f && 1.0f - p->exp_y > 0.0f))
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                    "clr_filter_params_make: gaussian alpha %g is too small for radius %g x %g: "
                    "the filter is zero everywhere",
                    (double)alpha, (double)p->radius_x, (double)p->radius_y);
  return CLR_SUCCESS;
}

static clr_result fill_sinc(float tau, clr_filter_params *p) {
  if (!(tau >= CLR_FILTER_MIN_TAU && tau <= CLR_FILTER_MAX_TAU))
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                    "clr_filter_params_make: sinc tau is %g; it must be in [%g, %g]", (double)tau,
                    (double)CLR_FILTER_MIN_TAU, (double)CLR_FILTER_MAX_TAU);
  p->tau = tau;
  p->inv_tau = 1.0f / tau;
  return CLR_SUCCESS;
}

clr_result clr_filter_params_make(const clr_filter_desc *desc, clr_filter_params *out) {
  clr_clear_error();
  if (!desc || !out)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_filter_params_make: %s is NULL",
                    desc ? "out" : "desc");
  clr_filter_desc full;
  int has_type = desc->struct_size >= offsetof(clr_filter_desc, type) + sizeof desc->type;
  clr_filter_desc_init(&full,
                       has_type && valid_type((int)desc->type) ? desc->type : CLR_FILTER_BOX);
  CLR_CHECK(clr_desc_adopt(&full, sizeof full, desc, "clr_filter_params_make: desc"));
  desc = &full;
  if (!valid_type((int)desc->type))
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                    "clr_filter_params_make: unknown filter type %d", (int)desc->type);
  if (desc->use_table != 0 && desc->use_table != 1)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "clr_filter_params_make: use_table is %d; it must be 0 or 1",
                    (int)desc->use_table);
  CLR_CHECK(check_radius(desc->radius[0], 0));
  CLR_CHECK(check_radius(desc->radius[1], 1));

  clr_filter_params p;
  memset(&p, 0, sizeof p);
  p.type = (clr_i32)desc->type;
  p.use_table = desc->use_table;
  p.radius_x = desc->radius[0];
  p.radius_y = desc->radius[1];
  p.inv_radius_x = 1.0f / p.radius_x;
  p.inv_radius_y = 1.0f / p.radius_y;
  switch (desc->type) {
    case CLR_FILTER_GAUSSIAN:
      CLR_CHECK(fill_gaussian(desc->alpha, &p));
      break;
    case CLR_FILTER_MITCHELL:
      CLR_CHECK(check_mitchell(desc->b, desc->c));
      p.b = desc->b;
      p.c = desc->c;
      break;
    case CLR_FILTER_CATMULLROM:
      p.b = 0.0f;
      p.c = 0.5f;
      break;
    case CLR_FILTER_SINC:
      CLR_CHECK(fill_sinc(desc->tau, &p));
      break;
    default:
      break;
  }
  *out = p;
  return CLR_SUCCESS;
}

clr_result clr_filter_params_table(const clr_filter_params *params,
                                   float table[CLR_FILTER_TABLE_ENTRIES]) {
  clr_clear_error();
  if (!params || !table)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_filter_params_table: %s is NULL",
                    params ? "table" : "params");
  if (!valid_type(params->type))
    return clr_fail(NULL, CLR_ERROR_INVALID_FILTER,
                    "clr_filter_params_table: unknown filter type %d", (int)params->type);
  if (!(params->radius_x >= CLR_FILTER_MIN_RADIUS && params->radius_x <= CLR_FILTER_MAX_RADIUS &&
        params->radius_y >= CLR_FILTER_MIN_RADIUS && params->radius_y <= CLR_FILTER_MAX_RADIUS))
    return clr_fail(NULL, CLR_ERROR_INVALID_RADIUS,
                    "clr_filter_params_table: radius %g x %g is outside [%g, %g] (use "
                    "clr_filter_params_make)",
                    (double)params->radius_x, (double)params->radius_y,
                    (double)CLR_FILTER_MIN_RADIUS, (double)CLR_FILTER_MAX_RADIUS);
  for (int iy = 0; iy < CLR_FILTER_TABLE_SIZE; ++iy)
    for (int ix = 0; ix < CLR_FILTER_TABLE_SIZE; ++ix)
      table[iy * CLR_FILTER_TABLE_SIZE + ix] = clr_filter_table_entry(params, ix, iy);
  return CLR_SUCCESS;
}

float clr_filter_params_evaluate(const clr_filter_params *params, const float *table, float x,
                                 float y) {
  if (!params) return 0.0f;
  if (params->use_table && !table) {
    if (!(fabsf(x) <= params->radius_x && fabsf(y) <= params->radius_y)) return 0.0f;
    return clr_filter_table_entry(params, clr_filter_table_index(x, params->inv_radius_x),
                                  clr_filter_table_index(y, params->inv_radius_y));
  }
  return clr_filter_eval(params, x, y, table);
}

clr_result clr_filter_check(const clr_filter_desc *desc) {
  clr_filter_params params;
  return clr_filter_params_make(desc, &params);
}

clr_result clr_filter_make_table(const clr_filter_desc *desc,
                                 float table[CLR_FILTER_TABLE_ENTRIES]) {
  clr_filter_params params;
  CLR_CHECK(clr_filter_params_make(desc, &params));
  if (!table) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_filter_make_table: table is NULL");
  return clr_filter_params_table(&params, table);
}

clr_result clr_filter_evaluate(const clr_filter_desc *desc, float x, float y, float *value) {
  clr_filter_params params;
  CLR_CHECK(clr_filter_params_make(desc, &params));
  if (!value) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_filter_evaluate: value is NULL");
  *value = clr_filter_params_evaluate(&params, NULL, x, y);
  return CLR_SUCCESS;
}
