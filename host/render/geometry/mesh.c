/* Host triangle meshes: ownership, validation, object-to-world transform, pbrt "trianglemesh". */
#include "mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"

void clr_mesh_free(clr_mesh *mesh) {
  if (!mesh) return;
  free(mesh->p);
  free(mesh->n);
  free(mesh->uv);
  free(mesh->indices);
  memset(mesh, 0, sizeof *mesh);
}

static void *alloc_floats(size_t count, size_t size) { return calloc(count ? count : 1, size); }

clr_result clr_mesh_alloc(clr_mesh *out, int32_t vertex_count, int32_t triangle_count,
                          int with_normals, int with_uv, const char *what) {
  memset(out, 0, sizeof *out);
  if (vertex_count < 0 || triangle_count < 0 || triangle_count > INT32_MAX / 3 ||
      vertex_count > INT32_MAX / 3)
    return clr_set_last_error(CLR_ERROR_SCENE, "%s: mesh too large (%ld vertices, %ld triangles)",
                              what, (long)vertex_count, (long)triangle_count);
  out->vertex_count = vertex_count;
  out->triangle_count = triangle_count;
  out->p = alloc_floats(3 * (size_t)vertex_count, sizeof(float));
  out->indices = alloc_floats(3 * (size_t)triangle_count, sizeof(uint32_t));
  if (with_normals) out->n = alloc_floats(3 * (size_t)vertex_count, sizeof(float));
  if (with_uv) out->uv = alloc_floats(2 * (size_t)vertex_count, sizeof(float));
  if (!out->p || !out->indices || (with_normals && !out->n) || (with_uv && !out->uv)) {
    clr_mesh_free(out);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                              "%s: cannot allocate a mesh of %ld vertices"
                              " and %ld triangles",
                              what, (long)vertex_count, (long)triangle_count);
  }
  return CLR_SUCCESS;
}

/* Index of the first non-finite value among `count` floats, or -1. */
static long first_non_finite(const float *values, size_t count) {
  for (size_t i = 0; i < count; ++i)
    if (!isfinite(values[i])) return (long)i;
  return -1;
}

clr_result clr_mesh_check(const clr_mesh *mesh, const char *what, clr_result code) {
  if (!mesh || !what)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_mesh_check: NULL argument");
  if (mesh->vertex_count < 0 || mesh->triangle_count < 0 || (mesh->vertex_count > 0 && !mesh->p) ||
      (mesh->triangle_count > 0 && !mesh->indices))
    return clr_set_last_error(code, "%s: inconsistent mesh (%ld vertices, %ld triangles)", what,
                              (long)mesh->vertex_count, (long)mesh->triangle_count);
  size_t n_indices = 3 * (size_t)mesh->triangle_count;
  for (size_t i = 0; i < n_indices; ++i)
    if (mesh->indices[i] >= (uint32_t)mesh->vertex_count)
      return clr_set_last_error(code,
                                "%s: vertex index %lu at position %zu (triangle %zu) is out of "
                                "range: the mesh has %ld vertices",
                                what, (unsigned long)mesh->indices[i], i, i / 3,
                                (long)mesh->vertex_count);
  const struct {
    const float *values;
    int width;
    const char *name;
  } arrays[3] = {{mesh->p, 3, "position"}, {mesh->n, 3, "normal"}, {mesh->uv, 2, "uv"}};
  for (int a = 0; a < 3; ++a) {
    if (!arrays[a].values) continue;
    long bad = first_non_finite(arrays[a].values, (size_t)arrays[a].width * mesh->vertex_count);
    if (bad >= 0)
      return clr_set_last_error(code, "%s: %s of vertex %ld is not finite (component %ld = %g)",
                                what, arrays[a].name, bad / arrays[a].width, bad % arrays[a].width,
                                (double)arrays[a].values[bad]);
  }
  return CLR_SUCCESS;
}

clr_result clr_mesh_validate(const clr_mesh *mesh, const char *what) {
  return clr_mesh_check(mesh, what ? what : "mesh", CLR_ERROR_SCENE);
}

/* Inverts a row-major 4x4 matrix by Gauss-Jordan elimination with partial pivoting; returns 0
 * when it is singular. */
static int invert4(const double m[16], double inv[16]) {
  double a[4][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 8; ++c) a[r][c] = c < 4 ? m[4 * r + c] : (c - 4 == r);
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r)
      if (fabs(a[r][col]) > fabs(a[pivot][col])) pivot = r;
    if (a[pivot][col] == 0.0 || !isfinite(a[pivot][col])) return 0;
    for (int c = 0; c < 8; ++c) {
      double t = a[col][c];
      a[col][c] = a[pivot][c];
      a[pivot][c] = t;
    }
    double scale = 1.0 / a[col][col];
    for (int c = 0; c < 8; ++c) a[col][c] *= scale;
    for (int r = 0; r < 4; ++r) {
      if (r == col || a[r][col] == 0.0) continue;
      double f = a[r][col];
      for (int c = 0; c < 8; ++c) a[r][c] -= f * a[col][c];
    }
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) inv[4 * r + c] = a[r][c + 4];
  return 1;
}

