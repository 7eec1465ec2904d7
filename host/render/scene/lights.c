/* pbrt-v3 lights: point, spot, distant, infinite (constant), diffuse area lights on triangles
 * (one light per triangle, as pbrt-v3's per-triangle shapes), spheres (cone sampling), disks and
 * cylinders (sampled by area). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "blackbody.h"
#include "envmap.h"
#include "render_error.h"
#include "lights.h"
#include "vec3.h"
#include "float_minmax.h"

static float luminance(const float c[3]) {
  return 0.212671f * c[0] + 0.715160f * c[1] + 0.072169f * c[2];
}

static void mat3_vec(const float m[3][3], const float v[3], float out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
}

static void coordinate_system(const float v1[3], float v2[3], float v3[3]) {
  if (fabsf(v1[0]) > fabsf(v1[1])) {
    float l = sqrtf(v1[0] * v1[0] + v1[2] * v1[2]);
    v2[0] = -v1[2] / l;
    v2[1] = 0.0f;
    v2[2] = v1[0] / l;
  } else {
    float l = sqrtf(v1[1] * v1[1] + v1[2] * v1[2]);
    v2[0] = 0.0f;
    v2[1] = v1[2] / l;
    v2[2] = -v1[1] / l;
  }
  rs_cross(v1, v2, v3);
}

/* Adds l, which then owns its envmap (freed when l cannot be added). */
static clr_result push_light(rs_light_set *set, const rs_light *l) {
  rs_light *n = realloc(set->items, (size_t)(set->count + 1) * sizeof *n);
  if (!n) {
    rs_envmap_free(l->envmap);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "lights");
  }
  set->items = n;
  set->items[set->count++] = *l;
  return CLR_SUCCESS;
}

static void scaled_colour(const clr_param_list *p, const char *name, float out[3]) {
  float one[3] = {1, 1, 1}, sc[3];
  clr_params_find_rgb(p, name, one, out);
  const clr_param *bb = clr_params_find(p, name, CLR_PARAM_BLACKBODY);
  if (bb && bb->count >= 2) { /* pbrt-v3: (temperature, scale) pairs; a light uses the first */
    rs_blackbody_rgb(bb->floats[0], out);
    for (int i = 0; i < 3; ++i) out[i] *= bb->floats[1];
  }
  clr_params_find_rgb(p, "scale", one, sc);
  const clr_param *fs = clr_params_find(p, "scale", CLR_PARAM_FLOAT);
  if (fs && fs->count == 1) sc[0] = sc[1] = sc[2] = fs->floats[0];
  for (int i = 0; i < 3; ++i) out[i] *= sc[i];
}

static void linear_part(const float m[4][4], float out[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i][j] = m[i][j];
}

/* Loads a pattern light's image (none: a factor of 1), its screen and power, and adds it. */
static clr_result pattern_light(rs_light_set *set, rs_light *l, const clr_param_list *p) {
  const char *map = clr_params_find_string(p, "mapname", "");
  float aspect = 1.0f, average = 1.0f;
  if (map[0]) {
    char path[4096];
    clr_params_resolve_path(p, map, path, sizeof path);
    const float one[3] = {1, 1, 1};
    clr_result r = rs_envmap_load(path, one, &l->envmap);
    if (r != CLR_SUCCESS)
      return clr_set_last_error(
          r, "%s:%d: %s light \"mapname\" \"%s\": %s", p->file ? p->file : "?", p->line,
          l->pattern == 1 ? "goniometric" : "projection", path, clr_last_error_message());
    aspect = (float)l->envmap->w / (float)l->envmap->h;
    average = l->envmap->mean_y;
  }
  float x = aspect > 1.0f ? aspect : 1.0f, y = aspect > 1.0f ? 1.0f : 1.0f / aspect;
  l->proj_screen[0] = -x;
  l->proj_screen[1] = x;
  l->proj_screen[2] = -y;
  l->proj_screen[3] = y;
  if (l->pattern == 1) {
    l->power = 4.0f * RS_PI * luminance(l->colour) * average;
  } else {
    float tan_diag = l->proj_tan * sqrtf(1.0f + 1.0f / (aspect * aspect));
    l->power = luminance(l->colour) * average * 2.0f * RS_PI * (1.0f - cosf(atanf(tan_diag)));
  }
  return push_light(set, l);
}

/* pbrt-v3 GonioPhotometricLight::Scale and ProjectionLight::Projection for the world direction
 * w leaving the light. */
