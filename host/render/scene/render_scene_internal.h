/* Private layout of clr_render_scene shared by camera.c, textures.c, lights.c and
 * render_scene.c. */
#ifndef CLR_RENDER_SCENE_INTERNAL_H
#define CLR_RENDER_SCENE_INTERNAL_H

#include "mesh.h"
#include "render_scene.h"

#define RS_PI 3.14159265358979323846f
#define RS_INV_PI 0.31830988618379067154f

/* A colour that is either constant or a spectrum texture (index into scene->textures). */
typedef struct rs_colour {
  int texture; /* -1: constant rgb */
  float rgb[3];
} rs_colour;

typedef enum { RS_TEX_CONSTANT, RS_TEX_CHECKER, RS_TEX_IMAGE } rs_texture_type;

typedef struct rs_texture {
  rs_texture_type type;
  float su, sv, du, dv; /* pbrt UVMapping2D */
  rs_colour value, tex1, tex2;
  int32_t width, height;
  float *rgb;   /* image texels, row 0 = top of the file */
  float scale;
  int nearest;  /* 1: nearest texel, 0: bilinear */
} rs_texture;

typedef enum { RS_CAMERA_PERSPECTIVE, RS_CAMERA_ORTHOGRAPHIC } rs_camera_type;

typedef struct rs_camera {
  rs_camera_type type;
  float fov, lens_radius, focal_distance, shutter_open, shutter_close;
  float frame_aspect;   /* <= 0: from the film resolution */
  float screen[4];      /* x0 x1 y0 y1; given when screen_given */
  int screen_given;
  clr_transform camera_to_world;
  clr_transform raster_to_camera;
} rs_camera;

typedef enum { RS_SHAPE_MESH, RS_SHAPE_SPHERE } rs_shape_type;

typedef struct rs_shape {
  rs_shape_type type;
  clr_mesh mesh;            /* world space, or object space for shapes of an object */
  float radius;
  clr_transform object_to_world; /* sphere: object to world (or to instance) */
  int flip_normal;          /* pbrt reverseOrientation ^ transformSwapsHandedness */
  int has_material;
  rs_colour kd;
  int first_light;          /* light index of triangle 0 / the sphere, -1 when not emitting */
  int in_object;
} rs_shape;

typedef enum {
  RS_LIGHT_POINT, RS_LIGHT_SPOT, RS_LIGHT_DISTANT, RS_LIGHT_INFINITE, RS_LIGHT_AREA_TRIANGLE,
  RS_LIGHT_AREA_SPHERE
} rs_light_type;

typedef struct rs_light {
  rs_light_type type;
  float colour[3];    /* I (point, spot) or L (others), scale applied */
  float pos[3];       /* point/spot position, sphere centre */
  float dir[3];       /* distant: unit direction toward the light */
  float to_light[3][3]; /* spot: world vector to light space; infinite: world to light */
  float light_to_world[3][3]; /* infinite */
  float cos_total, cos_falloff_start;
  int shape, prim, two_sided;
  float area;         /* triangle area */
  float radius;       /* sphere */
  int nsamples;
  float power;
} rs_light;

struct clr_render_scene {
  clr_tracer tracer;
  rs_camera camera;
  rs_texture *textures; /* one per desc texture (float textures left constant 0) */
  int texture_count;
  rs_shape *shapes;
  int shape_count;
  clr_transform *instances; /* instance to world */
  int instance_count;
  rs_light *lights;
  int light_count;
  int infinite_first, infinite_count; /* infinite lights are not contiguous: use the list */
  int *infinite;
  float world_center[3], world_radius;
};

/* textures.c */
clr_result rs_textures_build(clr_render_scene *s, const clr_scene_desc *d, clr_warn_fn warn,
                             void *wu);
void rs_textures_free(clr_render_scene *s);
/* Colour parameter `name` looked up in `first` then `second` (may be NULL), default def. */
void rs_colour_param(const clr_param_list *first, const clr_param_list *second, const char *name,
                     float def, rs_colour *out);
void rs_colour_eval(const clr_render_scene *s, const rs_colour *c, const float uv[2], float out[3]);

/* camera.c */
clr_result rs_camera_build(rs_camera *cam, const clr_scene_desc *d, clr_warn_fn warn, void *wu);

/* lights.c */
clr_result rs_lights_build(clr_render_scene *s, const clr_scene_desc *d, clr_warn_fn warn,
                           void *wu);
/* Adds the area lights of shape `shape_index` (after its geometry is final). */
clr_result rs_area_lights_add(clr_render_scene *s, int shape_index, const clr_area_light_desc *a);
/* Solid-angle pdf that light sampling from `p` would give direction wi that hits emitter light
 * `light` at distance t with the hit's geometric normal n_hit (unit). */
float rs_light_pdf(const clr_render_scene *s, int light, const float p[3], const float wi[3],
                   float t, const float n_hit[3]);
/* Radiance of an escaped ray from infinite light `light`. */
void rs_light_le(const clr_render_scene *s, int light, const float d[3], float le[3]);
int rs_light_is_delta(const rs_light *l);

/* small vector helpers */
static inline float rs_dot(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static inline void rs_cross(const float a[3], const float b[3], float r[3]) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}
void rs_normalize(float v[3]);
void rs_xform_m16(const clr_transform *t, float out[16]);

#endif
