/* pbrt-v3 Material::Bump: a float texture displaces the surface along its shading normal; the
 * shading dpdu/dpdv and normal follow the displaced surface (finite differences in u and v of
 * half the hit's screen-space (u, v) change, 0.0005 without ray differentials, as pbrt-v3). */
#ifndef CLR_RENDER_BUMP_H
#define CLR_RENDER_BUMP_H

#include "textures.h"

/* at: the hit's lookup (uv, p, differentials); dpdu, dpdv: shading partials (updated); dndu,
 * dndv: normal partials (may be zero); ns: the shading normal oriented as the shape's normal n
 * (updated, then faced toward n). */
void rs_bump(const rs_texture_set *tex, const rs_colour *d, const rs_tex_ctx *at, const float n[3],
             float dpdu[3], float dpdv[3], const float dndu[3], const float dndv[3], float ns[3]);

#endif
