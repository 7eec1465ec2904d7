/* The camera sample of one sample vector: film position, time and lens values, laid out as
 * pbrt-v3's camera requests or as pbrt-v4's GetCameraSample. */
#ifndef CLR_CAMERA_SAMPLE_H
#define CLR_CAMERA_SAMPLE_H

#include <stddef.h>
#include "clrender/filter.h"
#include "clrender/sampler.h"

typedef struct clr_camera_sample {
  float film_x, film_y;   /* raster position of the camera ray */
  float pixel_x, pixel_y; /* where the film takes the sample */
  float time, lens_u, lens_v;
} clr_camera_sample;

typedef struct clr_camera_layout {
  int pbrt_v4;        /* pbrt-v4's samplers: pbrt-v4's GetCameraSample */
  int filter_sampled; /* pbrt-v4's Filter::Sample of the scene's box or triangle filter: the
                       * film takes each sample at its pixel's centre (a box of radius 0.5) */
  clr_filter_type filter;
  float radius[2];
  /* time and lens values: their offsets from the film offset (2 and 3), or -1 where their
   * requests are skipped (clr_camera_layout_skip): time 0, lens (0.5, 0.5), never read */
  int time_value, lens_value;
} clr_camera_layout;

/* pbrt-v4's samplers (their names, or --seeding pbrt-v4): pbrt-v4's camera sample and layout. */
int clr_camera_sample_is_pbrt_v4(const clr_sampler_desc *sampler);

/* pbrt-v3's layout, or pbrt-v4's: the filter is sampled as pbrt-v4 does for the box and the
 * triangle (pbrt-v3's and pbrt-v4's filters alike, Sample's weight 1); other filters keep
 * pbrt-v4's box of radius 0.5 and the film's filtering. */
void clr_camera_layout_init(clr_camera_layout *layout, const clr_sampler_desc *sampler,
                            const clr_filter_desc *filter);

/* The offsets of the integrator's layout: time_offset, lens_offset -1 where skipped. */
void clr_camera_layout_skip(clr_camera_layout *layout, int camera_offset, int time_offset,
                            int lens_offset);

/* v: the sample vector's camera values (the film offset first, then time and lens). pbrt-v3:
 * film = pixel + offset. pbrt-v4: film = pixel + filter.Sample(offset).p + 0.5, GetCameraSample's
 * float operations in its order. */
void clr_camera_sample_from_values(const clr_camera_layout *layout, const float *v, int px, int py,
                                   clr_camera_sample *cs);

/* Camera samples as structure of arrays (each array holds a wave's n entries). */
typedef struct clr_camera_samples {
  float *film_x, *film_y, *pixel_x, *pixel_y, *time, *lens_u, *lens_v;
} clr_camera_samples;

/* The camera samples of n consecutive sample vectors of pixel row py (stride floats apart, v at
 * the first one's camera values), the first at column px, sample s of spp: each entry as
 * clr_camera_sample_from_values makes it, the same bits. */
void clr_camera_samples_from_values(const clr_camera_layout *layout, const float *v, size_t stride,
                                    int px, int py, int s, int spp, int n,
                                    const clr_camera_samples *out);

#endif
