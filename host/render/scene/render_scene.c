/* Builds the renderable scene (Embree geometry, materials, lights) from a parsed description
 * and answers surface queries for hits. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "microfacet.h"
#include "render_error.h"
#include "loop_subdiv.h"
#include "ply_reader.h"
#include "camera.h"
#include "lights.h"
#include "bump.h"
#include "surface_differentials.h"
#include "quadric_shapes.h"
#include "render_scene.h"
#include "shapes.h"
#include "textures.h"
#include "vec3.h"
#include "float_minmax.h"

/* An ObjectInstance: instance to world at the start (and end, when it moves) of TransformTimes. */
typedef struct rs_instance {
  clr_transform start, end;
  int moving;
} rs_instance;

struct clr_render_scene {
  clr_tracer tracer;
  rs_camera camera;
  rs_texture_set textures;
  rs_material *materials; /* one per description material, without shape parameters (mix) */
  int material_count;
  rs_shape *shapes;
  int shape_count;
  rs_instance *instances;
  int instance_count;
  rs_light_set lights;
  float world_center[3];
  float world_lo[3], world_hi[3]; /* pbrt-v3 Scene::WorldBound */
  int needs_differentials;        /* some shape's surface uses ray differentials */
  int reads_uv;                   /* some texture (only these read a surface's (u, v)) exists */
};

static void rs_xform_m16(const clr_transform *t, float out[16]) {
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[r * 4 + c] = t->m[r][c];
}

clr_tracer clr_render_scene_tracer(const clr_render_scene *scene) { return scene->tracer; }
void clr_render_scene_world_bounds(const clr_render_scene *scene, float lo[3], float hi[3]) {
  memcpy(lo, scene->world_lo, 3 * sizeof(float));
  memcpy(hi, scene->world_hi, 3 * sizeof(float));
}
int32_t clr_render_scene_light_count(const clr_render_scene *scene) { return scene->lights.count; }

void clr_render_scene_light_info(const clr_render_scene *scene, int32_t light,
                                 clr_light_info *info) {
  const rs_light *l = &scene->lights.items[light];
  info->power = l->power;
  info->nsamples = l->nsamples;
  info->is_delta = rs_light_is_delta(l);
  info->is_infinite = l->type == RS_LIGHT_INFINITE;
}

float clr_render_scene_light_pdf(const clr_render_scene *scene, int32_t light, const float p[3],
                                 const float wi[3], float t, const float n_hit[3]) {
  return rs_light_pdf(&scene->lights, light, p, wi, t, n_hit);
}

int clr_render_scene_light_may_hit(const clr_render_scene *scene, int32_t light,
                                   const clr_ray *ray) {
  return rs_light_shape_may_hit(&scene->lights, scene->shapes, light, ray);
}

void clr_render_scene_light_le(const clr_render_scene *scene, int32_t light, const float d[3],
                               float le[3]) {
  rs_light_le(&scene->lights, light, d, le);
}

void clr_render_scene_sample_light(const clr_render_scene *scene, int32_t light, const float p[3],
                                   const float ng[3], const float u[2], clr_light_sample *ls) {
  rs_lights_sample(&scene->lights, scene->shapes, light, p, ng, u, ls);
}

void clr_render_scene_sample_light_li(const clr_render_scene *scene, int32_t light,
                                      const float p[3], const float u[2], clr_light_sample *ls) {
  rs_lights_sample_li(&scene->lights, scene->shapes, light, p, u, ls);
}

int clr_render_scene_light_emitter_point(const clr_render_scene *scene, int32_t light,
                                         const float u[2], clr_emitter_point *e) {
  return rs_light_emitter_point(&scene->lights, scene->shapes, light, u, e);
}

int clr_render_scene_light_triangle(const clr_render_scene *scene, int32_t light,
                                    clr_light_triangle *t) {
  return rs_light_triangle(&scene->lights, scene->shapes, light, t);
}

int clr_render_scene_light_point(const clr_render_scene *scene, int32_t light, clr_light_point *p) {
  return rs_light_point(&scene->lights, light, p);
}

void clr_render_scene_escaped(const clr_render_scene *scene, const clr_ray *ray, float le[3]) {
  rs_lights_escaped(&scene->lights, ray, le);
}

clr_result clr_render_scene_set_film(clr_render_scene *scene, int32_t x_resolution,
                                     int32_t y_resolution) {
  return rs_camera_set_film(&scene->camera, x_resolution, y_resolution);
}

void clr_render_scene_set_samples_per_pixel(clr_render_scene *scene, int32_t spp) {
  scene->camera.differential_scale = 1.0f / sqrtf((float)(spp > 0 ? spp : 1));
}

float clr_render_scene_camera_ray(const clr_render_scene *scene, float film_x, float film_y,
                                  float time, float lens_u, float lens_v, clr_ray *ray,
                                  clr_ray_differential *rd) {
  if (rd) rd->has = 0;
  return rs_camera_ray(&scene->camera, film_x, film_y, time, lens_u, lens_v, ray,
                       scene->needs_differentials ? rd : NULL);
}

void clr_render_scene_camera_rays(const clr_render_scene *scene, const clr_camera_samples *samples,
                                  int n, clr_ray *rays, clr_ray_differential *rd, float *weights) {
  if (rd)
    for (int k = 0; k < n; ++k) rd[k].has = 0;
  rs_camera_rays(&scene->camera, samples, n, rays, scene->needs_differentials ? rd : NULL, weights);
}

void clr_render_scene_camera_reads(const clr_render_scene *s, int *time, int *lens) {
  int moves = s->camera.motion.animated;
  for (int k = 0; k < s->shape_count && !moves; ++k) moves = s->shapes[k].moving;
  for (int i = 0; i < s->instance_count && !moves; ++i) moves = s->instances[i].moving;
  *time = moves;
  *lens = s->camera.lens_radius > 0.0f;
}

int clr_render_scene_uses_differentials(const clr_render_scene *scene) {
  return scene->needs_differentials;
}

void clr_render_scene_spawn_ray(const clr_surface *s, const float d[3], clr_ray *ray) {
  float e = rs_spawn_eps(s->p) * (rs_dot(s->ng, d) < 0.0f ? -1.0f : 1.0f);
  ray->ox = s->p[0] + s->ng[0] * e;
  ray->oy = s->p[1] + s->ng[1] * e;
  ray->oz = s->p[2] + s->ng[2] * e;
  ray->dx = d[0];
  ray->dy = d[1];
  ray->dz = d[2];
  ray->tnear = 0.0f;
  ray->tfar = INFINITY;
  ray->time = s->time;
}

void clr_render_settings_from_desc(const clr_scene_desc *desc, clr_render_settings *st) {
  const clr_param_list *p = &desc->film.params;
  memset(st, 0, sizeof *st);
  st->x_resolution = clr_params_find_int(p, "xresolution", 1280);
  st->y_resolution = clr_params_find_int(p, "yresolution", 720);
  float def[4] = {0, 1, 0, 1};
  memcpy(st->crop_window, def, sizeof def);
  int n = 0;
  const float *cw = clr_params_find_floats(p, "cropwindow", &n);
  if (cw && n == 4) {
    st->crop_window[0] = rs_fminf(cw[0], cw[1]);
    st->crop_window[1] = rs_fmaxf(cw[0], cw[1]);
    st->crop_window[2] = rs_fminf(cw[2], cw[3]);
    st->crop_window[3] = rs_fmaxf(cw[2], cw[3]);
  }
  st->scale = clr_params_find_float(p, "scale", 1.0f);
  st->max_sample_luminance = clr_params_find_float(p, "maxsampleluminance", INFINITY);
  snprintf(st->filename, sizeof st->filename, "%s",
           clr_params_find_string(p, "filename", "pbrt.exr"));
}

