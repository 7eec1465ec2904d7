/* Sample generation on a context's device: per-sampler kernel and buffer caches, the launch plans
 * of each sampler family. */
#ifndef CLR_SAMPLER_DEVICE_H
#define CLR_SAMPLER_DEVICE_H

#include "clrender/sampler.h"
#include "sampler_types.h"

typedef struct clr_sampler_device clr_sampler_device;

/* An empty cache for one sampler (kernels and buffers are made on first use). */
clr_result clr_sampler_device_create(clr_context ctx, clr_sampler_device **out);
void clr_sampler_device_release(clr_sampler_device *device);

/* Generates the batch prepared in (p, slots) into out (device_values and/or host_values,
 * host_indices); returns once the values are in place. Calls on one cache are serialised. */
/* pmj_pixels: pmj02bn's GetPixel2D and point-set tables (clr_pmj02_pixel_table), NULL otherwise. */
clr_result clr_sampler_device_generate(clr_sampler_device *device, const clr_sampler_params *p,
                                       const clr_request_slot *slots, const float *pmj_pixels,
                                       const clr_sample_output *out);

#endif
