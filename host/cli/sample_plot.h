/* PNG plot of a 2D projection of sample vectors over the pixel grid. */
#ifndef CLR_SAMPLE_PLOT_H
#define CLR_SAMPLE_PLOT_H

#include "clrender/sampler.h"

/* values: pixel-major (row-major over `pixels`), then sample, then value, as clr_sampler_generate
 * writes them; proj picks the two values drawn inside each pixel's cell. */
clr_result clr_plot_samples(const char *path, clr_bounds2i pixels, int32_t samples_per_pixel,
                            int32_t values_per_sample, const float *values, const int32_t proj[2]);

#endif
