/* Spectrum textures of pbrt-v3: constant, checkerboard (2D, no antialiasing) and imagemap, all
 * with the uv mapping; colour parameters that may name a texture. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"
#include "clrender/image.h"
#include "textures.h"

void rs_colour_param(const clr_param_list *first, const clr_param_list *second, const char *name,
                     float def, rs_colour *out) {
  out->texture = -1;
  out->rgb[0] = out->rgb[1] = out->rgb[2] = def;
  const clr_param_list *lists[2] = {first, second};
  for (int i = 0; i < 2; ++i) {
    if (!lists[i]) continue;
    int t = clr_params_find_texture_index(lists[i], name, CLR_TEXTURE_SPECTRUM);
    if (t >= 0) {
      out->texture = t;
      return;
    }
    if (clr_params_find(lists[i], name, CLR_PARAM_RGB)) {
      float d[3] = {def, def, def};
      clr_params_find_rgb(lists[i], name, d, out->rgb);
      return;
    }
    const clr_param *f = clr_params_find(lists[i], name, CLR_PARAM_FLOAT);
    if (f && f->count == 1) {
      out->rgb[0] = out->rgb[1] = out->rgb[2] = f->floats[0];
      return;
    }
  }
}

/* Joins the scene file's directory and a relative file name. */
static void resolve_path(const char *scene_file, const char *name, char *out, size_t n) {
  if (name[0] == '/' || !scene_file) {
    snprintf(out, n, "%s", name);
    return;
  }
  const char *slash = strrchr(scene_file, '/');
  if (!slash) {
    snprintf(out, n, "%s", name);
    return;
  }
  snprintf(out, n, "%.*s/%s", (int)(slash - scene_file), scene_file, name);
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
  resolve_path(p->file, name, path, sizeof path);
  t->scale = clr_params_find_float(p, "scale", 1.0f);
  const char *filter = clr_params_find_string(p, "filtertype", "bilinear");
  t->nearest = strcmp(filter, "nearest") == 0;
  const char *wrap = clr_params_find_string(p, "wrap", "repeat");
  if (strcmp(wrap, "repeat") != 0 && warn) {
    char m[512];
    snprintf(m, sizeof m, "%s:%d: imagemap wrap \"%s\" not supported: using repeat", p->file,
             p->line, wrap);
    warn(wu, m);
  }
  clr_image image;
  clr_result r = clr_image_read(path, &image);
  t->width = image.width;
  t->height = image.height;
  t->rgb = image.rgb;
  if (r != CLR_SUCCESS)
    return clr_set_last_error(r, "%s:%d: imagemap \"%s\": %s", p->file, p->line, path,
                              clr_last_error_message());
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
    t->su = clr_params_find_float(p, "uscale", 1.0f);
    t->sv = clr_params_find_float(p, "vscale", 1.0f);
    t->du = clr_params_find_float(p, "udelta", 0.0f);
    t->dv = clr_params_find_float(p, "vdelta", 0.0f);
    const char *mapping = clr_params_find_string(p, "mapping", "uv");
    if (strcmp(mapping, "uv") != 0) warn_at(warn, wu, p, "texture mapping", mapping);
    if (td->kind == CLR_TEXTURE_FLOAT) {
      warn_at(warn, wu, p, "float texture (ignored)", td->type);
      continue;
    }
    if (strcmp(td->type, "constant") == 0) {
      rs_colour_param(p, NULL, "value", 1.0f, &t->value);
    } else if (strcmp(td->type, "checkerboard") == 0) {
      t->type = RS_TEX_CHECKER;
      rs_colour_param(p, NULL, "tex1", 1.0f, &t->tex1);
      rs_colour_param(p, NULL, "tex2", 0.0f, &t->tex2);
      if (clr_params_find_int(p, "dimension", 2) != 2)
        warn_at(warn, wu, p, "checkerboard dimension", "3");
      clr_params_find_string(p, "aamode", "none"); /* always unfiltered */
    } else if (strcmp(td->type, "scale") == 0) {   /* pbrt-v3 ScaleTexture: tex1 * tex2 */
      t->type = RS_TEX_SCALE;
      rs_colour_param(p, NULL, "tex1", 1.0f, &t->tex1);
      rs_colour_param(p, NULL, "tex2", 1.0f, &t->tex2);
    } else if (strcmp(td->type, "mix") == 0) { /* pbrt-v3 MixTexture: lerp(amount, tex1, tex2) */
      t->type = RS_TEX_MIX;
      rs_colour_param(p, NULL, "tex1", 0.0f, &t->tex1);
      rs_colour_param(p, NULL, "tex2", 1.0f, &t->tex2);
      t->amount = clr_params_find_float(p, "amount", 0.5f);
      if (clr_params_find(p, "amount", CLR_PARAM_TEXTURE))
        warn_at(warn, wu, p, "mix \"amount\" as a texture (using 0.5)", "texture");
    } else if (strcmp(td->type, "uv") == 0) { /* pbrt-v3 UVTexture: (s - floor s, t - floor t, 0) */
      t->type = RS_TEX_UV;
    } else if (strcmp(td->type, "imagemap") == 0) {
      t->type = RS_TEX_IMAGE;
      CLR_CHECK(build_image(t, td, warn, wu));
    } else {
      warn_at(warn, wu, p, "texture (using 0.5)", td->type);
    }
  }
  return CLR_SUCCESS;
}

