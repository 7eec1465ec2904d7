/* PFM output for the renderer (pbrt-v3's third image format). */
#ifndef CLR_RENDER_PFM_OUTPUT_H
#define CLR_RENDER_PFM_OUTPUT_H

#include "clrender/result.h"

/* rgb: interleaved float RGB, row-major, top row first. CLR_ERROR_IO naming the path on failure;
 * the file appears only when complete. */
clr_result clr_write_pfm(const char *path, const float *rgb, int width, int height);

#endif
