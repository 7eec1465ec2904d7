/* A pbrt-v3 BSDF as a list of BxDFs ("lobes") in the shading frame, for the materials built from
 * several of them (uber, substrate, translucent, mix, rough glass): BSDF::f, Pdf and Sample_f
 * with pbrt-v3's rules (the reflect test on the geometric normal, pdfs averaged over the matching
 * components, a specular component sampled alone). */
#ifndef CLR_RENDER_BSDF_LOBES_H
#define CLR_RENDER_BSDF_LOBES_H

#include <stdint.h>

#define CLR_MAX_LOBES 8

typedef enum {
  CLR_LOBE_LAMBERT_R,       /* LambertianReflection R, or OrenNayar (on_a, on_b) */
  CLR_LOBE_LAMBERT_T,       /* LambertianTransmission T */
  CLR_LOBE_MICROFACET_R,    /* MicrofacetReflection R, TrowbridgeReitz(ax, ay), fresnel */
  CLR_LOBE_MICROFACET_T,    /* MicrofacetTransmission T, TrowbridgeReitz(ax, ay), 1 | eta */
  CLR_LOBE_FRESNEL_BLEND,   /* FresnelBlend Rd = c, Rs = c2, TrowbridgeReitz(ax, ay) */
  CLR_LOBE_SPECULAR_R,      /* SpecularReflection R, fresnel */
  CLR_LOBE_SPECULAR_T,      /* SpecularTransmission T, 1 | eta */
  CLR_LOBE_FRESNEL_SPECULAR /* FresnelSpecular R = c, T = c2, 1 | eta */
} clr_lobe_type;

typedef enum { CLR_FRESNEL_NOOP, CLR_FRESNEL_DIELECTRIC, CLR_FRESNEL_CONDUCTOR } clr_fresnel_type;

typedef struct clr_lobe {
  clr_lobe_type type;
  clr_fresnel_type fresnel;
  float c[3], c2[3];
  float eta; /* dielectric: eta_i 1 outside, eta inside */
  float cond_eta[3], cond_k[3];
  float ax, ay;     /* TrowbridgeReitz alphas */
  float on_a, on_b; /* Oren-Nayar (1, 0: Lambertian) */
  float scale[3];   /* ScaledBxDF (MixMaterial), 1 otherwise */
} clr_lobe;

typedef struct clr_bsdf {
  int32_t n;
  float eta;                 /* BSDF::eta: the material's eta for the path tracer's etaScale */
  float ss[3], ts[3], ns[3]; /* shading frame (world) */
  float ng[3];               /* geometric normal (world) */
  clr_lobe lobes[CLR_MAX_LOBES];
} clr_bsdf;

/* Sample flags */
#define CLR_BSDF_SPECULAR 1
#define CLR_BSDF_TRANSMISSION 2

/* Masks of components considered */
#define CLR_BXDF_ALL 0
#define CLR_BXDF_NON_SPECULAR 1
#define CLR_BXDF_SPECULAR_REFLECTION 2
#define CLR_BXDF_SPECULAR_TRANSMISSION 3

/* A new lobe (scale 1, fresnel none, Lambertian Oren-Nayar terms); NULL when full. */
clr_lobe *clr_bsdf_add(clr_bsdf *b, clr_lobe_type type);
/* Components matching `mask`. */
int clr_bsdf_count(const clr_bsdf *b, int mask);
/* BSDF::f in the local frame (z = shading normal) times |cos wi|; `reflect` is the geometric
 * test (wi and wo on the same side of the geometric normal). Non-specular components only. */
void clr_bsdf_f_local(const clr_bsdf *b, const float wo[3], const float wi[3], int reflect,
                      float f[3]);
/* BSDF::Pdf over the components matching mask (specular ones count, with pdf 0). */
float clr_bsdf_pdf_local(const clr_bsdf *b, const float wo[3], const float wi[3], int mask);
/* BSDF::Sample_f: wi, pdf, f |cos wi|, *flags (CLR_BSDF_SPECULAR | CLR_BSDF_TRANSMISSION); 1 when
 * a direction with pdf > 0 and f not black was found. `reflect_of` tells the geometric side of a
 * local direction (callback-free: the caller passes ng in local coordinates). */
int clr_bsdf_sample_local(const clr_bsdf *b, const float wo[3], const float u[2], int mask,
                          const float ng_local[3], float wi[3], float *pdf, float f[3], int *flags);

/* The shading frame from dpdu and the shading normal (as the integrators' frame), and ng. */
void clr_bsdf_set_frame(clr_bsdf *b, const float dpdu[3], const float ns[3], const float ng[3]);
/* World-space wrappers: f |cos| (non-specular, reflect rule on ng), Pdf over mask, Sample_f. */
int clr_bsdf_f(const clr_bsdf *b, const float wo[3], const float wi[3], float f[3]);
float clr_bsdf_pdf(const clr_bsdf *b, const float wo[3], const float wi[3], int mask);
int clr_bsdf_sample(const clr_bsdf *b, const float wo[3], const float u[2], int mask, float wi[3],
                    float *pdf, float f[3], int *flags);

#endif
