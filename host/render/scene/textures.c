/* pbrt-v3's textures, float and spectrum (images through pbrt-v3's MIP map by ray differentials),
 * their 2D and 3D mappings, and colour or float parameters that may name a texture. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "render_error.h"
#include "clrender/image.h"
#include "blackbody.h"
#include "procedural_textures.h"
#include "textures.h"
#include "float_minmax.h"

static void set_grey(rs_colour *out, float v) { out->rgb[0] = out->rgb[1] = out->rgb[2] = v; }

/* A colour given as an RGB triple or a blackbody; false when the list gives neither. */
static bool find_colour_value(const clr_param_list *list, const char *name, float def,
                              rs_colour *out) {
  if (clr_params_find(list, name, CLR_PARAM_RGB)) {
    float d[3] = {def, def, def};
    clr_params_find_rgb(list, name, d, out->rgb);
    return true;
  }
  const clr_param *bb = clr_params_find(list, name, CLR_PARAM_BLACKBODY);
  if (bb && bb->count >= 2) { /* pbrt-v3: the first (temperature, scale) pair */
    rs_blackbody_rgb(bb->floats[0], out->rgb);
    for (int k = 0; k < 3; ++k) out->rgb[k] *= bb->floats[1];
    return true;
  }
  return false;
}

/* The first of the lists that gives `name`: a texture of `kind`, (spectrum) a colour, or a
 * single float; else the value def. */
static void find_texture_or_value(const clr_param_list *first, const clr_param_list *second,
                                  const char *name, float def, clr_texture_kind kind,
                                  rs_colour *out) {
  out->texture = -1;
  set_grey(out, def);
  const clr_param_list *lists[2] = {first, second};
  for (int i = 0; i < 2; ++i) {
    if (!lists[i]) continue;
    int t = clr_params_find_texture_index(lists[i], name, kind);
    if (t >= 0) {
      out->texture = t;
      return;
    }
    if (kind == CLR_TEXTURE_SPECTRUM && find_colour_value(lists[i], name, def, out)) return;
    const clr_param *f = clr_params_find(lists[i], name, CLR_PARAM_FLOAT);
    if (f && f->count == 1) {
      set_grey(out, f->floats[0]);
      return;
    }
  }
}

void rs_colour_param(const clr_param_list *first, const clr_param_list *second, const char *name,
                     float def, rs_colour *out) {
  find_texture_or_value(first, second, name, def, CLR_TEXTURE_SPECTRUM, out);
}

void rs_float_param(const clr_param_list *first, const clr_param_list *second, const char *name,
                    float def, rs_colour *out) {
  find_texture_or_value(first, second, name, def, CLR_TEXTURE_FLOAT, out);
}

static int has_extension(const char *name, const char *ext) {
  size_t n = strlen(name), e = strlen(ext);
  return n >= e && strcasecmp(name + n - e, ext) == 0;
}

/* pbrt-v3 GammaCorrect (sRGB encode) and InverseGammaCorrect. */
static float gamma_correct(float v) {
  return v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}
