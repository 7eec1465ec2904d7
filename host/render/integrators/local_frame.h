/* pbrt-v3's trigonometry of a unit direction in the local shading frame (z along the normal):
 * reflection.h's CosTheta family, for the BxDF lobes and the microfacet distribution. */
#ifndef CLR_LOCAL_FRAME_H
#define CLR_LOCAL_FRAME_H

#include <math.h>
#include "float_minmax.h"

static inline float cos2_theta(const float w[3]) { return w[2] * w[2]; }
static inline float sin2_theta(const float w[3]) { return rs_fmaxf(0.0f, 1.0f - cos2_theta(w)); }
static inline float tan2_theta(const float w[3]) { return sin2_theta(w) / cos2_theta(w); }
static inline float cos_phi(const float w[3]) {
  float s = sqrtf(sin2_theta(w));
  return s == 0.0f ? 1.0f : rs_fminf(1.0f, rs_fmaxf(-1.0f, w[0] / s));
}
static inline float sin_phi(const float w[3]) {
  float s = sqrtf(sin2_theta(w));
  return s == 0.0f ? 0.0f : rs_fminf(1.0f, rs_fmaxf(-1.0f, w[1] / s));
}

#endif