static void warn_fmt(clr_warn_fn warn, void *wu, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void warn_fmt(clr_warn_fn warn, void *wu, const char *fmt, ...) {
  if (!warn) return;
  char m[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(m, sizeof m, fmt, ap);
  va_end(ap);
  warn(wu, m);
}

static clr_result mesh_from_params(const clr_param_list *p, const char *what, clr_mesh *m) {
  int ni = 0, np = 0, nn = 0, nuv = 0;
  const int *ix = clr_params_find_ints(p, "indices", &ni);
  const float *P = clr_params_find_point3s(p, "P", &np);
  const float *N = clr_params_find_normals(p, "N", &nn);
  const float *uv = clr_params_find_point2s(p, "uv", &nuv);
  size_t uv_count = (size_t)nuv * 2;
  if (!uv) {
    uv = clr_params_find_floats(p, "uv", &nuv);
    uv_count = (size_t)nuv;
  }
  if (!uv) {
    uv = clr_params_find_point2s(p, "st", &nuv);
    uv_count = (size_t)nuv * 2;
  }
  if (!uv) {
    uv = clr_params_find_floats(p, "st", &nuv);
    uv_count = (size_t)nuv;
  }
  return clr_mesh_from_arrays(what, (const int32_t *)ix, (size_t)ni, P, (size_t)np * 3, N,
                              (size_t)nn * 3, uv, uv_count, m);
}

static clr_result build_mesh(const clr_shape_desc *sd, int moving, clr_mesh *m, clr_warn_fn warn,
                             void *wu) {
  const clr_param_list *p = &sd->params;
  char what[1200];
  snprintf(what, sizeof what, "%s:%d: Shape \"%s\"", p->file ? p->file : "?", p->line, sd->type);
  clr_result r;
  if (strcmp(sd->type, "trianglemesh") == 0) {
    r = mesh_from_params(p, what, m);
  } else if (strcmp(sd->type, "plymesh") == 0) {
    const char *name = clr_params_find_string(p, "filename", "");
    if (!name[0])
      return clr_set_last_error(CLR_ERROR_SCENE, "%s: parameter \"filename\" is required", what);
    char path[4096];
    clr_params_resolve_path(p, name, path, sizeof path);
    r = clr_ply_read(path, m);
    if (r != CLR_SUCCESS) return clr_set_last_error(r, "%s: %s", what, clr_last_error_message());
  } else {
    clr_mesh in;
    r = mesh_from_params(p, what, &in);
    if (r != CLR_SUCCESS) return r;
    int levels = clr_params_find_int(p, "nlevels", 3);
    r = clr_loop_subdivide(&in, levels, m);
    clr_mesh_free(&in);
    if (r != CLR_SUCCESS) return clr_set_last_error(r, "%s: %s", what, clr_last_error_message());
  }
  (void)warn;
  (void)wu;
  if (r != CLR_SUCCESS) return r;
  if (moving) return CLR_SUCCESS; /* placed by its instance */
  float xf[16];
  rs_xform_m16(&sd->object_to_world, xf);
  r = clr_mesh_transform(m, xf);
  if (r != CLR_SUCCESS) {
    clr_mesh_free(m);
    return clr_set_last_error(r, "%s: %s", what, clr_last_error_message());
  }
  return CLR_SUCCESS;
}

static void grow_bounds(clr_render_scene *s, float lo[3], float hi[3], const float p[3]) {
  (void)s;
  for (int i = 0; i < 3; ++i) {
    lo[i] = rs_fminf(lo[i], p[i]);
    hi[i] = rs_fmaxf(hi[i], p[i]);
  }
}

/* Object-space bounds of a shape (mesh vertices or sphere box). */
/* A shape's object-to-world, or identity for a moving shape (its instance places it). */
static const clr_transform *own_transform(const rs_shape *sh) {
  static const clr_transform identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}},
                                         {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  return sh->moving ? &identity : &sh->object_to_world;
}

static void shape_bounds(const rs_shape *sh, float lo[3], float hi[3]) {
  for (int i = 0; i < 3; ++i) {
    lo[i] = INFINITY;
    hi[i] = -INFINITY;
  }
  if (sh->type == RS_SHAPE_MESH) {
    for (int v = 0; v < sh->mesh.vertex_count; ++v)
      for (int i = 0; i < 3; ++i) {
        lo[i] = rs_fminf(lo[i], sh->mesh.p[3 * v + i]);
        hi[i] = rs_fmaxf(hi[i], sh->mesh.p[3 * v + i]);
      }
    return;
  }
  if (sh->type == RS_SHAPE_QUADRIC) {
    rs_quadric_bounds(&sh->quadric, own_transform(sh), lo, hi);
    return;
  }
  for (int c = 0; c < 8; ++c) {
    float q[3] = {(c & 1) ? sh->radius : -sh->radius, (c & 2) ? sh->radius : -sh->radius,
                  (c & 4) ? sh->radius : -sh->radius},
          w[3];
    if (sh->type == RS_SHAPE_DISK) q[2] = sh->height;
    clr_transform_point(own_transform(sh), q, w);
    for (int i = 0; i < 3; ++i) {
      lo[i] = rs_fminf(lo[i], w[i]);
      hi[i] = rs_fmaxf(hi[i], w[i]);
    }
  }
}

/* pbrt-v3 reads "bumpmap" of the material, the shape's parameters first. A mix has none of its
 * own: its first material's (a named one, so without shape parameters) applies, since pbrt-v3's
 * MixMaterial keeps that material's bumped shading frame for both materials' lobes. */
static void bump_param(const clr_scene_desc *d, const clr_shape_desc *sd,
                       const clr_material_desc *md, rs_colour *out) {
  const clr_param_list *shape = &sd->params;
  for (int depth = 0; md && md->type && strcmp(md->type, "mix") == 0; ++depth) {
    int i = depth < 8 ? clr_scene_desc_find_named_material(
                            d, clr_params_find_string(&md->params, "namedmaterial1", ""))
                      : -1;
    md = i >= 0 ? &d->materials[i] : NULL;
    shape = NULL;
  }
  if (md) rs_float_param(shape, &md->params, "bumpmap", 0.0f, out);
}

/* 1 when a texture parameter of `list` names a texture that ray differentials filter. */
static int params_use_differentials(const rs_texture_set *tex, const clr_param_list *list) {
  for (int i = 0; list && i < list->count; ++i) {
    const clr_param *p = &list->items[i];
    if (p->type == CLR_PARAM_TEXTURE &&
        (rs_texture_tree_uses_differentials(tex, p->float_texture) ||
         rs_texture_tree_uses_differentials(tex, p->spectrum_texture)))
      return 1;
  }
  return 0;
}

/* The same for a material and, for a mix, its named materials. */
static int material_uses_differentials(const clr_scene_desc *d, const rs_texture_set *tex,
                                       const clr_material_desc *md, int depth) {
  if (!md || depth > 8) return 0;
  if (params_use_differentials(tex, &md->params)) return 1;
  if (!md->type || strcmp(md->type, "mix") != 0) return 0;
  const char *names[2] = {"namedmaterial1", "namedmaterial2"};
  for (int k = 0; k < 2; ++k) {
    int i =
        clr_scene_desc_find_named_material(d, clr_params_find_string(&md->params, names[k], ""));
    if (i >= 0 && material_uses_differentials(d, tex, &d->materials[i], depth + 1)) return 1;
  }
  return 0;
}

static int material_is_supported(const clr_scene_desc *d, const clr_material_desc *md) {
  rs_material m;
  return rs_material_build(d, md, NULL, &m);
}

/* pbrt-v3 MatteMaterial: "sigma" in degrees, clamped to [0, 90]; 0 is Lambertian, else
 * OrenNayar with A = 1 - s^2 / (2 (s^2 + 0.33)), B = 0.45 s^2 / (s^2 + 0.09), s in radians. A
 * shape's own parameter overrides the material's, as for Kd. */
static void oren_nayar_params(const clr_shape_desc *sd, const clr_material_desc *md,
                              const char *mtype, rs_shape *sh) {
  sh->on_a = 1.0f;
  sh->on_b = 0.0f;
  if (strcmp(mtype, "matte") != 0) return;
  float sigma = clr_params_find_float(&md->params, "sigma", 0.0f);
  sigma = clr_params_find_float(&sd->params, "sigma", sigma);
  sigma = rs_fminf(90.0f, rs_fmaxf(0.0f, sigma));
  if (sigma == 0.0f) return;
  float s = sigma * RS_PI / 180.0f, s2 = s * s;
  sh->on_a = 1.0f - s2 / (2.0f * (s2 + 0.33f));
  sh->on_b = 0.45f * s2 / (s2 + 0.09f);
}

/* pbrt-v3 CreateMetalMaterial: eta and k default to copper (its spectra as RGB), roughness 0.01
 * (uroughness/vroughness override it; anisotropic is rendered isotropic with their mean),
 * remaproughness true. Only rgb eta and k; other spectra fall back to copper with a warning. */
static void metal_params(const clr_shape_desc *sd, const clr_material_desc *md,
                         const clr_param_list *p, clr_warn_fn warn, void *wu, rs_shape *sh) {
  static const float cu_eta[3] = {0.2004376970f, 0.9240334304f, 1.1022119527f};
  static const float cu_k[3] = {3.9129485033f, 2.4528477015f, 2.1421879552f};
  clr_params_find_rgb(&md->params, "eta", cu_eta, sh->m_eta);
  clr_params_find_rgb(&md->params, "k", cu_k, sh->m_k);
  const char *spectra[2] = {"eta", "k"};
  for (int i = 0; i < 2; ++i)
    if (clr_params_find(&md->params, spectra[i], CLR_PARAM_SPECTRUM))
      warn_fmt(warn, wu, "%s:%d: metal \"%s\" given as a spectrum: not supported, copper used",
               md->params.file ? md->params.file : p->file, md->params.line, spectra[i]);
  float rough = clr_params_find_float(&md->params, "roughness", 0.01f);
  float ur = clr_params_find_float(&md->params, "uroughness", rough);
  float vr = clr_params_find_float(&md->params, "vroughness", rough);
  (void)sd;
  float r = 0.5f * (ur + vr);
  sh->alpha =
      clr_params_find_bool(&md->params, "remaproughness", true) ? clr_tr_roughness_to_alpha(r) : r;
}

static clr_result build_materials(clr_render_scene *s, const clr_scene_desc *d) {
  s->materials = calloc((size_t)(d->material_count ? d->material_count : 1), sizeof *s->materials);
  if (!s->materials) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "materials");
  s->material_count = d->material_count;
  for (int i = 0; i < d->material_count; ++i)
    rs_material_build(d, &d->materials[i], NULL, &s->materials[i]);
  return CLR_SUCCESS;
}

