/* 4x4 affine/projective transforms with their inverses, computed as pbrt-v3's Transform. */
#ifndef CLR_TRANSFORM_H
#define CLR_TRANSFORM_H

#include <stdbool.h>

/* Row-major matrix m (points are column vectors: p' = m * p) and its inverse m_inv. */
typedef struct clr_transform {
  float m[4][4];
  float m_inv[4][4];
} clr_transform;

clr_transform clr_transform_identity(void);
bool clr_transform_is_identity(const clr_transform *t);

/* Inverse of a 4x4 matrix by Gauss-Jordan elimination with full pivoting (pbrt-v3 Inverse).
 * Returns false for a singular matrix; `out` is then all zeros. */
bool clr_matrix_inverse(const float m[4][4], float out[4][4]);
/* r = a * b, summed left to right in float like pbrt-v3 Matrix4x4::Mul. */
void clr_matrix_multiply(const float a[4][4], const float b[4][4], float r[4][4]);

/* Transform from a matrix, inverting it; returns false (m_inv zeros) when singular. */
bool clr_transform_from_matrix(const float m[4][4], clr_transform *out);
/* Swaps m and m_inv. */
clr_transform clr_transform_inverse(const clr_transform *t);
/* a * b: applies b first, then a (pbrt-v3 operator*). */
clr_transform clr_transform_compose(const clr_transform *a, const clr_transform *b);

clr_transform clr_transform_translate(float dx, float dy, float dz);
clr_transform clr_transform_scale(float sx, float sy, float sz);
/* Rotation by `angle_deg` degrees about the axis (ax, ay, az), normalized first. */
clr_transform clr_transform_rotate(float angle_deg, float ax, float ay, float az);
/* pbrt-v3 LookAt: the world-to-camera transform for a camera at `eye` looking at `look`.
 * Returns false (and the identity) when `up` is parallel to the viewing direction. */
bool clr_transform_look_at(const float eye[3], const float look[3], const float up[3],
                           clr_transform *out);

/* Applies t to a point (with homogeneous divide when w != 1), a vector, or a normal (by the
 * transposed inverse). */
void clr_transform_point(const clr_transform *t, const float p[3], float out[3]);
void clr_transform_vector(const clr_transform *t, const float v[3], float out[3]);
void clr_transform_normal(const clr_transform *t, const float n[3], float out[3]);
/* True when the upper 3x3 has a negative determinant (pbrt-v3 SwapsHandedness). */
bool clr_transform_swaps_handedness(const clr_transform *t);

#endif
