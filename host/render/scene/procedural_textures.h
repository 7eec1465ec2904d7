/* pbrt-v3's procedural textures: Perlin noise, FBm and turbulence, and the dots, fbm, wrinkled,
 * windy, marble and 3D checkerboard patterns evaluated at a texture-space point. */
#ifndef CLR_RENDER_PROCEDURAL_TEXTURES_H
#define CLR_RENDER_PROCEDURAL_TEXTURES_H

/* pbrt-v3 Noise(x, y, z): Perlin's improved gradient noise, in [-1, 1], 0 at integer points. */
float rs_noise(float x, float y, float z);
/* pbrt-v3 FBm / Turbulence: up to `octaves` octaves, fewer as the texture-space differentials
 * dpdx, dpdy grow (a smoothly faded partial octave; turbulence counts 0.2 for each dropped
 * one). The versions without _d take zero differentials: every octave. */
float rs_fbm_d(const float p[3], const float dpdx[3], const float dpdy[3], float omega,
               int octaves);
float rs_turbulence_d(const float p[3], const float dpdx[3], const float dpdy[3], float omega,
                      int octaves);
float rs_fbm(const float p[3], float omega, int octaves);
float rs_turbulence(const float p[3], float omega, int octaves);
/* pbrt-v3 WindyTexture: |FBm(0.1 p, 0.5, 3)| FBm(p, 0.5, 6) (differentials scaled alike). */
float rs_windy_d(const float p[3], const float dpdx[3], const float dpdy[3]);
float rs_windy(const float p[3]);
/* pbrt-v3 MarbleTexture's colour at p (before its `scale` is applied by the caller to p and the
 * differentials). */
void rs_marble_d(const float p[3], const float dpdx[3], const float dpdy[3], float omega,
                 int octaves, float variation, float out[3]);
void rs_marble(const float p[3], float omega, int octaves, float variation, float out[3]);
/* pbrt-v3 DotsTexture: 1 when (s, t) is inside a dot, 0 outside. */
int rs_dots_inside(float s, float t);
/* pbrt-v3 Checkerboard3DTexture: 1 for tex1 ((floor x + floor y + floor z) even), else 0. */
int rs_checker3d_first(const float p[3]);

#endif
