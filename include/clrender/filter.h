/* clrender reconstruction filters: pbrt-v3's box, triangle, gaussian, mitchell and sinc, plus
 * LuxCore's blackmanharris and Mitsuba's catmullrom, evaluated exactly or through pbrt-v3's 16x16
 * table. Radii are pbrt-v3's xwidth/ywidth (half the support width).
 *
 * Thread safety: every call is thread-safe (no state). NULL pointers return
 * CLR_ERROR_NULL_POINTER; clr_filter_type_name never returns NULL. */
#ifndef CLRENDER_FILTER_H
#define CLRENDER_FILTER_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/export.h"
#include "clrender/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Values equal the kernels' CLR_FILTER_TYPE_*. */
typedef enum clr_filter_type {
  CLR_FILTER_BOX = 0,
  CLR_FILTER_TRIANGLE = 1,
  CLR_FILTER_GAUSSIAN = 2,
  CLR_FILTER_MITCHELL = 3,
  CLR_FILTER_SINC = 4,
  CLR_FILTER_BLACKMANHARRIS = 5,
  CLR_FILTER_CATMULLROM = 6
} clr_filter_type;

/* Accepted radii: [CLR_FILTER_MIN_RADIUS, CLR_FILTER_MAX_RADIUS] pixels in x and y. */
#define CLR_FILTER_MIN_RADIUS (1.0f / 1024.0f)
#define CLR_FILTER_MAX_RADIUS 64.0f
/* Mitchell B and C must lie in [-CLR_FILTER_MAX_BC, CLR_FILTER_MAX_BC]. */
#define CLR_FILTER_MAX_BC 100.0f
/* Sinc tau must lie in [CLR_FILTER_MIN_TAU, CLR_FILTER_MAX_TAU]. */
#define CLR_FILTER_MIN_TAU (1.0f / 64.0f)
#define CLR_FILTER_MAX_TAU 1.0e6f
/* Entries of the table mode: 16 x 16 over the positive quadrant, row-major (index iy*16 + ix). */
#define CLR_FILTER_TABLE_ENTRIES 256

typedef struct clr_filter_desc {
  size_t struct_size; /* sizeof(clr_filter_desc), set by clr_filter_desc_init */
  clr_filter_type type;
  /* xwidth, ywidth (radii). Defaults: box 0.5, triangle 2, gaussian 2, mitchell 2, sinc 4,
   * blackmanharris 2 (LuxCore's film.filter.width), catmullrom 2 (Mitsuba). */
  float radius[2];
  float alpha;       /* gaussian, default 2 */
  float b, c;        /* mitchell, default 1/3 each; catmullrom always uses B = 0, C = 1/2 */
  float tau;         /* sinc, default 3 */
  int32_t use_table; /* 0 (default): exact evaluation; 1: pbrt-v3's 16x16 table, nearest entry */
} clr_filter_desc;

/* pbrt-v3's defaults for `type` (the defaults listed above). */
CLR_API void clr_filter_desc_init(clr_filter_desc *desc, clr_filter_type type);
/* pbrt-v3 scene names: "box", "triangle", "gaussian", "mitchell", "sinc", plus "blackmanharris"
 * and "catmullrom" (case-sensitive). CLR_ERROR_INVALID_FILTER for any other name. */
CLR_API clr_result clr_filter_type_from_name(const char *name, clr_filter_type *type);
/* The scene name of `type`, "unknown" for values outside the enum. */
CLR_API const char *clr_filter_type_name(clr_filter_type type);

/* Validates `desc`. Errors: CLR_ERROR_NULL_POINTER, CLR_ERROR_INVALID_ARGUMENT (struct_size,
 * use_table not 0/1), CLR_ERROR_INVALID_FILTER (type; alpha <= 0, non-finite or so small the
 * gaussian vanishes; B or C non-finite or beyond CLR_FILTER_MAX_BC; tau outside its range or
 * NaN), CLR_ERROR_INVALID_RADIUS (radius NaN, infinite or outside its range). Parameters a type
 * does not use are ignored. */
CLR_API clr_result clr_filter_check(const clr_filter_desc *desc);

/* pbrt-v3's filter table for `desc` (whatever its use_table): entry iy*16 + ix is the exact
 * filter at ((ix + .5) rx / 16, (iy + .5) ry / 16), bit-identical to the device's. */
CLR_API clr_result clr_filter_make_table(const clr_filter_desc *desc,
                                         float table[CLR_FILTER_TABLE_ENTRIES]);

/* The filter's value at offset (x, y) from the pixel centre, computed on the host with the
 * kernels' code (pbrt-v3's table entry when desc->use_table): the device's bits. */
CLR_API clr_result clr_filter_evaluate(const clr_filter_desc *desc, float x, float y, float *value);

#ifdef __cplusplus
}
#endif
#endif
