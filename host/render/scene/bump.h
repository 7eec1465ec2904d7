/* pbrt-v3 Material::Bump: a float texture displaces the surface along its shading normal; the
 * shading dpdu/dpdv and normal follow the displaced surface (finite differences of 0.0005 in u and
 * v, pbrt-v3's step without ray differentials). */
#ifndef CLR_RENDER_BUMP_H
#define CLR_RENDER_BUMP_H

#include "textures.h"

/* dpdu, dpdv: shading partials (updated); dndu, dndv: normal partials (may be zero); ns: the
 * shading normal oriented as the shape's normal n (updated, then faced toward n). */
void rs_bump(const rs_texture_set *tex, const rs_colour *d, const float p[3], const float uv[2],
             const float n[3], float dpdu[3], float dpdv[3], const float dndu[3],
             const float dndv[3], float ns[3]);

#endif
