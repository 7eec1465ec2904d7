/* Typed parameter lists: storage, pbrt-v3 ParamSet-style lookups and unused reporting. */
#include "scene_params.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void clr_warn_stderr(void *user, const char *message) {
  (void)user;
  fprintf(stderr, "clrender: warning: %s\n", message);
}

static const struct {
  const char *name;
  clr_param_type type;
} type_names[] = {
    {"integer", CLR_PARAM_INT},         {"float", CLR_PARAM_FLOAT},
    {"bool", CLR_PARAM_BOOL},           {"point2", CLR_PARAM_POINT2},
    {"vector2", CLR_PARAM_VECTOR2},     {"point3", CLR_PARAM_POINT3},
    {"point", CLR_PARAM_POINT3},        {"vector3", CLR_PARAM_VECTOR3},
    {"vector", CLR_PARAM_VECTOR3},      {"normal3", CLR_PARAM_NORMAL3},
    {"normal", CLR_PARAM_NORMAL3},      {"rgb", CLR_PARAM_RGB},
    {"color", CLR_PARAM_RGB},           {"xyz", CLR_PARAM_XYZ},
    {"blackbody", CLR_PARAM_BLACKBODY}, {"spectrum", CLR_PARAM_SPECTRUM},
    {"string", CLR_PARAM_STRING},       {"texture", CLR_PARAM_TEXTURE},
};

const char *clr_param_type_name(clr_param_type type) {
  for (size_t i = 0; i < sizeof type_names / sizeof type_names[0]; ++i)
    if (type_names[i].type == type) return type_names[i].name;
  return "unknown";
}

bool clr_param_type_from_name(const char *name, size_t length, clr_param_type *type) {
  for (size_t i = 0; i < sizeof type_names / sizeof type_names[0]; ++i) {
    if (strlen(type_names[i].name) == length && memcmp(type_names[i].name, name, length) == 0) {
      *type = type_names[i].type;
      return true;
    }
  }
  return false;
}

int clr_param_type_arity(clr_param_type type) {
  switch (type) {
    case CLR_PARAM_POINT2:
    case CLR_PARAM_VECTOR2:
    case CLR_PARAM_BLACKBODY:
    case CLR_PARAM_SPECTRUM:
      return 2;
    case CLR_PARAM_POINT3:
    case CLR_PARAM_VECTOR3:
    case CLR_PARAM_NORMAL3:
    case CLR_PARAM_RGB:
    case CLR_PARAM_XYZ:
      return 3;
    default:
      return 1;
  }
}

void clr_params_init(clr_param_list *list, const char *directive, const char *type,
                     const char *file, int line) {
  memset(list, 0, sizeof *list);
  list->directive = directive;
  list->type = type;
  list->file = file;
  list->line = line;
}

void clr_param_free(clr_param *param) {
  if (param->strings)
    for (int i = 0; i < param->count; ++i) free(param->strings[i]);
  free(param->strings);
  free(param->floats);
  free(param->ints);
  free(param->name);
  memset(param, 0, sizeof *param);
}

void clr_params_free(clr_param_list *list) {
  for (int i = 0; i < list->count; ++i) clr_param_free(&list->items[i]);
  free(list->items);
  list->items = NULL;
  list->count = list->capacity = 0;
}

static int index_of(const clr_param_list *list, const char *name, clr_param_type type) {
  for (int i = list->count - 1; i >= 0; --i)
    if (list->items[i].type == type && strcmp(list->items[i].name, name) == 0) return i;
  return -1;
}

clr_result clr_params_add(clr_param_list *list, clr_param *param) {
  int existing = index_of(list, param->name, param->type);
  if (existing >= 0) {
    clr_param_free(&list->items[existing]);
    list->items[existing] = *param;
    memset(param, 0, sizeof *param);
    return CLR_SUCCESS;
  }
  clr_result r =
      clr_grow_array((void **)&list->items, &list->capacity, list->count + 1, sizeof *param);
  if (r != CLR_SUCCESS) {
    clr_param_free(param);
    return r;
  }
  list->items[list->count++] = *param;
  memset(param, 0, sizeof *param);
  return CLR_SUCCESS;
}

const clr_param *clr_params_find(const clr_param_list *list, const char *name,
                                 clr_param_type type) {
  if (!list || !name) return NULL;
  int i = index_of(list, name, type);
  if (i < 0) return NULL;
  list->items[i].used = true;
  return &list->items[i];
}

/* The parameter when it holds exactly one item of its type (then marked used). */
static const clr_param *find_one(const clr_param_list *list, const char *name,
                                 clr_param_type type) {
  if (!list || !name) return NULL;
  int i = index_of(list, name, type);
  if (i < 0 || list->items[i].count != clr_param_type_arity(type)) return NULL;
  list->items[i].used = true;
  return &list->items[i];
}

