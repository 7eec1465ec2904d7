/* Rendered image output: float RGB EXR with render metadata and an sRGB PNG preview. */
#include <stdio.h>
#include <stdlib.h>
#include "clr_internal.h"
#include "exr_io.h"
#include "png_io.h"
#include "renderer.h"

clr_result clr_render_write_output(const char *exr_path, const char *png_path,
                                   const clr_render_image *im, const clr_render_stats *st) {
  size_t n = (size_t)im->width * (size_t)im->height;
  if (exr_path) {
    float *planes = malloc(3 * n * sizeof(float) + 1);
    if (!planes) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "clr_render_write_output");
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) planes[(size_t)c * n + i] = im->rgb[3 * i + (size_t)c];
    clr_exr_channel ch[3] = {{"R", planes, 0}, {"G", planes + n, 0}, {"B", planes + 2 * n, 0}};
    clr_exr_attribute attrs[6];
    int na = 0;
    attrs[na++] = (clr_exr_attribute){"partial", CLR_EXR_ATTR_INT, NULL, 0.0f, st ? st->partial : 0};
    attrs[na++] = (clr_exr_attribute){"software", CLR_EXR_ATTR_STRING, "clrender", 0.0f, 0};
    if (st) {
      attrs[na++] = (clr_exr_attribute){"clrender:spp", CLR_EXR_ATTR_INT, NULL, 0.0f, st->spp};
      attrs[na++] = (clr_exr_attribute){"clrender:sampler", CLR_EXR_ATTR_STRING, st->sampler, 0.0f, 0};
      attrs[na++] = (clr_exr_attribute){"clrender:integrator", CLR_EXR_ATTR_STRING, st->integrator, 0.0f, 0};
      attrs[na++] = (clr_exr_attribute){"clrender:render_seconds", CLR_EXR_ATTR_FLOAT, NULL,
                                        (float)st->seconds_render, 0};
    }
    clr_result r = clr_exr_write(exr_path, im->full_width, im->full_height, im->pixel_bounds, ch, 3,
                                 attrs, na);
    free(planes);
    if (r != CLR_SUCCESS) return r;
  }
  if (png_path) CLR_CHECK(clr_png_write_srgb(png_path, im->width, im->height, im->rgb));
  return CLR_SUCCESS;
}