static float pattern_factor(const rs_light *l, const float w[3], float rgb[3]) {
  rgb[0] = rgb[1] = rgb[2] = 1.0f;
  float wl[3];
  mat3_vec(l->to_light, w, wl);
  rs_normalize(wl);
  if (l->pattern == 1) {
    float t = wl[1]; /* pbrt-v3 swaps y and z */
    wl[1] = wl[2];
    wl[2] = t;
    float phi = atan2f(wl[1], wl[0]);
    if (phi < 0.0f) phi += 2.0f * RS_PI;
    float theta = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, wl[2])));
    if (l->envmap) rs_envmap_lookup(l->envmap, phi / (2.0f * RS_PI), theta / RS_PI, rgb);
    return 1.0f;
  }
  if (wl[2] < 1e-3f) return 0.0f;
  float px = wl[0] / (wl[2] * l->proj_tan), py = wl[1] / (wl[2] * l->proj_tan);
  const float *b = l->proj_screen;
  if (px < b[0] || px > b[1] || py < b[2] || py > b[3]) return 0.0f;
  if (l->envmap)
    rs_envmap_lookup(l->envmap, (px - b[0]) / (b[1] - b[0]), (py - b[2]) / (b[3] - b[2]), rgb);
  return 1.0f;
}

static clr_result build_light(rs_light_set *set, const clr_light_desc *ld, clr_warn_fn warn,
                              void *wu) {
  const clr_param_list *p = &ld->params;
  rs_light l;
  memset(&l, 0, sizeof l);
  l.shape = -1;
  l.nsamples = clr_params_find_int(p, "nsamples", 1);
  if (l.nsamples < 1) l.nsamples = 1;
  float zero[3] = {0, 0, 0}, zdir[3] = {0, 0, 1}, from[3], to[3];
  const clr_transform *ctm = &ld->light_to_world;
  if (strcmp(ld->type, "point") == 0 || strcmp(ld->type, "spot") == 0) {
    int spot = ld->type[0] == 's';
    l.type = spot ? RS_LIGHT_SPOT : RS_LIGHT_POINT;
    scaled_colour(p, "I", l.colour);
    clr_params_find_point3(p, "from", zero, from);
    clr_transform_point(ctm, from, l.pos);
    l.power = 4.0f * RS_PI * luminance(l.colour);
    if (spot) {
      clr_params_find_point3(p, "to", zdir, to);
      float cone = clr_params_find_float(p, "coneangle", 30.0f);
      float delta = clr_params_find_float(p, "conedeltaangle", 5.0f); /* pbrt-v3's name */
      l.cos_total = cosf(cone * RS_PI / 180.0f);
      l.cos_falloff_start = cosf((cone - delta) * RS_PI / 180.0f);
      float dir[3] = {to[0] - from[0], to[1] - from[1], to[2] - from[2]}, du[3], dv[3];
      rs_normalize(dir);
      coordinate_system(dir, du, dv);
      float dir_to_z[3][3] = {
          {du[0], du[1], du[2]}, {dv[0], dv[1], dv[2]}, {dir[0], dir[1], dir[2]}};
      float inv[3][3];
      linear_part(ctm->m_inv, inv);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          l.to_light[i][j] =
              dir_to_z[i][0] * inv[0][j] + dir_to_z[i][1] * inv[1][j] + dir_to_z[i][2] * inv[2][j];
      l.power =
          luminance(l.colour) * 2.0f * RS_PI * (1.0f - 0.5f * (l.cos_falloff_start + l.cos_total));
    }
  } else if (strcmp(ld->type, "goniometric") == 0 || strcmp(ld->type, "projection") == 0) {
    /* pbrt-v3 GonioPhotometricLight / ProjectionLight: a point light at the CTM's origin whose
     * intensity is scaled by an image looked up by direction */
    l.type = RS_LIGHT_POINT;
    l.pattern = ld->type[0] == 'g' ? 1 : 2;
    scaled_colour(p, "I", l.colour);
    clr_transform_point(ctm, zero, l.pos);
    linear_part(ctm->m_inv, l.to_light);
    float fov = l.pattern == 2 ? clr_params_find_float(p, "fov", 45.0f) : 45.0f;
    l.proj_tan = tanf(fov * RS_PI / 360.0f);
    return pattern_light(set, &l, p);
  } else if (strcmp(ld->type, "distant") == 0) {
    l.type = RS_LIGHT_DISTANT;
    scaled_colour(p, "L", l.colour);
    clr_params_find_point3(p, "from", zero, from);
    clr_params_find_point3(p, "to", zdir, to);
    float w[3] = {from[0] - to[0], from[1] - to[1], from[2] - to[2]};
    clr_transform_vector(ctm, w, l.dir);
    rs_normalize(l.dir);
    l.power = luminance(l.colour) * RS_PI * set->world_radius * set->world_radius;
  } else if (strcmp(ld->type, "infinite") == 0) {
    l.type = RS_LIGHT_INFINITE;
    scaled_colour(p, "L", l.colour);
    const char *map = clr_params_find_string(p, "mapname", "");
    linear_part(ctm->m, l.light_to_world);
    linear_part(ctm->m_inv, l.to_light);
    l.power = luminance(l.colour) * RS_PI * set->world_radius * set->world_radius;
    if (map[0]) {
      char path[4096];
      clr_params_resolve_path(p, map, path, sizeof path);
      clr_result r = rs_envmap_load(path, l.colour, &l.envmap);
      if (r != CLR_SUCCESS)
        return clr_set_last_error(r, "%s:%d: infinite light \"mapname\" \"%s\": %s",
                                  p->file ? p->file : "?", p->line, path, clr_last_error_message());
      l.power = l.envmap->mean_y * RS_PI * set->world_radius * set->world_radius;
    }
  } else {
    if (warn) {
      char m[512];
      snprintf(m, sizeof m, "%s:%d: light \"%s\" not supported: ignored", p->file, p->line,
               ld->type);
      warn(wu, m);
    }
    return CLR_SUCCESS;
  }
  return push_light(set, &l);
}