static float inverse_gamma_correct(float v) {
  return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

/* pbrt-v3 ImageTexture::convertIn on every texel: scale * (gamma ? InverseGammaCorrect(x) : x),
 * x the file's value (the PNG reader decodes sRGB already, so it is encoded back first); a
 * float texture keeps the luminance y. pbrt-v4's `invert` (1 - value, clamped at 0) after. */
static void convert_texels(rs_texture *t, int png, int gamma, int is_float, int invert) {
  size_t n = (size_t)t->width * (size_t)t->height;
  for (size_t i = 0; i < n; ++i) {
    float *v = t->rgb + 3 * i, raw[3];
    for (int k = 0; k < 3; ++k) raw[k] = png ? gamma_correct(v[k]) : v[k];
    if (is_float) {
      float y = 0.212671f * raw[0] + 0.715160f * raw[1] + 0.072169f * raw[2];
      raw[0] = raw[1] = raw[2] = y;
    }
    for (int k = 0; k < 3; ++k) {
      float x = t->scale * (gamma ? inverse_gamma_correct(raw[k]) : raw[k]);
      v[k] = invert ? rs_fmaxf(0.0f, 1.0f - x) : x;
    }
  }
}

/* pbrt-v4's "filtertype" when given (point/nearest and bilinear read the image unfiltered),
 * else pbrt-v3's "trilinear" (false: EWA) with "maxanisotropy". */
static clr_result image_filter(rs_texture *t, const clr_param_list *p, int *trilinear,
                               float *max_aniso, clr_warn_fn warn, void *wu) {
  const char *filter = clr_params_find_string(p, "filtertype", "");
  *trilinear = clr_params_find_bool(p, "trilinear", false);
  *max_aniso = clr_params_find_float(p, "maxanisotropy", 8.0f);
  if (!(*max_aniso > 0.0f && *max_aniso <= 1024.0f))
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s:%d: imagemap: \"maxanisotropy\" must be in (0, 1024], got %g",
                              p->file ? p->file : "?", p->line, (double)*max_aniso);
  t->filter = RS_FILTER_MIPMAP;
  if (strcmp(filter, "nearest") == 0 || strcmp(filter, "point") == 0) {
    t->filter = RS_FILTER_NEAREST;
  } else if (strcmp(filter, "bilinear") == 0) {
    t->filter = RS_FILTER_BILINEAR;
  } else if (strcmp(filter, "trilinear") == 0 || strcmp(filter, "ewa") == 0) {
    *trilinear = filter[0] == 't';
  } else if (filter[0] && warn) {
    char m[512];
    snprintf(m, sizeof m, "%s:%d: imagemap filtertype \"%s\" unknown: using %s", p->file, p->line,
             filter, *trilinear ? "trilinear" : "ewa");
    warn(wu, m);
  }
  return CLR_SUCCESS;
}

/* pbrt-v3's MIP map of the converted texels, flipped so that t = 0 is the bottom row. */
static clr_result build_mipmap(rs_texture *t, int trilinear, float max_aniso,
                               const clr_param_list *p) {
  size_t row = (size_t)t->width * 3;
  float *flipped = malloc(row * (size_t)t->height * sizeof *flipped);
  if (!flipped) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "imagemap: MIP map");
  for (int32_t y = 0; y < t->height; ++y)
    memcpy(flipped + row * (size_t)y, t->rgb + row * (size_t)(t->height - 1 - y),
           row * sizeof *flipped);
  clr_result r =
      rs_mipmap_build(&t->mip, t->width, t->height, flipped, t->wrap, trilinear, max_aniso);
  free(flipped);
  if (r != CLR_SUCCESS)
    return clr_set_last_error(r, "%s:%d: %s", p->file ? p->file : "?", p->line,
                              clr_last_error_message());
  free(t->rgb); /* only the pyramid is read */
  t->rgb = NULL;
  return CLR_SUCCESS;
}

static clr_result build_image(rs_texture *t, const clr_texture_desc *td, clr_warn_fn warn,
                              void *wu) {
  const clr_param_list *p = &td->params;
  const char *name = clr_params_find_string(p, "filename", "");
  if (!name[0])
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s:%d: imagemap: parameter \"filename\" is required",
                              p->file ? p->file : "?", p->line);
  char path[4096];
  clr_params_resolve_path(p, name, path, sizeof path);
  t->scale = clr_params_find_float(p, "scale", 1.0f);
  int trilinear;
  float max_aniso;
  CLR_CHECK(image_filter(t, p, &trilinear, &max_aniso, warn, wu));
  const char *wrap = clr_params_find_string(p, "wrap", "repeat");
  t->wrap = RS_WRAP_REPEAT;
  if (strcmp(wrap, "black") == 0)
    t->wrap = RS_WRAP_BLACK;
  else if (strcmp(wrap, "clamp") == 0)
    t->wrap = RS_WRAP_CLAMP;
  else if (strcmp(wrap, "repeat") != 0 && warn) {
    char m[512];
    snprintf(m, sizeof m, "%s:%d: imagemap wrap \"%s\" unknown: using repeat", p->file, p->line,
             wrap);
    warn(wu, m);
  }
  int png = has_extension(name, ".png");
  int gamma = clr_params_find_bool(p, "gamma", png || has_extension(name, ".tga"));
  int invert = clr_params_find_bool(p, "invert", false);
  clr_image image;
  clr_result r = clr_image_read(path, &image);
  t->width = image.width;
  t->height = image.height;
  t->rgb = image.rgb;
  if (r != CLR_SUCCESS)
    return clr_set_last_error(r, "%s:%d: imagemap \"%s\": %s", p->file, p->line, path,
                              clr_last_error_message());
  convert_texels(t, png, gamma, td->kind == CLR_TEXTURE_FLOAT, invert);
  if (t->filter == RS_FILTER_MIPMAP) CLR_CHECK(build_mipmap(t, trilinear, max_aniso, p));
  return CLR_SUCCESS;
}