/* Instance user ids of moving shapes: the shape index with this bit (not an instance desc). */
#define RS_MOVING_INSTANCE 0x80000000u

/* pbrt-v3's decomposition of a start and an end transform; 0 when its scale part is not
 * diagonal (a shear) or a transform mirrors (no rotation quaternion), which Embree's quaternion
 * instances cannot interpolate alike. */
static int motion_of(const clr_scene_desc *d, const clr_transform *start, const clr_transform *end,
                     rs_animated_transform *a, float scale[2][3]) {
  rs_animated_transform_init(a, start, end, d->transform_start_time, d->transform_end_time);
  if (clr_transform_swaps_handedness(start) || clr_transform_swaps_handedness(end)) return 0;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 3; ++i) {
      scale[k][i] = a->s[k][i][i];
      for (int j = 0; j < 3; ++j)
        if (i != j && !(fabsf(a->s[k][i][j]) <= 1e-5f * fabsf(a->s[k][i][i]))) return 0;
    }
  return 1;
}

/* *moves: 1 when start and end differ; an error naming file:line and `what` when that motion
 * shears or mirrors. */
static clr_result check_motion(const clr_scene_desc *d, const clr_transform *start,
                               const clr_transform *end, const char *file, int line,
                               const char *what, int *moves) {
  *moves = memcmp(&start->m, &end->m, sizeof start->m) != 0;
  rs_animated_transform a;
  float scale[2][3];
  if (!*moves || motion_of(d, start, end, &a, scale)) return CLR_SUCCESS;
  return clr_set_last_error(CLR_ERROR_SCENE,
                            "%s:%d: moving %s: its transform shears (the scale part is not "
                            "diagonal) or mirrors, which clrender's moving instances cannot "
                            "interpolate as pbrt-v3: not supported",
                            file ? file : "?", line, what);
}

/* Places group `group` (a moving shape in object space, or an object) by a two-step Embree
 * instance built from pbrt-v3's decomposition of its start and end transforms. */
static clr_result add_motion(clr_render_scene *s, const clr_scene_desc *d,
                             const clr_transform *start, const clr_transform *end, int32_t group,
                             uint32_t user_id) {
  rs_animated_transform a;
  float scale[2][3];
  motion_of(d, start, end, &a, scale);
  return clr_tracer_add_motion_instance(s->tracer, group, a.t, a.q, scale, user_id);
}

/* A mesh triangle's vertex (u, v): its "uv" values, or pbrt-v3's default (0,0), (1,0), (1,1). */
static inline void triangle_uvs(const clr_mesh *m, const uint32_t *ix, float uv0[2], float uv1[2],
                                float uv2[2]) {
  if (!m->uv) {
    uv0[0] = uv0[1] = uv1[1] = 0.0f;
    uv1[0] = uv2[0] = uv2[1] = 1.0f;
    return;
  }
  memcpy(uv0, m->uv + 2 * ix[0], 2 * sizeof *uv0);
  memcpy(uv1, m->uv + 2 * ix[1], 2 * sizeof *uv1);
  memcpy(uv2, m->uv + 2 * ix[2], 2 * sizeof *uv2);
}

/* A mesh triangle's unit normal (from its winding) and dpdu (from its uvs, or an axis-made
 * tangent where they are degenerate), as pbrt-v3's Triangle::Intersect computes them. */
static void triangle_frame(const clr_mesh *m, int32_t prim, float n[3], float dpdu[3]) {
  const uint32_t *ix = m->indices + 3 * (size_t)prim;
  const float *p0 = m->p + 3 * ix[0], *p1 = m->p + 3 * ix[1], *p2 = m->p + 3 * ix[2];
  float uv0[2], uv1[2], uv2[2];
  triangle_uvs(m, ix, uv0, uv1, uv2);
  float dp02[3], dp12[3];
  for (int i = 0; i < 3; ++i) {
    dp02[i] = p0[i] - p2[i];
    dp12[i] = p1[i] - p2[i];
  }
  rs_cross(dp02, dp12, n);
  rs_normalize(n);
  float du02 = uv0[0] - uv2[0], dv02 = uv0[1] - uv2[1], du12 = uv1[0] - uv2[0],
        dv12 = uv1[1] - uv2[1];
  float det = du02 * dv12 - dv02 * du12;
  if (fabsf(det) < 1e-8f) {
    float t[3];
    if (fabsf(n[0]) > fabsf(n[1])) {
      t[0] = -n[2];
      t[1] = 0;
      t[2] = n[0];
    } else {
      t[0] = 0;
      t[1] = n[2];
      t[2] = -n[1];
    }
    memcpy(dpdu, t, sizeof t);
  } else {
    float inv = 1.0f / det;
    for (int i = 0; i < 3; ++i) dpdu[i] = (dv12 * dp02[i] - dv02 * dp12[i]) * inv;
  }
}

/* Every triangle's frame, computed once (a surface reads it instead of a cross product, a square
 * root and four divisions per hit). */
static clr_result build_triangle_frames(rs_shape *sh) {
  size_t count = (size_t)sh->mesh.triangle_count;
  sh->tri_frames = malloc(6 * sizeof(float) * (count ? count : 1));
  if (!sh->tri_frames)
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "frames of %zu triangles", count);
  for (size_t t = 0; t < count; ++t)
    triangle_frame(&sh->mesh, (int32_t)t, sh->tri_frames + 6 * t, sh->tri_frames + 6 * t + 3);
  return CLR_SUCCESS;
}

