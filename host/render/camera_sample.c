#include "camera_sample.h"
#include <math.h>
#include "float_minmax.h"

#define ONE_MINUS_EPSILON 0x1.fffffep-1f

int clr_camera_sample_is_pbrt_v4(const clr_sampler_desc *sd) {
  return sd->seeding == CLR_SEEDING_PBRT_V4 || sd->type >= CLR_SAMPLER_INDEPENDENT;
}

void clr_camera_layout_init(clr_camera_layout *l, const clr_sampler_desc *sd,
                            const clr_filter_desc *fd) {
  l->pbrt_v4 = clr_camera_sample_is_pbrt_v4(sd);
  l->filter_sampled = l->pbrt_v4 && (fd->type == CLR_FILTER_BOX || fd->type == CLR_FILTER_TRIANGLE);
  l->filter = l->filter_sampled ? fd->type : CLR_FILTER_BOX;
  l->radius[0] = l->filter_sampled ? fd->radius[0] : 0.5f;
  l->radius[1] = l->filter_sampled ? fd->radius[1] : 0.5f;
  l->time_value = 2;
  l->lens_value = 3;
}

void clr_camera_layout_skip(clr_camera_layout *l, int camera_offset, int time_offset,
                            int lens_offset) {
  l->time_value = time_offset < 0 ? -1 : time_offset - camera_offset;
  l->lens_value = lens_offset < 0 ? -1 : lens_offset - camera_offset;
}

/* pbrt-v4's Lerp, (1 - t) a + t b (the build never contracts it into an FMA) */
static float lerp_v4(float t, float a, float b) { return (1.0f - t) * a + t * b; }

/* pbrt-v4's SampleLinear(u, a, b) for (0, 1) and (1, 0) */
static float sample_linear(float u, float a, float b) {
  if (u == 0.0f && a == 0.0f) return 0.0f;
  float x = u * (a + b) / (a + sqrtf(lerp_v4(u, a * a, b * b)));
  return rs_fminf(x, ONE_MINUS_EPSILON);
}

/* pbrt-v4's SampleTent: SampleDiscrete({0.5, 0.5}) picks a side and remaps u */
static float sample_tent(float u, float r) {
  float up = u == 1.0f ? ONE_MINUS_EPSILON : u; /* u * (0.5 + 0.5), NextFloatDown at the sum */
  if (!(up >= 0.5f)) return -r + r * sample_linear(rs_fminf(up / 0.5f, ONE_MINUS_EPSILON), 0, 1);
  return r * sample_linear(rs_fminf((up - 0.5f) / 0.5f, ONE_MINUS_EPSILON), 1, 0);
}

static float filter_offset(const clr_camera_layout *l, float u, float r) {
  return l->filter == CLR_FILTER_TRIANGLE ? sample_tent(u, r) : lerp_v4(u, -r, r);
}

void clr_camera_sample_from_values(const clr_camera_layout *l, const float *v, int px, int py,
                                   clr_camera_sample *cs) {
  if (l->pbrt_v4) { /* pPixel + fs.p + Vector2f(0.5f, 0.5f) */
    cs->film_x = ((float)px + filter_offset(l, v[0], l->radius[0])) + 0.5f;
    cs->film_y = ((float)py + filter_offset(l, v[1], l->radius[1])) + 0.5f;
  } else {
    cs->film_x = (float)px + v[0];
    cs->film_y = (float)py + v[1];
  }
  cs->pixel_x = l->filter_sampled ? (float)px + 0.5f : cs->film_x;
  cs->pixel_y = l->filter_sampled ? (float)py + 0.5f : cs->film_y;
  cs->time = l->time_value < 0 ? 0.0f : v[l->time_value];
  cs->lens_u = l->lens_value < 0 ? 0.5f : v[l->lens_value];
  cs->lens_v = l->lens_value < 0 ? 0.5f : v[l->lens_value + 1];
}

static void store_sample(const clr_camera_samples *out, int k, const clr_camera_sample *cs) {
  out->film_x[k] = cs->film_x;
  out->film_y[k] = cs->film_y;
  out->pixel_x[k] = cs->pixel_x;
  out->pixel_y[k] = cs->pixel_y;
  out->time[k] = cs->time;
  out->lens_u[k] = cs->lens_u;
  out->lens_v[k] = cs->lens_v;
}

/* out[k] = the k-th vector's value at offset, or fill where offset < 0 (a skipped request). */
static void gather_or_fill(const float *v, size_t stride, int offset, float fill, int n,
                           float *out) {
  if (offset < 0)
    for (int k = 0; k < n; ++k) out[k] = fill;
  else
    for (int k = 0; k < n; ++k) out[k] = v[(size_t)k * stride + (size_t)offset];
}

/* pbrt-v3's layout: film = pixel + offset, taken there; one pixel's samples at a time. */
static void v3_samples(const clr_camera_layout *l, const float *v, size_t stride, int px, int py,
                       int s, int spp, int n, const clr_camera_samples *out) {
  float fy = (float)py;
  for (int k = 0; k < n; ++px, s = 0) {
    int end = k + (spp - s < n - k ? spp - s : n - k);
    float fx = (float)px;
    for (; k < end; ++k) {
      const float *vk = v + (size_t)k * stride;
      out->film_x[k] = out->pixel_x[k] = fx + vk[0];
      out->film_y[k] = out->pixel_y[k] = fy + vk[1];
    }
  }
  gather_or_fill(v, stride, l->time_value, 0.0f, n, out->time);
  gather_or_fill(v, stride, l->lens_value, 0.5f, n, out->lens_u);
  gather_or_fill(v, stride, l->lens_value < 0 ? -1 : l->lens_value + 1, 0.5f, n, out->lens_v);
}

void clr_camera_samples_from_values(const clr_camera_layout *l, const float *v, size_t stride,
                                    int px, int py, int s, int spp, int n,
                                    const clr_camera_samples *out) {
  if (!l->pbrt_v4) {
    v3_samples(l, v, stride, px, py, s, spp, n, out);
    return;
  }
  for (int k = 0; k < n; ++k) {
    clr_camera_sample cs;
    clr_camera_sample_from_values(l, v + (size_t)k * stride, px, py, &cs);
    store_sample(out, k, &cs);
    if (++s == spp) {
      s = 0;
      ++px;
    }
  }
}
