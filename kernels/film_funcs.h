/* pbrt-v3 FilmTile::AddSample math shared by the kernels, the host reference and the host film
 * tiles: sample check, luminance clamp, filter footprint and one pixel's contribution. */
#ifndef CLR_FILM_FUNCS_H
#define CLR_FILM_FUNCS_H

#include "film_types.h"
#include "filter_funcs.h"

CLR_INLINE int clr_film_is_finite(float v) {
  return (clr_as_uint(v) & 0x7f800000u) != 0x7f800000u;
}

/* pbrt-v3 RGBSpectrum::y(), evaluated left to right. */
CLR_INLINE float clr_film_luminance(float r, float g, float b) {
  return 0.212671f * r + 0.715160f * g + 0.072169f * b;
}

/* pbrt's first and last pixel a filter of radius r centred at d reaches: ceil(d - r), floor(d + r). */
CLR_INLINE clr_i32 clr_film_first_pixel(float d, float radius) {
  return (clr_i32)clr_ceilf(d - radius);
}
CLR_INLINE clr_i32 clr_film_last_pixel(float d, float radius) {
  return (clr_i32)clr_floorf(d + radius);
}

/* Checks sample s (CLR_FILM_SAMPLE_FLOATS values) and fills *out; returns CLR_FILM_SAMPLE_*. */
CLR_INLINE clr_i32 clr_film_prepare(const clr_film_params *fp, const clr_filter_params *f,
                                    float x, float y, float r, float g, float b, float w,
                                    clr_film_prepared *out) {
  if (!clr_film_is_finite(x) || !clr_film_is_finite(y) || !clr_film_is_finite(r) ||
      !clr_film_is_finite(g) || !clr_film_is_finite(b) || !clr_film_is_finite(w))
    return CLR_FILM_SAMPLE_DROPPED;
  float lum = clr_film_luminance(r, g, b);
  if (!clr_film_is_finite(lum) || lum < CLR_FILM_MIN_LUMINANCE) return CLR_FILM_SAMPLE_DROPPED;
  if (!(x >= (float)fp->sample_x0 && x < (float)fp->sample_x1 && y >= (float)fp->sample_y0 &&
        y < (float)fp->sample_y1))
    return CLR_FILM_SAMPLE_OUTSIDE;
  if (fp->clamp_luminance && lum > fp->max_luminance) {
    float s = fp->max_luminance / lum;
    r *= s;
    g *= s;
    b *= s;
  }
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

/* The filter weight of a sample at d for pixel (px, py). Every supported filter is separable,
 * f = fx(px - dx) fy(py - dy): a per-axis evaluation can replace this one call (precomputing a
 * sample's reach_x x-weights and reach_y y-weights once) without changing the bits. */
CLR_INLINE float clr_film_filter_weight(const clr_filter_params *f, CLR_GLOBAL const float *table,
                                        float dx, float dy, clr_i32 px, clr_i32 py) {
  return clr_filter_eval(f, (float)px - dx, (float)py - dy, table);
}

/* Adds the contribution of a sample (radiance r g b, weight w) with filter weight fw to the sums
 * acc (r, g, b, weight): L * (w * fw) and fw, as pbrt-v3. A zero fw adds zeros, which never
 * changes a sum that starts at +0 (so masked lanes may add them). */
CLR_INLINE void clr_film_add(float r, float g, float b, float w, float fw, float *acc) {
  float wt = w * fw;
  acc[0] += r * wt;
  acc[1] += g * wt;
  acc[2] += b * wt;
  acc[3] += fw;
}

/* Adds prepared sample s to the sums acc of pixel (px, py) if its filter reaches the pixel. */
CLR_INLINE void clr_film_accumulate(const clr_filter_params *f, CLR_GLOBAL const float *table,
                                    const clr_film_prepared *s, clr_i32 px, clr_i32 py,
                                    float *acc) {
  if (px < s->x0 || px > s->x1 || py < s->y0 || py > s->y1) return;
  clr_film_add(s->r, s->g, s->b, s->w, clr_film_filter_weight(f, table, s->dx, s->dy, px, py), acc);
}

#endif
