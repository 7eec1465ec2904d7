/* A renderer camera layout for a sampler, seeding and filter (radius 0: the filter's default). */
#ifndef CLR_CAMERA_LAYOUT_TEST_UTIL_H
#define CLR_CAMERA_LAYOUT_TEST_UTIL_H

#include "camera_sample.h"

static inline clr_camera_layout layout_for(clr_sampler_type sampler, clr_seeding seeding,
                                           clr_filter_type filter, float radius) {
  clr_sampler_desc sd;
  clr_sampler_desc_init(&sd, sampler);
  sd.seeding = seeding;
  clr_filter_desc fd;
  clr_filter_desc_init(&fd, filter);
  if (radius > 0.0f) fd.radius[0] = fd.radius[1] = radius;
  clr_camera_layout l;
  clr_camera_layout_init(&l, &sd, &fd);
  return l;
}

#endif
