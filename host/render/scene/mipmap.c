/* pbrt-v3's MIPMap re-implemented from its definition (core/mipmap.h): Lanczos resampling to
 * powers of two, box-filtered levels, triangle, trilinear and EWA lookups. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "mipmap.h"
#include "render_error.h"
#include "float_minmax.h"

#define LANCZOS_TAU 2.0f
#define MAX_SIDE (1 << 20)   /* larger images are refused (the pyramid's indices stay in int) */
#define MAX_COORD 1073741824 /* 2^30: texel coordinates past it are looked up as black */

/* pbrt-v3 Lanczos(x, tau): windowed sinc over [-1, 1]. */
static float lanczos(float x) {
  const float pi = 3.14159265358979323846f;
  x = fabsf(x);
  if (x < 1e-5f) return 1.0f;
  if (x > 1.0f) return 0.0f;
  x *= pi;
  float s = sinf(x * LANCZOS_TAU) / (x * LANCZOS_TAU);
  return s * (sinf(x) / x);
}

/* pbrt-v3 Log2(float). */
static float log2_f(float x) { return logf(x) * 1.442695040888963387004650940071f; }

static int32_t round_up_pow2(int32_t v) {
  int32_t p = 1;
  while (p < v) p <<= 1;
  return p;
}

/* pbrt-v3 ResampleWeight: four Lanczos weights from firstTexel, normalised. */
typedef struct resample_weight {
  int first;
  float w[4];
} resample_weight;

static resample_weight *resample_weights(int old_res, int new_res) {
  resample_weight *wt = malloc((size_t)new_res * sizeof *wt);
  if (!wt) return NULL;
  const float filter_width = 2.0f;
  for (int i = 0; i < new_res; ++i) {
    float center = ((float)i + 0.5f) * (float)old_res / (float)new_res;
    wt[i].first = (int)floorf((center - filter_width) + 0.5f);
    for (int j = 0; j < 4; ++j) {
      float pos = (float)(wt[i].first + j) + 0.5f;
      wt[i].w[j] = lanczos((pos - center) / filter_width);
    }
    float inv = 1.0f / (wt[i].w[0] + wt[i].w[1] + wt[i].w[2] + wt[i].w[3]);
    for (int j = 0; j < 4; ++j) wt[i].w[j] *= inv;
  }
  return wt;
}

/* An index of a resampling tap under the wrap mode; -1 when it falls outside ("black"). */
static int wrap_tap(int i, int n, rs_wrap wrap) {
  if (wrap == RS_WRAP_REPEAT) {
    int m = i % n;
    return m < 0 ? m + n : m;
  }
  if (wrap == RS_WRAP_CLAMP) return i < 0 ? 0 : i >= n ? n - 1 : i;
  return i < 0 || i >= n ? -1 : i;
}

/* The s pass then the t pass of pbrt-v3's resampling into out (w2 x h2), clamped at 0. */
static clr_result resample(const float *img, int w, int h, int w2, int h2, rs_wrap wrap,
                           float *out) {
  resample_weight *sw = resample_weights(w, w2), *tw = resample_weights(h, h2);
  float *col = malloc((size_t)h2 * 3 * sizeof *col);
  if (!sw || !tw || !col) {
    free(sw);
    free(tw);
    free(col);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "imagemap: MIP map resampling");
  }
  for (int t = 0; t < h; ++t)
    for (int s = 0; s < w2; ++s) {
      float *o = out + 3 * ((size_t)t * (size_t)w2 + (size_t)s);
      o[0] = o[1] = o[2] = 0.0f;
      for (int j = 0; j < 4; ++j) {
        int x = wrap_tap(sw[s].first + j, w, wrap);
        if (x < 0) continue;
        const float *v = img + 3 * ((size_t)t * (size_t)w + (size_t)x);
        for (int k = 0; k < 3; ++k) o[k] += sw[s].w[j] * v[k];
      }
    }
  for (int s = 0; s < w2; ++s) {
    for (int t = 0; t < h2; ++t) {
      float *c = col + 3 * t;
      c[0] = c[1] = c[2] = 0.0f;
      for (int j = 0; j < 4; ++j) {
        int y = wrap_tap(tw[t].first + j, h, wrap);
        if (y < 0) continue;
        const float *v = out + 3 * ((size_t)y * (size_t)w2 + (size_t)s);
        for (int k = 0; k < 3; ++k) c[k] += tw[t].w[j] * v[k];
      }
    }
    for (int t = 0; t < h2; ++t)
      for (int k = 0; k < 3; ++k)
        out[3 * ((size_t)t * (size_t)w2 + (size_t)s) + k] = rs_fmaxf(0.0f, col[3 * t + k]);
  }
  free(sw);
  free(tw);
  free(col);
  return CLR_SUCCESS;
}