static void warn_at(clr_warn_fn warn, void *wu, const clr_param_list *p, const char *what,
                    const char *type) {
  if (!warn) return;
  char m[512];
  snprintf(m, sizeof m, "%s:%d: %s \"%s\" not supported", p->file ? p->file : "?", p->line, what,
           type);
  warn(wu, m);
}

/* A texture parameter of the texture's own kind (float or spectrum). */
static void kind_param(const clr_texture_desc *td, const char *name, float def, rs_colour *out) {
  if (td->kind == CLR_TEXTURE_FLOAT)
    rs_float_param(&td->params, NULL, name, def, out);
  else
    rs_colour_param(&td->params, NULL, name, def, out);
}

/* pbrt-v3's 2D mapping parameters (uv, spherical, cylindrical, planar). */
static void build_mapping(rs_texture *t, const clr_texture_desc *td, clr_warn_fn warn, void *wu) {
  const clr_param_list *p = &td->params;
  const char *mapping = clr_params_find_string(p, "mapping", "uv");
  t->mapping = RS_MAP_UV;
  if (strcmp(mapping, "spherical") == 0) {
    t->mapping = RS_MAP_SPHERICAL;
  } else if (strcmp(mapping, "cylindrical") == 0) {
    t->mapping = RS_MAP_CYLINDRICAL;
  } else if (strcmp(mapping, "planar") == 0) {
    static const float x[3] = {1, 0, 0}, y[3] = {0, 1, 0};
    t->mapping = RS_MAP_PLANAR;
    const clr_param *a = clr_params_find(p, "v1", CLR_PARAM_VECTOR3);
    const clr_param *b = clr_params_find(p, "v2", CLR_PARAM_VECTOR3);
    memcpy(t->v1, a && a->count == 3 ? a->floats : x, sizeof t->v1);
    memcpy(t->v2, b && b->count == 3 ? b->floats : y, sizeof t->v2);
  } else if (strcmp(mapping, "uv") != 0) {
    warn_at(warn, wu, p, "texture mapping (using uv)", mapping);
  }
  t->su = clr_params_find_float(p, "uscale", 1.0f);
  t->sv = clr_params_find_float(p, "vscale", 1.0f);
  t->du = clr_params_find_float(p, "udelta", 0.0f);
  t->dv = clr_params_find_float(p, "vdelta", 0.0f);
}

static int is_noise(rs_texture_type type) {
  return type == RS_TEX_FBM || type == RS_TEX_WRINKLED || type == RS_TEX_WINDY ||
         type == RS_TEX_MARBLE;
}

int rs_texture_uses_differentials(const rs_texture *t) {
  return (t->type == RS_TEX_IMAGE && t->filter == RS_FILTER_MIPMAP) || is_noise(t->type) ||
         (t->type == RS_TEX_CHECKER && t->checker_aa);
}

static int is_2d(rs_texture_type type) {
  return type == RS_TEX_CHECKER || type == RS_TEX_IMAGE || type == RS_TEX_UV || type == RS_TEX_DOTS;
}

/* pbrt-v3's 2D checkerboard "aamode": 1 for "closedform" (the default, and an unknown value,
 * with a warning as pbrt-v3 gives), 0 for "none". */
static int checker_aa_mode(const clr_param_list *p, clr_warn_fn warn, void *wu) {
  const char *aa = clr_params_find_string(p, "aamode", "closedform");
  if (strcmp(aa, "none") != 0 && strcmp(aa, "closedform") != 0 && warn) {
    char m[512];
    snprintf(m, sizeof m, "%s:%d: checkerboard aamode \"%s\" unknown: using closedform",
             p->file ? p->file : "?", p->line, aa);
    warn(wu, m);
  }
  return strcmp(aa, "none") != 0;
}

