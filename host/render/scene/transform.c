/* 4x4 transforms (pbrt-v3 src/core/transform.cpp semantics, float arithmetic in the same order). */
#include "transform.h"

#include <math.h>
#include <string.h>

static const float clr_pi = 3.14159265358979323846f;

static void matrix_set_identity(float m[4][4]) {
  memset(m, 0, 16 * sizeof(float));
  for (int i = 0; i < 4; ++i) m[i][i] = 1.0f;
}

static void matrix_transpose(const float m[4][4], float out[4][4]) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) out[i][j] = m[j][i];
}

clr_transform clr_transform_identity(void) {
  clr_transform t;
  matrix_set_identity(t.m);
  matrix_set_identity(t.m_inv);
  return t;
}

bool clr_transform_is_identity(const clr_transform *t) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (t->m[i][j] != (i == j ? 1.0f : 0.0f)) return false;
  return true;
}

void clr_matrix_multiply(const float a[4][4], const float b[4][4], float r[4][4]) {
  float tmp[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      tmp[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] + a[i][3] * b[3][j];
  memcpy(r, tmp, sizeof tmp);
}

/* Picks the largest remaining element as pivot; returns false when a column repeats. */
static bool choose_pivot(float minv[4][4], const int ipiv[4], int *irow, int *icol) {
  float big = 0.0f;
  *irow = 0;
  *icol = 0;
  for (int j = 0; j < 4; ++j) {
    if (ipiv[j] == 1) continue;
    for (int k = 0; k < 4; ++k) {
      if (ipiv[k] == 0) {
        if (fabsf(minv[j][k]) >= big) {
          big = fabsf(minv[j][k]);
          *irow = j;
          *icol = k;
        }
      } else if (ipiv[k] > 1) {
        return false;
      }
    }
  }
  return true;
}

static void swap_floats(float *a, float *b) {
  float t = *a;
  *a = *b;
  *b = t;
}

bool clr_matrix_inverse(const float m[4][4], float out[4][4]) {
  int indxc[4], indxr[4];
  int ipiv[4] = {0, 0, 0, 0};
  float minv[4][4];
  memcpy(minv, m, sizeof minv);
  for (int i = 0; i < 4; ++i) {
    int irow, icol;
    if (!choose_pivot(minv, ipiv, &irow, &icol)) goto singular;
    ++ipiv[icol];
    if (irow != icol)
      for (int k = 0; k < 4; ++k) swap_floats(&minv[irow][k], &minv[icol][k]);
    indxr[i] = irow;
    indxc[i] = icol;
    if (minv[icol][icol] == 0.0f) goto singular;
    /* pbrt-v3 computes the reciprocal in double and rounds it to float. */
    float pivinv = (float)(1.0 / (double)minv[icol][icol]);
    minv[icol][icol] = 1.0f;
    for (int j = 0; j < 4; ++j) minv[icol][j] *= pivinv;
    for (int j = 0; j < 4; ++j) {
      if (j == icol) continue;
      float save = minv[j][icol];
      minv[j][icol] = 0.0f;
      for (int k = 0; k < 4; ++k) minv[j][k] -= minv[icol][k] * save;
    }
  }
  for (int j = 3; j >= 0; --j)
    if (indxr[j] != indxc[j])
      for (int k = 0; k < 4; ++k) swap_floats(&minv[k][indxr[j]], &minv[k][indxc[j]]);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!isfinite(minv[i][j])) goto singular;
  memcpy(out, minv, sizeof minv);
  return true;
singular:
  memset(out, 0, 16 * sizeof(float));
  return false;
}

bool clr_transform_from_matrix(const float m[4][4], clr_transform *out) {
  memcpy(out->m, m, 16 * sizeof(float));
  return clr_matrix_inverse(m, out->m_inv);
}

clr_transform clr_transform_inverse(const clr_transform *t) {
  clr_transform r;
  memcpy(r.m, t->m_inv, sizeof r.m);
  memcpy(r.m_inv, t->m, sizeof r.m_inv);
  return r;
}

clr_transform clr_transform_compose(const clr_transform *a, const clr_transform *b) {
  clr_transform r;
  clr_matrix_multiply(a->m, b->m, r.m);
  clr_matrix_multiply(b->m_inv, a->m_inv, r.m_inv);
  return r;
}

clr_transform clr_transform_translate(float dx, float dy, float dz) {
  clr_transform t = clr_transform_identity();
  t.m[0][3] = dx;
  t.m[1][3] = dy;
  t.m[2][3] = dz;
  t.m_inv[0][3] = -dx;
  t.m_inv[1][3] = -dy;
  t.m_inv[2][3] = -dz;
  return t;
}

