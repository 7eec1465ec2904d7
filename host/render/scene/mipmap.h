/* pbrt-v3's MIPMap (core/mipmap.h), re-implemented from its definition: the image resampled to
 * power-of-two sides with Lanczos weights, box-filtered levels, and its bilinear ("triangle"),
 * trilinear and EWA lookups with the three wrap modes. RGB texels; (s, t) = (0, 0) is the lower
 * left corner (row 0 of level 0 is the image's bottom row). */
#ifndef CLR_RENDER_MIPMAP_H
#define CLR_RENDER_MIPMAP_H

#include <stdint.h>
#include "clrender/result.h"

typedef enum { RS_WRAP_REPEAT, RS_WRAP_BLACK, RS_WRAP_CLAMP } rs_wrap;

typedef struct rs_mip_level {
  int32_t width, height;
  float *rgb; /* width * height texels, row-major from t = 0 */
} rs_mip_level;

#define RS_EWA_LUT_SIZE 128

typedef struct rs_mipmap {
  rs_mip_level *levels; /* levels[0]: the (resampled) image; the last is 1x1 */
  int count;
  rs_wrap wrap;
  int trilinear;                  /* 1: trilinear lookups, 0: EWA */
  float max_anisotropy;           /* EWA: the ellipse's largest major / minor ratio */
  float ewa_lut[RS_EWA_LUT_SIZE]; /* pbrt-v3's Gaussian weights by squared radius */
} rs_mipmap;

/* Builds the pyramid of a width x height RGB image whose row 0 is the bottom row. Sides that
 * are not powers of two are resampled up to the next ones (negative results clamped to 0). */
clr_result rs_mipmap_build(rs_mipmap *m, int32_t width, int32_t height, const float *rgb,
                           rs_wrap wrap, int trilinear, float max_anisotropy);
void rs_mipmap_free(rs_mipmap *m);

/* Texel (s, t) of `level` under the wrap mode (0 outside for "black"). */
void rs_mipmap_texel(const rs_mipmap *m, int level, int s, int t, float out[3]);
/* pbrt-v3 MIPMap::triangle: bilinear interpolation of `level` at st. */
void rs_mipmap_bilinear(const rs_mipmap *m, int level, const float st[2], float out[3]);
/* pbrt-v3 MIPMap::Lookup(st, width): trilinear between the levels of a filter width. */
void rs_mipmap_trilinear(const rs_mipmap *m, const float st[2], float width, float out[3]);
/* pbrt-v3 MIPMap::Lookup(st, dst0, dst1) with EWA (an anisotropic Gaussian ellipse). */
void rs_mipmap_ewa(const rs_mipmap *m, const float st[2], const float dst0[2], const float dst1[2],
                   float out[3]);
/* The filtered lookup the map was built for: trilinear or EWA. */
void rs_mipmap_lookup(const rs_mipmap *m, const float st[2], const float dstdx[2],
                      const float dstdy[2], float out[3]);

#endif
