/* pbrt-v3 materials (materials/ in its source) as BxDF lists, re-implemented from their definitions. */
#include <math.h>
#include <string.h>
#include "materials.h"
#include "microfacet.h"
#include "float_minmax.h"

static const struct {
  const char *name;
  rs_material_type type;
} material_names[] = {{"matte", RS_MAT_MATTE}, {"plastic", RS_MAT_PLASTIC},
                      {"metal", RS_MAT_METAL}, {"mirror", RS_MAT_MIRROR},
                      {"glass", RS_MAT_GLASS}, {"substrate", RS_MAT_SUBSTRATE},
                      {"uber", RS_MAT_UBER},   {"translucent", RS_MAT_TRANSLUCENT},
                      {"mix", RS_MAT_MIX},     {"none", RS_MAT_NONE},
                      {"", RS_MAT_NONE}};

static int find_bool(const clr_param_list *shape, const clr_param_list *mat, const char *name,
                     int def) {
  int v = clr_params_find_bool(mat, name, def);
  return shape ? clr_params_find_bool(shape, name, v) : v;
}

static void metal_spectra(const clr_param_list *p, rs_material *m) {
  static const float cu_eta[3] = {0.2004376970f, 0.9240334304f, 1.1022119527f};
  static const float cu_k[3] = {3.9129485033f, 2.4528477015f, 2.1421879552f};
  clr_params_find_rgb(p, "eta", cu_eta, m->m_eta);
  clr_params_find_rgb(p, "k", cu_k, m->m_k);
}

int rs_material_build(const clr_scene_desc *d, const clr_material_desc *md,
                      const clr_param_list *shape, rs_material *m) {
  memset(m, 0, sizeof *m);
  const char *type = md->type ? md->type : "";
  const clr_param_list *p = &md->params;
  int known = 0;
  m->type = RS_MAT_MATTE;
  for (size_t i = 0; i < sizeof material_names / sizeof material_names[0]; ++i)
    if (strcmp(type, material_names[i].name) == 0) {
      m->type = material_names[i].type;
      known = 1;
    }
  m->remap = find_bool(shape, p, "remaproughness", 1);
  m->mix[0] = m->mix[1] = -1;
  switch (m->type) {
    case RS_MAT_MATTE:
      rs_colour_param(shape, p, "Kd", 0.5f, &m->kd);
      rs_float_param(shape, p, "sigma", 0.0f, &m->sigma);
      break;
    case RS_MAT_PLASTIC:
      rs_colour_param(shape, p, "Kd", 0.25f, &m->kd);
      rs_colour_param(shape, p, "Ks", 0.25f, &m->ks);
      rs_float_param(shape, p, "roughness", 0.1f, &m->rough);
      break;
    case RS_MAT_METAL:
      metal_spectra(p, m);
      rs_float_param(shape, p, "roughness", 0.01f, &m->rough);
      rs_float_param(shape, p, "uroughness", -1.0f, &m->urough);
      rs_float_param(shape, p, "vroughness", -1.0f, &m->vrough);
      break;
    case RS_MAT_MIRROR:
      rs_colour_param(shape, p, "Kr", 0.9f, &m->kr);
      break;
    case RS_MAT_GLASS:
      rs_colour_param(shape, p, "Kr", 1.0f, &m->kr);
      rs_colour_param(shape, p, "Kt", 1.0f, &m->kt);
      rs_float_param(shape, p, "index", 1.5f, &m->eta);
      if (clr_params_find(p, "eta", CLR_PARAM_FLOAT) ||
          clr_params_find(p, "eta", CLR_PARAM_TEXTURE))
        rs_float_param(shape, p, "eta", 1.5f, &m->eta);
      rs_float_param(shape, p, "uroughness", 0.0f, &m->urough);
      rs_float_param(shape, p, "vroughness", 0.0f, &m->vrough);
      break;
    case RS_MAT_SUBSTRATE:
      rs_colour_param(shape, p, "Kd", 0.5f, &m->kd);
      rs_colour_param(shape, p, "Ks", 0.5f, &m->ks);
      rs_float_param(shape, p, "uroughness", 0.1f, &m->urough);
      rs_float_param(shape, p, "vroughness", 0.1f, &m->vrough);
      break;
    case RS_MAT_UBER:
      rs_colour_param(shape, p, "Kd", 0.25f, &m->kd);
      rs_colour_param(shape, p, "Ks", 0.25f, &m->ks);
      rs_colour_param(shape, p, "Kr", 0.0f, &m->kr);
      rs_colour_param(shape, p, "Kt", 0.0f, &m->kt);
      rs_colour_param(shape, p, "opacity", 1.0f, &m->opacity);
      rs_float_param(shape, p, "roughness", 0.1f, &m->rough);
      rs_float_param(shape, p, "uroughness", -1.0f, &m->urough);
      rs_float_param(shape, p, "vroughness", -1.0f, &m->vrough);
      rs_float_param(shape, p, "index", 1.5f, &m->eta);
      if (clr_params_find(p, "eta", CLR_PARAM_FLOAT) ||
          clr_params_find(p, "eta", CLR_PARAM_TEXTURE))
        rs_float_param(shape, p, "eta", 1.5f, &m->eta);
      break;
    case RS_MAT_TRANSLUCENT:
      rs_colour_param(shape, p, "Kd", 0.25f, &m->kd);
      rs_colour_param(shape, p, "Ks", 0.25f, &m->ks);
      rs_colour_param(shape, p, "reflect", 0.5f, &m->reflect);
      rs_colour_param(shape, p, "transmit", 0.5f, &m->transmit);
      rs_float_param(shape, p, "roughness", 0.1f, &m->rough);
      break;
    case RS_MAT_MIX: {
      rs_colour_param(shape, p, "amount", 0.5f, &m->amount);
      const char *names[2] = {clr_params_find_string(p, "namedmaterial1", ""),
                              clr_params_find_string(p, "namedmaterial2", "")};
      for (int i = 0; i < 2; ++i) m->mix[i] = clr_scene_desc_find_named_material(d, names[i]);
      break;
    }
    default:
      break;
  }
  return known;
}

