/* Loop subdivision surfaces as pbrt-v3's "loopsubdiv" shape computes them. */
#ifndef CLR_LOOP_SUBDIV_H
#define CLR_LOOP_SUBDIV_H

#include "mesh.h"

/* More triangles than this after subdivision (input triangles * 4^nlevels) are refused up front
 * with CLR_ERROR_INVALID_ARGUMENT. */
#define CLR_LOOP_SUBDIV_MAX_TRIANGLES (1 << 22)

/* Subdivides the triangles of `in` (only its positions and indices are used, as in pbrt-v3)
 * `nlevels` times with Loop's rules (beta = 3/16 for valence 3, else 3/(8 valence); boundary
 * vertices 3/4 + 1/8 + 1/8, boundary edges the midpoint), then moves every vertex to its limit
 * position and sets `out->n` to the limit-surface normal cross(S, T) from pbrt-v3's tangent
 * formulas (not unit length; its sign follows the face winding like pbrt's). Vertices are
 * ordered like pbrt's: old vertices keep their index, each level appends one per edge.
 * Vertices that no triangle uses are dropped first. Non-manifold input (an edge in more than
 * two triangles or in two triangles of opposite winding, a vertex joining separate fans, a
 * triangle repeating a vertex) is rejected with CLR_ERROR_SCENE naming the edge or vertex;
 * nlevels < 0 is CLR_ERROR_INVALID_ARGUMENT; a result above 2^31 / 3 triangles or vertices is
 * CLR_ERROR_SCENE. `out` is zeroed on failure. */
clr_result clr_loop_subdivide(const clr_mesh *in, int32_t nlevels, clr_mesh *out);

#endif