clr_result rs_lights_build(rs_light_set *set, const clr_scene_desc *d, clr_warn_fn warn, void *wu) {
  for (int i = 0; i < d->light_count; ++i) CLR_CHECK(build_light(set, &d->lights[i], warn, wu));
  return CLR_SUCCESS;
}

void rs_lights_free(rs_light_set *set) {
  for (int i = 0; i < set->count; ++i) rs_envmap_free(set->items[i].envmap);
  free(set->items);
  free(set->infinite);
  set->items = NULL;
  set->infinite = NULL;
  set->count = set->infinite_count = 0;
}

static void tri_vertices(const rs_shape *sh, int prim, const float **p0, const float **p1,
                         const float **p2) {
  const uint32_t *ix = sh->mesh.indices + 3 * prim;
  *p0 = sh->mesh.p + 3 * ix[0];
  *p1 = sh->mesh.p + 3 * ix[1];
  *p2 = sh->mesh.p + 3 * ix[2];
}

clr_result rs_area_lights_add(rs_light_set *set, rs_shape *sh, int shape_index,
                              const clr_area_light_desc *a) {
  rs_light l;
  memset(&l, 0, sizeof l);
  scaled_colour(&a->params, "L", l.colour);
  l.two_sided = clr_params_find_bool(&a->params, "twosided", false);
  l.nsamples = clr_params_find_int(&a->params, "nsamples", 1);
  if (l.nsamples < 1) l.nsamples = 1;
  l.shape = shape_index;
  sh->first_light = set->count;
  float sides = l.two_sided ? 2.0f : 1.0f;
  if (sh->type == RS_SHAPE_SPHERE) {
    l.type = RS_LIGHT_AREA_SPHERE;
    float o[3] = {0, 0, 0};
    clr_transform_point(&sh->object_to_world, o, l.pos);
    l.radius = sh->radius;
    l.power = luminance(l.colour) * sides * RS_PI * 4.0f * RS_PI * l.radius * l.radius;
    return push_light(set, &l);
  }
  if (sh->type == RS_SHAPE_DISK) {
    l.type = RS_LIGHT_AREA_DISK;
    l.area = sh->phimax * 0.5f * (sh->radius * sh->radius - sh->inner_radius * sh->inner_radius);
    l.power = luminance(l.colour) * sides * RS_PI * l.area;
    return push_light(set, &l);
  }
  if (sh->type == RS_SHAPE_QUADRIC) { /* a cylinder: render_scene rejects the other quadrics */
    const clr_quadric *q = &sh->quadric;
    l.type = RS_LIGHT_AREA_CYLINDER;
    l.area = (float)((q->zmax - q->zmin) * q->radius * q->phimax);
    l.power = luminance(l.colour) * sides * RS_PI * l.area;
    return push_light(set, &l);
  }
  l.type = RS_LIGHT_AREA_TRIANGLE;
  for (int t = 0; t < sh->mesh.triangle_count; ++t) {
    const float *p0, *p1, *p2;
    tri_vertices(sh, t, &p0, &p1, &p2);
    float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]}, c[3];
    rs_cross(e1, e2, c);
    l.prim = t;
    l.area = 0.5f * sqrtf(rs_dot(c, c));
    memcpy(l.tri_n, c, sizeof c);
    rs_normalize(l.tri_n);
    l.power = luminance(l.colour) * sides * RS_PI * l.area;
    CLR_CHECK(push_light(set, &l));
  }
  return CLR_SUCCESS;
}

