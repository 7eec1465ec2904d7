/* Reconstruction filters (pbrt-v3's box, triangle, gaussian, mitchell and sinc, LuxCore's
 * Blackman-Harris, Mitsuba's Catmull-Rom) with arithmetic that gives the same bits on the host and
 * on OpenCL devices: only + - * floor and comparisons, no libm transcendentals, no division, and
 * subnormals flushed to zero explicitly (devices may flush them, the host does not).
 *
 * All filters are separable, f(x,y) = g(|x|; rx) * g(|y|; ry), and zero outside |x| <= rx,
 * |y| <= ry (the support is closed, as in pbrt-v3's film loop):
 *   box            g = 1
 *   triangle       g = max(0, r - a)
 *   gaussian       g = max(0, e^(-alpha a^2) - e^(-alpha r^2))
 *   mitchell       g = M(a/r), pbrt-v3's Mitchell1D: t = 2a/r, k(t)/6 with B, C
 *   sinc           g = sinc(a) * sinc(a/tau), sinc(x) = sin(pi x)/(pi x)  (Lanczos window)
 *   blackmanharris g = 0.35875 + 0.48829 cos(pi u) + 0.14128 cos(2 pi u) + 0.01168 cos(3 pi u),
 *                  u = a/r: LuxCore's A0 + A1 cos(2 pi v) + A2 cos(4 pi v) + A3 cos(6 pi v) with
 *                  v = (u+1)/2 (A1 = -0.48829, A3 = -0.01168); g(r) = 6e-5, as in LuxCore
 *   catmullrom     mitchell with B = 0, C = 1/2 (Mitsuba 0.6's catmullrom, halfSize = radius)
 */
#ifndef CLR_FILTER_FUNCS_H
#define CLR_FILTER_FUNCS_H

#include "clr_platform.h"
#include "filter_types.h"

#define CLR_FLT_MIN_NORMAL 0x1p-126f

/* Subnormals (and -0) become +0, so FTZ devices and the host agree. */
CLR_INLINE float clr_flush_subnormal(float v) {
  return clr_fabsf(v) < CLR_FLT_MIN_NORMAL ? 0.0f : v;
}

/* e^x for x in [-87, 88] within about 1 ulp; 0 below -87 (and for NaN), +inf above 88.
 * x = k ln2 + r with a Cody-Waite split of ln2 (k * ln2_hi is exact), e^r by Taylor to r^8. */
CLR_INLINE float clr_exp_portable(float x) {
  if (!(x >= -87.0f)) return 0.0f;
  if (x > 88.0f) return clr_as_float(0x7f800000u);
  float k = clr_floorf(x * 0x1.715476p+0f + 0.5f);
  float r = (x - k * 0x1.62e4p-1f) - k * 0x1.7f7d1cp-20f;
  float p = 0x1.a01a02p-16f;
  p = p * r + 0x1.a01a02p-13f;
  p = p * r + 0x1.6c16c2p-10f;
  p = p * r + 0x1.111112p-7f;
  p = p * r + 0x1.555556p-5f;
  p = p * r + 0x1.555556p-3f;
  p = p * r + 0.5f;
  float er = 1.0f + (r + (r * r) * p);
  return er * clr_as_float((clr_u32)((clr_i32)k + 127) << 23);
}

/* sin(pi f) for |f| <= 1/4: f * (pi + s q(s)), pi split in hi + lo for accuracy. */
CLR_INLINE float clr_sinpi_kernel(float f) {
  float s = f * f;
  float q = -0x1.e30750p-8f;
  q = q * s + 0x1.507834p-4f;
  q = q * s - 0x1.32d2ccp-1f;
  q = q * s + 0x1.466bc6p+1f;
  q = q * s - 0x1.4abbcep+2f;
  return f * 0x1.921fb6p+1f + f * (-0x1.777a5cp-24f + s * q);
}

/* cos(pi f) for |f| <= 1/4: Taylor to f^12. */
CLR_INLINE float clr_cospi_kernel(float f) {
  float s = f * f;
  float q = 0x1.f9d38ap-10f;
  q = q * s - 0x1.a6d1f2p-6f;
  q = q * s + 0x1.e1f506p-3f;
  q = q * s - 0x1.55d3c8p+0f;
  q = q * s + 0x1.03c1f0p+2f;
  q = q * s - 0x1.3bd3ccp+2f;
  return 1.0f + s * q;
}

/* sin(pi (x + quarter_turns / 2)): x = k/2 + f exactly with |f| <= 1/4, then one kernel by
 * quadrant. |x| >= 2^23 (all integers), inf and NaN give 0. */
