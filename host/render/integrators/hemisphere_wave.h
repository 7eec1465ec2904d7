/* pbrt-v3's cosine-weighted hemisphere samples (clr_cosine_hemisphere, lambertian.h) across a
 * wave of sample values, in a branch-free loop GCC vectorises: the same bits. */
#ifndef CLR_HEMISPHERE_WAVE_H
#define CLR_HEMISPHERE_WAVE_H

#include <stdint.h>

/* (x[k], y[k], z[k]) = clr_cosine_hemisphere((u0[k], u1[k])) for k < n; no array overlaps
 * another. */
void clr_wave_cosine_hemisphere(int32_t n, const float *restrict u0, const float *restrict u1,
                                float *restrict x, float *restrict y, float *restrict z);

#endif
