/* Reconstruction filter parameters shared by the film kernels and the host reference: 32-bit
 * scalars only. Radii are pbrt-v3's xwidth/ywidth. */
#ifndef CLR_FILTER_TYPES_H
#define CLR_FILTER_TYPES_H

#include "clr_platform.h"

#define CLR_FILTER_TYPE_BOX 0
#define CLR_FILTER_TYPE_TRIANGLE 1
#define CLR_FILTER_TYPE_GAUSSIAN 2
#define CLR_FILTER_TYPE_MITCHELL 3
#define CLR_FILTER_TYPE_SINC 4
#define CLR_FILTER_TYPE_BLACKMANHARRIS 5
#define CLR_FILTER_TYPE_CATMULLROM 6
#define CLR_FILTER_TYPE_COUNT 7

/* pbrt-v3's filter table: 16x16 entries over the positive quadrant, nearest lookup. */
#define CLR_FILTER_TABLE_SIZE 16

typedef struct clr_filter_params {
  clr_i32 type;      /* CLR_FILTER_TYPE_* */
  clr_i32 use_table; /* 0: exact evaluation; 1: pbrt-v3's 16x16 table */
  float radius_x, radius_y;
  float inv_radius_x, inv_radius_y; /* 1/radius rounded on the host */
  float alpha;                      /* gaussian */
  float exp_x, exp_y;               /* gaussian: e^(-alpha r^2), computed by the shared exp */
  float b, c;                       /* mitchell */
  float tau, inv_tau;               /* sinc: tau and 1/tau rounded on the host */
  clr_i32 pad[3];                   /* keeps the size a multiple of 16 bytes (64) */
} clr_filter_params;

#endif