int rs_light_is_delta(const rs_light *l) {
  return l->type == RS_LIGHT_POINT || l->type == RS_LIGHT_SPOT || l->type == RS_LIGHT_DISTANT;
}

/* Area light emission toward w from a point with oriented normal n. */
static void area_emit(const rs_light *l, const float n[3], const float w[3], float li[3]) {
  if (l->two_sided || rs_dot(n, w) > 0.0f)
    memcpy(li, l->colour, 3 * sizeof(float));
  else
    li[0] = li[1] = li[2] = 0.0f;
}

/* Points on the sphere itself count as inside (pbrt-v3 tests its offset ray origin): cone
 * sampling from them would see the sphere from the wrong side. */
static int sphere_inside(float dc2, float r) { return dc2 <= r * r * (1.0f + 2e-4f); }

/* pbrt-v3 Cylinder::Sample(u): z uniform in [zmin, zmax], phi uniform in [0, phimax]; the
 * normal (x, y, 0) transformed, flipped as the shape's hit normals are. */
static void sample_cylinder(const rs_shape *sh, const float u[2], float pt[3], float n[3]) {
  const clr_quadric *q = &sh->quadric;
  float z = (float)(q->zmin + u[0] * (q->zmax - q->zmin)), phi = (float)(u[1] * q->phimax);
  float r = (float)q->radius;
  float po[3] = {r * cosf(phi), r * sinf(phi), z}, no[3] = {po[0], po[1], 0.0f};
  clr_transform_point(&sh->object_to_world, po, pt);
  clr_transform_normal(&sh->object_to_world, no, n);
  rs_normalize(n);
  if (sh->flip_normal) rs_negate(n);
}

/* Samples a point on the emitter: position, oriented normal, area-measure pdf or (cone)
 * solid-angle pdf with *solid = 1. */
static void sample_emitter(const rs_shape *shapes, const rs_light *l, const float ref[3],
                           const float u[2], float pt[3], float n[3], float *pdf, int *solid) {
  *solid = 0;
  if (l->type == RS_LIGHT_AREA_TRIANGLE) {
    const rs_shape *sh = &shapes[l->shape];
    const float *p0, *p1, *p2;
    tri_vertices(sh, l->prim, &p0, &p1, &p2);
    float su0 = sqrtf(u[0]);
    float b0 = 1.0f - su0, b1 = u[1] * su0, b2 = 1.0f - b0 - b1;
    for (int i = 0; i < 3; ++i) pt[i] = b0 * p0[i] + b1 * p1[i] + b2 * p2[i];
    memcpy(n, l->tri_n, sizeof l->tri_n);
    float ns[3];
    rs_orient_triangle_normal(sh, sh->mesh.indices + 3 * l->prim, b0, b1, b2, n, ns);
    *pdf = 1.0f / l->area;
    return;
  }
  if (l->type == RS_LIGHT_AREA_DISK) {
    /* pbrt-v3 Disk::Sample(u): the full disk of `radius` (innerradius and phimax are ignored
     * there too), pdf 1 / Area() */
    const rs_shape *sh = &shapes[l->shape];
    float dx, dy, z[3] = {0.0f, 0.0f, 1.0f};
    rs_concentric_disk(u[0], u[1], &dx, &dy);
    float po[3] = {dx * sh->radius, dy * sh->radius, sh->height};
    clr_transform_point(&sh->object_to_world, po, pt);
    clr_transform_normal(&sh->object_to_world, z, n);
    rs_normalize(n);
    if (sh->flip_normal) rs_negate(n);
    *pdf = 1.0f / l->area;
    return;
  }
  if (l->type == RS_LIGHT_AREA_CYLINDER) {
    sample_cylinder(&shapes[l->shape], u, pt, n);
    *pdf = 1.0f / l->area;
    return;
  }
  /* sphere */
  const rs_shape *sh = &shapes[l->shape];
  float wc[3] = {l->pos[0] - ref[0], l->pos[1] - ref[1], l->pos[2] - ref[2]};
  float dc2 = rs_dot(wc, wc), r = l->radius;
  if (sphere_inside(dc2, r)) {
    float z = 1.0f - 2.0f * u[0], rr = sqrtf(rs_fmaxf(0.0f, 1.0f - z * z)),
          phi = 2.0f * RS_PI * u[1];
    n[0] = rr * cosf(phi);
    n[1] = rr * sinf(phi);
    n[2] = z;
    for (int i = 0; i < 3; ++i) pt[i] = l->pos[i] + r * n[i];
    if (sh->flip_normal) rs_negate(n);
    *pdf = 1.0f / (4.0f * RS_PI * r * r);
    return;
  }
  float dc = sqrtf(dc2);
  for (int i = 0; i < 3; ++i) wc[i] /= dc;
  float wx[3], wy[3];
  coordinate_system(wc, wx, wy);
  float sin_max = r / dc, sin_max2 = sin_max * sin_max, inv_sin_max = 1.0f / sin_max;
  float cos_max = sqrtf(rs_fmaxf(0.0f, 1.0f - sin_max2));
  float cos_t = (cos_max - 1.0f) * u[0] + 1.0f, sin_t2 = 1.0f - cos_t * cos_t;
  if (sin_max2 < 0.00068523f) {
    sin_t2 = sin_max2 * u[0];
    cos_t = sqrtf(1.0f - sin_t2);
  }
  float cos_a = sin_t2 * inv_sin_max +
                cos_t * sqrtf(rs_fmaxf(0.0f, 1.0f - sin_t2 * inv_sin_max * inv_sin_max));
  float sin_a = sqrtf(rs_fmaxf(0.0f, 1.0f - cos_a * cos_a)), phi = u[1] * 2.0f * RS_PI;
  for (int i = 0; i < 3; ++i)
    n[i] = -(sin_a * cosf(phi) * wx[i] + sin_a * sinf(phi) * wy[i] + cos_a * wc[i]);
  for (int i = 0; i < 3; ++i) pt[i] = l->pos[i] + r * n[i];
  if (sh->flip_normal) rs_negate(n);
  *pdf = 1.0f / (2.0f * RS_PI * (1.0f - cos_max));
  *solid = 1;
}