static clr_result build_shapes(clr_render_scene *s, const clr_scene_desc *d, clr_warn_fn warn,
                               void *wu, int32_t *object_group) {
  char warned[32][64];
  int warned_count = 0;
  s->shapes = calloc((size_t)(d->shape_count ? d->shape_count : 1), sizeof *s->shapes);
  if (!s->shapes) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "shapes");
  for (int i = 0; i < d->shape_count; ++i) {
    const clr_shape_desc *sd = &d->shapes[i];
    const clr_param_list *p = &sd->params;
    rs_shape *sh = &s->shapes[s->shape_count];
    sh->first_light = -1;
    sh->in_object = sd->object >= 0;
    sh->object_to_world = sd->object_to_world;
    sh->object_to_world_end = sd->object_to_world_end;
    char what[96];
    snprintf(what, sizeof what, "Shape \"%.64s\"", sd->type);
    CLR_CHECK(check_motion(d, &sd->object_to_world, &sd->object_to_world_end, p->file, p->line,
                           what, &sh->moving));
    sh->flip_normal =
        sd->reverse_orientation != clr_transform_swaps_handedness(&sd->object_to_world);
    if (strcmp(sd->type, "sphere") == 0) {
      sh->type = RS_SHAPE_SPHERE;
      sh->radius = clr_params_find_float(p, "radius", 1.0f);
      if (!(sh->radius > 0.0f))
        return clr_set_last_error(CLR_ERROR_SCENE,
                                  "%s:%d: Shape \"sphere\": \"radius\" must be "
                                  "positive, got %g",
                                  p->file ? p->file : "?", p->line, (double)sh->radius);
      /* pbrt-v3 CreateSphereShape: zmin, zmax (clamped and sorted), phimax degrees */
      float r = sh->radius, z0 = clr_params_find_float(p, "zmin", -r),
            z1 = clr_params_find_float(p, "zmax", r);
      float pm = clr_params_find_float(p, "phimax", 360.0f);
      sh->zmin = rs_fminf(rs_fmaxf(rs_fminf(z0, z1), -r), r);
      sh->zmax = rs_fminf(rs_fmaxf(rs_fmaxf(z0, z1), -r), r);
      sh->phimax = rs_fminf(rs_fmaxf(pm, 0.0f), 360.0f) * RS_PI / 180.0f;
      sh->partial = !(sh->zmin <= -r && sh->zmax >= r && pm >= 360.0f);
      if (sh->partial && sd->area_light >= 0)
        warn_fmt(warn, wu,
                 "%s:%d: partial sphere as an area light: sampled as the full sphere (as "
                 "pbrt-v3 does)",
                 p->file ? p->file : "?", p->line);
    } else if (strcmp(sd->type, "disk") == 0) { /* pbrt-v3 CreateDiskShape */
      sh->type = RS_SHAPE_DISK;
      sh->height = clr_params_find_float(p, "height", 0.0f);
      sh->radius = clr_params_find_float(p, "radius", 1.0f);
      sh->inner_radius = clr_params_find_float(p, "innerradius", 0.0f);
      float phimax = clr_params_find_float(p, "phimax", 360.0f);
      if (!(sh->radius > 0.0f) || !(sh->inner_radius >= 0.0f) || !(sh->inner_radius < sh->radius) ||
          !(phimax > 0.0f && phimax <= 360.0f) || !isfinite(sh->height))
        return clr_set_last_error(CLR_ERROR_SCENE,
                                  "%s:%d: Shape \"disk\": needs 0 <= \"innerradius\" "
                                  "< \"radius\" and 0 < \"phimax\" <= 360, got %g, %g, %g",
                                  p->file ? p->file : "?", p->line, (double)sh->inner_radius,
                                  (double)sh->radius, (double)phimax);
      sh->phimax = phimax * RS_PI / 180.0f;
    } else if (rs_is_quadric(sd->type)) {
      sh->type = RS_SHAPE_QUADRIC;
      CLR_CHECK(rs_quadric_from_params(sd->type, p, &sh->quadric));
    } else if (strcmp(sd->type, "trianglemesh") == 0 || strcmp(sd->type, "plymesh") == 0 ||
               strcmp(sd->type, "loopsubdiv") == 0) {
      sh->type = RS_SHAPE_MESH;
      CLR_CHECK(build_mesh(sd, sh->moving, &sh->mesh, warn, wu));
      clr_result r = build_triangle_frames(sh);
      if (r != CLR_SUCCESS) {
        clr_mesh_free(&sh->mesh);
        return r;
      }
    } else {
      warn_fmt(warn, wu, "%s:%d: shape \"%s\" not supported: ignored", p->file, p->line, sd->type);
      clr_params_mark_used(p); /* one warning for the skipped shape, not one per parameter */
      continue;
    }
    s->shape_count++;
    const clr_material_desc *md = &d->materials[sd->material >= 0 ? sd->material : 0];
    const char *mtype = md->type ? md->type : "";
    sh->has_material = !(mtype[0] == 0 || strcmp(mtype, "none") == 0);
    sh->mirror = strcmp(mtype, "mirror") == 0;
    sh->plastic = strcmp(mtype, "plastic") == 0;
    sh->glass = strcmp(mtype, "glass") == 0;
    if (sh->glass) { /* pbrt-v3 CreateGlassMaterial: Kr 1, Kt 1, eta ("index" in old scenes) 1.5 */
      rs_colour_param(&sd->params, &md->params, "Kr", 1.0f, &sh->kr);
      rs_colour_param(&sd->params, &md->params, "Kt", 1.0f, &sh->kt);
      float eta = clr_params_find_float(&md->params, "index", 1.5f);
      sh->eta = clr_params_find_float(&md->params, "eta", eta);
    }
    sh->metal = strcmp(mtype, "metal") == 0;
    if (sh->metal) metal_params(sd, md, p, warn, wu, sh);
    if (sh->mirror)
      rs_colour_param(&sd->params, &md->params, "Kr", 0.9f, &sh->kr); /* pbrt-v3 default */
    else if (sh->glass || sh->metal)
      sh->kd = (rs_colour){-1, {0.0f, 0.0f, 0.0f}};
    else
      rs_colour_param(&sd->params, &md->params, "Kd", sh->plastic ? 0.25f : 0.5f, &sh->kd);
    if (sh->plastic) { /* pbrt-v3 CreatePlasticMaterial defaults */
      rs_colour_param(&sd->params, &md->params, "Ks", 0.25f, &sh->ks);
      float rough = clr_params_find_float(&md->params, "roughness", 0.1f);
      rough = clr_params_find_float(&sd->params, "roughness", rough);
      int remap = clr_params_find_bool(&md->params, "remaproughness", true);
      sh->alpha = remap ? clr_tr_roughness_to_alpha(rough) : rough;
    }
    oren_nayar_params(sd, md, mtype, sh);
    sh->bump = (rs_colour){-1, {0.0f, 0.0f, 0.0f}};
    if (sh->has_material) bump_param(d, sd, md, &sh->bump);
    /* ray differentials at camera hits: filtered textures, and pbrt-v3's bump step */
    sh->needs_differentials =
        sh->has_material &&
        (sh->bump.texture >= 0 || params_use_differentials(&s->textures, &sd->params) ||
         material_uses_differentials(d, &s->textures, md, 0));
    s->needs_differentials |= sh->needs_differentials;
    if (sh->has_material) {
      sh->general = 0;
      if (rs_material_build(d, md, &sd->params, &sh->gmat) && rs_material_needs_lobes(&sh->gmat))
        sh->general = 1;
    }
    if (sh->has_material && !material_is_supported(d, md)) {
      int seen = 0;
      for (int k = 0; k < warned_count; ++k) seen |= strcmp(warned[k], mtype) == 0;
      if (!seen) {
        if (warned_count < 32) snprintf(warned[warned_count++], 64, "%s", mtype);
        warn_fmt(warn, wu, "%s:%d: material \"%s\" not supported: rendered as matte with its Kd",
                 md->params.file ? md->params.file : p->file, md->params.line, mtype);
      }
    }
    int32_t group = 0;
    if (sd->object >= 0) {
      if (object_group[sd->object] == 0)
        CLR_CHECK(clr_tracer_new_group(s->tracer, &object_group[sd->object]));
      group = object_group[sd->object];
    }
    int index = s->shape_count - 1;
    const clr_transform *place = own_transform(sh); /* object to group */
    if (sh->moving) CLR_CHECK(clr_tracer_new_group(s->tracer, &group));
    if (sh->type == RS_SHAPE_MESH) {
      CLR_CHECK(clr_tracer_add_mesh(s->tracer, group, &sh->mesh, (uint32_t)index, NULL));
    } else if (sh->type == RS_SHAPE_QUADRIC) {
      float xf[16];
      rs_xform_m16(place, xf);
      CLR_CHECK(clr_tracer_add_quadric(s->tracer, group, xf, &sh->quadric, (uint32_t)index, NULL));
    } else if (sh->type == RS_SHAPE_DISK) {
      float xf[16];
      rs_xform_m16(place, xf);
      CLR_CHECK(clr_tracer_add_disk(s->tracer, group, xf, sh->height, sh->radius, sh->inner_radius,
                                    sh->phimax * 180.0f / RS_PI, (uint32_t)index, NULL));
    } else {
      float xf[16];
      rs_xform_m16(place, xf);
      if (sh->partial)
        CLR_CHECK(clr_tracer_add_partial_sphere(s->tracer, group, xf, sh->radius, sh->zmin,
                                                sh->zmax, sh->phimax * 180.0f / RS_PI,
                                                (uint32_t)index, NULL));
      else
        CLR_CHECK(clr_tracer_add_sphere(s->tracer, group, xf, sh->radius, (uint32_t)index, NULL));
    }
    if (sh->moving)
      CLR_CHECK(add_motion(s, d, &sd->object_to_world, &sd->object_to_world_end, group,
                           RS_MOVING_INSTANCE | (uint32_t)index));
    if (sd->area_light >= 0) {
      const clr_area_light_desc *a = &d->area_lights[sd->area_light];
      if (sh->type == RS_SHAPE_QUADRIC && sh->quadric.type != CLR_QUADRIC_CYLINDER) {
        /* pbrt-v3's Cone/Paraboloid/Hyperboloid::Sample stop with "not implemented" */
        return clr_set_last_error(CLR_ERROR_SCENE,
                                  "%s:%d: area light on a \"%s\": pbrt-v3 cannot sample it "
                                  "(its Sample is not implemented); a cylinder, disk, sphere or "
                                  "triangle mesh can emit",
                                  p->file ? p->file : "?", p->line, sd->type);
      } else if (strcmp(a->type, "diffuse") != 0 && strcmp(a->type, "area") != 0) {
        warn_fmt(warn, wu, "%s:%d: area light \"%s\" not supported: ignored", p->file, p->line,
                 a->type);
      } else {
        CLR_CHECK(rs_area_lights_add(&s->lights, &s->shapes[index], index, a));
      }
    }
  }
  return CLR_SUCCESS;
}

