/* pbrt-v3 microfacet.cpp / reflection.cpp: the TrowbridgeReitz distribution of every microfacet
 * lobe, and the plastic and metal lobes of the fast path, transcribed in float. */
#include <math.h>
#include "microfacet.h"
#include "local_frame.h"
#include "float_minmax.h"

#define MF_PI 3.14159265358979323846f

float clr_tr_roughness_to_alpha(float roughness) {
  float r = rs_fmaxf(roughness, 1e-3f), x = logf(r);
  return 1.62142f + 0.819955f * x + 0.1734f * x * x + 0.0171201f * x * x * x +
         0.000640711f * x * x * x * x;
}

float clr_fr_dielectric(float cos_i, float eta_i, float eta_t) {
  cos_i = rs_fminf(1.0f, rs_fmaxf(-1.0f, cos_i));
  if (!(cos_i > 0.0f)) {
    float t = eta_i;
    eta_i = eta_t;
    eta_t = t;
    cos_i = fabsf(cos_i);
  }
  float sin_i = sqrtf(rs_fmaxf(0.0f, 1.0f - cos_i * cos_i)), sin_t = eta_i / eta_t * sin_i;
  if (sin_t >= 1.0f) return 1.0f;
  float cos_t = sqrtf(rs_fmaxf(0.0f, 1.0f - sin_t * sin_t));
  float rparl = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  float rperp = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  return (rparl * rparl + rperp * rperp) / 2.0f;
}

static float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* TrowbridgeReitz D(wh); ax == ay takes cos^2 phi + sin^2 phi as exactly 1. */
float clr_tr_d(const float wh[3], float ax, float ay) {
  float t2 = tan2_theta(wh);
  if (isinf(t2) || isnan(t2)) return 0.0f;
  float c4 = cos2_theta(wh) * cos2_theta(wh), e = t2 / (ax * ax);
  if (ax != ay) {
    float cp = cos_phi(wh), sp = sin_phi(wh);
    e = (cp * cp / (ax * ax) + sp * sp / (ay * ay)) * t2;
  }
  return 1.0f / (MF_PI * ax * ay * c4 * (1.0f + e) * (1.0f + e));
}

static float tr_lambda(const float w[3], float ax, float ay) {
  if (ax == ay) {
    float t2 = tan2_theta(w);
    if (isinf(t2) || isnan(t2)) return 0.0f;
    return (-1.0f + sqrtf(1.0f + ax * ax * t2)) / 2.0f;
  }
  float abs_tan = fabsf(sqrtf(sin2_theta(w)) / w[2]);
  if (isinf(abs_tan) || isnan(abs_tan)) return 0.0f;
  float cp = cos_phi(w), sp = sin_phi(w);
  float alpha = sqrtf(cp * cp * ax * ax + sp * sp * ay * ay);
  float a2t2 = (alpha * abs_tan) * (alpha * abs_tan);
  return (-1.0f + sqrtf(1.0f + a2t2)) / 2.0f;
}

static float tr_g1(const float w[3], float ax, float ay) {
  return 1.0f / (1.0f + tr_lambda(w, ax, ay));
}

float clr_tr_g(const float wo[3], const float wi[3], float ax, float ay) {
  return 1.0f / (1.0f + tr_lambda(wo, ax, ay) + tr_lambda(wi, ax, ay));
}

/* TrowbridgeReitzDistribution::Pdf with sampleVisibleArea */
float clr_tr_pdf_wh(const float wo[3], const float wh[3], float ax, float ay) {
  return clr_tr_d(wh, ax, ay) * tr_g1(wo, ax, ay) * fabsf(dot3(wo, wh)) / fabsf(wo[2]);
}

void clr_tr_sample11(float cos_t, float u1, float u2, float *sx, float *sy) {
  if (cos_t > 0.9999f) {
    float r = sqrtf(u1 / (1.0f - u1)), phi = 6.28318530718f * u2;
    *sx = r * cosf(phi);
    *sy = r * sinf(phi);
    return;
  }
  float sin_t = sqrtf(rs_fmaxf(0.0f, 1.0f - cos_t * cos_t)), tan_t = sin_t / cos_t,
        a = 1.0f / tan_t;
  float g1 = 2.0f / (1.0f + sqrtf(1.0f + 1.0f / (a * a)));
  float A = 2.0f * u1 / g1 - 1.0f, tmp = 1.0f / (A * A - 1.0f);
  if (tmp > 1e10f) tmp = 1e10f;
  float B = tan_t, D = sqrtf(rs_fmaxf(B * B * tmp * tmp - (A * A - B * B) * tmp, 0.0f));
  float x1 = B * tmp - D, x2 = B * tmp + D;
  *sx = (A < 0.0f || x2 > 1.0f / tan_t) ? x1 : x2;
  float S;
  if (u2 > 0.5f) {
    S = 1.0f;
    u2 = 2.0f * (u2 - 0.5f);
  } else {
    S = -1.0f;
    u2 = 2.0f * (0.5f - u2);
  }
  float z = (u2 * (u2 * (u2 * 0.27385f - 0.73369f) + 0.46341f)) /
            (u2 * (u2 * (u2 * 0.093073f + 0.309420f) - 1.000000f) + 0.597999f);
  *sy = S * z * sqrtf(1.0f + *sx * *sx);
}

