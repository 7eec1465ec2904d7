/* pbrt-v3 AnimatedTransform (core/transform.cpp) and Quaternion (core/quaternion.cpp),
 * re-implemented from their definitions. */
#include <math.h>
#include <string.h>
#include "animated_transform.h"
#include "float_minmax.h"

static void quat_from_matrix(const float m[4][4], float q[4]) {
  float trace = m[0][0] + m[1][1] + m[2][2];
  if (trace > 0.0f) {
    float s = sqrtf(trace + 1.0f);
    q[3] = s / 2.0f;
    s = 0.5f / s;
    q[0] = (m[2][1] - m[1][2]) * s;
    q[1] = (m[0][2] - m[2][0]) * s;
    q[2] = (m[1][0] - m[0][1]) * s;
    return;
  }
  const int nxt[3] = {1, 2, 0};
  int i = 0;
  if (m[1][1] > m[0][0]) i = 1;
  if (m[2][2] > m[i][i]) i = 2;
  int j = nxt[i], k = nxt[j];
  float s = sqrtf((m[i][i] - (m[j][j] + m[k][k])) + 1.0f);
  q[i] = s * 0.5f;
  if (s != 0.0f) s = 0.5f / s;
  q[3] = (m[k][j] - m[j][k]) * s;
  q[j] = (m[j][i] + m[i][j]) * s;
  q[k] = (m[k][i] + m[i][k]) * s;
}

/* Quaternion::ToTransform's matrix (a rotation, row-major, column vectors). */
static void quat_to_matrix(const float q[4], float m[4][4]) {
  float x = q[0], y = q[1], z = q[2], w = q[3];
  float xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z, wx = x * w,
        wy = y * w, wz = z * w;
  memset(m, 0, 16 * sizeof(float));
  m[0][0] = 1 - 2 * (yy + zz);
  m[1][0] = 2 * (xy + wz);
  m[2][0] = 2 * (xz - wy);
  m[0][1] = 2 * (xy - wz);
  m[1][1] = 1 - 2 * (xx + zz);
  m[2][1] = 2 * (yz + wx);
  m[0][2] = 2 * (xz + wy);
  m[1][2] = 2 * (yz - wx);
  m[2][2] = 1 - 2 * (xx + yy);
  m[3][3] = 1;
}

static void transpose(const float a[4][4], float t[4][4]) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) t[i][j] = a[j][i];
}

/* AnimatedTransform::Decompose: m = T R S. */
static void decompose(const float m[4][4], float t[3], float q[4], float s[4][4]) {
  for (int i = 0; i < 3; ++i) t[i] = m[i][3];
  float M[4][4], R[4][4];
  memcpy(M, m, sizeof M);
  for (int i = 0; i < 3; ++i) M[i][3] = M[3][i] = 0.0f;
  M[3][3] = 1.0f;
  memcpy(R, M, sizeof R);
  float norm;
  int count = 0;
  do {
    float rt[4][4], rit[4][4], next[4][4];
    transpose(R, rt);
    if (!clr_matrix_inverse(rt, rit)) break;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) next[i][j] = 0.5f * (R[i][j] + rit[i][j]);
    norm = 0.0f;
    for (int i = 0; i < 3; ++i) {
      float n =
          fabsf(R[i][0] - next[i][0]) + fabsf(R[i][1] - next[i][1]) + fabsf(R[i][2] - next[i][2]);
      norm = rs_fmaxf(norm, n);
    }
    memcpy(R, next, sizeof R);
  } while (++count < 100 && norm > 0.0001f);
  quat_from_matrix(R, q);
  float rinv[4][4];
  if (!clr_matrix_inverse(R, rinv)) {
    memcpy(s, M, sizeof M);
    return;
  }
  clr_matrix_multiply(rinv, M, s);
}

void rs_animated_transform_init(rs_animated_transform *a, const clr_transform *start,
                                const clr_transform *end, float start_time, float end_time) {
  memset(a, 0, sizeof *a);
  a->start = *start;
  a->end = *end;
  a->start_time = start_time;
  a->end_time = end_time;
  a->animated = memcmp(start->m, end->m, sizeof start->m) != 0;
  if (!a->animated) return;
  decompose(start->m, a->t[0], a->q[0], a->s[0]);
  decompose(end->m, a->t[1], a->q[1], a->s[1]);
  float d = a->q[0][0] * a->q[1][0] + a->q[0][1] * a->q[1][1] + a->q[0][2] * a->q[1][2] +
            a->q[0][3] * a->q[1][3];
  if (d < 0.0f)
    for (int k = 0; k < 4; ++k) a->q[1][k] = -a->q[1][k];
}

static void normalize4(float q[4]) {
  float l = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (l > 0.0f)
    for (int k = 0; k < 4; ++k) q[k] /= l;
}

/* pbrt-v3 Slerp. */
static void slerp(float t, const float q1[4], const float q2[4], float out[4]) {
  float c = q1[0] * q2[0] + q1[1] * q2[1] + q1[2] * q2[2] + q1[3] * q2[3];
  if (c > 0.9995f) {
    for (int k = 0; k < 4; ++k) out[k] = (1 - t) * q1[k] + t * q2[k];
    normalize4(out);
    return;
  }
  float theta = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, c))), tp = theta * t, perp[4];
  for (int k = 0; k < 4; ++k) perp[k] = q2[k] - q1[k] * c;
  normalize4(perp);
  for (int k = 0; k < 4; ++k) out[k] = q1[k] * cosf(tp) + perp[k] * sinf(tp);
}

void rs_animated_transform_at(const rs_animated_transform *a, float time, clr_transform *out) {
  if (!a->animated || time <= a->start_time) {
    *out = a->start;
    return;
  }
  if (time >= a->end_time) {
    *out = a->end;
    return;
  }
  float dt = (time - a->start_time) / (a->end_time - a->start_time), q[4], r[4][4], s[4][4],
        rs[4][4];
  slerp(dt, a->q[0], a->q[1], q);
  quat_to_matrix(q, r);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) s[i][j] = (1 - dt) * a->s[0][i][j] + dt * a->s[1][i][j];
  clr_matrix_multiply(r, s, rs);
  for (int i = 0; i < 3; ++i) rs[i][3] += (1 - dt) * a->t[0][i] + dt * a->t[1][i];
  if (!clr_transform_from_matrix(rs, out)) *out = a->start;
}
