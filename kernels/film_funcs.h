/* pbrt-v3 FilmTile::AddSample math shared by the kernels, the host reference and the host film
 * tiles: sample check, luminance clamp, filter footprint and one pixel's contribution. */
#ifndef CLR_FILM_FUNCS_H
#define CLR_FILM_FUNCS_H

#include "film_types.h"
#include "filter_funcs.h"

CLR_INLINE int clr_film_is_finite(float v) { return (clr_as_uint(v) & 0x7f800000u) != 0x7f800000u; }

/* pbrt-v3 RGBSpectrum::y(), evaluated left to right. */
CLR_INLINE float clr_film_luminance(float r, float g, float b) {
  return 0.212671f * r + 0.715160f * g + 0.072169f * b;
}

/* (clr_i32)ceil(x) and (clr_i32)floor(x) for |x| < 2^31 without a libm call (the kernels' ceil
 * and floor are branchy on some devices): the truncation, plus or minus one where it dropped a
 * fraction ((float)i is exact: below 2^24 every integer is a float, above it x itself is an
 * integer). */
CLR_INLINE clr_i32 clr_film_ceil_i32(float x) {
  clr_i32 i = (clr_i32)x;
  return i + (x > (float)i);
}
CLR_INLINE clr_i32 clr_film_floor_i32(float x) {
  clr_i32 i = (clr_i32)x;
  return i - (x < (float)i);
}

/* pbrt's first and last pixel a filter of radius r centred at d reaches: ceil(d - r), floor(d + r). */
CLR_INLINE clr_i32 clr_film_first_pixel(float d, float radius) {
  return clr_film_ceil_i32(d - radius);
}
CLR_INLINE clr_i32 clr_film_last_pixel(float d, float radius) {
  return clr_film_floor_i32(d + radius);
}

/* Checks sample s (CLR_FILM_SAMPLE_FLOATS values) and fills *out; returns CLR_FILM_SAMPLE_*. */
CLR_INLINE clr_i32 clr_film_prepare(const clr_film_params *fp, const clr_filter_params *f, float x,
                                    float y, float r, float g, float b, float w,
                                    clr_film_prepared *out) {
  if (!clr_film_is_finite(x) || !clr_film_is_finite(y) || !clr_film_is_finite(r) ||
      !clr_film_is_finite(g) || !clr_film_is_finite(b) || !clr_film_is_finite(w))
    return CLR_FILM_SAMPLE_DROPPED;
  float lum = clr_film_luminance(r, g, b);
  if (!clr_film_is_finite(lum) || lum < CLR_FILM_MIN_LUMINANCE) return CLR_FILM_SAMPLE_DROPPED;
  /* Half-open sample bounds, plus a sample exactly at distance `radius` past the last pixel's
   * centre: it reaches that pixel (pbrt-v3's footprint includes it), so crops merge exactly. */
  if (!(x >= (float)fp->sample_x0 &&
        (x < (float)fp->sample_x1 || x == (float)fp->pixel_x1 - 0.5f + f->radius_x) &&
        y >= (float)fp->sample_y0 &&
        (y < (float)fp->sample_y1 || y == (float)fp->pixel_y1 - 0.5f + f->radius_y)))
    return CLR_FILM_SAMPLE_OUTSIDE;
  if (fp->clamp_luminance && lum > fp->max_luminance) {
    float s = fp->max_luminance / lum;
    r *= s;
    g *= s;
    b *= s;
  }
  if (!clr_film_is_finite(r * w) || !clr_film_is_finite(g * w) || !clr_film_is_finite(b * w))
    return CLR_FILM_SAMPLE_DROPPED; /* L * w overflows */
  out->dx = x - 0.5f;
  out->dy = y - 0.5f;
  out->r = r;
  out->g = g;
  out->b = b;
  out->w = w;
  out->x0 = clr_film_first_pixel(out->dx, f->radius_x);
  out->x1 = clr_film_last_pixel(out->dx, f->radius_x);
  out->y0 = clr_film_first_pixel(out->dy, f->radius_y);
  out->y1 = clr_film_last_pixel(out->dy, f->radius_y);
  return CLR_FILM_SAMPLE_OK;
}

/* One separable factor of the film's filter weight: the x (axis 0) or y (axis 1) factor for
 * pixel coordinate p of a sample at d. factors: the 2 x 16 table factors (table mode). */
CLR_ALWAYS_INLINE float clr_film_filter_factor(const clr_filter_params *f,
                                               CLR_GLOBAL const float *factors, clr_i32 axis,
                                               float d, clr_i32 p) {
  return clr_filter_eval_1d(f, axis, (float)p - d, factors);
}

/* The filter weight from its two factors: equal bit for bit to clr_filter_eval at
 * (px - dx, py - dy) with pbrt's 16x16 table in table mode (clr_filter_eval_1d). */
CLR_INLINE float clr_film_weight(float fx, float fy) { return clr_flush_subnormal(fx * fy); }

/* The filter weight of a sample at d for pixel (px, py). */
CLR_INLINE float clr_film_filter_weight(const clr_filter_params *f, CLR_GLOBAL const float *factors,
                                        float dx, float dy, clr_i32 px, clr_i32 py) {
  return clr_film_weight(clr_film_filter_factor(f, factors, 0, dx, px),
                         clr_film_filter_factor(f, factors, 1, dy, py));
}

/* Adds the contribution of a sample (radiance times camera weight: rw gw bw) with filter weight
 * fw to the sums acc (r, g, b, weight): (L * w) * fw and fw, pbrt-v3's L * sampleWeight *
 * filterWeight. A zero fw adds zeros, which never changes a sum that starts at +0 (so masked
 * lanes may add them). */
CLR_INLINE void clr_film_add(float rw, float gw, float bw, float fw, float *acc) {
  acc[0] += rw * fw;
  acc[1] += gw * fw;
  acc[2] += bw * fw;
  acc[3] += fw;
}

/* Adds prepared sample s to the sums acc of pixel (px, py) if its filter reaches the pixel.
 * factors: clr_filter_table_factor's 2 x 16 table (table mode). */
CLR_INLINE void clr_film_accumulate(const clr_filter_params *f, CLR_GLOBAL const float *factors,
                                    const clr_film_prepared *s, clr_i32 px, clr_i32 py,
                                    float *acc) {
  if (px < s->x0 || px > s->x1 || py < s->y0 || py > s->y1) return;
  clr_film_add(s->r * s->w, s->g * s->w, s->b * s->w,
               clr_film_filter_weight(f, factors, s->dx, s->dy, px, py), acc);
}

#endif
