/* pbrt-v3 SurfaceInteraction::ComputeDifferentials: screen-space derivatives of p and (u, v). */
#include <math.h>
#include <string.h>
#include "surface_differentials.h"
#include "vec3.h"

/* Where the ray (o, d) meets the plane through p of normal n; 0 when it does not (inf or NaN). */
static int plane_hit(const float o[3], const float d[3], const float p[3], const float n[3],
                     float out[3]) {
  float t = -(rs_dot(n, o) - rs_dot(n, p)) / rs_dot(n, d);
  if (!isfinite(t)) return 0;
  for (int i = 0; i < 3; ++i) out[i] = o[i] + t * d[i];
  return 1;
}

/* pbrt-v3 SolveLinearSystem2x2. */
static int solve2x2(const float a[2][2], const float b[2], float *x0, float *x1) {
  float det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
  if (fabsf(det) < 1e-10f) return 0;
  *x0 = (a[1][1] * b[0] - a[0][1] * b[1]) / det;
  *x1 = (a[0][0] * b[1] - a[1][0] * b[0]) / det;
  return !isnan(*x0) && !isnan(*x1);
}

void rs_compute_differentials(const clr_ray_differential *rd, const float p[3], const float n[3],
                              const float dpdu[3], const float dpdv[3], rs_tex_ctx *tc) {
  tc->dudx = tc->dvdx = tc->dudy = tc->dvdy = 0.0f;
  memset(tc->dpdx, 0, sizeof tc->dpdx);
  memset(tc->dpdy, 0, sizeof tc->dpdy);
  float px[3], py[3];
  if (!rd || !rd->has || !plane_hit(rd->rx_o, rd->rx_d, p, n, px) ||
      !plane_hit(rd->ry_o, rd->ry_d, p, n, py))
    return;
  for (int i = 0; i < 3; ++i) {
    tc->dpdx[i] = px[i] - p[i];
    tc->dpdy[i] = py[i] - p[i];
  }
  int d0 = 0, d1 = 1; /* drop the dimension where |n| is largest */
  if (fabsf(n[0]) > fabsf(n[1]) && fabsf(n[0]) > fabsf(n[2]))
    d0 = 1, d1 = 2;
  else if (fabsf(n[1]) > fabsf(n[2]))
    d0 = 0, d1 = 2;
  float a[2][2] = {{dpdu[d0], dpdv[d0]}, {dpdu[d1], dpdv[d1]}};
  float bx[2] = {px[d0] - p[d0], px[d1] - p[d1]}, by[2] = {py[d0] - p[d0], py[d1] - p[d1]};
  if (!solve2x2(a, bx, &tc->dudx, &tc->dvdx)) tc->dudx = tc->dvdx = 0.0f;
  if (!solve2x2(a, by, &tc->dudy, &tc->dvdy)) tc->dudy = tc->dvdy = 0.0f;
}
