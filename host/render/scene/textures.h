/* Spectrum textures (constant, checkerboard, imagemap, scale, mix, uv) and colour parameters that
 * may name one. */
#ifndef CLR_RENDER_TEXTURES_H
#define CLR_RENDER_TEXTURES_H

#include <stdint.h>
#include "clrender/result.h"
#include "scene_desc.h"

/* A colour that is either constant or a spectrum texture (index into the texture set). */
typedef struct rs_colour {
  int texture; /* -1: constant rgb */
  float rgb[3];
} rs_colour;

typedef enum {
  RS_TEX_CONSTANT,
  RS_TEX_CHECKER,
  RS_TEX_IMAGE,
  RS_TEX_SCALE,
  RS_TEX_MIX,
  RS_TEX_UV
} rs_texture_type;

typedef struct rs_texture {
  rs_texture_type type;
  float su, sv, du, dv; /* pbrt UVMapping2D */
  rs_colour value, tex1, tex2;
  float amount; /* mix: constant "amount" (float textures are not evaluated) */
  int32_t width, height;
  float *rgb; /* image texels, row 0 = top of the file */
  float scale;
  int nearest; /* 1: nearest texel, 0: bilinear */
} rs_texture;

/* The scene's textures, one per description texture (float textures left constant). */
typedef struct rs_texture_set {
  rs_texture *items;
  int count;
} rs_texture_set;

clr_result rs_textures_build(rs_texture_set *set, const clr_scene_desc *d, clr_warn_fn warn,
                             void *wu);
void rs_textures_free(rs_texture_set *set);
/* Colour parameter `name` looked up in `first` then `second` (may be NULL), default def. */
void rs_colour_param(const clr_param_list *first, const clr_param_list *second, const char *name,
                     float def, rs_colour *out);
void rs_colour_eval(const rs_texture_set *set, const rs_colour *c, const float uv[2], float out[3]);

#endif