static int is_texture(const rs_colour *c) { return c->texture >= 0; }

int rs_material_needs_lobes(const rs_material *m) {
  switch (m->type) {
    case RS_MAT_SUBSTRATE:
    case RS_MAT_UBER:
    case RS_MAT_TRANSLUCENT:
    case RS_MAT_MIX:
      return 1;
    case RS_MAT_GLASS:
      return is_texture(&m->urough) || is_texture(&m->vrough) || is_texture(&m->eta) ||
             m->urough.rgb[0] != 0.0f || m->vrough.rgb[0] != 0.0f;
    case RS_MAT_MATTE:
      return is_texture(&m->sigma);
    case RS_MAT_PLASTIC:
      return is_texture(&m->rough);
    case RS_MAT_METAL:
      return is_texture(&m->rough) || is_texture(&m->urough) || is_texture(&m->vrough) ||
             (m->urough.rgb[0] >= 0.0f && m->vrough.rgb[0] >= 0.0f &&
              m->urough.rgb[0] != m->vrough.rgb[0]);
    default:
      return 0;
  }
}

static void clamp01(float c[3]) { /* Spectrum::Clamp(0, inf) */
  for (int k = 0; k < 3; ++k) c[k] = rs_fmaxf(0.0f, c[k]);
}
static int black(const float c[3]) { return c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f; }

typedef struct eval_ctx {
  const rs_texture_set *tex;
  const rs_tex_ctx *at;
} eval_ctx;

static void colour(const eval_ctx *e, const rs_colour *c, float out[3]) {
  rs_colour_eval(e->tex, c, e->at, out);
  clamp01(out);
}
static float value(const eval_ctx *e, const rs_colour *c) {
  return rs_float_eval(e->tex, c, e->at);
}

static float alpha(const rs_material *m, float r) {
  return m->remap ? clr_tr_roughness_to_alpha(r) : r;
}

static clr_lobe *add(clr_bsdf *b, clr_lobe_type type, const float c[3]) {
  clr_lobe *l = clr_bsdf_add(b, type);
  if (l && c) memcpy(l->c, c, sizeof l->c);
  return l;
}

/* Roughness: uroughness/vroughness when given (>= 0), else roughness; remapped. */
static void roughness(const eval_ctx *e, const rs_material *m, float *ax, float *ay) {
  float r = value(e, &m->rough);
  float u = m->urough.texture >= 0 || m->urough.rgb[0] >= 0.0f ? value(e, &m->urough) : r;
  float v = m->vrough.texture >= 0 || m->vrough.rgb[0] >= 0.0f ? value(e, &m->vrough) : r;
  *ax = alpha(m, u);
  *ay = alpha(m, v);
}

