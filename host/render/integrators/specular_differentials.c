/* pbrt-v3's specular ray differentials, re-derived: differentiate wi(wo, n) along x and y with
 * dwo = -(offset direction) - wo and dn = sf->dndx. */
#include "specular_differentials.h"
#include "vec3.h"

/* The offset origins p + dpdx, p + dpdy; 0 when there are no differentials to propagate. */
static int offset_origins(const clr_surface *sf, const clr_ray_differential *in,
                          clr_ray_differential *out) {
  out->has = in && in->has && sf->has_differentials;
  if (!out->has) return 0;
  for (int a = 0; a < 3; ++a) {
    out->rx_o[a] = sf->p[a] + sf->dpdx[a];
    out->ry_o[a] = sf->p[a] + sf->dpdy[a];
  }
  return 1;
}

void rs_reflect_differential(const clr_surface *sf, const clr_ray_differential *in,
                             const float wo[3], const float wi[3], clr_ray_differential *out) {
  if (!offset_origins(sf, in, out)) return;
  const float *n = sf->ns;
  float won = rs_dot(wo, n);
  for (int axis = 0; axis < 2; ++axis) {
    const float *d = axis ? in->ry_d : in->rx_d, *dn = axis ? sf->dndy : sf->dndx;
    float *od = axis ? out->ry_d : out->rx_d, dwo[3];
    for (int a = 0; a < 3; ++a) dwo[a] = -d[a] - wo[a];
    float ddn = rs_dot(dwo, n) + rs_dot(wo, dn);
    for (int a = 0; a < 3; ++a) od[a] = wi[a] - dwo[a] + 2.0f * (won * dn[a] + ddn * n[a]);
  }
}

void rs_transmit_differential(const clr_surface *sf, const clr_ray_differential *in,
                              const float wo[3], const float wi[3], float eta,
                              clr_ray_differential *out) {
  if (!offset_origins(sf, in, out)) return;
  float s = rs_dot(wo, sf->ns) < 0.0f ? -1.0f : 1.0f; /* the normal on wo's side */
  float n[3] = {s * sf->ns[0], s * sf->ns[1], s * sf->ns[2]};
  float won = rs_dot(wo, n), win = fabsf(rs_dot(wi, n));
  if (win == 0.0f) {
    out->has = 0;
    return;
  }
  float mu = eta * won - win;
  for (int axis = 0; axis < 2; ++axis) {
    const float *d = axis ? in->ry_d : in->rx_d, *dn0 = axis ? sf->dndy : sf->dndx;
    float *od = axis ? out->ry_d : out->rx_d, dwo[3], dn[3];
    for (int a = 0; a < 3; ++a) {
      dwo[a] = -d[a] - wo[a];
      dn[a] = s * dn0[a];
    }
    float ddn = rs_dot(dwo, n) + rs_dot(wo, dn);
    float dmu = (eta - eta * eta * won / win) * ddn;
    for (int a = 0; a < 3; ++a) od[a] = wi[a] - eta * dwo[a] + mu * dn[a] + dmu * n[a];
  }
}
