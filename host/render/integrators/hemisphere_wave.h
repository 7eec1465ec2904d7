/* pbrt-v3's cosine-weighted hemisphere samples (clr_cosine_hemisphere, lambertian.h) across a
 * wave of sample values, in a branch-free loop GCC vectorises: the same bits. */
#ifndef CLR_HEMISPHERE_WAVE_H
#define CLR_HEMISPHERE_WAVE_H

#include <stdint.h>

/* (x[k], y[k], z[k]) = clr_cosine_hemisphere((u0[k], u1[k])) for k < n; no array overlaps
 * another. */
void clr_wave_cosine_hemisphere(int32_t n, const float *restrict u0, const float *restrict u1,
                                float *restrict x, float *restrict y, float *restrict z);

/* pbrt-v3 AOIntegrator's cosine-sampled directions at one point, in place: (x[k], y[k], z[k])
 * becomes wi = ss x + ts y + n z (frame = ss, ts, n), cos_n[k] = Dot(wi, n) and term[k] =
 * cos_n / (pdf count) with pdf = |z| / pi (0 where the pdf is 0), as ao_integrator.c's scalar
 * loop computes them. */
void clr_wave_ao_directions(int32_t n, const float frame[9], float count, float *restrict x,
                            float *restrict y, float *restrict z, float *restrict cos_n,
                            float *restrict term);

#endif
