/* pbrt-v3 Material::Bump (core/material.cpp), re-implemented from its definition. */
#include <math.h>
#include "bump.h"
#include "vec3.h"

/* pbrt-v3's finite-difference step: half the summed screen-space change, else 0.0005. */
static float bump_step(float dx, float dy) {
  float d = 0.5f * (fabsf(dx) + fabsf(dy));
  return d == 0.0f ? 0.0005f : d;
}

void rs_bump(const rs_texture_set *tex, const rs_colour *d, const rs_tex_ctx *at, const float n[3],
             float dpdu[3], float dpdv[3], const float dndu[3], const float dndv[3], float ns[3]) {
  float du = bump_step(at->dudx, at->dudy), dv = bump_step(at->dvdx, at->dvdy);
  rs_tex_ctx e = *at;
  e.uv[0] += du;
  for (int i = 0; i < 3; ++i) e.p[i] += du * dpdu[i];
  float u_disp = rs_float_eval(tex, d, &e);
  e = *at;
  e.uv[1] += dv;
  for (int i = 0; i < 3; ++i) e.p[i] += dv * dpdv[i];
  float v_disp = rs_float_eval(tex, d, &e);
  float disp = rs_float_eval(tex, d, at);
  for (int i = 0; i < 3; ++i) {
    dpdu[i] += (u_disp - disp) / du * ns[i] + disp * dndu[i];
    dpdv[i] += (v_disp - disp) / dv * ns[i] + disp * dndv[i];
  }
  float m[3];
  rs_cross(dpdu, dpdv, m);
  rs_normalize(m);
  if (!(rs_dot(m, m) > 0.0f)) return;
  if (rs_dot(m, n) < 0.0f) /* SetShadingGeometry, orientation not authoritative */
    for (int i = 0; i < 3; ++i) m[i] = -m[i];
  for (int i = 0; i < 3; ++i) ns[i] = m[i];
}