static float spot_falloff(const rs_light *l, const float w[3]) {
  float wl[3];
  mat3_vec(l->to_light, w, wl);
  rs_normalize(wl);
  float c = wl[2];
  if (c < l->cos_total) return 0.0f;
  if (c >= l->cos_falloff_start) return 1.0f;
  float d = (c - l->cos_total) / (l->cos_falloff_start - l->cos_total);
  return (d * d) * (d * d);
}

/* Shadow ray from p (offset along ng toward the target side) to `target`. */
static void shadow_to(const float p[3], const float ng[3], const float target[3], clr_ray *r) {
  float o[3], d[3];
  float side =
      (ng[0] * (target[0] - p[0]) + ng[1] * (target[1] - p[1]) + ng[2] * (target[2] - p[2])) < 0
          ? -1.0f
          : 1.0f;
  float e = rs_spawn_eps(p) * side;
  for (int i = 0; i < 3; ++i) o[i] = p[i] + ng[i] * e;
  for (int i = 0; i < 3; ++i) d[i] = target[i] - o[i];
  float dist = sqrtf(rs_dot(d, d));
  r->ox = o[0];
  r->oy = o[1];
  r->oz = o[2];
  r->dx = d[0] / dist;
  r->dy = d[1] / dist;
  r->dz = d[2] / dist;
  r->tnear = 0.0f;
  r->tfar = dist * (1.0f - 1e-3f);
}

/* Sample_Li without the shadow ray: wi, li, pdf and is_delta; the point to aim a shadow ray at
 * in target. 0 when the sample is unusable (ls is then all zero but is_delta). */
