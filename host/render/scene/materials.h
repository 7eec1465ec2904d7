/* pbrt-v3 materials built as lists of BxDFs (integrators/bsdf_lobes.h) at each hit: uber,
 * substrate, translucent, mix, rough glass, and matte/plastic/metal/mirror/glass when they are
 * part of a mix or take float textures (sigma, roughness). */
#ifndef CLR_RENDER_MATERIALS_H
#define CLR_RENDER_MATERIALS_H

#include "bsdf_lobes.h"
#include "scene_desc.h"
#include "textures.h"

typedef enum {
  RS_MAT_NONE,
  RS_MAT_MATTE,
  RS_MAT_PLASTIC,
  RS_MAT_METAL,
  RS_MAT_MIRROR,
  RS_MAT_GLASS,
  RS_MAT_SUBSTRATE,
  RS_MAT_UBER,
  RS_MAT_TRANSLUCENT,
  RS_MAT_MIX
} rs_material_type;

typedef struct rs_material {
  rs_material_type type;
  rs_colour kd, ks, kr, kt, opacity, reflect, transmit, amount; /* spectrum parameters */
  rs_colour sigma, rough, urough, vrough, eta;                  /* float parameters */
  float m_eta[3], m_k[3];                                       /* metal (rgb) */
  int remap;
  int mix[2]; /* mix: indices of its named materials in the scene's material list */
} rs_material;

/* The material of description `md` (its type), with a shape's parameters `shape` (may be NULL)
 * looked up first as pbrt-v3 does. Unknown types give RS_MAT_MATTE with a 0 return. */
int rs_material_build(const clr_scene_desc *d, const clr_material_desc *md,
                      const clr_param_list *shape, rs_material *m);
/* 1 when a material must go through the lobe BSDF (not one of the integrators' fixed cases). */
int rs_material_needs_lobes(const rs_material *m);
/* pbrt-v3 Material::ComputeScatteringFunctions (allowMultipleLobes false) into b (b->n = 0 and
 * eta 1 first). `all` is the scene's material list (for mix). */
void rs_material_bsdf(const rs_material *m, const rs_material *all, int count,
                      const rs_texture_set *tex, const rs_tex_ctx *ctx, clr_bsdf *b);

#endif
