/* pbrt-v3 Material::Bump (core/material.cpp), re-implemented from its definition. */
#include "bump.h"
#include "vec3.h"

void rs_bump(const rs_texture_set *tex, const rs_colour *d, const float p[3], const float uv[2],
             const float n[3], float dpdu[3], float dpdv[3], const float dndu[3],
             const float dndv[3], float ns[3]) {
  const float du = 0.0005f, dv = 0.0005f;
  rs_tex_ctx at = {{uv[0] + du, uv[1]},
                   {p[0] + du * dpdu[0], p[1] + du * dpdu[1], p[2] + du * dpdu[2]}};
  float u_disp = rs_float_eval(tex, d, &at);
  at = (rs_tex_ctx){{uv[0], uv[1] + dv},
                    {p[0] + dv * dpdv[0], p[1] + dv * dpdv[1], p[2] + dv * dpdv[2]}};
  float v_disp = rs_float_eval(tex, d, &at);
  at = (rs_tex_ctx){{uv[0], uv[1]}, {p[0], p[1], p[2]}};
  float disp = rs_float_eval(tex, d, &at);
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
