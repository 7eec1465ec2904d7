/* pbrt-v3's procedural textures (core/texture.cpp Noise, FBm, Turbulence; textures/dots, fbm,
 * wrinkled, windy, marble, checkerboard 3D), re-implemented from their definitions. */
#include <math.h>
#include "procedural_textures.h"
#include "float_minmax.h"

/* Ken Perlin's permutation of 0..255 from his public-domain reference implementation of
 * improved noise (2002); pbrt-v3's NoisePerm is this table twice. It is Perlin's data, not a
 * generated sequence, so it is kept as data. */
static const unsigned char perlin_perm[256] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103,
    30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,
    197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174,
    20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158, 231,
    83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,  245, 40,  244, 102, 143,
    54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,  18,  169, 200, 196,
    135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124,
    123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,
    182, 189, 28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101,
    155, 167, 43,  172, 9,   129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185,
    112, 104, 218, 246, 97,  228, 251, 34,  242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,
    51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176,
    115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243,
    141, 128, 195, 78,  66,  215, 61,  156, 180,
};

static int perm(int i) { return perlin_perm[i & 255]; }

static float grad(int x, int y, int z, float dx, float dy, float dz) {
  int h = perm(perm(perm(x) + y) + z) & 15;
  float u = h < 8 || h == 12 || h == 13 ? dx : dy;
  float v = h < 4 || h == 12 || h == 13 ? dy : dz;
  return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

/* 6 t^5 - 15 t^4 + 10 t^3 */
static float noise_weight(float t) {
  float t3 = t * t * t, t4 = t3 * t;
  return 6.0f * t4 * t - 15.0f * t4 + 10.0f * t3;
}

static float lerp(float t, float a, float b) { return (1.0f - t) * a + t * b; }

/* Coordinates whose floor fits an int (others: the pattern is flat there). */
static int in_range(float x, float y, float z) {
  return fabsf(x) < 1e9f && fabsf(y) < 1e9f && fabsf(z) < 1e9f;
}

float rs_noise(float x, float y, float z) {
  if (!in_range(x, y, z)) return 0.0f;
  float fx = floorf(x), fy = floorf(y), fz = floorf(z);
  int ix = (int)fx, iy = (int)fy, iz = (int)fz;
  float dx = x - fx, dy = y - fy, dz = z - fz;
  ix &= 255;
  iy &= 255;
  iz &= 255;
  float w000 = grad(ix, iy, iz, dx, dy, dz), w100 = grad(ix + 1, iy, iz, dx - 1, dy, dz);
  float w010 = grad(ix, iy + 1, iz, dx, dy - 1, dz);
  float w110 = grad(ix + 1, iy + 1, iz, dx - 1, dy - 1, dz);
  float w001 = grad(ix, iy, iz + 1, dx, dy, dz - 1);
  float w101 = grad(ix + 1, iy, iz + 1, dx - 1, dy, dz - 1);
  float w011 = grad(ix, iy + 1, iz + 1, dx, dy - 1, dz - 1);
  float w111 = grad(ix + 1, iy + 1, iz + 1, dx - 1, dy - 1, dz - 1);
  float wx = noise_weight(dx), wy = noise_weight(dy), wz = noise_weight(dz);
  float x00 = lerp(wx, w000, w100), x10 = lerp(wx, w010, w110);
  float x01 = lerp(wx, w001, w101), x11 = lerp(wx, w011, w111);
  return lerp(wz, lerp(wy, x00, x10), lerp(wy, x01, x11));
}

static float noise_at(const float p[3], float lambda) {
  return rs_noise(lambda * p[0], lambda * p[1], lambda * p[2]);
}

/* pbrt-v3's octave count for a footprint: -1 - log2(the longer differential) / 2, clamped to
 * [0, max_octaves] (max_octaves when the differentials are zero). */
static float octave_count(const float dpdx[3], const float dpdy[3], int max_octaves) {
  float lx = dpdx[0] * dpdx[0] + dpdx[1] * dpdx[1] + dpdx[2] * dpdx[2];
  float ly = dpdy[0] * dpdy[0] + dpdy[1] * dpdy[1] + dpdy[2] * dpdy[2];
  float n = -1.0f - 0.5f * (logf(rs_fmaxf(lx, ly)) * 1.442695040888963387004650940071f);
  if (!(n > 0.0f)) return 0.0f; /* NaN differentials too */
  return n < (float)max_octaves ? n : (float)max_octaves;
}

/* pbrt-v3 SmoothStep(0.3, 0.7, x). */
static float smooth_step(float x) {
  float t = rs_fminf(1.0f, rs_fmaxf(0.0f, (x - 0.3f) / (0.7f - 0.3f)));
  return t * t * (3.0f - 2.0f * t);
}

float rs_fbm_d(const float p[3], const float dpdx[3], const float dpdy[3], float omega,
               int octaves) {
  float n = octave_count(dpdx, dpdy, octaves);
  int whole = (int)floorf(n);
  float sum = 0.0f, lambda = 1.0f, o = 1.0f;
  for (int i = 0; i < whole; ++i) {
    sum += o * noise_at(p, lambda);
    lambda *= 1.99f;
    o *= omega;
  }
  float f = smooth_step(n - (float)whole); /* the partial octave, faded in */
  return f > 0.0f ? sum + o * f * noise_at(p, lambda) : sum;
}

float rs_turbulence_d(const float p[3], const float dpdx[3], const float dpdy[3], float omega,
                      int octaves) {
  float n = octave_count(dpdx, dpdy, octaves);
  int whole = (int)floorf(n);
  float sum = 0.0f, lambda = 1.0f, o = 1.0f;
  for (int i = 0; i < whole; ++i) {
    sum += o * fabsf(noise_at(p, lambda));
    lambda *= 1.99f;
    o *= omega;
  }
  float f = smooth_step(n - (float)whole); /* the partial octave, then 0.2 for each clamped one */
  sum += o * (f > 0.0f ? (1.0f - f) * 0.2f + f * fabsf(noise_at(p, lambda)) : 0.2f);
  for (int i = whole; i < octaves; ++i) { /* pbrt-v3 keeps o for the first of them */
    sum += o * 0.2f;
    o *= omega;
  }
  return sum;
}

static const float zero3[3] = {0.0f, 0.0f, 0.0f};

float rs_fbm(const float p[3], float omega, int octaves) {
  return rs_fbm_d(p, zero3, zero3, omega, octaves);
}

float rs_turbulence(const float p[3], float omega, int octaves) {
  return rs_turbulence_d(p, zero3, zero3, omega, octaves);
}

float rs_windy_d(const float p[3], const float dpdx[3], const float dpdy[3]) {
  float q[3] = {0.1f * p[0], 0.1f * p[1], 0.1f * p[2]};
  float qx[3] = {0.1f * dpdx[0], 0.1f * dpdx[1], 0.1f * dpdx[2]};
  float qy[3] = {0.1f * dpdy[0], 0.1f * dpdy[1], 0.1f * dpdy[2]};
  return fabsf(rs_fbm_d(q, qx, qy, 0.5f, 3)) * rs_fbm_d(p, dpdx, dpdy, 0.5f, 6);
}

float rs_windy(const float p[3]) { return rs_windy_d(p, zero3, zero3); }

void rs_marble_d(const float p[3], const float dpdx[3], const float dpdy[3], float omega,
                 int octaves, float variation, float out[3]) {
  static const float c[9][3] = {{.58f, .58f, .6f}, {.58f, .58f, .6f}, {.58f, .58f, .6f},
                                {.5f, .5f, .5f},   {.6f, .59f, .58f}, {.58f, .58f, .6f},
                                {.58f, .58f, .6f}, {.2f, .2f, .33f},  {.58f, .58f, .6f}};
  const int nseg = 9 - 3;
  float marble = p[1] + variation * rs_fbm_d(p, dpdx, dpdy, omega, octaves);
  float t = 0.5f + 0.5f * sinf(marble);
  if (!(t >= 0.0f && t <= 1.0f)) t = 0.5f; /* a NaN point */
  int first = (int)floorf(t * (float)nseg);
  if (first > 1) first = 1; /* pbrt-v3's std::min(1, ...) */
  t = t * (float)nseg - (float)first;
  for (int k = 0; k < 3; ++k) { /* Bezier spline by de Casteljau */
    float c0 = c[first][k], c1 = c[first + 1][k], c2 = c[first + 2][k], c3 = c[first + 3][k];
    float s0 = lerp(t, c0, c1), s1 = lerp(t, c1, c2), s2 = lerp(t, c2, c3);
    s0 = lerp(t, s0, s1);
    s1 = lerp(t, s1, s2);
    out[k] = 1.5f * lerp(t, s0, s1);
  }
}

void rs_marble(const float p[3], float omega, int octaves, float variation, float out[3]) {
  rs_marble_d(p, zero3, zero3, omega, octaves, variation, out);
}

int rs_dots_inside(float s, float t) {
  if (!in_range(s, t, 0.0f)) return 0;
  float s_cell = floorf(s + 0.5f), t_cell = floorf(t + 0.5f);
  if (!(rs_noise(s_cell + 0.5f, t_cell + 0.5f, 0.5f) > 0.0f)) return 0;
  const float radius = 0.35f, max_shift = 0.5f - radius;
  float sc = s_cell + max_shift * rs_noise(s_cell + 1.5f, t_cell + 2.8f, 0.5f);
  float tc = t_cell + max_shift * rs_noise(s_cell + 4.5f, t_cell + 9.8f, 0.5f);
  float ds = s - sc, dt = t - tc;
  return ds * ds + dt * dt < radius * radius;
}

int rs_checker3d_first(const float p[3]) {
  if (!in_range(p[0], p[1], p[2])) return 1;
  return ((int)floorf(p[0]) + (int)floorf(p[1]) + (int)floorf(p[2])) % 2 == 0;
}