/* Type and parameters of one texture; 0 when the type is unknown. */
static int build_type(rs_texture *t, const clr_texture_desc *td, clr_warn_fn warn, void *wu) {
  const clr_param_list *p = &td->params;
  const char *type = td->type;
  if (strcmp(type, "constant") == 0) {
    kind_param(td, "value", 1.0f, &t->value);
  } else if (strcmp(type, "checkerboard") == 0) {
    int dim = clr_params_find_int(p, "dimension", 2);
    t->type = dim == 3 ? RS_TEX_CHECKER3D : RS_TEX_CHECKER;
    kind_param(td, "tex1", 1.0f, &t->tex1);
    kind_param(td, "tex2", 0.0f, &t->tex2);
    if (dim != 3) t->checker_aa = checker_aa_mode(p, warn, wu);
  } else if (strcmp(type, "scale") == 0) { /* pbrt-v3 ScaleTexture: tex1 * tex2 */
    t->type = RS_TEX_SCALE;
    kind_param(td, "tex1", 1.0f, &t->tex1);
    kind_param(td, "tex2", 1.0f, &t->tex2);
  } else if (strcmp(type, "mix") == 0) { /* pbrt-v3 MixTexture: lerp(amount, tex1, tex2) */
    t->type = RS_TEX_MIX;
    kind_param(td, "tex1", 0.0f, &t->tex1);
    kind_param(td, "tex2", 1.0f, &t->tex2);
    rs_float_param(p, NULL, "amount", 0.5f, &t->amount);
  } else if (strcmp(type, "uv") == 0) { /* pbrt-v3 UVTexture: (s - floor s, t - floor t, 0) */
    t->type = RS_TEX_UV;
  } else if (strcmp(type, "dots") == 0) {
    t->type = RS_TEX_DOTS; /* pbrt-v3 passes "inside" as the outside texture and vice versa */
    kind_param(td, "outside", 0.0f, &t->tex1);
    kind_param(td, "inside", 1.0f, &t->tex2);
  } else if (strcmp(type, "fbm") == 0 || strcmp(type, "wrinkled") == 0) {
    t->type = type[0] == 'f' ? RS_TEX_FBM : RS_TEX_WRINKLED;
    t->octaves = clr_params_find_int(p, "octaves", 8);
    t->omega = clr_params_find_float(p, "roughness", 0.5f);
  } else if (strcmp(type, "windy") == 0) {
    t->type = RS_TEX_WINDY;
  } else if (strcmp(type, "marble") == 0 && td->kind == CLR_TEXTURE_SPECTRUM) {
    t->type = RS_TEX_MARBLE;
    t->octaves = clr_params_find_int(p, "octaves", 8);
    t->omega = clr_params_find_float(p, "roughness", 0.5f);
    t->scale = clr_params_find_float(p, "scale", 1.0f);
    t->variation = clr_params_find_float(p, "variation", 0.2f);
  } else if (strcmp(type, "imagemap") == 0) {
    t->type = RS_TEX_IMAGE;
  } else {
    return 0;
  }
  if (t->octaves < 0 || t->octaves > 64) t->octaves = t->octaves < 0 ? 0 : 64;
  return 1;
}

clr_result rs_textures_build(rs_texture_set *set, const clr_scene_desc *d, clr_warn_fn warn,
                             void *wu) {
  set->count = d->texture_count;
  set->items = calloc((size_t)(d->texture_count ? d->texture_count : 1), sizeof *set->items);
  if (!set->items) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "textures");
  for (int i = 0; i < d->texture_count; ++i) {
    const clr_texture_desc *td = &d->textures[i];
    const clr_param_list *p = &td->params;
    rs_texture *t = &set->items[i];
    t->type = RS_TEX_CONSTANT;
    t->value.texture = -1;
    t->value.rgb[0] = t->value.rgb[1] = t->value.rgb[2] = 0.5f;
    t->world_to_texture = clr_transform_inverse(&td->texture_to_world);
    t->world_to_texture_3d = td->texture_to_world;
    if (!build_type(t, td, warn, wu)) {
      warn_at(warn, wu, p,
              td->kind == CLR_TEXTURE_FLOAT ? "float texture (using 0.5)" : "texture (using 0.5)",
              td->type);
      clr_params_mark_used(p);
      continue;
    }
    if (is_2d(t->type)) build_mapping(t, td, warn, wu);
    if (t->type == RS_TEX_IMAGE) CLR_CHECK(build_image(t, td, warn, wu));
  }
  return CLR_SUCCESS;
}