static int sample_li(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                     const float p[3], const float u[2], clr_light_sample *ls, float target[3]) {
  const rs_light *l = &set->items[light];
  memset(ls, 0, sizeof *ls);
  ls->is_delta = rs_light_is_delta(l);
  switch (l->type) {
    case RS_LIGHT_POINT:
    case RS_LIGHT_SPOT: {
      float d[3] = {l->pos[0] - p[0], l->pos[1] - p[1], l->pos[2] - p[2]};
      float d2 = rs_dot(d, d);
      if (!(d2 > 0.0f)) return 0;
      memcpy(ls->wi, d, sizeof d);
      rs_normalize(ls->wi);
      float f = 1.0f, pat[3] = {1.0f, 1.0f, 1.0f};
      if (l->type == RS_LIGHT_SPOT) {
        float w[3] = {-ls->wi[0], -ls->wi[1], -ls->wi[2]};
        f = spot_falloff(l, w);
      } else if (l->pattern) {
        float w[3] = {-ls->wi[0], -ls->wi[1], -ls->wi[2]};
        f = pattern_factor(l, w, pat);
      }
      for (int i = 0; i < 3; ++i) ls->li[i] = l->colour[i] * pat[i] * f / d2;
      ls->pdf = 1.0f;
      memcpy(target, l->pos, 3 * sizeof(float));
      break;
    }
    case RS_LIGHT_DISTANT:
      memcpy(ls->wi, l->dir, sizeof ls->wi);
      memcpy(ls->li, l->colour, sizeof ls->li);
      ls->pdf = 1.0f;
      for (int i = 0; i < 3; ++i) target[i] = p[i] + l->dir[i] * 2.0f * set->world_radius;
      break;
    case RS_LIGHT_INFINITE: {
      float uv[2] = {u[0], u[1]}, map_pdf = 1.0f;
      if (l->envmap && !((map_pdf = rs_envmap_sample(l->envmap, u, uv)) > 0.0f)) return 0;
      float theta = uv[1] * RS_PI, phi = uv[0] * 2.0f * RS_PI;
      float st = sinf(theta), ct = cosf(theta);
      if (st == 0.0f) return 0;
      float wl[3] = {st * cosf(phi), st * sinf(phi), ct};
      mat3_vec(l->light_to_world, wl, ls->wi);
      rs_normalize(ls->wi);
      ls->pdf = map_pdf / (2.0f * RS_PI * RS_PI * st);
      if (l->envmap)
        rs_envmap_lookup(l->envmap, uv[0], uv[1], ls->li);
      else
        memcpy(ls->li, l->colour, sizeof ls->li);
      for (int i = 0; i < 3; ++i) target[i] = p[i] + ls->wi[i] * 2.0f * set->world_radius;
      break;
    }
    default: {
      float pt[3], n[3], pdf;
      int solid;
      sample_emitter(shapes, l, p, u, pt, n, &pdf, &solid);
      float d[3] = {pt[0] - p[0], pt[1] - p[1], pt[2] - p[2]};
      float d2 = rs_dot(d, d);
      if (!(d2 > 0.0f)) return 0;
      float dist = sqrtf(d2);
      for (int i = 0; i < 3; ++i) ls->wi[i] = d[i] / dist;
      if (!solid) {
        float c = fabsf(rs_dot(n, ls->wi));
        pdf = c > 0.0f ? pdf * d2 / c : 0.0f;
        if (!isfinite(pdf)) pdf = 0.0f;
      }
      ls->pdf = pdf;
      float w[3] = {-ls->wi[0], -ls->wi[1], -ls->wi[2]};
      area_emit(l, n, w, ls->li);
      memcpy(target, pt, 3 * sizeof(float));
      break;
    }
  }
  return 1;
}

void rs_lights_sample(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                      const float p[3], const float ng[3], const float u[2], clr_light_sample *ls) {
  float target[3];
  if (sample_li(set, shapes, light, p, u, ls, target)) shadow_to(p, ng, target, &ls->shadow);
}

void rs_lights_sample_li(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                         const float p[3], const float u[2], clr_light_sample *ls) {
  float target[3];
  sample_li(set, shapes, light, p, u, ls, target);
}

int rs_light_emitter_point(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                           const float u[2], clr_emitter_point *e) {
  const rs_light *l = &set->items[light];
  if (l->type != RS_LIGHT_AREA_TRIANGLE && l->type != RS_LIGHT_AREA_DISK &&
      l->type != RS_LIGHT_AREA_CYLINDER)
    return 0;
  int solid;
  sample_emitter(shapes, l, NULL, u, e->p, e->n, &e->pdf, &solid);
  e->two_sided = l->two_sided;
  memcpy(e->le, l->colour, sizeof e->le);
  return 1;
}

int rs_light_triangle(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                      clr_light_triangle *t) {
  const rs_light *l = &set->items[light];
  if (l->type != RS_LIGHT_AREA_TRIANGLE || shapes[l->shape].mesh.n) return 0;
  const rs_shape *sh = &shapes[l->shape];
  const float *p0, *p1, *p2;
  tri_vertices(sh, l->prim, &p0, &p1, &p2);
  for (int i = 0; i < 3; ++i) {
    t->p0[i] = p0[i];
    t->p1[i] = p1[i];
    t->p2[i] = p2[i];
    t->n[i] = sh->flip_normal ? -l->tri_n[i] : l->tri_n[i]; /* as sample_emitter's */
    t->le[i] = l->colour[i];
  }
  t->inv_area = 1.0f / l->area;
  t->two_sided = l->two_sided;
  return 1;
}

