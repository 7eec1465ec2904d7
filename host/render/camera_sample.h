/* The camera sample of one sample vector: film position, time and lens values, laid out as
 * pbrt-v3's camera requests or as pbrt-v4's GetCameraSample. */
#ifndef CLR_CAMERA_SAMPLE_H
#define CLR_CAMERA_SAMPLE_H

#include "clrender/sampler.h"

typedef struct clr_camera_sample {
  float film_x, film_y; /* raster position */
  float time, lens_u, lens_v;
} clr_camera_sample;

/* v: the sample vector's camera values (the film offset first, then time and lens). pbrt-v3:
 * film = pixel + offset. pbrt-v4: film = pixel + BoxFilter(radius 0.5).Sample(offset).p + 0.5,
 * GetCameraSample's float operations in its order. */
void clr_camera_sample_from_values(const float *v, int pbrt_v4, int px, int py,
                                   clr_camera_sample *cs);

/* pbrt-v4's samplers (their names, or --seeding pbrt-v4): pbrt-v4's camera sample and layout. */
int clr_camera_sample_is_pbrt_v4(const clr_sampler_desc *sampler);

#endif