void rs_textures_free(rs_texture_set *set) {
  for (int i = 0; i < set->count; ++i) {
    free(set->items[i].rgb);
    rs_mipmap_free(&set->items[i].mip);
  }
  free(set->items);
  set->items = NULL;
  set->count = 0;
}

static int wrap_index(int i, int n) {
  int m = i % n;
  return m < 0 ? m + n : m;
}

/* pbrt-v3 MIPMap::Texel at level 0 with its wrap mode. */
static void texel(const rs_texture *t, int x, int y, float out[3]) {
  if (t->wrap == RS_WRAP_REPEAT) {
    x = wrap_index(x, t->width);
    y = wrap_index(y, t->height);
  } else if (t->wrap == RS_WRAP_CLAMP) {
    x = x < 0 ? 0 : x >= t->width ? t->width - 1 : x;
    y = y < 0 ? 0 : y >= t->height ? t->height - 1 : y;
  } else if (x < 0 || y < 0 || x >= t->width || y >= t->height) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  /* pbrt flips images so that t = 0 is the bottom row */
  const float *v = t->rgb + 3 * ((size_t)(t->height - 1 - y) * (size_t)t->width + (size_t)x);
  out[0] = v[0];
  out[1] = v[1];
  out[2] = v[2];
}

/* The unfiltered image at st: nearest texel or bilinear. */
static void image_lookup(const rs_texture *t, float st_s, float st_t, float out[3]) {
  float x = st_s * (float)t->width - 0.5f, y = st_t * (float)t->height - 0.5f;
  if (!(fabsf(x) < 1e9f && fabsf(y) < 1e9f)) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  if (t->filter == RS_FILTER_NEAREST) {
    texel(t, (int)floorf(x + 0.5f), (int)floorf(y + 0.5f), out);
    return;
  }
  int x0 = (int)floorf(x), y0 = (int)floorf(y);
  float dx = x - (float)x0, dy = y - (float)y0, a[3], b[3], c[3], e[3];
  texel(t, x0, y0, a);
  texel(t, x0 + 1, y0, b);
  texel(t, x0, y0 + 1, c);
  texel(t, x0 + 1, y0 + 1, e);
  for (int k = 0; k < 3; ++k)
    out[k] =
        (1 - dx) * (1 - dy) * a[k] + dx * (1 - dy) * b[k] + (1 - dx) * dy * c[k] + dx * dy * e[k];
}

static void sphere_st(const rs_texture *t, const float p[3], float st[2]) {
  const float inv_pi = 0.31830988618379067154f, inv_2pi = 0.15915494309189533577f;
  float q[3];
  clr_transform_point(&t->world_to_texture, p, q);
  float len = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  if (len > 0.0f)
    for (int k = 0; k < 3; ++k) q[k] /= len;
  float phi = atan2f(q[1], q[0]);
  st[0] = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, q[2]))) * inv_pi;
  st[1] = (phi < 0.0f ? phi + 2.0f * 3.14159265f : phi) * inv_2pi;
}

static void cylinder_st(const rs_texture *t, const float p[3], float st[2]) {
  const float inv_2pi = 0.15915494309189533577f;
  float q[3];
  clr_transform_point(&t->world_to_texture, p, q);
  st[0] = (3.14159265f + atan2f(q[1], q[0])) * inv_2pi;
  st[1] = q[2];
}

/* pbrt-v3's spherical/cylindrical differentials: a finite step `delta` along dpdx or dpdy, with
 * the seam of the second coordinate folded back. */
static void st_step(const rs_texture *t, const float p[3], const float dp[3], float delta,
                    const float st[2], float d[2]) {
  float q[3] = {p[0] + delta * dp[0], p[1] + delta * dp[1], p[2] + delta * dp[2]}, sq[2];
  if (t->mapping == RS_MAP_SPHERICAL)
    sphere_st(t, q, sq);
  else
    cylinder_st(t, q, sq);
  d[0] = (sq[0] - st[0]) / delta;
  d[1] = (sq[1] - st[1]) / delta;
  if (d[1] > 0.5f)
    d[1] = 1.0f - d[1];
  else if (d[1] < -0.5f)
    d[1] = -(d[1] + 1.0f);
}

