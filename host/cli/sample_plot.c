/* Draws each pixel's samples, projected on two of their values, inside the pixel's grid cell. */
#include <stdlib.h>
#include "clrender/result.h"
#include "clrender/image.h"
#include "sample_plot.h"

static void put(float *rgb, int w, int h, int x, int y, float r, float g, float b) {
  if (x < 0 || y < 0 || x >= w || y >= h) return;
  float *p = rgb + 3 * ((size_t)y * w + x);
  p[0] = r;
  p[1] = g;
  p[2] = b;
}

static void draw_grid(float *rgb, int w, int h, int cell) {
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (x % cell == 0 || y % cell == 0) put(rgb, w, h, x, y, 0.35f, 0.35f, 0.35f);
}

clr_result clr_plot_samples(const char *path, clr_bounds2i pixels, int32_t spp, int32_t values,
                            const float *v, const int32_t proj[2]) {
  int pw = pixels.x1 - pixels.x0, ph = pixels.y1 - pixels.y0;
  if (!path || !v || pw <= 0 || ph <= 0 || spp <= 0)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "plot: empty pixel range or no output path");
  int longest = pw > ph ? pw : ph;
  int cell = 512 / longest;
  cell = cell < 8 ? 8 : (cell > 256 ? 256 : cell);
  int w = pw * cell + 1, h = ph * cell + 1;
  if ((size_t)w * (size_t)h > ((size_t)1 << 26))
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "plot: %dx%d pixels make too large an image; plot fewer pixels", pw,
                              ph);
  float *rgb = malloc((size_t)w * h * 3 * sizeof(float));
  if (!rgb) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "plot: out of memory");
  for (size_t i = 0; i < (size_t)w * h * 3; ++i) rgb[i] = 1.0f;
  draw_grid(rgb, w, h, cell);
  int dot = cell >= 32 ? 1 : 0;
  for (int py = 0; py < ph; ++py)
    for (int px = 0; px < pw; ++px)
      for (int s = 0; s < spp; ++s) {
        const float *sv = v + (((size_t)py * pw + px) * spp + s) * values;
        int x = px * cell + (int)(sv[proj[0]] * (float)cell);
        int y = py * cell + (int)(sv[proj[1]] * (float)cell);
        for (int dy = -dot; dy <= dot; ++dy)
          for (int dx = -dot; dx <= dot; ++dx) put(rgb, w, h, x + dx, y + dy, 0.8f, 0.05f, 0.0f);
      }
  clr_image image = {w, h, rgb};
  clr_result r = clr_image_write_png(path, &image);
  free(rgb);
  return r;
}