static void normalize3(float v[3]) {
  float l = sqrtf(dot3(v, v));
  if (l > 0.0f)
    for (int i = 0; i < 3; ++i) v[i] /= l;
}

void clr_tr_sample_wh(const float wo_in[3], const float u[2], float ax, float ay, float wh[3]) {
  int flip = wo_in[2] < 0.0f;
  float wo[3] = {flip ? -wo_in[0] : wo_in[0], flip ? -wo_in[1] : wo_in[1],
                 flip ? -wo_in[2] : wo_in[2]};
  float st[3] = {ax * wo[0], ay * wo[1], wo[2]};
  normalize3(st);
  float sx, sy;
  clr_tr_sample11(st[2], u[0], u[1], &sx, &sy);
  float cp = cos_phi(st), sp = sin_phi(st);
  float tmp = cp * sx - sp * sy;
  sy = sp * sx + cp * sy;
  sx = tmp;
  wh[0] = -ax * sx;
  wh[1] = -ay * sy;
  wh[2] = 1.0f;
  normalize3(wh);
  if (flip)
    for (int k = 0; k < 3; ++k) wh[k] = -wh[k];
}

/* The unit half vector wh of wo and wi, and the cosine of wi with Faceforward(wh, (0,0,1));
 * false where there is none (a grazing direction, or wi = -wo). */
static inline int half_vector(const float wo[3], const float wi[3], float wh[3], float *cos_h) {
  wh[0] = wi[0] + wo[0];
  wh[1] = wi[1] + wo[1];
  wh[2] = wi[2] + wo[2];
  if (wi[2] == 0.0f || wo[2] == 0.0f) return 0;
  if (wh[0] == 0.0f && wh[1] == 0.0f && wh[2] == 0.0f) return 0;
  float l = sqrtf(dot3(wh, wh));
  for (int i = 0; i < 3; ++i) wh[i] /= l;
  float ff[3] = {wh[0], wh[1], wh[2]};
  if (ff[2] < 0.0f)
    for (int i = 0; i < 3; ++i) ff[i] = -ff[i];
  *cos_h = dot3(wi, ff);
  return 1;
}

float clr_microfacet_f(const float wo[3], const float wi[3], float alpha) {
  float co = fabsf(wo[2]), ci = fabsf(wi[2]), wh[3], cos_h;
  if (!half_vector(wo, wi, wh, &cos_h)) return 0.0f;
  float F = clr_fr_dielectric(cos_h, 1.5f, 1.0f);
  return clr_tr_d(wh, alpha, alpha) * clr_tr_g(wo, wi, alpha, alpha) * F / (4.0f * ci * co);
}

float clr_fr_conductor(float cos_i, float eta, float k) {
  cos_i = rs_fminf(1.0f, fabsf(cos_i));
  float c2 = cos_i * cos_i, s2 = 1.0f - c2, eta2 = eta * eta, k2 = k * k;
  float t0 = eta2 - k2 - s2, a2b2 = sqrtf(t0 * t0 + 4.0f * eta2 * k2), t1 = a2b2 + c2;
  float a = sqrtf(rs_fmaxf(0.0f, 0.5f * (a2b2 + t0))), t2 = 2.0f * cos_i * a;
  float rs = (t1 - t2) / (t1 + t2), t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
  float rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5f * (rp + rs);
}

float clr_microfacet_dg(const float wo[3], const float wi[3], float alpha, float *cos_h) {
  float co = fabsf(wo[2]), ci = fabsf(wi[2]), wh[3];
  *cos_h = 0.0f;
  if (!half_vector(wo, wi, wh, cos_h)) return 0.0f;
  return clr_tr_d(wh, alpha, alpha) * clr_tr_g(wo, wi, alpha, alpha) / (4.0f * ci * co);
}

int clr_microfacet_sample_wi(const float wo[3], const float u[2], float alpha, float wi[3],
                             float *pdf) {
  *pdf = 0.0f;
  if (wo[2] == 0.0f) return 0;
  float wh[3];
  clr_tr_sample_wh(wo, u, alpha, alpha, wh);
  float d = dot3(wo, wh);
  if (d < 0.0f) return 0;
  for (int i = 0; i < 3; ++i) wi[i] = -wo[i] + 2.0f * d * wh[i];
  if (!(wo[2] * wi[2] > 0.0f)) return 0;
  *pdf = clr_tr_pdf_wh(wo, wh, alpha, alpha) / (4.0f * d);
  return *pdf > 0.0f;
}

float clr_microfacet_pdf(const float wo[3], const float wi[3], float alpha) {
  if (!(wo[2] * wi[2] > 0.0f)) return 0.0f;
  float wh[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
  float l = sqrtf(dot3(wh, wh));
  if (!(l > 0.0f)) return 0.0f;
  for (int i = 0; i < 3; ++i) wh[i] /= l;
  return clr_tr_pdf_wh(wo, wh, alpha, alpha) / (4.0f * dot3(wo, wh));
}

float clr_microfacet_sample(const float wo[3], const float u[2], float alpha, float wi[3],
                            float *pdf) {
  if (!clr_microfacet_sample_wi(wo, u, alpha, wi, pdf)) return 0.0f;
  return clr_microfacet_f(wo, wi, alpha);
}
