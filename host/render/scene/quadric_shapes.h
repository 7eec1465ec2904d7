/* The renderer's side of pbrt-v3's quadric shapes (cylinder, cone, paraboloid, hyperboloid):
 * their parameters from a Shape directive and the surface at a hit. */
#ifndef CLR_RENDER_QUADRIC_SHAPES_H
#define CLR_RENDER_QUADRIC_SHAPES_H

#include "clrender/result.h"
#include "quadrics.h"
#include "scene_desc.h"
#include "transform.h"

/* 1 when `type` names a quadric shape. */
int rs_is_quadric(const char *type);
/* pbrt-v3's Create*Shape parameters and defaults; an error names the file, line and values. */
clr_result rs_quadric_from_params(const char *type, const clr_param_list *p, clr_quadric *q);
/* The hit at world point pw (object_to_world o2w): the point refined onto the surface where
 * pbrt-v3 does (cylinder), the normal dpdu x dpdv, (u, v) and dpdu, all in world space. */
void rs_quadric_surface(const clr_quadric *q, const clr_transform *o2w, const float pw[3],
                        float p[3], float n[3], float uv[2], float dpdu[3]);
/* World bounds of the quadric's object-space box. */
void rs_quadric_bounds(const clr_quadric *q, const clr_transform *o2w, float lo[3], float hi[3]);

#endif