static float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void rs_texture_map_2d(const rs_texture *t, const rs_tex_ctx *ctx, float st[2], float dstdx[2],
                       float dstdy[2]) {
  switch (t->mapping) {
    case RS_MAP_SPHERICAL:
    case RS_MAP_CYLINDRICAL: {
      float delta = t->mapping == RS_MAP_SPHERICAL ? 0.1f : 0.01f;
      if (t->mapping == RS_MAP_SPHERICAL)
        sphere_st(t, ctx->p, st);
      else
        cylinder_st(t, ctx->p, st);
      if (!dstdx) return;
      st_step(t, ctx->p, ctx->dpdx, delta, st, dstdx);
      st_step(t, ctx->p, ctx->dpdy, delta, st, dstdy);
      return;
    }
    case RS_MAP_PLANAR:
      st[0] = t->du + dot3(ctx->p, t->v1);
      st[1] = t->dv + dot3(ctx->p, t->v2);
      if (!dstdx) return;
      dstdx[0] = dot3(ctx->dpdx, t->v1);
      dstdx[1] = dot3(ctx->dpdx, t->v2);
      dstdy[0] = dot3(ctx->dpdy, t->v1);
      dstdy[1] = dot3(ctx->dpdy, t->v2);
      return;
    default:
      st[0] = t->su * ctx->uv[0] + t->du;
      st[1] = t->sv * ctx->uv[1] + t->dv;
      if (!dstdx) return;
      dstdx[0] = t->su * ctx->dudx;
      dstdx[1] = t->sv * ctx->dvdx;
      dstdy[0] = t->su * ctx->dudy;
      dstdy[1] = t->sv * ctx->dvdy;
  }
}

/* pbrt-v3's integral of the 0/1 "odd check" indicator over [0, x]. */
static float bump_int(float x) {
  float h = floorf(x / 2);
  return h + 2 * rs_fmaxf(x / 2 - h - 0.5f, 0.0f);
}

/* The odd checks' share of a box of half-widths ds, dt around st along one axis. */
static float odd_share(float x, float d) {
  if (d > 0.0f) return (bump_int(x + d) - bump_int(x - d)) / (2 * d);
  return (float)((((int)floorf(x)) % 2 + 2) % 2); /* a zero width: the indicator itself */
}

/* pbrt-v3 Checkerboard2DTexture's closed-form box filter: tex2's weight over the footprint of
 * dstdx, dstdy (0.5 past a check's width), or -1 when it lies inside one check (point sample). */
static float checker_box(const float st[2], const float dx[2], const float dy[2]) {
  float ds = rs_fmaxf(fabsf(dx[0]), fabsf(dy[0])), dt = rs_fmaxf(fabsf(dx[1]), fabsf(dy[1]));
  if (floorf(st[0] - ds) == floorf(st[0] + ds) && floorf(st[1] - dt) == floorf(st[1] + dt))
    return -1.0f;
  if (!(ds <= 1.0f && dt <= 1.0f)) return 0.5f; /* NaN widths too */
  float si = odd_share(st[0], ds), ti = odd_share(st[1], dt);
  return si + ti - 2 * si * ti;
}

static void fill(float out[3], float v) { out[0] = out[1] = out[2] = v; }