static clr_result build_instances(clr_render_scene *s, const clr_scene_desc *d,
                                  const int32_t *object_group) {
  s->instances = calloc((size_t)(d->instance_count ? d->instance_count : 1), sizeof *s->instances);
  if (!s->instances) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "instances");
  for (int i = 0; i < d->instance_count; ++i) {
    const clr_instance_desc *in = &d->instances[i];
    rs_instance *si = &s->instances[i];
    si->start = in->instance_to_world;
    si->end = in->instance_to_world_end;
    s->instance_count = i + 1;
    CLR_CHECK(
        check_motion(d, &si->start, &si->end, in->file, in->line, "ObjectInstance", &si->moving));
    if (object_group[in->object] == 0) continue; /* empty object */
    if (si->moving) {
      CLR_CHECK(add_motion(s, d, &si->start, &si->end, object_group[in->object], (uint32_t)i));
      continue;
    }
    float xf[16];
    rs_xform_m16(&si->start, xf);
    CLR_CHECK(clr_tracer_add_instance(s->tracer, object_group[in->object], xf, (uint32_t)i));
  }
  return CLR_SUCCESS;
}

#define MOTION_BOUND_STEPS 64

/* Grows lo..hi by box a..b moving from `start` to `end` over TransformTimes: its corners at 65
 * times of pbrt-v3's interpolation (pbrt-v3's MotionBounds solves for each corner's extremes;
 * a turn of angle A misses at most 1 - cos(A / 128) of its radius). */
static void grow_motion_bounds(clr_render_scene *s, const clr_scene_desc *d,
                               const clr_transform *start, const clr_transform *end,
                               const float a[3], const float b[3], float lo[3], float hi[3]) {
  rs_animated_transform at;
  int steps = memcmp(&start->m, &end->m, sizeof start->m) ? MOTION_BOUND_STEPS : 0;
  if (steps)
    rs_animated_transform_init(&at, start, end, d->transform_start_time, d->transform_end_time);
  for (int k = 0; k <= steps; ++k) {
    float f = steps ? (float)k / (float)steps : 0.0f, m[3], w[3];
    clr_transform x = *start;
    if (steps) rs_animated_transform_at(&at, (1.0f - f) * at.start_time + f * at.end_time, &x);
    for (int c = 0; c < 8; ++c) {
      m[0] = (c & 1) ? b[0] : a[0];
      m[1] = (c & 2) ? b[1] : a[1];
      m[2] = (c & 4) ? b[2] : a[2];
      clr_transform_point(&x, m, w);
      grow_bounds(s, lo, hi, w);
    }
  }
}

static void world_bounds(clr_render_scene *s, const clr_scene_desc *d) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int k = 0; k < s->shape_count; ++k) {
    float a[3], b[3];
    shape_bounds(&s->shapes[k], a, b);
    if (!(a[0] <= b[0])) continue;
    if (s->shapes[k].moving) {
      grow_motion_bounds(s, d, &s->shapes[k].object_to_world, &s->shapes[k].object_to_world_end, a,
                         b, lo, hi);
      continue;
    }
    if (!s->shapes[k].in_object) {
      grow_bounds(s, lo, hi, a);
      grow_bounds(s, lo, hi, b);
      continue;
    }
    for (int i = 0; i < d->instance_count; ++i)
      grow_motion_bounds(s, d, &s->instances[i].start, &s->instances[i].end, a, b, lo, hi);
  }
  if (!(lo[0] <= hi[0])) {
    lo[0] = lo[1] = lo[2] = 0;
    hi[0] = hi[1] = hi[2] = 0;
  }
  float diag[3];
  memcpy(s->world_lo, lo, sizeof lo);
  memcpy(s->world_hi, hi, sizeof hi);
  for (int i = 0; i < 3; ++i) {
    s->world_center[i] = 0.5f * (lo[i] + hi[i]);
    diag[i] = hi[i] - s->world_center[i];
  }
  s->lights.world_radius = rs_fmaxf(sqrtf(rs_dot(diag, diag)), 1e-3f);
}

clr_result clr_render_scene_build(const clr_scene_desc *d, clr_warn_fn warn, void *wu,
                                  clr_render_scene **out) {
  if (!d || !out) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_render_scene_build: NULL");
  *out = NULL;
  clr_render_scene *s = calloc(1, sizeof *s);
  int32_t *object_group = calloc((size_t)(d->object_count + 1), sizeof *object_group);
  if (!s || !object_group) {
    free(s);
    free(object_group);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "clr_render_scene_build");
  }
  clr_result r = clr_tracer_create(&s->tracer);
  if (r == CLR_SUCCESS) r = rs_camera_build(&s->camera, d, warn, wu);
  if (r == CLR_SUCCESS) r = rs_textures_build(&s->textures, d, warn, wu);
  s->reads_uv = s->textures.count > 0;
  if (r == CLR_SUCCESS) r = build_materials(s, d);
  /* sphere hits' (u, v) go unread: surfaces take them from the point (sphere_surface) */
  if (r == CLR_SUCCESS) r = clr_tracer_set_sphere_uv(s->tracer, 0);
  if (r == CLR_SUCCESS) r = build_shapes(s, d, warn, wu, object_group);
  if (r == CLR_SUCCESS) r = build_instances(s, d, object_group);
  if (r == CLR_SUCCESS) {
    world_bounds(s, d);
    /* lights after the bounds (distant and infinite lights use the world radius) */
    rs_light_set *ls = &s->lights;
    int area_lights = ls->count;
    rs_light *area = ls->items;
    ls->items = NULL;
    ls->count = 0;
    r = rs_lights_build(ls, d, warn, wu);
    if (r == CLR_SUCCESS && area_lights) {
      rs_light *all = realloc(ls->items, (size_t)(ls->count + area_lights) * sizeof *all);
      if (!all) {
        r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "lights");
      } else {
        memcpy(all + ls->count, area, (size_t)area_lights * sizeof *all);
        for (int k = 0; k < s->shape_count; ++k)
          if (s->shapes[k].first_light >= 0) s->shapes[k].first_light += ls->count;
        ls->items = all;
        ls->count += area_lights;
      }
    }
    free(area);
  }
  if (r == CLR_SUCCESS) {
    rs_light_set *ls = &s->lights;
    ls->infinite = calloc((size_t)(ls->count + 1), sizeof *ls->infinite);
    if (!ls->infinite) r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "lights");
    for (int k = 0; r == CLR_SUCCESS && k < ls->count; ++k)
      if (ls->items[k].type == RS_LIGHT_INFINITE) ls->infinite[ls->infinite_count++] = k;
  }
  if (r == CLR_SUCCESS) r = clr_tracer_commit(s->tracer);
  free(object_group);
  if (r != CLR_SUCCESS) {
    clr_render_scene_free(s);
    return r;
  }
  *out = s;
  return CLR_SUCCESS;
}

void clr_render_scene_free(clr_render_scene *s) {
  if (!s) return;
  if (s->tracer) clr_tracer_release(s->tracer);
  rs_textures_free(&s->textures);
  free(s->materials);
  for (int i = 0; i < s->shape_count; ++i) {
    clr_mesh_free(&s->shapes[i].mesh);
    free(s->shapes[i].tri_frames);
  }
  free(s->shapes);
  free(s->instances);
  rs_lights_free(&s->lights);
  free(s);
}

