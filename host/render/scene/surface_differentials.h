/* pbrt-v3 SurfaceInteraction::ComputeDifferentials, re-implemented from its definition. */
#ifndef CLR_RENDER_SURFACE_DIFFERENTIALS_H
#define CLR_RENDER_SURFACE_DIFFERENTIALS_H

#include "ray_differential.h"
#include "textures.h"

/* The screen-space changes of a hit (point p, geometric normal n, partials dpdu, dpdv) from the
 * offset rays of rd: where they meet the hit's tangent plane gives tc->dpdx, dpdy, and solving
 * dpdx = dudx dpdu + dvdx dpdv in the two coordinates where n is smallest gives dudx ... dvdy.
 * All stay 0 when rd is NULL or has none, when an offset ray is parallel to the plane, and (the
 * (u, v) ones) when the partials are degenerate. */
void rs_compute_differentials(const clr_ray_differential *rd, const float p[3], const float n[3],
                              const float dpdu[3], const float dpdv[3], rs_tex_ctx *tc);

#endif
