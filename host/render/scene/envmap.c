/* pbrt-v3 InfiniteAreaLight's image (a PNG's bytes / 255 taken as linear, as pbrt-v3's ReadImage
 * does for light maps) and Distribution2D (sampling.h), re-implemented from their
 * definitions; the map is not resampled to powers of two nor MIP-filtered as pbrt-v3 does. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "clrender/image.h"
#include "envmap.h"
#include "render_error.h"

#define PI_F 3.14159265358979323846f

static int wrap(int i, int n) {
  int m = i % n;
  return m < 0 ? m + n : m;
}

void rs_envmap_lookup(const rs_envmap *m, float s, float t, float out[3]) {
  float x = s * (float)m->w - 0.5f, y = t * (float)m->h - 0.5f;
  if (!(fabsf(x) < 1e9f && fabsf(y) < 1e9f)) x = y = 0.0f;
  int x0 = (int)floorf(x), y0 = (int)floorf(y);
  float dx = x - (float)x0, dy = y - (float)y0;
  const float *a = m->rgb + 3 * ((size_t)wrap(y0, m->h) * (size_t)m->w + (size_t)wrap(x0, m->w));
  const float *b =
      m->rgb + 3 * ((size_t)wrap(y0, m->h) * (size_t)m->w + (size_t)wrap(x0 + 1, m->w));
  const float *c =
      m->rgb + 3 * ((size_t)wrap(y0 + 1, m->h) * (size_t)m->w + (size_t)wrap(x0, m->w));
  const float *d =
      m->rgb + 3 * ((size_t)wrap(y0 + 1, m->h) * (size_t)m->w + (size_t)wrap(x0 + 1, m->w));
  for (int k = 0; k < 3; ++k)
    out[k] =
        (1 - dx) * (1 - dy) * a[k] + dx * (1 - dy) * b[k] + (1 - dx) * dy * c[k] + dx * dy * d[k];
}

static float luminance(const float c[3]) {
  return 0.212671f * c[0] + 0.715160f * c[1] + 0.072169f * c[2];
}

/* pbrt-v3 Distribution1D: cdf[0..n] from func[0..n); returns funcInt. */
static float build_1d(const float *func, int n, float *cdf) {
  cdf[0] = 0.0f;
  for (int i = 1; i <= n; ++i) cdf[i] = cdf[i - 1] + func[i - 1] / (float)n;
  float integral = cdf[n];
  for (int i = 1; i <= n; ++i) cdf[i] = integral == 0.0f ? (float)i / (float)n : cdf[i] / integral;
  return integral;
}

/* Distribution1D::SampleContinuous: the continuous sample in [0, 1), its pdf and offset. */
static float sample_1d(const float *func, const float *cdf, float integral, int n, float u,
                       float *pdf, int *off) {
  int lo = 0, hi = n - 1; /* FindInterval: the last i with cdf[i] <= u */
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if (cdf[mid] <= u)
      lo = mid;
    else
      hi = mid - 1;
  }
  *off = lo;
  float du = u - cdf[lo];
  if (cdf[lo + 1] - cdf[lo] > 0.0f) du /= cdf[lo + 1] - cdf[lo];
  *pdf = integral > 0.0f ? func[lo] / integral : 0.0f;
  return ((float)lo + du) / (float)n;
}

clr_result rs_envmap_load(const char *path, const float L[3], rs_envmap **out) {
  *out = NULL;
  clr_image im;
  CLR_CHECK(clr_image_read(path, &im));
  rs_envmap *m = calloc(1, sizeof *m);
  if (!m) {
    clr_image_free(&im);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "infinite light map");
  }
  m->w = im.width;
  m->h = im.height;
  m->rgb = im.rgb;
  size_t n = (size_t)m->w * (size_t)m->h;
  double sum_y = 0.0;
  size_t len = strlen(path);
  int png = len >= 4 && strcasecmp(path + len - 4, ".png") == 0;
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      float v = m->rgb[3 * i + k]; /* pbrt-v3 reads a PNG map's bytes / 255 as linear values */
      if (png) v = v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
      m->rgb[3 * i + k] = v * L[k];
    }
    sum_y += luminance(m->rgb + 3 * i);
  }
  m->mean_y = (float)(sum_y / (double)n);
  m->dw = 2 * m->w;
  m->dh = 2 * m->h;
  size_t dn = (size_t)m->dw * (size_t)m->dh;
  m->func = malloc(dn * sizeof *m->func);
  m->cdf = malloc((size_t)m->dh * (size_t)(m->dw + 1) * sizeof *m->cdf);
  m->row_int = malloc((size_t)m->dh * sizeof *m->row_int);
  m->marg_cdf = malloc((size_t)(m->dh + 1) * sizeof *m->marg_cdf);
  if (!m->func || !m->cdf || !m->row_int || !m->marg_cdf) {
    rs_envmap_free(m);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "infinite light map distribution");
  }
  for (int v = 0; v < m->dh; ++v) {
    float vp = ((float)v + 0.5f) / (float)m->dh, st = sinf(PI_F * vp), c[3];
    for (int u = 0; u < m->dw; ++u) {
      rs_envmap_lookup(m, ((float)u + 0.5f) / (float)m->dw, vp, c);
      m->func[(size_t)v * (size_t)m->dw + (size_t)u] = luminance(c) * st;
    }
    m->row_int[v] = build_1d(m->func + (size_t)v * (size_t)m->dw, m->dw,
                             m->cdf + (size_t)v * (size_t)(m->dw + 1));
  }
  m->marg_int = build_1d(m->row_int, m->dh, m->marg_cdf);
  *out = m;
  return CLR_SUCCESS;
}

void rs_envmap_free(rs_envmap *m) {
  if (!m) return;
  free(m->rgb);
  free(m->func);
  free(m->cdf);
  free(m->row_int);
  free(m->marg_cdf);
  free(m);
}

float rs_envmap_sample(const rs_envmap *m, const float u[2], float st[2]) {
  float pv, pu;
  int v, off;
  st[1] = sample_1d(m->row_int, m->marg_cdf, m->marg_int, m->dh, u[1], &pv, &v);
  st[0] = sample_1d(m->func + (size_t)v * (size_t)m->dw, m->cdf + (size_t)v * (size_t)(m->dw + 1),
                    m->row_int[v], m->dw, u[0], &pu, &off);
  return pu * pv;
}

float rs_envmap_pdf(const rs_envmap *m, float s, float t) {
  int iu = (int)(s * (float)m->dw), iv = (int)(t * (float)m->dh);
  iu = iu < 0 ? 0 : iu >= m->dw ? m->dw - 1 : iu;
  iv = iv < 0 ? 0 : iv >= m->dh ? m->dh - 1 : iv;
  return m->marg_int > 0.0f ? m->func[(size_t)iv * (size_t)m->dw + (size_t)iu] / m->marg_int : 0.0f;
}