CLR_INLINE float clr_sinpi_shifted(float x, clr_i32 quarter_turns) {
  float ax = clr_fabsf(x);
  if (!(ax < 0x1p23f)) return 0.0f;
  float twice = 2.0f * x;
  float k = ax < 0x1p22f ? clr_floorf(twice + 0.5f) : twice; /* 2x is an integer from 2^22 on */
  float f = x - k * 0.5f;
  clr_i32 quadrant = ((clr_i32)k + quarter_turns) & 3;
  float v = (quadrant & 1) ? clr_cospi_kernel(f) : clr_sinpi_kernel(f);
  return (quadrant & 2) ? -v : v;
}

/* sin(pi x) within about 1 ulp, exact zeros at integers. */
CLR_INLINE float clr_sinpi_portable(float x) { return clr_sinpi_shifted(x, 0); }

/* cos(pi x) within about 1 ulp. */
CLR_INLINE float clr_cospi_portable(float x) { return clr_sinpi_shifted(x, 1); }

/* 1/x for x in [2^-100, 2^100] within about 1 ulp: bit-trick seed and four Newton steps. */
CLR_INLINE float clr_rcp_portable(float x) {
  float y = clr_as_float(0x7ef311c3u - clr_as_uint(x));
  y = y * (2.0f - x * y);
  y = y * (2.0f - x * y);
  y = y * (2.0f - x * y);
  y = y * (2.0f - x * y);
  return y;
}

/* sin(pi a)/(pi a) for 0 <= a < 2^22: Taylor in a^2 to a^14 below 1/2, else sinpi * 1/a * 1/pi. */
CLR_INLINE float clr_sinc_portable(float a) {
  if (a < 0.5f) {
    float s = a * a;
    float q = -0x1.d42498p-18f;
    q = q * s + 0x1.37471ap-13f;
    q = q * s - 0x1.33816ap-9f;
    q = q * s + 0x1.ac6806p-6f;
    q = q * s - 0x1.86a8e4p-3f;
    q = q * s + 0x1.9f9cb4p-1f;
    q = q * s - 0x1.a51a66p+0f;
    return 1.0f + s * q;
  }
  return clr_sinpi_portable(a) * clr_rcp_portable(a) * 0x1.45f306p-2f;
}

/* pbrt-v3's Mitchell1D at u = |x|/r in [0, 1] (t = 2u). The outer cubic is pbrt's polynomial
 * factored as (2-t)^2 ((2B+6C) - (B+6C) t), so it is exactly 0 at t = 2. */
CLR_INLINE float clr_mitchell_1d(float u, float b, float c) {
  float t = 2.0f * u;
  float inner = (((12.0f - 9.0f * b) - 6.0f * c) * t + ((-18.0f + 12.0f * b) + 6.0f * c)) * t * t +
                (6.0f - 2.0f * b);
  float w = 2.0f - t;
  float outer = w * w * ((2.0f * b + 6.0f * c) - (b + 6.0f * c) * t);
  return (t > 1.0f ? outer : inner) * 0x1.555556p-3f;
}

/* Blackman-Harris at u = |x|/r in [0, 1] as a cubic in c = cos(pi u) (cos 2w = 2c^2 - 1,
 * cos 3w = 4c^3 - 3c): (A0 - A2) + (A1 - 3 A3) c + 2 A2 c^2 + 4 A3 c^3, positive A's above. */
CLR_INLINE float clr_blackman_harris_1d(float u) {
  float c = clr_cospi_portable(u);
  return ((0.04672f * c + 0.28256f) * c + 0.45325f) * c + 0.21747f;
}

/* One factor of the separable filter at a = |x| <= radius. */
CLR_ALWAYS_INLINE float clr_filter_1d(const clr_filter_params *f, float a, float radius,
                                      float inv_radius, float exp_edge) {
  switch (f->type) {
    case CLR_FILTER_TYPE_BOX:
      return 1.0f;
    case CLR_FILTER_TYPE_TRIANGLE:
      return clr_fmaxf(0.0f, radius - a);
    case CLR_FILTER_TYPE_GAUSSIAN:
      return clr_fmaxf(0.0f, clr_exp_portable(-(f->alpha * (a * a))) - exp_edge);
    case CLR_FILTER_TYPE_MITCHELL:
    case CLR_FILTER_TYPE_CATMULLROM:
      return clr_mitchell_1d(clr_fminf(a * inv_radius, 1.0f), f->b, f->c);
    case CLR_FILTER_TYPE_SINC:
      return clr_sinc_portable(a) * clr_sinc_portable(a * f->inv_tau);
    case CLR_FILTER_TYPE_BLACKMANHARRIS:
      return clr_blackman_harris_1d(clr_fminf(a * inv_radius, 1.0f));
    default:
      return 0.0f;
  }
}