static int level_count(int32_t w, int32_t h) {
  int32_t m = w > h ? w : h;
  int n = 1;
  while (m > 1) {
    m >>= 1;
    ++n;
  }
  return n;
}

/* Level i from level i - 1: pbrt-v3's box filter of four texels read under the wrap mode. */
static void box_filter_level(const rs_mipmap *m, int i) {
  rs_mip_level *l = &m->levels[i];
  for (int t = 0; t < l->height; ++t)
    for (int s = 0; s < l->width; ++s) {
      float a[3], b[3], c[3], d[3];
      rs_mipmap_texel(m, i - 1, 2 * s, 2 * t, a);
      rs_mipmap_texel(m, i - 1, 2 * s + 1, 2 * t, b);
      rs_mipmap_texel(m, i - 1, 2 * s, 2 * t + 1, c);
      rs_mipmap_texel(m, i - 1, 2 * s + 1, 2 * t + 1, d);
      float *o = l->rgb + 3 * ((size_t)t * (size_t)l->width + (size_t)s);
      for (int k = 0; k < 3; ++k) o[k] = 0.25f * (a[k] + b[k] + c[k] + d[k]);
    }
}

clr_result rs_mipmap_build(rs_mipmap *m, int32_t w, int32_t h, const float *rgb, rs_wrap wrap,
                           int trilinear, float max_anisotropy) {
  memset(m, 0, sizeof *m);
  if (w < 1 || h < 1 || w > MAX_SIDE || h > MAX_SIDE)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "imagemap: %dx%d image: MIP maps take sides of 1 to %d texels",
                              (int)w, (int)h, MAX_SIDE);
  m->wrap = wrap;
  m->trilinear = trilinear;
  m->max_anisotropy = max_anisotropy;
  int32_t w2 = round_up_pow2(w), h2 = round_up_pow2(h);
  m->count = level_count(w2, h2);
  m->levels = calloc((size_t)m->count, sizeof *m->levels);
  if (!m->levels) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "imagemap: MIP map");
  for (int i = 0; i < m->count; ++i) {
    rs_mip_level *l = &m->levels[i];
    l->width = i ? (m->levels[i - 1].width / 2 > 1 ? m->levels[i - 1].width / 2 : 1) : w2;
    l->height = i ? (m->levels[i - 1].height / 2 > 1 ? m->levels[i - 1].height / 2 : 1) : h2;
    l->rgb = malloc((size_t)l->width * (size_t)l->height * 3 * sizeof(float));
    if (!l->rgb) {
      rs_mipmap_free(m);
      return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "imagemap: MIP map of %dx%d", (int)w2,
                                (int)h2);
    }
  }
  if (w2 != w || h2 != h) {
    clr_result r = resample(rgb, w, h, w2, h2, wrap, m->levels[0].rgb);
    if (r != CLR_SUCCESS) {
      rs_mipmap_free(m);
      return r;
    }
  } else {
    memcpy(m->levels[0].rgb, rgb, (size_t)w * (size_t)h * 3 * sizeof(float));
  }
  for (int i = 1; i < m->count; ++i) box_filter_level(m, i);
  for (int i = 0; i < RS_EWA_LUT_SIZE; ++i) { /* exp(-2 r^2) - exp(-2) at r^2 = i / 127 */
    float r2 = (float)i / (float)(RS_EWA_LUT_SIZE - 1);
    m->ewa_lut[i] = expf(-2.0f * r2) - expf(-2.0f);
  }
  return CLR_SUCCESS;
}