clr_result clr_mesh_transform(clr_mesh *mesh, const float m[16]) {
  if (!mesh || !m)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_mesh_transform: NULL argument");
  double md[16], inv[16];
  for (int i = 0; i < 16; ++i) md[i] = m[i];
  if (!invert4(md, inv))
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "clr_mesh_transform: singular object-to-world matrix");
  size_t nv = (size_t)mesh->vertex_count;
  float *p = malloc(3 * (nv ? nv : 1) * sizeof(float));
  float *n = mesh->n ? malloc(3 * (nv ? nv : 1) * sizeof(float)) : NULL;
  if (!p || (mesh->n && !n)) {
    free(p);
    free(n);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                              "clr_mesh_transform: no memory for %zu vertices", nv);
  }
  for (size_t v = 0; v < nv; ++v) {
    const float *x = mesh->p + 3 * v;
    double h[4];
    for (int r = 0; r < 4; ++r)
      h[r] = md[4 * r] * x[0] + md[4 * r + 1] * x[1] + md[4 * r + 2] * x[2] + md[4 * r + 3];
    for (int r = 0; r < 3; ++r) p[3 * v + r] = (float)(h[3] == 1.0 ? h[r] : h[r] / h[3]);
    if (n) {
      const float *y = mesh->n + 3 * v; /* n' = inverse^T n */
      for (int r = 0; r < 3; ++r)
        n[3 * v + r] = (float)(inv[r] * y[0] + inv[4 + r] * y[1] + inv[8 + r] * y[2]);
    }
  }
  long bad = first_non_finite(p, 3 * nv);
  if (bad < 0 && n) bad = first_non_finite(n, 3 * nv);
  if (bad >= 0) {
    free(p);
    free(n);
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "clr_mesh_transform: vertex %ld is not finite after "
                              "the transform",
                              bad / 3);
  }
  free(mesh->p);
  mesh->p = p;
  if (n) {
    free(mesh->n);
    mesh->n = n;
  }
  return CLR_SUCCESS;
}

clr_result clr_mesh_from_arrays(const char *what, const int32_t *indices, size_t index_count,
                                const float *P, size_t p_count, const float *N, size_t n_count,
                                const float *uv, size_t uv_count, clr_mesh *out) {
  static const int32_t default_indices[3] = {0, 1, 2};
  if (!out) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_mesh_from_arrays: out is NULL");
  memset(out, 0, sizeof *out);
  if (!what) what = "trianglemesh";
  if (!P || p_count == 0)
    return clr_set_last_error(CLR_ERROR_SCENE, "%s: \"P\" parameter not provided", what);
  if (p_count % 3)
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s: %zu values given for \"point P\", not a multiple "
                              "of 3",
                              what, p_count);
  size_t nv = p_count / 3;
  if (!indices || index_count == 0) {
    if (nv != 3)
      return clr_set_last_error(CLR_ERROR_SCENE,
                                "%s: vertex indices \"indices\" not provided (only "
                                "allowed with exactly 3 points, %zu given)",
                                what, nv);
    indices = default_indices;
    index_count = 3;
  }
  if (index_count % 3)
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s: number of vertex indices %zu is not a multiple of 3", what,
                              index_count);
  if (N && n_count != p_count)
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s: %zu values given for \"normal N\", expected %zu "
                              "(one normal per \"P\")",
                              what, n_count, p_count);
  if (uv && uv_count != 2 * nv)
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s: %zu values given for \"uv\", expected %zu "
                              "(one pair per \"P\")",
                              what, uv_count, 2 * nv);
  if (nv > INT32_MAX / 3 || index_count / 3 > INT32_MAX / 3)
    return clr_set_last_error(CLR_ERROR_SCENE, "%s: mesh too large (%zu points, %zu indices)", what,
                              nv, index_count);
  for (size_t i = 0; i < index_count; ++i)
    if (indices[i] < 0 || (size_t)indices[i] >= nv)
      return clr_set_last_error(CLR_ERROR_SCENE,
                                "%s: vertex index %ld at position %zu (triangle %zu) "
                                "is out of range: %zu \"P\" values were given",
                                what, (long)indices[i], i, i / 3, nv);
  CLR_CHECK(
      clr_mesh_alloc(out, (int32_t)nv, (int32_t)(index_count / 3), N != NULL, uv != NULL, what));
  memcpy(out->p, P, 3 * nv * sizeof(float));
  if (N) memcpy(out->n, N, 3 * nv * sizeof(float));
  if (uv) memcpy(out->uv, uv, 2 * nv * sizeof(float));
  for (size_t i = 0; i < index_count; ++i) out->indices[i] = (uint32_t)indices[i];
  clr_result r = clr_mesh_validate(out, what);
  if (r != CLR_SUCCESS) clr_mesh_free(out);
  return r;
}