static void matte(const eval_ctx *e, const rs_material *m, clr_bsdf *b) {
  float kd[3];
  colour(e, &m->kd, kd);
  if (black(kd)) return;
  clr_lobe *l = add(b, CLR_LOBE_LAMBERT_R, kd);
  float sigma = rs_fminf(90.0f, rs_fmaxf(0.0f, value(e, &m->sigma)));
  if (!l || sigma == 0.0f) return;
  float s = sigma * 3.14159265f / 180.0f, s2 = s * s;
  l->on_a = 1.0f - s2 / (2.0f * (s2 + 0.33f));
  l->on_b = 0.45f * s2 / (s2 + 0.09f);
}

static void plastic(const eval_ctx *e, const rs_material *m, clr_bsdf *b) {
  float kd[3], ks[3];
  colour(e, &m->kd, kd);
  colour(e, &m->ks, ks);
  if (!black(kd)) add(b, CLR_LOBE_LAMBERT_R, kd);
  if (black(ks)) return;
  clr_lobe *l = add(b, CLR_LOBE_MICROFACET_R, ks);
  if (!l) return;
  l->ax = l->ay = alpha(m, value(e, &m->rough));
  l->fresnel = CLR_FRESNEL_DIELECTRIC;
  l->eta = 1.0f / 1.5f; /* FresnelDielectric(1.5, 1): only the ratio matters */
}

static void metal(const eval_ctx *e, const rs_material *m, clr_bsdf *b) {
  const float one[3] = {1, 1, 1};
  clr_lobe *l = add(b, CLR_LOBE_MICROFACET_R, one);
  if (!l) return;
  roughness(e, m, &l->ax, &l->ay);
  l->fresnel = CLR_FRESNEL_CONDUCTOR;
  memcpy(l->cond_eta, m->m_eta, sizeof l->cond_eta);
  memcpy(l->cond_k, m->m_k, sizeof l->cond_k);
}

static void glass(const eval_ctx *e, const rs_material *m, clr_bsdf *b) {
  float kr[3], kt[3], eta = value(e, &m->eta);
  colour(e, &m->kr, kr);
  colour(e, &m->kt, kt);
  b->eta = eta;
  if (black(kr) && black(kt)) return;
  float ur = value(e, &m->urough), vr = value(e, &m->vrough);
  int specular = ur == 0.0f && vr == 0.0f;
  if (!black(kr)) {
    clr_lobe *l = add(b, specular ? CLR_LOBE_SPECULAR_R : CLR_LOBE_MICROFACET_R, kr);
    if (l) {
      l->fresnel = CLR_FRESNEL_DIELECTRIC;
      l->eta = eta;
      l->ax = alpha(m, ur);
      l->ay = alpha(m, vr);
    }
  }
  if (!black(kt)) {
    clr_lobe *l = add(b, specular ? CLR_LOBE_SPECULAR_T : CLR_LOBE_MICROFACET_T, kt);
    if (l) {
      l->eta = eta;
      l->ax = alpha(m, ur);
      l->ay = alpha(m, vr);
    }
  }
}

static void substrate(const eval_ctx *e, const rs_material *m, clr_bsdf *b) {
  float kd[3], ks[3];
  colour(e, &m->kd, kd);
  colour(e, &m->ks, ks);
  if (black(kd) && black(ks)) return;
  clr_lobe *l = add(b, CLR_LOBE_FRESNEL_BLEND, kd);
  if (!l) return;
  memcpy(l->c2, ks, sizeof l->c2);
  l->ax = alpha(m, value(e, &m->urough));
  l->ay = alpha(m, value(e, &m->vrough));
}

static void scaled(float c[3], const float op[3]) {
  for (int k = 0; k < 3; ++k) c[k] *= op[k];
}

static void uber(const eval_ctx *e, const rs_material *m, clr_bsdf *b) {
  float eta = value(e, &m->eta), op[3], t[3], kd[3], ks[3], kr[3], kt[3];
  colour(e, &m->opacity, op);
  for (int k = 0; k < 3; ++k) t[k] = rs_fmaxf(0.0f, 1.0f - op[k]);
  b->eta = black(t) ? eta : 1.0f; /* pbrt-v3: BSDF(si, 1) when the surface lets light through */
  if (!black(t)) add(b, CLR_LOBE_SPECULAR_T, t); /* SpecularTransmission(t, 1, 1) */
  colour(e, &m->kd, kd);
  scaled(kd, op);
  if (!black(kd)) add(b, CLR_LOBE_LAMBERT_R, kd);
  colour(e, &m->ks, ks);
  scaled(ks, op);
  if (!black(ks)) {
    clr_lobe *l = add(b, CLR_LOBE_MICROFACET_R, ks);
    if (l) {
      l->fresnel = CLR_FRESNEL_DIELECTRIC;
      l->eta = eta;
      roughness(e, m, &l->ax, &l->ay);
    }
  }
  colour(e, &m->kr, kr);
  scaled(kr, op);
  if (!black(kr)) {
    clr_lobe *l = add(b, CLR_LOBE_SPECULAR_R, kr);
    if (l) {
      l->fresnel = CLR_FRESNEL_DIELECTRIC;
      l->eta = eta;
    }
  }
  colour(e, &m->kt, kt);
  scaled(kt, op);
  if (!black(kt)) {
    clr_lobe *l = add(b, CLR_LOBE_SPECULAR_T, kt);
    if (l) l->eta = eta;
  }
}