void rs_mipmap_free(rs_mipmap *m) {
  for (int i = 0; m->levels && i < m->count; ++i) free(m->levels[i].rgb);
  free(m->levels);
  memset(m, 0, sizeof *m);
}

void rs_mipmap_texel(const rs_mipmap *m, int level, int s, int t, float out[3]) {
  const rs_mip_level *l = &m->levels[level];
  s = wrap_tap(s, l->width, m->wrap);
  t = wrap_tap(t, l->height, m->wrap);
  if (s < 0 || t < 0) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  const float *v = l->rgb + 3 * ((size_t)t * (size_t)l->width + (size_t)s);
  out[0] = v[0];
  out[1] = v[1];
  out[2] = v[2];
}

static int coord_ok(float x) { return fabsf(x) < (float)MAX_COORD; }

void rs_mipmap_bilinear(const rs_mipmap *m, int level, const float st[2], float out[3]) {
  level = level < 0 ? 0 : level >= m->count ? m->count - 1 : level;
  const rs_mip_level *l = &m->levels[level];
  float s = st[0] * (float)l->width - 0.5f, t = st[1] * (float)l->height - 0.5f;
  if (!coord_ok(s) || !coord_ok(t)) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  int s0 = (int)floorf(s), t0 = (int)floorf(t);
  float ds = s - (float)s0, dt = t - (float)t0, a[3], b[3], c[3], d[3];
  rs_mipmap_texel(m, level, s0, t0, a);
  rs_mipmap_texel(m, level, s0, t0 + 1, b);
  rs_mipmap_texel(m, level, s0 + 1, t0, c);
  rs_mipmap_texel(m, level, s0 + 1, t0 + 1, d);
  float wa = (1 - ds) * (1 - dt), wb = (1 - ds) * dt, wc = ds * (1 - dt), wd = ds * dt;
  for (int k = 0; k < 3; ++k) out[k] = wa * a[k] + wb * b[k] + wc * c[k] + wd * d[k];
}

static void lerp3(float f, const float a[3], const float b[3], float out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = (1 - f) * a[k] + f * b[k];
}

void rs_mipmap_trilinear(const rs_mipmap *m, const float st[2], float width, float out[3]) {
  float level = (float)(m->count - 1) + log2_f(rs_fmaxf(width, 1e-8f));
  if (!(level >= 0.0f)) { /* NaN widths too */
    rs_mipmap_bilinear(m, 0, st, out);
  } else if (level >= (float)(m->count - 1)) {
    rs_mipmap_texel(m, m->count - 1, 0, 0, out);
  } else {
    int i = (int)floorf(level);
    float a[3], b[3];
    rs_mipmap_bilinear(m, i, st, a);
    rs_mipmap_bilinear(m, i + 1, st, b);
    lerp3(level - (float)i, a, b, out);
  }
}

static float ewa_weight(const rs_mipmap *m, float r2) {
  int i = r2 > 0.0f ? (int)(r2 * RS_EWA_LUT_SIZE) : 0; /* r2 < 1; never below 0 by rounding */
  return m->ewa_lut[i < RS_EWA_LUT_SIZE - 1 ? i : RS_EWA_LUT_SIZE - 1];
}