/* The filter at offset (x, y) from the pixel center; exactly 0 outside the radius. */
CLR_INLINE float clr_filter_eval_exact(const clr_filter_params *f, float x, float y) {
  float ax = clr_fabsf(clr_flush_subnormal(x));
  float ay = clr_fabsf(clr_flush_subnormal(y));
  if (!(ax <= f->radius_x && ay <= f->radius_y)) return 0.0f;
  float gx = clr_flush_subnormal(clr_filter_1d(f, ax, f->radius_x, f->inv_radius_x, f->exp_x));
  float gy = clr_flush_subnormal(clr_filter_1d(f, ay, f->radius_y, f->inv_radius_y, f->exp_y));
  return clr_flush_subnormal(gx * gy);
}

/* pbrt-v3's FilmTile::AddSample table index: min(floor(|d * (1/r) * 16|), 15), with the clamp
 * applied before the conversion so huge or NaN offsets stay defined. */
CLR_INLINE clr_i32 clr_filter_table_index(float d, float inv_radius) {
  float scaled = clr_fabsf(d * inv_radius * (float)CLR_FILTER_TABLE_SIZE);
  return (clr_i32)clr_floorf(clr_fminf(scaled, (float)(CLR_FILTER_TABLE_SIZE - 1)));
}

/* pbrt-v3's Film table entry (ix, iy): the exact filter at ((i + .5) r / 16). */
CLR_INLINE float clr_filter_table_entry(const clr_filter_params *f, clr_i32 ix, clr_i32 iy) {
  float inv_size = 0.0625f; /* 1 / CLR_FILTER_TABLE_SIZE, exact */
  float px = ((float)ix + 0.5f) * f->radius_x * inv_size;
  float py = ((float)iy + 0.5f) * f->radius_y * inv_size;
  return clr_filter_eval_exact(f, px, py);
}

/* pbrt-v3's separable table factor i of `axis` (0: x, 1: y): the exact 1D filter at
 * ((i + .5) r / 16), subnormals flushed. Table entry (ix, iy) is exactly
 * flush(factor(0, ix) * factor(1, iy)). */
CLR_INLINE float clr_filter_table_factor(const clr_filter_params *f, clr_i32 axis, clr_i32 i) {
  float radius = axis ? f->radius_y : f->radius_x;
  float p = ((float)i + 0.5f) * radius * 0.0625f;
  return clr_flush_subnormal(clr_filter_1d(f, p, radius, axis ? f->inv_radius_y : f->inv_radius_x,
                                           axis ? f->exp_y : f->exp_x));
}

/* One separable factor of the filter as the film uses it, at offset d along `axis` (0: x, 1: y);
 * exactly 0 outside the radius. Table mode reads `factors`: CLR_FILTER_TABLE_SIZE x factors then
 * CLR_FILTER_TABLE_SIZE y factors (clr_filter_table_factor; unused in exact mode). For every
 * filter and mode clr_filter_eval(f, x, y, table) ==
 * clr_flush_subnormal(clr_filter_eval_1d(f, 0, x, factors) * clr_filter_eval_1d(f, 1, y, factors))
 * bit for bit. */
CLR_ALWAYS_INLINE float clr_filter_eval_1d(const clr_filter_params *f, clr_i32 axis, float d,
                                           CLR_GLOBAL const float *factors) {
  float radius = axis ? f->radius_y : f->radius_x;
  float inv_radius = axis ? f->inv_radius_y : f->inv_radius_x;
  if (f->use_table) {
    if (!(clr_fabsf(d) <= radius)) return 0.0f;
    return factors[axis * CLR_FILTER_TABLE_SIZE + clr_filter_table_index(d, inv_radius)];
  }
  float a = clr_fabsf(clr_flush_subnormal(d));
  if (!(a <= radius)) return 0.0f;
  return clr_flush_subnormal(clr_filter_1d(f, a, radius, inv_radius, axis ? f->exp_y : f->exp_x));
}

/* The filter as the film uses it: exact, or the nearest entry of the 16x16 table (row-major,
 * y major) of the positive quadrant when f->use_table. Exactly 0 outside the radius. */
CLR_INLINE float clr_filter_eval(const clr_filter_params *f, float x, float y,
                                 CLR_GLOBAL const float *table) {
  if (!f->use_table) return clr_filter_eval_exact(f, x, y);
  if (!(clr_fabsf(x) <= f->radius_x && clr_fabsf(y) <= f->radius_y)) return 0.0f;
  clr_i32 ix = clr_filter_table_index(x, f->inv_radius_x);
  clr_i32 iy = clr_filter_table_index(y, f->inv_radius_y);
  return table[iy * CLR_FILTER_TABLE_SIZE + ix];
}

#endif
