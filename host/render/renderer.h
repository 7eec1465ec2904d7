/* The render loop behind clr_render_file, callable on a parsed description (tests, bench). */
#ifndef CLR_RENDERER_H
#define CLR_RENDERER_H

#include "render.h"
#include "scene_desc.h"

/* The rendered image over the film's pixel bounds (row-major RGB, malloc'ed). */
typedef struct clr_render_image {
  int32_t full_width, full_height;
  clr_bounds2i pixel_bounds;
  int32_t width, height;
  float *rgb;
} clr_render_image;

/* Renders `desc`; writes the EXR/PNG files when write_files, returns the image in *image when
 * image is not NULL (free image->rgb). */
clr_result clr_render_desc(const clr_scene_desc *desc, const clr_render_options *options,
                           clr_render_stats *stats, int write_files, clr_render_image *image);

/* The progress bar's seconds left after `done` of `total` tiles merged at `elapsed` seconds, the
 * first one at `first_elapsed`: the rate after the first tile times the tiles left. */
double clr_progress_eta(int done, int total, double elapsed, double first_elapsed);

#endif
