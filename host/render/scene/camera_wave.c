/* A wave's camera rays: the pinhole (perspective, no lens, not moving) in structure-of-arrays
 * loops with rs_camera_ray's float operations in its order; other cameras ray by ray. */
#include <math.h>
#include "camera.h"
#include "float_minmax.h"

/* rs_camera_ray's normalize: divides by the length where it is positive. */
static inline float unit_or_same(float x, float len) { return len > 0.0f ? x / len : x; }

/* The pinhole's world directions (raster point to camera point, normalized, to world). */
static void pinhole_directions(const rs_camera *cam, const float *film_x, const float *film_y,
                               int n, float *dx, float *dy, float *dz) {
  const float(*r)[4] = cam->raster_to_camera.m, (*w)[4] = cam->camera_to_world.m;
  /* the raster point's z (0) times each row's third entry, as clr_transform_point sums it */
  float r0z = r[0][2] * 0.0f, r1z = r[1][2] * 0.0f, r2z = r[2][2] * 0.0f, r3z = r[3][2] * 0.0f;
  for (int k = 0; k < n; ++k) {
    float x = film_x[k], y = film_y[k];
    float c0 = r[0][0] * x + r[0][1] * y + r0z + r[0][3];
    float c1 = r[1][0] * x + r[1][1] * y + r1z + r[1][3];
    float c2 = r[2][0] * x + r[2][1] * y + r2z + r[2][3];
    float c3 = r[3][0] * x + r[3][1] * y + r3z + r[3][3];
    float inv = 1.0f / c3;
    float p0 = c3 == 1.0f ? c0 : inv * c0, p1 = c3 == 1.0f ? c1 : inv * c1,
          p2 = c3 == 1.0f ? c2 : inv * c2;
    float lc = sqrtf(p0 * p0 + p1 * p1 + p2 * p2);
    p0 = unit_or_same(p0, lc), p1 = unit_or_same(p1, lc), p2 = unit_or_same(p2, lc);
    float d0 = w[0][0] * p0 + w[0][1] * p1 + w[0][2] * p2;
    float d1 = w[1][0] * p0 + w[1][1] * p1 + w[1][2] * p2;
    float d2 = w[2][0] * p0 + w[2][1] * p1 + w[2][2] * p2;
    float lw = sqrtf(d0 * d0 + d1 * d1 + d2 * d2);
    dx[k] = unit_or_same(d0, lw), dy[k] = unit_or_same(d1, lw), dz[k] = unit_or_same(d2, lw);
  }
}

/* The rays' motion times: rs_camera_ray's shutter time on the transform times, clamped. */
static void ray_times(const rs_camera *cam, const float *time, int n, float *out) {
  float open = cam->shutter_open, close = cam->shutter_close;
  float start = cam->motion.start_time, span = cam->motion.end_time - cam->motion.start_time;
  if (!(span > 0.0f)) {
    for (int k = 0; k < n; ++k) out[k] = 0.0f;
    return;
  }
  int negative_zero = 0;
  for (int k = 0; k < n; ++k) { /* rs_fminf(rs_fmaxf(y, 0), 1) as selects, but where y is -0 */
    float y = ((1.0f - time[k]) * open + time[k] * close - start) / span;
    out[k] = y > 0.0f ? (y < 1.0f ? y : 1.0f) : 0.0f;
    negative_zero |= (y == 0.0f) & (copysignf(1.0f, y) < 0.0f);
  }
  for (int k = 0; negative_zero && k < n; ++k) {
    float shutter_t = (1.0f - time[k]) * open + time[k] * close;
    out[k] = rs_fminf(rs_fmaxf((shutter_t - start) / span, 0.0f), 1.0f);
  }
}

static void pinhole_rays(const rs_camera *cam, const clr_camera_samples *cs, int n, clr_ray *rays,
                         float *weights) {
  float dx[RS_CAMERA_WAVE], dy[RS_CAMERA_WAVE], dz[RS_CAMERA_WAVE], t[RS_CAMERA_WAVE];
  pinhole_directions(cam, cs->film_x, cs->film_y, n, dx, dy, dz);
  ray_times(cam, cs->time, n, t);
  const float *o = cam->origin_world;
  for (int k = 0; k < n; ++k) {
    rays[k] = (clr_ray){o[0], o[1], o[2], 0.0f, dx[k], dy[k], dz[k], INFINITY, t[k]};
    weights[k] = 1.0f;
  }
}

void rs_camera_rays(const rs_camera *cam, const clr_camera_samples *cs, int n, clr_ray *rays,
                    clr_ray_differential *rd, float *weights) {
  for (int k0 = 0; k0 < n; k0 += RS_CAMERA_WAVE) {
    int m = n - k0 < RS_CAMERA_WAVE ? n - k0 : RS_CAMERA_WAVE;
    if (cam->fixed_origin && !rd) {
      clr_camera_samples part = {cs->film_x + k0,  cs->film_y + k0, cs->pixel_x + k0,
                                 cs->pixel_y + k0, cs->time + k0,   cs->lens_u + k0,
                                 cs->lens_v + k0};
      pinhole_rays(cam, &part, m, rays + k0, weights + k0);
      continue;
    }
    for (int k = k0; k < k0 + m; ++k)
      weights[k] = rs_camera_ray(cam, cs->film_x[k], cs->film_y[k], cs->time[k], cs->lens_u[k],
                                 cs->lens_v[k], &rays[k], rd ? &rd[k] : NULL);
  }
}