static void mesh_surface(const rs_shape *sh, const clr_hit *hit, float p[3], float n[3],
                         float ns[3], int *has_ns, float uv[2], float dpdu[3]) {
  const uint32_t *ix = sh->mesh.indices + 3 * hit->prim_id;
  const float *p0 = sh->mesh.p + 3 * ix[0], *p1 = sh->mesh.p + 3 * ix[1],
              *p2 = sh->mesh.p + 3 * ix[2];
  float b1 = hit->u, b2 = hit->v, b0 = 1.0f - b1 - b2;
  for (int i = 0; i < 3; ++i) p[i] = b0 * p0[i] + b1 * p1[i] + b2 * p2[i];
  float uv0[2], uv1[2], uv2[2];
  triangle_uvs(&sh->mesh, ix, uv0, uv1, uv2);
  for (int i = 0; i < 2; ++i) uv[i] = b0 * uv0[i] + b1 * uv1[i] + b2 * uv2[i];
  const float *frame = sh->tri_frames + 6 * (size_t)hit->prim_id;
  memcpy(n, frame, 3 * sizeof *n);
  memcpy(dpdu, frame + 3, 3 * sizeof *dpdu);
  *has_ns = rs_orient_triangle_normal(sh, ix, b0, b1, b2, n, ns);
}

/* pbrt-v3 Sphere's (u, v) at object point po (over the clipped ranges of a partial sphere). */
static void sphere_uv(const rs_shape *sh, const float po[3], float uv[2]) {
  float phi = atan2f(po[1], po[0]);
  if (phi < 0.0f) phi += 2.0f * RS_PI;
  float ct = rs_fminf(1.0f, rs_fmaxf(-1.0f, po[2] / sh->radius));
  uv[0] = phi / (2.0f * RS_PI);
  uv[1] = 1.0f - acosf(ct) / RS_PI;
  if (sh->partial) {
    float tz0 = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, sh->zmin / sh->radius)));
    float tz1 = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, sh->zmax / sh->radius)));
    uv[0] = phi / sh->phimax;
    uv[1] = (acosf(ct) - tz0) / (tz1 - tz0);
  }
}

/* uv (phi, theta) only when want_uv, else 0, 0 (nothing else depends on them). */
static void sphere_surface(const rs_shape *sh, const clr_transform *o2w, const clr_ray *ray,
                           const clr_hit *hit, int want_uv, float p[3], float n[3], float uv[2],
                           float dpdu[3]) {
  float pw[3] = {ray->ox + hit->t * ray->dx, ray->oy + hit->t * ray->dy,
                 ray->oz + hit->t * ray->dz};
  float po[3];
  clr_transform w2o = clr_transform_inverse(o2w);
  clr_transform_point(&w2o, pw, po);
  float len = sqrtf(rs_dot(po, po));
  if (len > 0.0f)
    for (int i = 0; i < 3; ++i) po[i] *= sh->radius / len;
  if (po[0] == 0.0f && po[1] == 0.0f) po[0] = 1e-5f * sh->radius;
  uv[0] = uv[1] = 0.0f;
  if (want_uv) sphere_uv(sh, po, uv);
  float du_o[3] = {-2.0f * RS_PI * po[1], 2.0f * RS_PI * po[0], 0.0f};
  if (sh->partial) {
    du_o[0] = -sh->phimax * po[1];
    du_o[1] = sh->phimax * po[0];
  }
  clr_transform_point(o2w, po, p);
  clr_transform_normal(o2w, po, n);
  rs_normalize(n);
  clr_transform_vector(o2w, du_o, dpdu);
  if (sh->flip_normal) rs_negate(n);
}

/* pbrt-v3 Disk::Intersect's interaction: the hit refined onto z = height, n the object z axis,
 * uv (phi / phimax, (radius - r) / (radius - innerradius)), dpdu (-phimax y, phimax x, 0). */
static void disk_surface(const rs_shape *sh, const clr_transform *o2w, const clr_ray *ray,
                         const clr_hit *hit, float p[3], float n[3], float uv[2], float dpdu[3]) {
  float pw[3] = {ray->ox + hit->t * ray->dx, ray->oy + hit->t * ray->dy,
                 ray->oz + hit->t * ray->dz};
  float po[3], z[3] = {0.0f, 0.0f, 1.0f};
  clr_transform w2o = clr_transform_inverse(o2w);
  clr_transform_point(&w2o, pw, po);
  po[2] = sh->height;
  float du_o[3] = {-sh->phimax * po[1], sh->phimax * po[0], 0.0f};
  clr_transform_point(o2w, po, p);
  clr_transform_normal(o2w, z, n);
  rs_normalize(n);
  clr_transform_vector(o2w, du_o, dpdu);
  uv[0] = hit->u;
  uv[1] = hit->v;
  if (sh->flip_normal) rs_negate(n);
}

/* pbrt-v3 Sphere's object-space dpdv at object point po. */
static void sphere_dpdv(const rs_shape *sh, const float po[3], float v[3]) {
  float r = sh->radius, zr = sqrtf(po[0] * po[0] + po[1] * po[1]);
  float ct = rs_fminf(1.0f, rs_fmaxf(-1.0f, po[2] / r)), st = sqrtf(rs_fmaxf(0.0f, 1.0f - ct * ct));
  float t0 = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, sh->partial ? sh->zmin / r : -1.0f)));
  float t1 = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, sh->partial ? sh->zmax / r : 1.0f)));
  float cp = zr > 0.0f ? po[0] / zr : 1.0f, sp = zr > 0.0f ? po[1] / zr : 0.0f;
  v[0] = (t1 - t0) * po[2] * cp;
  v[1] = (t1 - t0) * po[2] * sp;
  v[2] = -(t1 - t0) * r * st;
}

/* pbrt-v3's geometric dpdv at a hit (world point pw; n: the normal for a mesh whose (u, v) are
 * degenerate, where dpdv = n x dpdu). o2w: object (or mesh) to world. */
static void geometric_dpdv(const rs_shape *sh, const clr_transform *o2w, const clr_hit *hit,
                           const float pw[3], const float n[3], const float dpdu[3],
                           float dpdv[3]) {
  float po[3] = {0, 0, 0}, v[3] = {0, 0, 0};
  if (sh->type != RS_SHAPE_MESH) {
    clr_transform w2o = clr_transform_inverse(o2w);
    clr_transform_point(&w2o, pw, po);
  }
  if (sh->type == RS_SHAPE_MESH) {
    const uint32_t *ix = sh->mesh.indices + 3 * hit->prim_id;
    const float *p0 = sh->mesh.p + 3 * ix[0], *p1 = sh->mesh.p + 3 * ix[1],
                *p2 = sh->mesh.p + 3 * ix[2];
    float uv0[2], uv1[2], uv2[2];
    triangle_uvs(&sh->mesh, ix, uv0, uv1, uv2);
    float du02 = uv0[0] - uv2[0], dv02 = uv0[1] - uv2[1], du12 = uv1[0] - uv2[0],
          dv12 = uv1[1] - uv2[1], det = du02 * dv12 - dv02 * du12;
    if (fabsf(det) < 1e-8f) {
      rs_cross(n, dpdu, dpdv);
      return;
    }
    for (int i = 0; i < 3; ++i) v[i] = (-du12 * (p0[i] - p2[i]) + du02 * (p1[i] - p2[i])) / det;
  } else if (sh->type == RS_SHAPE_SPHERE) {
    sphere_dpdv(sh, po, v);
  } else if (sh->type == RS_SHAPE_DISK) {
    float r = sqrtf(po[0] * po[0] + po[1] * po[1]),
          k = r > 0.0f ? (sh->inner_radius - sh->radius) / r : 0.0f;
    v[0] = po[0] * k;
    v[1] = po[1] * k;
  } else {
    double pd[3] = {po[0], po[1], po[2]}, uvd[2], du[3], dv[3];
    clr_quadric_param(&sh->quadric, pd, uvd, du, dv);
    for (int i = 0; i < 3; ++i) v[i] = (float)dv[i];
  }
  clr_transform_vector(o2w, v, dpdv);
}

