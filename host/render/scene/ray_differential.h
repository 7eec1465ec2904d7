/* pbrt-v3 RayDifferential's offset rays: the camera rays through the raster points one pixel
 * to the right (x) and one down (y), scaled toward the main ray by 1 / sqrt(spp). */
#ifndef CLR_RENDER_RAY_DIFFERENTIAL_H
#define CLR_RENDER_RAY_DIFFERENTIAL_H

#include <stdint.h>

typedef struct clr_ray_differential {
  float rx_o[3], rx_d[3], ry_o[3], ry_d[3]; /* world space */
  int32_t has;                              /* 0: none (offsets undefined) */
} clr_ray_differential;

#endif
