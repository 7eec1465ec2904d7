/* pbrt-v3 InfiniteAreaLight with a "mapname": a lat-long image (EXR, or PNG whose bytes / 255 are
 * taken as linear as pbrt-v3 does; t = 0 is the file's
 * first row, u = phi / 2 pi, v = theta / pi in light space) times L, looked up bilinearly with
 * wrap repeat, and importance-sampled by pbrt-v3's Distribution2D over a 2w x 2h grid of the
 * map's luminance times sin theta. */
#ifndef CLR_RENDER_ENVMAP_H
#define CLR_RENDER_ENVMAP_H

#include "clrender/result.h"

typedef struct rs_envmap {
  int w, h;
  float *rgb; /* w * h * 3, L applied */
  int dw, dh; /* the distribution's resolution */
  float *func, *cdf, *row_int, *marg_cdf;
  float marg_int;
  float mean_y; /* mean luminance of the map (for Light::Power) */
} rs_envmap;

/* Reads `path` and builds the distribution; errors name the file. */
clr_result rs_envmap_load(const char *path, const float L[3], rs_envmap **out);
void rs_envmap_free(rs_envmap *m);
void rs_envmap_lookup(const rs_envmap *m, float s, float t, float out[3]);
/* Distribution2D::SampleContinuous: (s, t) and its pdf in [0,1]^2 (0: none). */
float rs_envmap_sample(const rs_envmap *m, const float u[2], float st[2]);
/* Distribution2D::Pdf at (s, t). */
float rs_envmap_pdf(const rs_envmap *m, float s, float t);

#endif
