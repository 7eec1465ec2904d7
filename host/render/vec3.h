/* Small 3-vector helpers and constants shared by the renderer's modules. */
#ifndef CLR_RENDER_VEC3_H
#define CLR_RENDER_VEC3_H

#include <math.h>
#include "float_minmax.h"

#define RS_PI 3.14159265358979323846f
#define RS_INV_PI 0.31830988618379067154f

static inline float rs_dot(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void rs_cross(const float a[3], const float b[3], float r[3]) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}

static inline void rs_negate(float v[3]) {
  v[0] = -v[0];
  v[1] = -v[1];
  v[2] = -v[2];
}

static inline void rs_normalize(float v[3]) {
  float l = sqrtf(rs_dot(v, v));
  if (l > 0.0f) {
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
  }
}

/* pbrt-v3 ConcentricSampleDisk: (u0, u1) in [0,1)^2 to the unit disk. */
static inline void rs_concentric_disk(float u0, float u1, float *x, float *y) {
  float ox = 2.0f * u0 - 1.0f, oy = 2.0f * u1 - 1.0f;
  if (ox == 0.0f && oy == 0.0f) {
    *x = *y = 0.0f;
    return;
  }
  float r, theta;
  if (fabsf(ox) > fabsf(oy)) {
    r = ox;
    theta = (RS_PI / 4.0f) * (oy / ox);
  } else {
    r = oy;
    theta = RS_PI / 2.0f - (RS_PI / 4.0f) * (ox / oy);
  }
  *x = r * cosf(theta);
  *y = r * sinf(theta);
}

/* Offset that moves a ray origin at p off its surface (avoids self-intersection). */
static inline float rs_spawn_eps(const float p[3]) {
  float m = rs_fmaxf(fabsf(p[0]), rs_fmaxf(fabsf(p[1]), fabsf(p[2])));
  return 1e-4f * (1.0f + m);
}

#endif
