/* pbrt-v3's plastic glossy lobe: MicrofacetReflection with an isotropic TrowbridgeReitz
 * distribution (visible-normal sampling) and FresnelDielectric(1.5, 1), in the local shading
 * frame (z = normal). */
#ifndef CLR_RENDER_MICROFACET_H
#define CLR_RENDER_MICROFACET_H

/* TrowbridgeReitzDistribution::RoughnessToAlpha (remaproughness true). */
float clr_tr_roughness_to_alpha(float roughness);
/* TrowbridgeReitzSample11: the slopes of a visible normal for alpha 1, incident cos_t. */
void clr_tr_sample11(float cos_t, float u1, float u2, float *sx, float *sy);
/* TrowbridgeReitzDistribution (pbrt-v3 microfacet.cpp, anisotropic alphas ax, ay; the one copy
 * for every lobe): D(wh), G(wo, wi), Sample_wh with visible normals, Pdf(wo, wh). */
float clr_tr_d(const float wh[3], float ax, float ay);
float clr_tr_g(const float wo[3], const float wi[3], float ax, float ay);
void clr_tr_sample_wh(const float wo[3], const float u[2], float ax, float ay, float wh[3]);
float clr_tr_pdf_wh(const float wo[3], const float wh[3], float ax, float ay);
/* pbrt-v3 FrDielectric(cos_i, eta_i, eta_t). */
float clr_fr_dielectric(float cos_i, float eta_i, float eta_t);
/* pbrt-v3 FrConductor(|cos_i|, 1, eta, k) for one channel. */
float clr_fr_conductor(float cos_i, float eta, float k);
/* D(wh) G(wo, wi) / (4 |cos_o| |cos_i|) and *cos_h = wi . Faceforward(wh, z): the Fresnel-free
 * part of MicrofacetReflection::f (0 when it is 0). */
float clr_microfacet_dg(const float wo[3], const float wi[3], float alpha, float *cos_h);
/* MicrofacetReflection::Sample_f's direction and pdf; 1 when usable. */
int clr_microfacet_sample_wi(const float wo[3], const float u[2], float alpha, float wi[3],
                             float *pdf);
/* MicrofacetReflection::f / R (R = Ks applied by the caller). */
float clr_microfacet_f(const float wo[3], const float wi[3], float alpha);
/* MicrofacetReflection::Pdf. */
float clr_microfacet_pdf(const float wo[3], const float wi[3], float alpha);
/* MicrofacetReflection::Sample_f: wi and pdf; returns f / R (0 when no direction). */
float clr_microfacet_sample(const float wo[3], const float u[2], float alpha, float wi[3],
                            float *pdf);

#endif
