/* pbrt-v3's film geometry (film.cpp, api.cpp): crop window rounding and sample bounds. */
#include <math.h>
#include "clr_internal.h"
#include "film_geometry.h"

static float clampf(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

clr_result clr_film_geometry_bounds(const clr_film_geometry *g, const char *who,
                                    clr_bounds2i *pixel_bounds, clr_bounds2i *sample_bounds) {
  if (!g) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "%s: film geometry is NULL", who);
  if (g->x_resolution <= 0 || g->y_resolution <= 0 || g->x_resolution > CLR_MAX_RESOLUTION ||
      g->y_resolution > CLR_MAX_RESOLUTION ||
      (int64_t)g->x_resolution * g->y_resolution > CLR_MAX_PIXELS)
    return clr_fail(NULL, CLR_ERROR_INVALID_RESOLUTION,
                    "%s: resolution %dx%d is invalid (each side 1..%d, at most %d pixels)", who,
                    (int)g->x_resolution, (int)g->y_resolution, CLR_MAX_RESOLUTION, CLR_MAX_PIXELS);
  for (int i = 0; i < 2; ++i) {
    float r = g->filter_radius[i];
    if (!(r > 0.0f) || !isfinite(r) || r > CLR_MAX_FILTER_RADIUS)
      return clr_fail(NULL, CLR_ERROR_INVALID_RADIUS,
                      "%s: filter radius %s = %g must be positive, finite and at most %g", who,
                      i ? "y" : "x", (double)r, (double)CLR_MAX_FILTER_RADIUS);
  }
  const float *c = g->crop_window;
  for (int i = 0; i < 4; ++i)
    if (!(c[i] >= 0.0f && c[i] <= 1.0f))
      return clr_fail(NULL, CLR_ERROR_INVALID_CROP_WINDOW,
                      "%s: crop window [%g %g %g %g] must lie in [0,1]", who, (double)c[0],
                      (double)c[1], (double)c[2], (double)c[3]);
  /* api.cpp sorts and clamps each pair; film.cpp rounds the corners up. */
  float x0 = clampf(fminf(c[0], c[1]), 0, 1), x1 = clampf(fmaxf(c[0], c[1]), 0, 1);
  float y0 = clampf(fminf(c[2], c[3]), 0, 1), y1 = clampf(fmaxf(c[2], c[3]), 0, 1);
  clr_bounds2i pb;
  pb.x0 = (int32_t)ceilf((float)g->x_resolution * x0);
  pb.x1 = (int32_t)ceilf((float)g->x_resolution * x1);
  pb.y0 = (int32_t)ceilf((float)g->y_resolution * y0);
  pb.y1 = (int32_t)ceilf((float)g->y_resolution * y1);
  if (pb.x1 <= pb.x0 || pb.y1 <= pb.y0)
    return clr_fail(NULL, CLR_ERROR_INVALID_CROP_WINDOW,
                    "%s: crop window [%g %g %g %g] covers no pixel of the %dx%d film", who,
                    (double)c[0], (double)c[1], (double)c[2], (double)c[3], (int)g->x_resolution,
                    (int)g->y_resolution);
  if (pixel_bounds) *pixel_bounds = pb;
  if (sample_bounds) {
    sample_bounds->x0 = (int32_t)floorf((float)pb.x0 + 0.5f - g->filter_radius[0]);
    sample_bounds->y0 = (int32_t)floorf((float)pb.y0 + 0.5f - g->filter_radius[1]);
    sample_bounds->x1 = (int32_t)ceilf((float)pb.x1 - 0.5f + g->filter_radius[0]);
    sample_bounds->y1 = (int32_t)ceilf((float)pb.y1 - 0.5f + g->filter_radius[1]);
  }
  return CLR_SUCCESS;
}
