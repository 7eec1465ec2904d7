/* The BSDF of a surface record: pbrt-v3's f (times |cos wi| folded in as the integrators use it),
 * pdf and sampling, for matte, plastic and metal surfaces and lobe lists (clr_surface.general). */
#ifndef CLR_SURFACE_BSDF_H
#define CLR_SURFACE_BSDF_H

#include "render_scene.h"

/* f(wo, wi) into f; 0 when it is black. */
int clr_surface_bsdf_eval(const clr_surface *s, const float wo[3], const float wi[3], float f[3]);
/* The pdf of sampling wi from wo. */
float clr_surface_bsdf_pdf(const clr_surface *s, const float wo[3], const float wi[3]);
/* A direction wi from values u, its pdf and f; 0 when the sample is unusable. */
int clr_surface_bsdf_sample(const clr_surface *s, const float wo[3], const float u_in[2],
                            float wi[3], float *pdf, float f[3]);

#endif
