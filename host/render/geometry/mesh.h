/* Host triangle meshes: ownership, validation, object-to-world transform, pbrt "trianglemesh". */
#ifndef CLR_MESH_H
#define CLR_MESH_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/result.h"

/* An indexed triangle mesh owning its arrays (all from malloc). Optional arrays are NULL. */
typedef struct clr_mesh {
  int32_t vertex_count, triangle_count;
  float *p;          /* 3 * vertex_count positions */
  float *n;          /* 3 * vertex_count shading normals (not necessarily unit length) or NULL */
  float *uv;         /* 2 * vertex_count texture coordinates or NULL */
  uint32_t *indices; /* 3 * triangle_count vertex indices */
} clr_mesh;

/* Frees the arrays and zeroes the struct; NULL and zeroed meshes are fine. */
void clr_mesh_free(clr_mesh *mesh);

/* Checks counts, that every index is < vertex_count and that positions, normals and uvs are
 * finite. CLR_ERROR_SCENE names `what`, the first bad index, its position and the vertex count. */
clr_result clr_mesh_validate(const clr_mesh *mesh, const char *what);
/* Same checks, failing with `code` (e.g. CLR_ERROR_FILE_FORMAT for meshes read from files). */
clr_result clr_mesh_check(const clr_mesh *mesh, const char *what, clr_result code);

/* Applies a row-major 4x4 object-to-world matrix like pbrt-v3's Transform: points with the
 * homogeneous divide, normals by the transposed inverse (not renormalised). A singular matrix or
 * non-finite result gives CLR_ERROR_SCENE and leaves the mesh unchanged. */
clr_result clr_mesh_transform(clr_mesh *mesh, const float m[16]);

/* Builds a mesh from pbrt "trianglemesh" parameters (counts are numbers of array elements, not
 * of points): "integer indices" (may be NULL/0 when exactly 3 points are given, as in pbrt),
 * "point P", optional "normal N" and "point2 uv"/"float uv". Unlike pbrt, which drops N or uv
 * with a warning when their count differs from P's, a mismatch is an error. Errors are
 * CLR_ERROR_SCENE naming `what`; `out` is zeroed on failure. */
clr_result clr_mesh_from_arrays(const char *what, const int32_t *indices, size_t index_count,
                                const float *P, size_t p_count, const float *N, size_t n_count,
                                const float *uv, size_t uv_count, clr_mesh *out);

/* Allocates zeroed arrays for a mesh with the given counts (n and uv only when asked for).
 * CLR_ERROR_OUT_OF_MEMORY (naming `what`) on failure, with `out` zeroed. */
clr_result clr_mesh_alloc(clr_mesh *out, int32_t vertex_count, int32_t triangle_count,
                          int with_normals, int with_uv, const char *what);

#endif