clr_transform clr_transform_scale(float sx, float sy, float sz) {
  clr_transform t = clr_transform_identity();
  t.m[0][0] = sx;
  t.m[1][1] = sy;
  t.m[2][2] = sz;
  t.m_inv[0][0] = 1.0f / sx;
  t.m_inv[1][1] = 1.0f / sy;
  t.m_inv[2][2] = 1.0f / sz;
  return t;
}

/* pbrt-v3 Normalize: multiply by the float reciprocal of the length. */
static void normalize3(const float v[3], float out[3]) {
  float length = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  float inv = 1.0f / length;
  out[0] = v[0] * inv;
  out[1] = v[1] * inv;
  out[2] = v[2] * inv;
}

/* pbrt-v3 Cross: products and differences in double, rounded to float. */
static void cross3(const float a[3], const float b[3], float out[3]) {
  double ax = a[0], ay = a[1], az = a[2], bx = b[0], by = b[1], bz = b[2];
  out[0] = (float)((ay * bz) - (az * by));
  out[1] = (float)((az * bx) - (ax * bz));
  out[2] = (float)((ax * by) - (ay * bx));
}

clr_transform clr_transform_rotate(float angle_deg, float ax, float ay, float az) {
  const float axis[3] = {ax, ay, az};
  float a[3];
  normalize3(axis, a);
  float radians = (clr_pi / 180.0f) * angle_deg;
  float s = sinf(radians), c = cosf(radians);
  clr_transform t = clr_transform_identity();
  t.m[0][0] = a[0] * a[0] + (1 - a[0] * a[0]) * c;
  t.m[0][1] = a[0] * a[1] * (1 - c) - a[2] * s;
  t.m[0][2] = a[0] * a[2] * (1 - c) + a[1] * s;
  t.m[1][0] = a[0] * a[1] * (1 - c) + a[2] * s;
  t.m[1][1] = a[1] * a[1] + (1 - a[1] * a[1]) * c;
  t.m[1][2] = a[1] * a[2] * (1 - c) - a[0] * s;
  t.m[2][0] = a[0] * a[2] * (1 - c) - a[1] * s;
  t.m[2][1] = a[1] * a[2] * (1 - c) + a[0] * s;
  t.m[2][2] = a[2] * a[2] + (1 - a[2] * a[2]) * c;
  matrix_transpose(t.m, t.m_inv);
  return t;
}

bool clr_transform_look_at(const float eye[3], const float look[3], const float up[3],
                           clr_transform *out) {
  const float view[3] = {look[0] - eye[0], look[1] - eye[1], look[2] - eye[2]};
  float dir[3], up_n[3], right_raw[3], right[3], new_up[3];
  normalize3(view, dir);
  normalize3(up, up_n);
  cross3(up_n, dir, right_raw);
  float right_len = sqrtf(right_raw[0] * right_raw[0] + right_raw[1] * right_raw[1] +
                          right_raw[2] * right_raw[2]);
  if (!(right_len > 0.0f) || !isfinite(right_len)) {
    *out = clr_transform_identity();
    return false;
  }
  normalize3(right_raw, right);
  cross3(dir, right, new_up);
  float camera_to_world[4][4];
  matrix_set_identity(camera_to_world);
  for (int i = 0; i < 3; ++i) {
    camera_to_world[i][0] = right[i];
    camera_to_world[i][1] = new_up[i];
    camera_to_world[i][2] = dir[i];
    camera_to_world[i][3] = eye[i];
  }
  memcpy(out->m_inv, camera_to_world, sizeof camera_to_world);
  if (!clr_matrix_inverse(camera_to_world, out->m)) {
    *out = clr_transform_identity();
    return false;
  }
  return true;
}

void clr_transform_point(const clr_transform *t, const float p[3], float out[3]) {
  const float(*m)[4] = t->m;
  float r[4];
  for (int i = 0; i < 4; ++i) r[i] = m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3];
  if (r[3] == 1.0f) {
    out[0] = r[0], out[1] = r[1], out[2] = r[2];
  } else {
    float inv = 1.0f / r[3];
    out[0] = inv * r[0], out[1] = inv * r[1], out[2] = inv * r[2];
  }
}

void clr_transform_vector(const clr_transform *t, const float v[3], float out[3]) {
  const float(*m)[4] = t->m;
  float r[3];
  for (int i = 0; i < 3; ++i) r[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  memcpy(out, r, sizeof r);
}

void clr_transform_normal(const clr_transform *t, const float n[3], float out[3]) {
  const float(*mi)[4] = t->m_inv;
  float r[3];
  for (int i = 0; i < 3; ++i) r[i] = mi[0][i] * n[0] + mi[1][i] * n[1] + mi[2][i] * n[2];
  memcpy(out, r, sizeof r);
}

bool clr_transform_swaps_handedness(const clr_transform *t) {
  const float(*m)[4] = t->m;
  float det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
              m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
              m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return det < 0.0f;
}