/* A sphere's dndu, dndv (n = p / r): its object-space dpdu, dpdv over r, as normals. */
static void sphere_normal_partials(const rs_shape *sh, const clr_transform *o2w, const float pw[3],
                                   float dndu[3], float dndv[3]) {
  float po[3], dv_o[3];
  clr_transform w2o = clr_transform_inverse(o2w);
  clr_transform_point(&w2o, pw, po);
  sphere_dpdv(sh, po, dv_o);
  float phimax = sh->partial ? sh->phimax : 2.0f * RS_PI, r = sh->radius;
  float du_o[3] = {-phimax * po[1] / r, phimax * po[0] / r, 0.0f};
  for (int i = 0; i < 3; ++i) dv_o[i] /= r;
  clr_transform_normal(o2w, du_o, dndu);
  clr_transform_normal(o2w, dv_o, dndv);
}

/* A quadric's dndu, dndv (pbrt-v3's Weingarten equations in its Intersect) at world point pw,
 * as normals; raw: the normal they are the partials of (dpdu x dpdv, unit in object space). */
static void quadric_normal_partials(const rs_shape *sh, const clr_transform *o2w, const float pw[3],
                                    float dndu[3], float dndv[3], float raw[3]) {
  float po[3];
  clr_transform w2o = clr_transform_inverse(o2w);
  clr_transform_point(&w2o, pw, po);
  double pd[3] = {po[0], po[1], po[2]}, du[3], dv[3], uv[2], pu[3], pv[3];
  clr_quadric_normal_partials(&sh->quadric, pd, du, dv);
  clr_quadric_param(&sh->quadric, pd, uv, pu, pv);
  float duf[3], dvf[3], pu_f[3], pv_f[3], n[3];
  for (int i = 0; i < 3; ++i) {
    duf[i] = (float)du[i], dvf[i] = (float)dv[i];
    pu_f[i] = (float)pu[i], pv_f[i] = (float)pv[i];
  }
  rs_cross(pu_f, pv_f, n);
  clr_transform_normal(o2w, duf, dndu);
  clr_transform_normal(o2w, dvf, dndv);
  clr_transform_normal(o2w, n, raw);
}

/* pbrt-v3 Triangle's dndu, dndv from the vertex normals (0 where the (u, v) are degenerate);
 * raw: the interpolated normal they are the partials of. Mesh space. */
static void mesh_normal_partials(const rs_shape *sh, const clr_hit *hit, float dndu[3],
                                 float dndv[3], float raw[3]) {
  const uint32_t *ix = sh->mesh.indices + 3 * hit->prim_id;
  const float *n0 = sh->mesh.n + 3 * ix[0], *n1 = sh->mesh.n + 3 * ix[1],
              *n2 = sh->mesh.n + 3 * ix[2];
  float uv0[2], uv1[2], uv2[2];
  triangle_uvs(&sh->mesh, ix, uv0, uv1, uv2);
  float b1 = hit->u, b2 = hit->v, b0 = 1.0f - b1 - b2;
  float du02 = uv0[0] - uv2[0], dv02 = uv0[1] - uv2[1], du12 = uv1[0] - uv2[0],
        dv12 = uv1[1] - uv2[1], det = du02 * dv12 - dv02 * du12;
  for (int i = 0; i < 3; ++i) {
    raw[i] = b0 * n0[i] + b1 * n1[i] + b2 * n2[i];
    float dn02 = n0[i] - n2[i], dn12 = n1[i] - n2[i];
    dndu[i] = fabsf(det) < 1e-8f ? 0.0f : (dv12 * dn02 - dv02 * dn12) / det;
    dndv[i] = fabsf(det) < 1e-8f ? 0.0f : (du02 * dn12 - du12 * dn02) / det;
  }
}

/* The shading normal's screen-space changes at a specular hit (pbrt-v3's shading.dndu dudx +
 * shading.dndv dvdx), oriented as ns: spheres, quadrics and meshes with normals; 0 for flat
 * shapes. o2w: the shape's object (or instance) to world. */
static void shading_normal_differentials(const rs_shape *sh, const clr_transform *o2w,
                                         const clr_hit *hit, const float pw[3],
                                         const rs_tex_ctx *tc, const float ns[3], float dndx[3],
                                         float dndy[3]) {
  float dndu[3] = {0, 0, 0}, dndv[3] = {0, 0, 0}, raw[3] = {0, 0, 0};
  if (sh->type == RS_SHAPE_SPHERE) {
    float po[3];
    clr_transform w2o = clr_transform_inverse(o2w);
    clr_transform_point(&w2o, pw, po);
    clr_transform_normal(o2w, po, raw);
    sphere_normal_partials(sh, o2w, pw, dndu, dndv);
  } else if (sh->type == RS_SHAPE_QUADRIC) {
    quadric_normal_partials(sh, o2w, pw, dndu, dndv, raw);
  } else if (sh->type == RS_SHAPE_MESH && sh->mesh.n) {
    float du[3], dv[3], r[3];
    mesh_normal_partials(sh, hit, du, dv, r);
    clr_transform_normal(o2w, du, dndu);
    clr_transform_normal(o2w, dv, dndv);
    clr_transform_normal(o2w, r, raw);
  }
  float sign = rs_dot(raw, ns) < 0.0f ? -1.0f : 1.0f;
  for (int i = 0; i < 3; ++i) {
    dndx[i] = sign * (dndu[i] * tc->dudx + dndv[i] * tc->dvdx);
    dndy[i] = sign * (dndu[i] * tc->dudy + dndv[i] * tc->dvdy);
  }
}

/* pbrt-v3's shading dpdv (and dndu, dndv for spheres and quadrics; 0 for the other shapes), for
 * Material::Bump; dpdu becomes the unit shading tangent for meshes with normals, as pbrt-v3's
 * Triangle sets it. geo_dpdv: the geometric dpdv. */
static void bump_partials(const rs_shape *sh, const clr_transform *o2w, const float pw[3],
                          const float ns[3], int has_ns, const float geo_dpdv[3], float dpdu[3],
                          float dpdv[3], float dndu[3], float dndv[3]) {
  memset(dndu, 0, 3 * sizeof(float));
  memset(dndv, 0, 3 * sizeof(float));
  if (sh->type == RS_SHAPE_MESH && has_ns) {
    float ss[3] = {dpdu[0], dpdu[1], dpdu[2]}, ts[3];
    rs_normalize(ss);
    rs_cross(ss, ns, ts);
    if (rs_dot(ts, ts) > 0.0f) {
      rs_normalize(ts);
      rs_cross(ts, ns, ss);
    }
    memcpy(dpdu, ss, sizeof ss);
    memcpy(dpdv, ts, sizeof ts);
    return;
  }
  memcpy(dpdv, geo_dpdv, 3 * sizeof(float));
  float raw[3];
  if (sh->type == RS_SHAPE_SPHERE) sphere_normal_partials(sh, o2w, pw, dndu, dndv);
  if (sh->type == RS_SHAPE_QUADRIC) quadric_normal_partials(sh, o2w, pw, dndu, dndv, raw);
}

/* A moving shape's object-to-world at the hit's time, as Embree placed it; 0 on failure. */
static int moving_transform(const clr_render_scene *s, const clr_hit *hit, clr_transform *out) {
  float m16[16], m[4][4];
  if (clr_tracer_instance_transform(s->tracer, hit->inst_id, hit->time, m16) != CLR_SUCCESS)
    return 0;
  memcpy(m, m16, sizeof m);
  return clr_transform_from_matrix(m, out);
}

void clr_render_scene_surface(const clr_render_scene *s, const clr_ray *ray, const clr_hit *hit,
                              clr_surface *out) {
  clr_render_scene_surface_differential(s, ray, NULL, hit, out);
}

/* A hit's point, normal n (oriented as the shape's), shading normal ns (when *has_ns), (u, v) (0, 0
 * for a sphere unless want_uv) and dpdu, all in world space; the instance's (or moving shape's)
 * transform, or NULL, is returned (*moved holds it when it moves). */