int rs_light_point(const rs_light_set *set, int32_t light, clr_light_point *p) {
  const rs_light *l = &set->items[light];
  if (l->type != RS_LIGHT_POINT || l->pattern) return 0;
  memcpy(p->pos, l->pos, sizeof p->pos);
  memcpy(p->intensity, l->colour, sizeof p->intensity);
  return 1;
}

/* pbrt-v3's lat-long coordinates of a light-space unit direction: (phi / 2 pi, theta / pi). */
static void envmap_coords(const float w[3], float *s, float *t) {
  float phi = atan2f(w[1], w[0]);
  if (phi < 0.0f) phi += 2.0f * RS_PI;
  *s = phi / (2.0f * RS_PI);
  *t = acosf(rs_fminf(1.0f, rs_fmaxf(-1.0f, w[2]))) / RS_PI;
}

float rs_light_pdf(const rs_light_set *set, int light, const float p[3], const float wi[3], float t,
                   const float n_hit[3]) {
  const rs_light *l = &set->items[light];
  if (l->type == RS_LIGHT_INFINITE) {
    float wl[3];
    mat3_vec(l->to_light, wi, wl);
    rs_normalize(wl);
    float ct = rs_fminf(1.0f, rs_fmaxf(-1.0f, wl[2]));
    float st = sqrtf(rs_fmaxf(0.0f, 1.0f - ct * ct)), map_pdf = 1.0f;
    if (l->envmap) {
      float s_, t_;
      envmap_coords(wl, &s_, &t_);
      map_pdf = rs_envmap_pdf(l->envmap, s_, t_);
    }
    return st == 0.0f ? 0.0f : map_pdf / (2.0f * RS_PI * RS_PI * st);
  }
  if (l->type == RS_LIGHT_AREA_SPHERE) {
    float wc[3] = {l->pos[0] - p[0], l->pos[1] - p[1], l->pos[2] - p[2]};
    float dc2 = rs_dot(wc, wc);
    if (!sphere_inside(dc2, l->radius)) {
      float sin2 = l->radius * l->radius / dc2, cos_max = sqrtf(rs_fmaxf(0.0f, 1.0f - sin2));
      return 1.0f / (2.0f * RS_PI * (1.0f - cos_max));
    }
    float c = fabsf(rs_dot(n_hit, wi));
    return c > 0.0f ? t * t / (c * 4.0f * RS_PI * l->radius * l->radius) : 0.0f;
  }
  if (l->type == RS_LIGHT_AREA_TRIANGLE || l->type == RS_LIGHT_AREA_DISK ||
      l->type == RS_LIGHT_AREA_CYLINDER) {
    float c = fabsf(rs_dot(n_hit, wi));
    return c > 0.0f ? t * t / (c * l->area) : 0.0f;
  }
  return 0.0f;
}

void rs_light_le(const rs_light_set *set, int light, const float d[3], float le[3]) {
  const rs_light *l = &set->items[light];
  if (l->type == RS_LIGHT_INFINITE && l->envmap) {
    float wl[3], s_, t_;
    mat3_vec(l->to_light, d, wl);
    rs_normalize(wl);
    envmap_coords(wl, &s_, &t_);
    rs_envmap_lookup(l->envmap, s_, t_, le);
  } else if (l->type == RS_LIGHT_INFINITE)
    memcpy(le, l->colour, 3 * sizeof(float));
  else
    le[0] = le[1] = le[2] = 0.0f;
}

void rs_lights_escaped(const rs_light_set *set, const clr_ray *ray, float le[3]) {
  le[0] = le[1] = le[2] = 0.0f;
  float d[3] = {ray->dx, ray->dy, ray->dz}, c[3];
  for (int i = 0; i < set->infinite_count; ++i) {
    rs_light_le(set, set->infinite[i], d, c);
    for (int k = 0; k < 3; ++k) le[k] += c[k];
  }
}

/* The ray's origin and direction in the shape's object space. */
static inline void ray_to_object(const rs_shape *sh, const clr_ray *ray, float o[3], float d[3]) {
  clr_transform w2o = clr_transform_inverse(&sh->object_to_world);
  float ow[3] = {ray->ox, ray->oy, ray->oz}, dw[3] = {ray->dx, ray->dy, ray->dz};
  clr_transform_point(&w2o, ow, o);
  clr_transform_vector(&w2o, dw, d);
}