void rs_textures_free(rs_texture_set *set) {
  for (int i = 0; i < set->count; ++i) free(set->items[i].rgb);
  free(set->items);
  set->items = NULL;
  set->count = 0;
}

static int wrap_index(int i, int n) {
  int m = i % n;
  return m < 0 ? m + n : m;
}

static void texel(const rs_texture *t, int x, int y, float out[3]) {
  x = wrap_index(x, t->width);
  y = wrap_index(y, t->height);
  /* pbrt flips images so that t = 0 is the bottom row */
  const float *v = t->rgb + 3 * ((size_t)(t->height - 1 - y) * (size_t)t->width + (size_t)x);
  out[0] = v[0];
  out[1] = v[1];
  out[2] = v[2];
}

static void image_lookup(const rs_texture *t, float st_s, float st_t, float out[3]) {
  float x = st_s * (float)t->width - 0.5f, y = st_t * (float)t->height - 0.5f;
  if (t->nearest) {
    texel(t, (int)floorf(x + 0.5f), (int)floorf(y + 0.5f), out);
  } else {
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
  for (int k = 0; k < 3; ++k) out[k] *= t->scale;
}

static void colour_eval(const rs_texture_set *set, const rs_colour *c, const float uv[2],
                        float out[3], int depth) {
  for (; depth < 16; ++depth) {
    if (c->texture < 0) {
      memcpy(out, c->rgb, 3 * sizeof(float));
      return;
    }
    const rs_texture *t = &set->items[c->texture];
    float st_s = t->su * uv[0] + t->du, st_t = t->sv * uv[1] + t->dv;
    switch (t->type) {
      case RS_TEX_CONSTANT:
        c = &t->value;
        break;
      case RS_TEX_CHECKER:
        c = (((int)floorf(st_s) + (int)floorf(st_t)) % 2 == 0) ? &t->tex1 : &t->tex2;
        break;
      case RS_TEX_IMAGE:
        image_lookup(t, st_s, st_t, out);
        return;
      case RS_TEX_UV:
        out[0] = st_s - floorf(st_s);
        out[1] = st_t - floorf(st_t);
        out[2] = 0.0f;
        return;
      case RS_TEX_SCALE:
      case RS_TEX_MIX: {
        float a[3], b[3];
        colour_eval(set, &t->tex1, uv, a, depth + 1);
        colour_eval(set, &t->tex2, uv, b, depth + 1);
        for (int k = 0; k < 3; ++k)
          out[k] =
              t->type == RS_TEX_SCALE ? a[k] * b[k] : (1.0f - t->amount) * a[k] + t->amount * b[k];
        return;
      }
    }
  }
  out[0] = out[1] = out[2] = 0.5f;
}

void rs_colour_eval(const rs_texture_set *set, const rs_colour *c, const float uv[2],
                    float out[3]) {
  colour_eval(set, c, uv, out, 0);
}