/* pbrt-v3 MIPMap::EWA at one level: the Gaussian-weighted texels inside the ellipse. */
static void ewa_level(const rs_mipmap *m, int level, const float st_in[2], const float d0_in[2],
                      const float d1_in[2], float out[3]) {
  if (level >= m->count) {
    rs_mipmap_texel(m, m->count - 1, 0, 0, out);
    return;
  }
  const rs_mip_level *l = &m->levels[level];
  float w = (float)l->width, h = (float)l->height;
  float st[2] = {st_in[0] * w - 0.5f, st_in[1] * h - 0.5f};
  float d0[2] = {d0_in[0] * w, d0_in[1] * h}, d1[2] = {d1_in[0] * w, d1_in[1] * h};
  float A = d0[1] * d0[1] + d1[1] * d1[1] + 1;
  float B = -2 * (d0[0] * d0[1] + d1[0] * d1[1]);
  float C = d0[0] * d0[0] + d1[0] * d1[0] + 1;
  float inv_f = 1 / (A * C - B * B * 0.25f);
  A *= inv_f;
  B *= inv_f;
  C *= inv_f;
  float det = -B * B + 4 * A * C, inv_det = 1 / det;
  float u_sqrt = sqrtf(det * C), v_sqrt = sqrtf(A * det);
  float fs0 = ceilf(st[0] - 2 * inv_det * u_sqrt), fs1 = floorf(st[0] + 2 * inv_det * u_sqrt);
  float ft0 = ceilf(st[1] - 2 * inv_det * v_sqrt), ft1 = floorf(st[1] + 2 * inv_det * v_sqrt);
  out[0] = out[1] = out[2] = 0.0f;
  if (!coord_ok(fs0) || !coord_ok(fs1) || !coord_ok(ft0) || !coord_ok(ft1)) return;
  float sum[3] = {0, 0, 0}, sum_w = 0;
  for (int it = (int)ft0; it <= (int)ft1; ++it) {
    float tt = (float)it - st[1];
    for (int is = (int)fs0; is <= (int)fs1; ++is) {
      float ss = (float)is - st[0];
      float r2 = A * ss * ss + B * ss * tt + C * tt * tt;
      if (r2 < 1) {
        float wt = ewa_weight(m, r2), v[3];
        rs_mipmap_texel(m, level, is, it, v);
        for (int k = 0; k < 3; ++k) sum[k] += v[k] * wt;
        sum_w += wt;
      }
    }
  }
  if (sum_w > 0)
    for (int k = 0; k < 3; ++k) out[k] = sum[k] / sum_w;
}

static int finite2(const float v[2]) { return isfinite(v[0]) && isfinite(v[1]); }

void rs_mipmap_ewa(const rs_mipmap *m, const float st[2], const float dst0[2], const float dst1[2],
                   float out[3]) {
  float d0[2] = {dst0[0], dst0[1]}, d1[2] = {dst1[0], dst1[1]};
  if (!finite2(d0) || !finite2(d1)) d0[0] = d0[1] = d1[0] = d1[1] = 0.0f;
  if (d0[0] * d0[0] + d0[1] * d0[1] < d1[0] * d1[0] + d1[1] * d1[1]) {
    float t0 = d0[0], t1 = d0[1];
    d0[0] = d1[0];
    d0[1] = d1[1];
    d1[0] = t0;
    d1[1] = t1;
  }
  float major = sqrtf(d0[0] * d0[0] + d0[1] * d0[1]);
  float minor = sqrtf(d1[0] * d1[0] + d1[1] * d1[1]);
  if (minor * m->max_anisotropy < major && minor > 0) { /* clamp the eccentricity */
    float scale = major / (minor * m->max_anisotropy);
    d1[0] *= scale;
    d1[1] *= scale;
    minor *= scale;
  }
  if (minor == 0) {
    rs_mipmap_bilinear(m, 0, st, out);
    return;
  }
  float lod = rs_fmaxf(0.0f, (float)(m->count - 1) + log2_f(minor));
  if (!(lod < (float)m->count)) { /* both levels past the last: its single texel */
    rs_mipmap_texel(m, m->count - 1, 0, 0, out);
    return;
  }
  int ilod = (int)floorf(lod);
  float a[3], b[3];
  ewa_level(m, ilod, st, d0, d1, a);
  ewa_level(m, ilod + 1, st, d0, d1, b);
  lerp3(lod - (float)ilod, a, b, out);
}

void rs_mipmap_lookup(const rs_mipmap *m, const float st[2], const float dstdx[2],
                      const float dstdy[2], float out[3]) {
  if (m->trilinear) {
    float width = rs_fmaxf(rs_fmaxf(fabsf(dstdx[0]), fabsf(dstdx[1])),
                           rs_fmaxf(fabsf(dstdy[0]), fabsf(dstdy[1])));
    rs_mipmap_trilinear(m, st, width, out);
    return;
  }
  rs_mipmap_ewa(m, st, dstdx, dstdy, out);
}
