#include "camera_sample.h"

/* pbrt-v4's Lerp, (1 - t) a + t b (the build never contracts it into an FMA) */
static float lerp_v4(float t, float a, float b) { return (1.0f - t) * a + t * b; }

void clr_camera_sample_from_values(const float *v, int pbrt_v4, int px, int py,
                                   clr_camera_sample *cs) {
  if (pbrt_v4) { /* pPixel + fs.p + Vector2f(0.5f, 0.5f) */
    cs->film_x = ((float)px + lerp_v4(v[0], -0.5f, 0.5f)) + 0.5f;
    cs->film_y = ((float)py + lerp_v4(v[1], -0.5f, 0.5f)) + 0.5f;
  } else {
    cs->film_x = (float)px + v[0];
    cs->film_y = (float)py + v[1];
  }
  cs->time = v[2];
  cs->lens_u = v[3];
  cs->lens_v = v[4];
}

int clr_camera_sample_is_pbrt_v4(const clr_sampler_desc *sd) {
  return sd->seeding == CLR_SEEDING_PBRT_V4 || sd->type >= CLR_SAMPLER_INDEPENDENT;
}