static void colour_eval(const rs_texture_set *set, const rs_colour *c, const rs_tex_ctx *ctx,
                        float out[3], int depth) {
  for (; depth < 16; ++depth) {
    if (c->texture < 0) {
      memcpy(out, c->rgb, 3 * sizeof(float));
      return;
    }
    const rs_texture *t = &set->items[c->texture];
    float st[2] = {0.0f, 0.0f}, q[3], dx[2], dy[2];
    int mip = t->type == RS_TEX_IMAGE && t->filter == RS_FILTER_MIPMAP;
    int filtered = mip || (t->type == RS_TEX_CHECKER && t->checker_aa);
    if (is_2d(t->type))
      rs_texture_map_2d(t, ctx, st, filtered ? dx : NULL, filtered ? dy : NULL);
    else if (t->type != RS_TEX_CONSTANT && t->type != RS_TEX_SCALE && t->type != RS_TEX_MIX)
      clr_transform_point(&t->world_to_texture_3d, ctx->p, q); /* pbrt-v3 IdentityMapping3D */
    float qx[3], qy[3];
    if (is_noise(t->type)) {
      clr_transform_vector(&t->world_to_texture_3d, ctx->dpdx, qx);
      clr_transform_vector(&t->world_to_texture_3d, ctx->dpdy, qy);
    }
    switch (t->type) {
      case RS_TEX_CONSTANT:
        c = &t->value;
        break;
      case RS_TEX_CHECKER: {
        if (!(fabsf(st[0]) < 1e9f && fabsf(st[1]) < 1e9f)) st[0] = st[1] = 0.0f;
        float area2 = filtered ? checker_box(st, dx, dy) : -1.0f;
        if (area2 < 0.0f) {
          c = (((int)floorf(st[0]) + (int)floorf(st[1])) % 2 == 0) ? &t->tex1 : &t->tex2;
          break;
        }
        float a[3], b[3];
        colour_eval(set, &t->tex1, ctx, a, depth + 1);
        colour_eval(set, &t->tex2, ctx, b, depth + 1);
        for (int k = 0; k < 3; ++k) out[k] = (1 - area2) * a[k] + area2 * b[k];
        return;
      }
      case RS_TEX_CHECKER3D:
        c = rs_checker3d_first(q) ? &t->tex1 : &t->tex2;
        break;
      case RS_TEX_DOTS:
        c = rs_dots_inside(st[0], st[1]) ? &t->tex1 : &t->tex2;
        break;
      case RS_TEX_IMAGE:
        if (mip)
          rs_mipmap_lookup(&t->mip, st, dx, dy, out);
        else
          image_lookup(t, st[0], st[1], out);
        return;
      case RS_TEX_UV:
        out[0] = st[0] - floorf(st[0]);
        out[1] = st[1] - floorf(st[1]);
        out[2] = 0.0f;
        return;
      case RS_TEX_FBM:
        fill(out, rs_fbm_d(q, qx, qy, t->omega, t->octaves));
        return;
      case RS_TEX_WRINKLED:
        fill(out, rs_turbulence_d(q, qx, qy, t->omega, t->octaves));
        return;
      case RS_TEX_WINDY:
        fill(out, rs_windy_d(q, qx, qy));
        return;
      case RS_TEX_MARBLE:
        for (int k = 0; k < 3; ++k) {
          q[k] *= t->scale;
          qx[k] *= t->scale;
          qy[k] *= t->scale;
        }
        rs_marble_d(q, qx, qy, t->omega, t->octaves, t->variation, out);
        return;
      case RS_TEX_SCALE:
      case RS_TEX_MIX: {
        float a[3], b[3], m[3];
        colour_eval(set, &t->tex1, ctx, a, depth + 1);
        colour_eval(set, &t->tex2, ctx, b, depth + 1);
        if (t->type == RS_TEX_MIX) colour_eval(set, &t->amount, ctx, m, depth + 1);
        for (int k = 0; k < 3; ++k)
          out[k] = t->type == RS_TEX_SCALE ? a[k] * b[k] : (1.0f - m[0]) * a[k] + m[0] * b[k];
        return;
      }
    }
  }
  fill(out, 0.5f);
}

void rs_colour_eval(const rs_texture_set *set, const rs_colour *c, const rs_tex_ctx *ctx,
                    float out[3]) {
  colour_eval(set, c, ctx, out, 0);
}

float rs_float_eval(const rs_texture_set *set, const rs_colour *c, const rs_tex_ctx *ctx) {
  float v[3];
  colour_eval(set, c, ctx, v, 0);
  return v[0];
}

static int tree_uses_differentials(const rs_texture_set *set, const rs_colour *c, int depth) {
  if (c->texture < 0 || c->texture >= set->count || depth > 16) return 0;
  const rs_texture *t = &set->items[c->texture];
  if (rs_texture_uses_differentials(t)) return 1;
  switch (t->type) {
    case RS_TEX_CONSTANT:
      return tree_uses_differentials(set, &t->value, depth + 1);
    case RS_TEX_MIX:
      if (tree_uses_differentials(set, &t->amount, depth + 1)) return 1;
      /* fall through */
    case RS_TEX_SCALE:
    case RS_TEX_CHECKER:
    case RS_TEX_CHECKER3D:
    case RS_TEX_DOTS:
      return tree_uses_differentials(set, &t->tex1, depth + 1) ||
             tree_uses_differentials(set, &t->tex2, depth + 1);
    default:
      return 0;
  }
}

int rs_texture_tree_uses_differentials(const rs_texture_set *set, int index) {
  rs_colour c = {index, {0, 0, 0}};
  return tree_uses_differentials(set, &c, 0);
}
