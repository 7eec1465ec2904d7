/* pbrt-v3 textures, float and spectrum: constant, scale, mix, uv, checkerboard (2D and 3D),
 * imagemap, dots, fbm, wrinkled, windy, marble; the 2D mappings uv, spherical, cylindrical,
 * planar; colour and float parameters that may name one. */
#ifndef CLR_RENDER_TEXTURES_H
#define CLR_RENDER_TEXTURES_H

#include <stdint.h>
#include "clrender/result.h"
#include "mipmap.h"
#include "scene_desc.h"
#include "transform.h"

/* A colour or float that is either constant or a texture (index into the texture set). Float
 * values are kept in all three channels. */
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
  RS_TEX_UV,
  RS_TEX_CHECKER3D,
  RS_TEX_DOTS,
  RS_TEX_FBM,
  RS_TEX_WRINKLED,
  RS_TEX_WINDY,
  RS_TEX_MARBLE
} rs_texture_type;

typedef enum { RS_MAP_UV, RS_MAP_SPHERICAL, RS_MAP_CYLINDRICAL, RS_MAP_PLANAR } rs_mapping;
/* How an imagemap is looked up: pbrt-v3's MIP map (trilinear or EWA by the ray differentials,
 * the default), or the unfiltered image (pbrt-v4's "point" and "bilinear"). */
typedef enum { RS_FILTER_MIPMAP, RS_FILTER_NEAREST, RS_FILTER_BILINEAR } rs_image_filter;

typedef struct rs_texture {
  rs_texture_type type;
  rs_mapping mapping;
  float su, sv, du, dv;           /* pbrt UVMapping2D; planar: du, dv */
  float v1[3], v2[3];             /* PlanarMapping2D */
  clr_transform world_to_texture; /* the spherical/cylindrical mappings */
  /* 3D textures: pbrt-v3 passes the Texture's CTM itself (not its inverse) to IdentityMapping3D
   * as the world-to-texture transform */
  clr_transform world_to_texture_3d;
  rs_colour value, tex1, tex2, amount;
  int32_t width, height;
  float *rgb;    /* unfiltered lookups: texels, row 0 = top of the file, scale and gamma applied */
  rs_mipmap mip; /* RS_FILTER_MIPMAP: pbrt-v3's pyramid of the same texels */
  float scale;
  rs_image_filter filter;
  int checker_aa; /* 2D checkerboard: pbrt-v3's closed-form box filter ("aamode") */
  rs_wrap wrap;
  int octaves;
  float omega, variation; /* fbm/wrinkled/marble "roughness"; marble "variation" */
} rs_texture;

/* The scene's textures, one per description texture. */
typedef struct rs_texture_set {
  rs_texture *items;
  int count;
} rs_texture_set;

/* Where a texture is looked up: the surface's (u, v) and world point, and their screen-space
 * derivatives from ray differentials (pbrt-v3 SurfaceInteraction dudx ... dpdy; all 0 without
 * differentials, which gives the unfiltered level-0 lookup). */
typedef struct rs_tex_ctx {
  float uv[2];
  float p[3];
  float dudx, dvdx, dudy, dvdy;
  float dpdx[3], dpdy[3];
} rs_tex_ctx;

/* A lookup at (uv, p) without differentials. */
static inline rs_tex_ctx rs_tex_ctx_at(const float uv[2], const float p[3]) {
  rs_tex_ctx c = {{uv[0], uv[1]}, {p[0], p[1], p[2]}, 0, 0, 0, 0, {0, 0, 0}, {0, 0, 0}};
  return c;
}

clr_result rs_textures_build(rs_texture_set *set, const clr_scene_desc *d, clr_warn_fn warn,
                             void *wu);
void rs_textures_free(rs_texture_set *set);
/* Colour parameter `name` looked up in `first` then `second` (may be NULL), default def. */
void rs_colour_param(const clr_param_list *first, const clr_param_list *second, const char *name,
                     float def, rs_colour *out);
/* Float parameter `name` (a float or a float texture) in `first` then `second`, default def. */
void rs_float_param(const clr_param_list *first, const clr_param_list *second, const char *name,
                    float def, rs_colour *out);
void rs_colour_eval(const rs_texture_set *set, const rs_colour *c, const rs_tex_ctx *ctx,
                    float out[3]);
float rs_float_eval(const rs_texture_set *set, const rs_colour *c, const rs_tex_ctx *ctx);
/* 1 for the textures that ray differentials filter: MIP-mapped imagemaps, the 2D checkerboard
 * (closed form), and fbm, wrinkled, windy and marble (octaves dropped as pbrt-v3's FBm and
 * Turbulence do). */
int rs_texture_uses_differentials(const rs_texture *t);
/* 1 when texture `index` (-1: none) or one it reads is such a texture. */
int rs_texture_tree_uses_differentials(const rs_texture_set *set, int index);
/* pbrt-v3 TextureMapping2D::Map of a 2D texture: st and its derivatives dstdx, dstdy. */
void rs_texture_map_2d(const rs_texture *t, const rs_tex_ctx *ctx, float st[2], float dstdx[2],
                       float dstdy[2]);

#endif
