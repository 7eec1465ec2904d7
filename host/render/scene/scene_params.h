/* Typed parameter lists of scene directives ("float radius" [1]) with pbrt-style lookups that
 * remember which parameters were used, so unused ones can be reported. */
#ifndef CLR_SCENE_PARAMS_H
#define CLR_SCENE_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include "clrender/result.h"
#include "grow.h"

/* Receives one warning message (no trailing newline). */
typedef void (*clr_warn_fn)(void *user, const char *message);
/* Default warning sink: prints "clrender: warning: MESSAGE" to stderr. */
void clr_warn_stderr(void *user, const char *message);

typedef enum clr_param_type {
  CLR_PARAM_INT,
  CLR_PARAM_FLOAT,
  CLR_PARAM_BOOL,
  CLR_PARAM_POINT2,
  CLR_PARAM_VECTOR2,
  CLR_PARAM_POINT3,    /* "point" or "point3" */
  CLR_PARAM_VECTOR3,   /* "vector" or "vector3" */
  CLR_PARAM_NORMAL3,   /* "normal" or "normal3" */
  CLR_PARAM_RGB,       /* "rgb" or "color" */
  CLR_PARAM_XYZ,       /* kept raw, warned about */
  CLR_PARAM_BLACKBODY, /* (temperature, scale) pairs, kept raw, warned about */
  CLR_PARAM_SPECTRUM,  /* (lambda, value) pairs or file names, kept raw, warned about */
  CLR_PARAM_STRING,
  CLR_PARAM_TEXTURE
} clr_param_type;

/* Namespaces of textures: a "texture" parameter may name one of each. */
typedef enum clr_texture_kind { CLR_TEXTURE_FLOAT, CLR_TEXTURE_SPECTRUM } clr_texture_kind;

typedef struct clr_param {
  clr_param_type type;
  char *name;
  int count;      /* scalars stored: floats, ints or strings (a point3 list of 2 points has 6) */
  float *floats;  /* FLOAT, POINT*, VECTOR*, NORMAL3, RGB, XYZ, BLACKBODY, numeric SPECTRUM */
  int *ints;      /* INT, BOOL (0 or 1) */
  char **strings; /* STRING, TEXTURE, SPECTRUM given as file names */
  int line;       /* where the parameter's declaration is */
  /* TEXTURE: indices into clr_scene_desc.textures of the float and spectrum textures of that
   * name visible where the directive was (-1 when none). */
  int float_texture;
  int spectrum_texture;
  bool used;
} clr_param;

/* Parameters of one directive. directive ("Shape") and type ("sphere") are static strings or
 * strings owned by the directive's description; file is owned by the scene description. */
typedef struct clr_param_list {
  clr_param *items;
  int count;
  int capacity;
  const char *directive;
  const char *type;
  const char *file;
  int line;
} clr_param_list;

/* Name of the type as declared ("point3", "rgb", ...). */
const char *clr_param_type_name(clr_param_type type);
/* Parses a declared type name of `length` bytes; false when unknown. */
bool clr_param_type_from_name(const char *name, size_t length, clr_param_type *type);
/* Scalars per item: 2 for point2/vector2/blackbody/numeric spectrum, 3 for point3/vector3/
 * normal3/rgb/xyz, 1 otherwise. */
int clr_param_type_arity(clr_param_type type);

void clr_params_init(clr_param_list *list, const char *directive, const char *type,
                     const char *file, int line);
/* Moves *param into the list (replacing a parameter of the same name and type, as pbrt-v3);
 * on failure *param is freed. Either way *param is left empty. */
clr_result clr_params_add(clr_param_list *list, clr_param *param);
void clr_params_free(clr_param_list *list);
void clr_param_free(clr_param *param);

/* Finds the parameter `name` of `type` (NULL if absent) and marks it used. */
const clr_param *clr_params_find(const clr_param_list *list, const char *name, clr_param_type type);

/* Single-value lookups: the value when the parameter exists with that type and exactly one
 * item (then it is marked used), else `def`. */
float clr_params_find_float(const clr_param_list *list, const char *name, float def);
int clr_params_find_int(const clr_param_list *list, const char *name, int def);
bool clr_params_find_bool(const clr_param_list *list, const char *name, bool def);
const char *clr_params_find_string(const clr_param_list *list, const char *name, const char *def);
/* Writes the single point3 / rgb value to out, or def. */
void clr_params_find_point3(const clr_param_list *list, const char *name, const float def[3],
                            float out[3]);
void clr_params_find_rgb(const clr_param_list *list, const char *name, const float def[3],
                         float out[3]);
/* Path of the file `name` a parameter of the list gives: as given when absolute or when the
 * list's scene file has no directory, else in that directory (pbrt-v3 ResolveFilename). */
void clr_params_resolve_path(const clr_param_list *list, const char *name, char *out, size_t size);
/* Texture name of a "texture" parameter, or def. */
const char *clr_params_find_texture(const clr_param_list *list, const char *name, const char *def);
/* Index (into clr_scene_desc.textures) of the texture of that kind referenced by parameter
 * `name`, or -1. */
int clr_params_find_texture_index(const clr_param_list *list, const char *name,
                                  clr_texture_kind kind);

/* Array lookups: pointer to the values and their count, or NULL with *count = 0. Counts are in
 * items: floats for find_floats, points for find_point3s (3 floats each), and so on. */
const float *clr_params_find_floats(const clr_param_list *list, const char *name, int *count);
const int *clr_params_find_ints(const clr_param_list *list, const char *name, int *count);
const float *clr_params_find_point2s(const clr_param_list *list, const char *name, int *count);
const float *clr_params_find_point3s(const clr_param_list *list, const char *name, int *count);
const float *clr_params_find_vector3s(const clr_param_list *list, const char *name, int *count);
const float *clr_params_find_normals(const clr_param_list *list, const char *name, int *count);

/* Warns once per parameter never looked up: "FILE:LINE: unused parameter 'foo' in Shape
 * 'sphere'" (every warning starts with FILE:LINE). warn NULL prints to stderr. Returns the number of warnings. */
int clr_params_report_unused(const clr_param_list *list, clr_warn_fn warn, void *user);
/* Marks every parameter used (a directive skipped whole was warned about once already). */
void clr_params_mark_used(const clr_param_list *list);

#endif
