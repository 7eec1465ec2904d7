/* In-memory description of a parsed pbrt-v3 scene, for a renderer to consume. Objects refer
 * to each other by index into the arrays of clr_scene_desc. Every type name and parameter list
 * is kept as written; the renderer interprets them and may call clr_scene_desc_report_unused
 * afterwards to warn about parameters it never looked up (as pbrt-v3 does). */
#ifndef CLR_SCENE_DESC_H
#define CLR_SCENE_DESC_H

#include <stdbool.h>
#include "scene_params.h"
#include "transform.h"

/* Camera, Sampler, Film, PixelFilter, Integrator. `given` is false when the directive was
 * absent and pbrt-v3's default type (RenderOptions) is used with no parameters. */
typedef struct clr_scene_option {
  char *type;
  clr_param_list params;
  bool given;
} clr_scene_option;

typedef struct clr_camera_desc {
  char *type; /* default "perspective" */
  clr_param_list params;
  bool given;
  /* Inverse of the CTM at the Camera directive (identity when absent). m_inv is world-to-camera.
   * Also the named coordinate system "camera". */
  clr_transform camera_to_world;
  clr_transform camera_to_world_end; /* at TransformTimes' end (ActiveTransform EndTime/All) */
} clr_camera_desc;

/* Material (anonymous, name NULL) or MakeNamedMaterial (type from its "string type").
 * materials[0] is the default: "matte" with no parameters, used before any Material. pbrt-v3
 * lets a Shape's own parameters override its material's (TextureParams): look a material
 * parameter up in the shape's list first. A "mix" material names its two named materials by
 * string: resolve them with clr_scene_desc_find_named_material. Type "none" or "" means no
 * material (pbrt-v3: invisible surface). */
typedef struct clr_material_desc {
  char *name;
  char *type;
  clr_param_list params;
} clr_material_desc;

typedef struct clr_texture_desc {
  char *name;
  clr_texture_kind kind; /* "float" or "spectrum"/"color" */
  char *type;            /* texture class: "checkerboard", "imagemap", ... */
  clr_param_list params; /* "texture" parameters here are resolved as in clr_param */
  clr_transform texture_to_world;
} clr_texture_desc;

typedef struct clr_light_desc {
  char *type;
  clr_param_list params;
  clr_transform light_to_world;
} clr_light_desc;

/* AreaLightSource; the light-to-world transform of each emitting shape is that shape's
 * object_to_world. Shared by all shapes declared while it was current. */
typedef struct clr_area_light_desc {
  char *type;
  clr_param_list params;
} clr_area_light_desc;

typedef struct clr_shape_desc {
  char *type;
  clr_param_list params;
  clr_transform object_to_world;     /* for shapes in an object: object-to-instance */
  clr_transform object_to_world_end; /* at TransformTimes' end: differs for moving shapes */
  bool reverse_orientation;
  int material;   /* index into materials (resolved NamedMaterial or current Material) */
  int area_light; /* index into area_lights, -1 when none (always -1 inside objects) */
  int object;     /* index into objects when declared inside ObjectBegin/End, else -1 */
} clr_shape_desc;

/* ObjectBegin/End: its shapes are not part of the scene by themselves. */
typedef struct clr_object_desc {
  char *name;
  int *shapes; /* indices into shapes */
  int shape_count;
  int shape_capacity;
} clr_object_desc;

typedef struct clr_instance_desc {
  int object; /* index into objects */
  clr_transform instance_to_world;
  clr_transform instance_to_world_end; /* at TransformTimes' end (ActiveTransform EndTime) */
  const char *file;                    /* where the ObjectInstance is */
  int line;
} clr_instance_desc;

typedef struct clr_scene_desc {
  clr_camera_desc camera;
  float transform_start_time, transform_end_time; /* TransformTimes (0 1) */
  clr_scene_option sampler;                       /* default "halton" */
  clr_scene_option film;                          /* default "image" */
  clr_scene_option filter;                        /* default "box" */
  clr_scene_option integrator;                    /* default "path" */

  clr_material_desc *materials;
  int material_count, material_capacity;
  clr_texture_desc *textures;
  int texture_count, texture_capacity;
  clr_light_desc *lights;
  int light_count, light_capacity;
  clr_area_light_desc *area_lights;
  int area_light_count, area_light_capacity;
  clr_shape_desc *shapes;
  int shape_count, shape_capacity;
  clr_object_desc *objects;
  int object_count, object_capacity;
  clr_instance_desc *instances;
  int instance_count, instance_capacity;

  /* Paths of the files read (the parameter lists' `file` point here). */
  char **files;
  int file_count, file_capacity;
} clr_scene_desc;

/* Empty description with pbrt-v3's default options and the default material; NULL when out of
 * memory. */
clr_scene_desc *clr_scene_desc_create(void);
void clr_scene_desc_free(clr_scene_desc *desc);

/* Stores a copy of `path` in desc->files and returns it (NULL when out of memory). */
const char *clr_scene_desc_add_file(clr_scene_desc *desc, const char *path);

/* Index of the last material made with MakeNamedMaterial `name`, or -1. */
int clr_scene_desc_find_named_material(const clr_scene_desc *desc, const char *name);
/* Index of the last object named `name`, or -1. */
int clr_scene_desc_find_object(const clr_scene_desc *desc, const char *name);

/* clr_params_report_unused over every parameter list of the scene; returns the count. */
int clr_scene_desc_report_unused(const clr_scene_desc *desc, clr_warn_fn warn, void *user);

#endif