/* pbrt-v3 Light::Pdf_Li asks the light's own shape first: Shape::Pdf(ref, wi) intersects the ray
 * with that shape only (a triangle here) and is 0 when it misses; a sphere seen from outside
 * returns its cone pdf without a test, and from on or inside it the ray is intersected with the
 * sphere (an outward ray from its surface misses). Double-precision
 * Moller-Trumbore with closed edges. */
int rs_light_shape_may_hit(const rs_light_set *set, const rs_shape *shapes, int light,
                           const clr_ray *ray) {
  const rs_light *l = &set->items[light];
  if (l->type == RS_LIGHT_AREA_SPHERE) {
    double oc[3] = {(double)ray->ox - l->pos[0], (double)ray->oy - l->pos[1],
                    (double)ray->oz - l->pos[2]};
    double c2 = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2], r2 = (double)l->radius * l->radius;
    /* pbrt-v3 offsets the reference point toward the centre: a point on the sphere counts as
     * inside; the ray origin here is already offset outward by the spawn epsilon */
    float o[3] = {ray->ox, ray->oy, ray->oz};
    double on = (double)l->radius + 2.0 * rs_spawn_eps(o);
    if (c2 > on * on) return 1; /* outside: the cone pdf, no test */
    /* on or inside the sphere: Shape::Pdf intersects the ray with it */
    double b = oc[0] * ray->dx + oc[1] * ray->dy + oc[2] * ray->dz;
    double dd = (double)ray->dx * ray->dx + (double)ray->dy * ray->dy + (double)ray->dz * ray->dz;
    double disc = b * b - dd * (c2 - r2);
    if (disc < 0.0) return 0;
    double t = (-b + sqrt(disc)) / dd; /* the far root: the only one ahead when inside */
    return t > (double)ray->tnear && t > 1e-6 * l->radius && t < (double)ray->tfar &&
           (c2 < r2 || b < 0.0);
  }
  if (l->type == RS_LIGHT_AREA_DISK) { /* Disk::Intersect in object space */
    const rs_shape *sh = &shapes[l->shape];
    float o[3], d[3];
    ray_to_object(sh, ray, o, d);
    if (d[2] == 0.0f) return 0;
    double t = ((double)sh->height - o[2]) / d[2];
    if (!(t > 0.0) || !(t > (double)ray->tnear) || !(t < (double)ray->tfar)) return 0;
    double x = o[0] + t * d[0], y = o[1] + t * d[1], r2 = x * x + y * y;
    if (r2 > (double)sh->radius * sh->radius || r2 < (double)sh->inner_radius * sh->inner_radius)
      return 0;
    double phi = atan2(y, x);
    if (phi < 0.0) phi += 2.0 * RS_PI;
    return phi <= (double)sh->phimax * (1.0 + 1e-6);
  }
  if (l->type == RS_LIGHT_AREA_CYLINDER) { /* Cylinder::Intersect in object space */
    const rs_shape *sh = &shapes[l->shape];
    float o[3], d[3];
    ray_to_object(sh, ray, o, d);
    double od[3] = {o[0], o[1], o[2]}, dd[3] = {d[0], d[1], d[2]}, t;
    return clr_quadric_intersect(&sh->quadric, od, dd, ray->tfar, &t) && t >= (double)ray->tnear;
  }
  if (l->type != RS_LIGHT_AREA_TRIANGLE) return 1;
  const float *p0, *p1, *p2;
  tri_vertices(&shapes[l->shape], l->prim, &p0, &p1, &p2);
  double o[3] = {ray->ox, ray->oy, ray->oz}, d[3] = {ray->dx, ray->dy, ray->dz};
  double e1[3], e2[3], s[3], pv[3], q[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = (double)p1[i] - p0[i];
    e2[i] = (double)p2[i] - p0[i];
    s[i] = o[i] - p0[i];
  }
  pv[0] = d[1] * e2[2] - d[2] * e2[1];
  pv[1] = d[2] * e2[0] - d[0] * e2[2];
  pv[2] = d[0] * e2[1] - d[1] * e2[0];
  double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
  if (det == 0.0) return 0;
  double inv = 1.0 / det, u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) * inv;
  if (u < 0.0 || u > 1.0) return 0;
  q[0] = s[1] * e1[2] - s[2] * e1[1];
  q[1] = s[2] * e1[0] - s[0] * e1[2];
  q[2] = s[0] * e1[1] - s[1] * e1[0];
  double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
  if (v < 0.0 || u + v > 1.0) return 0;
  double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
  return t > (double)ray->tnear && t < (double)ray->tfar;
}
