/* pbrt-v3 lights: point, spot, distant, infinite (constant), diffuse area lights on triangles
 * (one light per triangle), spheres, disks and cylinders. */
#ifndef CLR_RENDER_LIGHTS_H
#define CLR_RENDER_LIGHTS_H

#include <stdint.h>
#include "clrender/result.h"
#include "scene_desc.h"
#include "shapes.h"
#include "tracer.h"

typedef enum {
  RS_LIGHT_POINT,
  RS_LIGHT_SPOT,
  RS_LIGHT_DISTANT,
  RS_LIGHT_INFINITE,
  RS_LIGHT_AREA_TRIANGLE,
  RS_LIGHT_AREA_SPHERE,
  RS_LIGHT_AREA_DISK,
  RS_LIGHT_AREA_CYLINDER
} rs_light_type;

typedef struct rs_light {
  rs_light_type type;
  float colour[3];            /* I (point, spot) or L (others), scale applied */
  float pos[3];               /* point/spot position, sphere centre */
  float dir[3];               /* distant: unit direction toward the light */
  float to_light[3][3];       /* spot: world vector to light space; infinite: world to light */
  float light_to_world[3][3]; /* infinite */
  float cos_total, cos_falloff_start;
  int shape, prim, two_sided;
  float area;     /* triangle area; disk, cylinder: pbrt-v3 Disk/Cylinder::Area (object space) */
  float tri_n[3]; /* triangle: unit normal e1 x e2, before the shading normals' flip */
  float radius;   /* sphere */
  int nsamples;
  float power;
  struct rs_envmap *envmap; /* infinite, goniometric, projection "mapname" (owned), or NULL */
  int pattern;              /* point light: 0, 1 goniometric, 2 projection */
  float proj_tan;           /* projection: tan(fov / 2) */
  float proj_screen[4];     /* projection: screen bounds x0 x1 y0 y1 */
} rs_light;

/* Every light of the scene; infinite lights also listed apart (they are not contiguous). */
typedef struct rs_light_set {
  rs_light *items;
  int count;
  int *infinite;
  int infinite_count;
  float world_radius; /* distant and infinite lights reach past the scene's bounding sphere */
} rs_light_set;

/* One light sample from point p (with normal n, may be zero vector for none) using u in [0,1)^2:
 * direction wi (unit), incident radiance li (the integrator divides by pdf), pdf (solid angle;
 * for delta lights 1 and *is_delta = 1), and the shadow ray to test (origin offset from p along
 * the geometric normal, tfar short of the light). pdf == 0 means no contribution. */
typedef struct clr_light_sample {
  float wi[3];
  float li[3];
  float pdf;
  int32_t is_delta;
  clr_ray shadow;
} clr_light_sample;

/* The point Sample_Li picks on a triangle, disk or cylinder area light, which does not depend on
 * the reference point: its position, oriented normal and area-measure pdf, and what the light
 * sends toward the side n faces (both sides when two_sided). */
typedef struct clr_emitter_point {
  float p[3], n[3];
  float pdf;
  int32_t two_sided;
  float le[3];
} clr_emitter_point;

/* A triangle area light whose Sample_Li normal is its face normal (no shading normals): its
 * vertices, that normal as sample points get it (flipped with the shape), 1 / area, two_sided
 * and L; what integrators/light_wave.c samples. */
typedef struct clr_light_triangle {
  float p0[3], p1[3], p2[3], n[3];
  float inv_area;
  int32_t two_sided;
  float le[3];
} clr_light_triangle;

/* A point light without a pattern (goniometric, projection): its position and I; what
 * integrators/light_wave.c samples. */
typedef struct clr_light_point {
  float pos[3], intensity[3];
} clr_light_point;

/* The LightSource directives (needs set->world_radius). */
clr_result rs_lights_build(rs_light_set *set, const clr_scene_desc *d, clr_warn_fn warn, void *wu);
/* Adds the area lights of `shape` (index shape_index, geometry final) and sets its first_light. */
clr_result rs_area_lights_add(rs_light_set *set, rs_shape *shape, int shape_index,
                              const clr_area_light_desc *a);
void rs_lights_free(rs_light_set *set);
int rs_light_is_delta(const rs_light *l);
void rs_lights_sample(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                      const float p[3], const float ng[3], const float u[2], clr_light_sample *ls);
/* rs_lights_sample without the shadow ray (ls->shadow stays zero): the same wi, li and pdf. */
void rs_lights_sample_li(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                         const float p[3], const float u[2], clr_light_sample *ls);
/* Solid-angle pdf that light sampling from `p` would give direction wi that hits emitter light
 * `light` at distance t with the hit's geometric normal n_hit (unit). */
float rs_light_pdf(const rs_light_set *set, int light, const float p[3], const float wi[3], float t,
                   const float n_hit[3]);
/* 0 when ray certainly misses area light `light`'s own shape (pbrt-v3 Light::Pdf_Li is then 0
 * and the scene ray is not traced), else 1. */
/* The emitter point of light `light` for u; 0 (nothing written) for lights whose points depend on
 * the reference point or that have none. */
int rs_light_emitter_point(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                           const float u[2], clr_emitter_point *e);
/* Light `light`'s triangle; 0 (nothing written) for other lights and triangles with shading
 * normals. */
int rs_light_triangle(const rs_light_set *set, const rs_shape *shapes, int32_t light,
                      clr_light_triangle *t);
/* Light `light` as a plain point light; 0 (nothing written) for other lights. */
int rs_light_point(const rs_light_set *set, int32_t light, clr_light_point *p);
int rs_light_shape_may_hit(const rs_light_set *set, const rs_shape *shapes, int light,
                           const clr_ray *ray);
/* Radiance of an escaped ray from infinite light `light`. */
void rs_light_le(const rs_light_set *set, int light, const float d[3], float le[3]);
/* Radiance arriving along a ray that escaped the scene, summed over the infinite lights. */
void rs_lights_escaped(const rs_light_set *set, const clr_ray *ray, float le[3]);

#endif