float clr_params_find_float(const clr_param_list *list, const char *name, float def) {
  const clr_param *p = find_one(list, name, CLR_PARAM_FLOAT);
  return p ? p->floats[0] : def;
}

int clr_params_find_int(const clr_param_list *list, const char *name, int def) {
  const clr_param *p = find_one(list, name, CLR_PARAM_INT);
  return p ? p->ints[0] : def;
}

bool clr_params_find_bool(const clr_param_list *list, const char *name, bool def) {
  const clr_param *p = find_one(list, name, CLR_PARAM_BOOL);
  return p ? p->ints[0] != 0 : def;
}

const char *clr_params_find_string(const clr_param_list *list, const char *name, const char *def) {
  const clr_param *p = find_one(list, name, CLR_PARAM_STRING);
  return p ? p->strings[0] : def;
}

static void find_triple(const clr_param_list *list, const char *name, clr_param_type type,
                        const float def[3], float out[3]) {
  const clr_param *p = find_one(list, name, type);
  const float *src = p ? p->floats : def;
  for (int i = 0; i < 3; ++i) out[i] = src[i];
}

void clr_params_find_point3(const clr_param_list *list, const char *name, const float def[3],
                            float out[3]) {
  find_triple(list, name, CLR_PARAM_POINT3, def, out);
}

void clr_params_find_rgb(const clr_param_list *list, const char *name, const float def[3],
                         float out[3]) {
  find_triple(list, name, CLR_PARAM_RGB, def, out);
}

void clr_params_resolve_path(const clr_param_list *list, const char *name, char *out, size_t size) {
  const char *slash = list->file ? strrchr(list->file, '/') : NULL;
  if (name[0] == '/' || !slash)
    snprintf(out, size, "%s", name);
  else
    snprintf(out, size, "%.*s/%s", (int)(slash - list->file), list->file, name);
}

const char *clr_params_find_texture(const clr_param_list *list, const char *name, const char *def) {
  const clr_param *p = find_one(list, name, CLR_PARAM_TEXTURE);
  return p ? p->strings[0] : def;
}

int clr_params_find_texture_index(const clr_param_list *list, const char *name,
                                  clr_texture_kind kind) {
  const clr_param *p = find_one(list, name, CLR_PARAM_TEXTURE);
  if (!p) return -1;
  return kind == CLR_TEXTURE_FLOAT ? p->float_texture : p->spectrum_texture;
}

static const clr_param *find_array(const clr_param_list *list, const char *name,
                                   clr_param_type type, int *count) {
  const clr_param *p = clr_params_find(list, name, type);
  if (count) *count = p ? p->count / clr_param_type_arity(type) : 0;
  return p;
}

const float *clr_params_find_floats(const clr_param_list *list, const char *name, int *count) {
  const clr_param *p = find_array(list, name, CLR_PARAM_FLOAT, count);
  return p ? p->floats : NULL;
}

const int *clr_params_find_ints(const clr_param_list *list, const char *name, int *count) {
  const clr_param *p = find_array(list, name, CLR_PARAM_INT, count);
  return p ? p->ints : NULL;
}

const float *clr_params_find_point2s(const clr_param_list *list, const char *name, int *count) {
  const clr_param *p = find_array(list, name, CLR_PARAM_POINT2, count);
  return p ? p->floats : NULL;
}

const float *clr_params_find_point3s(const clr_param_list *list, const char *name, int *count) {
  const clr_param *p = find_array(list, name, CLR_PARAM_POINT3, count);
  return p ? p->floats : NULL;
}

const float *clr_params_find_vector3s(const clr_param_list *list, const char *name, int *count) {
  const clr_param *p = find_array(list, name, CLR_PARAM_VECTOR3, count);
  return p ? p->floats : NULL;
}

const float *clr_params_find_normals(const clr_param_list *list, const char *name, int *count) {
  const clr_param *p = find_array(list, name, CLR_PARAM_NORMAL3, count);
  return p ? p->floats : NULL;
}

int clr_params_report_unused(const clr_param_list *list, clr_warn_fn warn, void *user) {
  if (!list) return 0;
  if (!warn) warn = clr_warn_stderr;
  int reported = 0;
  for (int i = 0; i < list->count; ++i) {
    const clr_param *p = &list->items[i];
    if (p->used) continue;
    char message[512];
    snprintf(message, sizeof message, "%s:%d: unused parameter '%s' in %s '%s'",
             list->file ? list->file : "<unknown>", p->line, p->name,
             list->directive ? list->directive : "directive", list->type ? list->type : "");
    warn(user, message);
    ++reported;
  }
  return reported;
}

void clr_params_mark_used(const clr_param_list *list) {
  if (!list) return;
  for (int i = 0; i < list->count; ++i) list->items[i].used = true;
}
