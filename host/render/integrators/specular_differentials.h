/* pbrt-v3 SamplerIntegrator::SpecularReflect / SpecularTransmit's ray differentials. */
#ifndef CLR_RENDER_SPECULAR_DIFFERENTIALS_H
#define CLR_RENDER_SPECULAR_DIFFERENTIALS_H

#include "ray_differential.h"
#include "render_scene.h"

/* The offset rays of the ray leaving sf along wi (wo: toward the incoming ray's origin) after a
 * perfect reflection about sf->ns; out->has is 0 when `in` or sf has no differentials. */
void rs_reflect_differential(const clr_surface *sf, const clr_ray_differential *in,
                             const float wo[3], const float wi[3], clr_ray_differential *out);

/* The same after a refraction with relative index eta (incident over transmitted side). */
void rs_transmit_differential(const clr_surface *sf, const clr_ray_differential *in,
                              const float wo[3], const float wi[3], float eta,
                              clr_ray_differential *out);

#endif