static void translucent(const eval_ctx *e, const rs_material *m, clr_bsdf *b) {
  const float eta = 1.5f;
  float r[3], t[3], kd[3], ks[3], c[3];
  b->eta = eta;
  colour(e, &m->reflect, r);
  colour(e, &m->transmit, t);
  if (black(r) && black(t)) return;
  colour(e, &m->kd, kd);
  if (!black(kd)) {
    for (int k = 0; k < 3; ++k) c[k] = r[k] * kd[k];
    if (!black(r)) add(b, CLR_LOBE_LAMBERT_R, c);
    for (int k = 0; k < 3; ++k) c[k] = t[k] * kd[k];
    if (!black(t)) add(b, CLR_LOBE_LAMBERT_T, c);
  }
  colour(e, &m->ks, ks);
  if (black(ks)) return;
  float a = alpha(m, value(e, &m->rough));
  for (int q = 0; q < 2; ++q) {
    const float *w = q ? t : r;
    if (black(w)) continue;
    for (int k = 0; k < 3; ++k) c[k] = w[k] * ks[k];
    clr_lobe *l = add(b, q ? CLR_LOBE_MICROFACET_T : CLR_LOBE_MICROFACET_R, c);
    if (!l) continue;
    l->ax = l->ay = a;
    l->eta = eta;
    l->fresnel = q ? CLR_FRESNEL_NOOP : CLR_FRESNEL_DIELECTRIC;
  }
}

static void build(const rs_material *m, const rs_material *all, int count, const eval_ctx *e,
                  clr_bsdf *b, int depth);

/* pbrt-v3 MixMaterial: namedmaterial1's lobes scaled by amount, namedmaterial2's by 1 - amount
 * (both clamped at 0); the BSDF's eta is the first material's. */
static void mix(const rs_material *m, const rs_material *all, int count, const eval_ctx *e,
                clr_bsdf *b, int depth) {
  float s1[3], s2[3];
  colour(e, &m->amount, s1);
  for (int k = 0; k < 3; ++k) s2[k] = rs_fmaxf(0.0f, 1.0f - s1[k]);
  for (int q = 0; q < 2; ++q) {
    int first = b->n;
    float eta = b->eta;
    if (m->mix[q] >= 0 && m->mix[q] < count) build(&all[m->mix[q]], all, count, e, b, depth + 1);
    if (q == 1) b->eta = eta;
    for (int i = first; i < b->n; ++i)
      for (int k = 0; k < 3; ++k) b->lobes[i].scale[k] *= q ? s2[k] : s1[k];
  }
}

static void build(const rs_material *m, const rs_material *all, int count, const eval_ctx *e,
                  clr_bsdf *b, int depth) {
  if (depth > 8) return;
  switch (m->type) {
    case RS_MAT_MATTE:
      matte(e, m, b);
      break;
    case RS_MAT_PLASTIC:
      plastic(e, m, b);
      break;
    case RS_MAT_METAL:
      metal(e, m, b);
      break;
    case RS_MAT_MIRROR: {
      float kr[3];
      colour(e, &m->kr, kr);
      if (!black(kr)) add(b, CLR_LOBE_SPECULAR_R, kr);
      break;
    }
    case RS_MAT_GLASS:
      glass(e, m, b);
      break;
    case RS_MAT_SUBSTRATE:
      substrate(e, m, b);
      break;
    case RS_MAT_UBER:
      uber(e, m, b);
      break;
    case RS_MAT_TRANSLUCENT:
      translucent(e, m, b);
      break;
    case RS_MAT_MIX:
      mix(m, all, count, e, b, depth);
      break;
    default:
      break;
  }
}

void rs_material_bsdf(const rs_material *m, const rs_material *all, int count,
                      const rs_texture_set *tex, const rs_tex_ctx *ctx, clr_bsdf *b) {
  eval_ctx e = {tex, ctx};
  b->n = 0;
  b->eta = 1.0f;
  build(m, all, count, &e, b, 0);
}