static const clr_transform *hit_geometry(const clr_render_scene *s, const rs_shape *sh,
                                         const clr_ray *ray, const clr_hit *hit, int want_uv,
                                         clr_transform *moved, float p[3], float n[3], float ns[3],
                                         int *has_ns, float uv[2], float dpdu[3]) {
  const clr_transform *inst = NULL;
  uint32_t inst_user = CLR_TRACER_INVALID_ID;
  if (hit->inst_id != CLR_TRACER_INVALID_ID &&
      clr_tracer_instance_info(s->tracer, hit->inst_id, NULL, &inst_user) == CLR_SUCCESS &&
      inst_user < (uint32_t)s->instance_count)
    inst = &s->instances[inst_user].start;
  int moves = sh->moving || (inst && s->instances[inst_user].moving);
  if (moves && moving_transform(s, hit, moved)) inst = moved;
  *has_ns = 0;
  if (sh->type == RS_SHAPE_MESH) {
    mesh_surface(sh, hit, p, n, ns, has_ns, uv, dpdu);
    if (inst) {
      float q[3];
      clr_transform_point(inst, p, q);
      memcpy(p, q, sizeof q);
      clr_transform_normal(inst, n, q);
      memcpy(n, q, sizeof q);
      rs_normalize(n);
      clr_transform_vector(inst, dpdu, q);
      memcpy(dpdu, q, sizeof q);
      if (*has_ns) {
        clr_transform_normal(inst, ns, q);
        memcpy(ns, q, 3 * sizeof *ns);
      }
    }
  } else if (sh->type == RS_SHAPE_DISK) {
    clr_transform o2w = inst ? clr_transform_compose(inst, own_transform(sh)) : *own_transform(sh);
    disk_surface(sh, &o2w, ray, hit, p, n, uv, dpdu);
  } else if (sh->type == RS_SHAPE_QUADRIC) {
    clr_transform o2w = inst ? clr_transform_compose(inst, own_transform(sh)) : *own_transform(sh);
    float pw[3] = {ray->ox + hit->t * ray->dx, ray->oy + hit->t * ray->dy,
                   ray->oz + hit->t * ray->dz};
    rs_quadric_surface(&sh->quadric, &o2w, pw, p, n, uv, dpdu);
    if (sh->flip_normal) rs_negate(n);
  } else {
    clr_transform o2w = inst ? clr_transform_compose(inst, own_transform(sh)) : *own_transform(sh);
    sphere_surface(sh, &o2w, ray, hit, want_uv, p, n, uv, dpdu);
  }
  return inst;
}

/* The geometric normal facing the side the ray came from. */
static void facing_normal(const clr_ray *ray, const float n[3], float ng[3]) {
  float wo[3] = {-ray->dx, -ray->dy, -ray->dz};
  memcpy(ng, n, 3 * sizeof *ng);
  if (rs_dot(ng, wo) < 0.0f) rs_negate(ng);
}

void clr_render_scene_surface_geometry(const clr_render_scene *s, const clr_ray *ray,
                                       const clr_hit *hit, clr_surface *out) {
  const rs_shape *sh = &s->shapes[hit->user_id];
  if (sh->has_material && sh->bump.texture >= 0) { /* a bump map may turn dpdu */
    clr_render_scene_surface_differential(s, ray, NULL, hit, out);
    return;
  }
  clr_transform moved;
  float ns[3];
  int has_ns;
  hit_geometry(s, sh, ray, hit, 0, &moved, out->p, out->n_geom, ns, &has_ns, out->uv, out->dpdu);
  facing_normal(ray, out->n_geom, out->ng);
  out->has_material = sh->has_material;
  out->time = ray->time;
}

void clr_render_scene_surface_differential(const clr_render_scene *s, const clr_ray *ray,
                                           const clr_ray_differential *rd, const clr_hit *hit,
                                           clr_surface *out) {
  const rs_shape *sh = &s->shapes[hit->user_id];
  clr_transform moved;
  /* written in place: copies of them reloaded 8 bytes at a time could not be forwarded from
   * hit_geometry's 4-byte stores */
  float *p = out->p, *n = out->n_geom, *uv = out->uv, *dpdu = out->dpdu, ns[3];
  int has_ns;
  const clr_transform *inst =
      hit_geometry(s, sh, ray, hit, s->reads_uv, &moved, p, n, ns, &has_ns, uv, dpdu);
  rs_tex_ctx tc = rs_tex_ctx_at(uv, p);
  int bump = sh->has_material && sh->bump.texture >= 0;
  float geo_dpdv[3];
  clr_transform o2w;
  int specular = sh->has_material && (sh->mirror || sh->glass || sh->general);
  int diffs = rd && rd->has && (sh->needs_differentials || specular);
  if (bump || diffs) {
    o2w = sh->type == RS_SHAPE_MESH ? clr_transform_identity() : *own_transform(sh);
    if (inst) o2w = clr_transform_compose(inst, &o2w);
    geometric_dpdv(sh, &o2w, hit, p, n, dpdu, geo_dpdv);
    if (diffs) rs_compute_differentials(rd, p, n, dpdu, geo_dpdv, &tc);
  }
  if (bump) { /* pbrt-v3 Material::Bump */
    float nsh[3], dpdv[3], dndu[3], dndv[3];
    memcpy(nsh, has_ns ? ns : n, sizeof nsh);
    rs_normalize(nsh);
    if (rs_dot(nsh, n) < 0.0f) rs_negate(nsh);
    bump_partials(sh, &o2w, p, nsh, has_ns, geo_dpdv, dpdu, dpdv, dndu, dndv);
    rs_bump(&s->textures, &sh->bump, &tc, n, dpdu, dpdv, dndu, dndv, nsh);
    memcpy(ns, nsh, sizeof ns);
    has_ns = 1;
  }
  float wo[3] = {-ray->dx, -ray->dy, -ray->dz};
  facing_normal(ray, n, out->ng);
  if (has_ns) {
    rs_normalize(ns);
    memcpy(out->ns, ns, sizeof ns);
    if (rs_dot(out->ns, out->ng) < 0.0f) rs_negate(out->ns);
  } else {
    memcpy(out->ns, out->ng, sizeof out->ns);
  }
  out->has_differentials = diffs && specular;
  if (out->has_differentials) {
    memcpy(out->dpdx, tc.dpdx, sizeof out->dpdx);
    memcpy(out->dpdy, tc.dpdy, sizeof out->dpdy);
    shading_normal_differentials(sh, &o2w, hit, p, &tc, out->ns, out->dndx, out->dndy);
  }
  out->has_material = sh->has_material;
  out->general = sh->has_material && sh->general;
  if (out->general) {
    rs_material_bsdf(&sh->gmat, s->materials, s->material_count, &s->textures, &tc, &out->bsdf);
    float nso[3] = {out->ns[0], out->ns[1], out->ns[2]}; /* pbrt: oriented as the shape's n */
    if (rs_dot(nso, n) < 0.0f) rs_negate(nso);
    clr_bsdf_set_frame(&out->bsdf, out->dpdu, nso, n);
  }
  out->on_a = sh->on_a;
  out->on_b = sh->on_b;
  out->mirror = sh->has_material && sh->mirror && !sh->general;
  out->glass = sh->has_material && sh->glass && !sh->general;
  out->metal = sh->has_material && sh->metal && !sh->general;
  memcpy(out->m_eta, sh->m_eta, sizeof out->m_eta);
  memcpy(out->m_k, sh->m_k, sizeof out->m_k);
  out->eta = sh->eta;
  out->kt[0] = out->kt[1] = out->kt[2] = 0.0f;
  if (out->glass) rs_colour_eval(&s->textures, &sh->kt, &tc, out->kt);
  out->plastic = sh->has_material && sh->plastic && !sh->general;
  out->alpha = sh->alpha;
  out->ks[0] = out->ks[1] = out->ks[2] = 0.0f;
  if (out->plastic) rs_colour_eval(&s->textures, &sh->ks, &tc, out->ks);
  out->kr[0] = out->kr[1] = out->kr[2] = 0.0f;
  if (out->mirror || out->glass) rs_colour_eval(&s->textures, &sh->kr, &tc, out->kr);
  if (sh->has_material && !sh->mirror && !sh->glass && !sh->metal && !sh->general)
    rs_colour_eval(&s->textures, &sh->kd, &tc, out->kd);
  else
    out->kd[0] = out->kd[1] = out->kd[2] = 0.0f;
  out->time = ray->time;
  out->area_light = -1;
  out->le[0] = out->le[1] = out->le[2] = 0.0f;
  if (sh->first_light >= 0) {
    out->area_light = sh->first_light + (sh->type == RS_SHAPE_MESH ? (int32_t)hit->prim_id : 0);
    const rs_light *l = &s->lights.items[out->area_light];
    if (l->two_sided || rs_dot(n, wo) > 0.0f) memcpy(out->le, l->colour, sizeof out->le);
  }
}
