/* Scene description: creation with pbrt-v3 defaults, lookups by name, release. */
#include "scene_desc.h"

#include <stdlib.h>
#include <string.h>

static char *copy_string(const char *s) {
  size_t n = strlen(s) + 1;
  char *c = malloc(n);
  if (c) memcpy(c, s, n);
  return c;
}

static bool init_option(clr_scene_option *option, const char *directive, const char *type) {
  option->type = copy_string(type);
  option->given = false;
  clr_params_init(&option->params, directive, option->type, NULL, 0);
  return option->type != NULL;
}

static bool add_default_material(clr_scene_desc *desc) {
  if (clr_grow_array((void **)&desc->materials, &desc->material_capacity, 1,
                     sizeof *desc->materials) != CLR_SUCCESS)
    return false;
  clr_material_desc *m = &desc->materials[0];
  memset(m, 0, sizeof *m);
  m->type = copy_string("matte");
  if (!m->type) return false;
  clr_params_init(&m->params, "Material", m->type, NULL, 0);
  desc->material_count = 1;
  return true;
}

clr_scene_desc *clr_scene_desc_create(void) {
  clr_scene_desc *desc = calloc(1, sizeof *desc);
  if (!desc) return NULL;
  desc->camera.type = copy_string("perspective");
  clr_params_init(&desc->camera.params, "Camera", desc->camera.type, NULL, 0);
  desc->camera.camera_to_world = clr_transform_identity();
  desc->camera.camera_to_world_end = clr_transform_identity();
  desc->transform_start_time = 0.0f;
  desc->transform_end_time = 1.0f;
  bool ok = desc->camera.type != NULL;
  ok = init_option(&desc->sampler, "Sampler", "halton") && ok;
  ok = init_option(&desc->film, "Film", "image") && ok;
  ok = init_option(&desc->filter, "PixelFilter", "box") && ok;
  ok = init_option(&desc->integrator, "Integrator", "path") && ok;
  ok = ok && add_default_material(desc);
  if (!ok) {
    clr_scene_desc_free(desc);
    return NULL;
  }
  return desc;
}

static void free_option(clr_scene_option *option) {
  free(option->type);
  clr_params_free(&option->params);
}

void clr_scene_desc_free(clr_scene_desc *desc) {
  if (!desc) return;
  free(desc->camera.type);
  clr_params_free(&desc->camera.params);
  free_option(&desc->sampler);
  free_option(&desc->film);
  free_option(&desc->filter);
  free_option(&desc->integrator);
  for (int i = 0; i < desc->material_count; ++i) {
    free(desc->materials[i].name);
    free(desc->materials[i].type);
    clr_params_free(&desc->materials[i].params);
  }
  free(desc->materials);
  for (int i = 0; i < desc->texture_count; ++i) {
    free(desc->textures[i].name);
    free(desc->textures[i].type);
    clr_params_free(&desc->textures[i].params);
  }
  free(desc->textures);
  for (int i = 0; i < desc->light_count; ++i) {
    free(desc->lights[i].type);
    clr_params_free(&desc->lights[i].params);
  }
  free(desc->lights);
  for (int i = 0; i < desc->area_light_count; ++i) {
    free(desc->area_lights[i].type);
    clr_params_free(&desc->area_lights[i].params);
  }
  free(desc->area_lights);
  for (int i = 0; i < desc->shape_count; ++i) {
    free(desc->shapes[i].type);
    clr_params_free(&desc->shapes[i].params);
  }
  free(desc->shapes);
  for (int i = 0; i < desc->object_count; ++i) {
    free(desc->objects[i].name);
    free(desc->objects[i].shapes);
  }
  free(desc->objects);
  free(desc->instances);
  for (int i = 0; i < desc->file_count; ++i) free(desc->files[i]);
  free(desc->files);
  free(desc);
}

const char *clr_scene_desc_add_file(clr_scene_desc *desc, const char *path) {
  if (clr_grow_array((void **)&desc->files, &desc->file_capacity, desc->file_count + 1,
                     sizeof *desc->files) != CLR_SUCCESS)
    return NULL;
  char *copy = copy_string(path);
  if (!copy) return NULL;
  desc->files[desc->file_count++] = copy;
  return copy;
}

int clr_scene_desc_find_named_material(const clr_scene_desc *desc, const char *name) {
  for (int i = desc->material_count - 1; i >= 0; --i)
    if (desc->materials[i].name && strcmp(desc->materials[i].name, name) == 0) return i;
  return -1;
}

int clr_scene_desc_find_object(const clr_scene_desc *desc, const char *name) {
  for (int i = desc->object_count - 1; i >= 0; --i)
    if (strcmp(desc->objects[i].name, name) == 0) return i;
  return -1;
}

int clr_scene_desc_report_unused(const clr_scene_desc *desc, clr_warn_fn warn, void *user) {
  int n = clr_params_report_unused(&desc->camera.params, warn, user);
  n += clr_params_report_unused(&desc->sampler.params, warn, user);
  n += clr_params_report_unused(&desc->film.params, warn, user);
  n += clr_params_report_unused(&desc->filter.params, warn, user);
  n += clr_params_report_unused(&desc->integrator.params, warn, user);
  for (int i = 0; i < desc->material_count; ++i)
    n += clr_params_report_unused(&desc->materials[i].params, warn, user);
  for (int i = 0; i < desc->texture_count; ++i)
    n += clr_params_report_unused(&desc->textures[i].params, warn, user);
  for (int i = 0; i < desc->light_count; ++i)
    n += clr_params_report_unused(&desc->lights[i].params, warn, user);
  for (int i = 0; i < desc->area_light_count; ++i)
    n += clr_params_report_unused(&desc->area_lights[i].params, warn, user);
  for (int i = 0; i < desc->shape_count; ++i)
    n += clr_params_report_unused(&desc->shapes[i].params, warn, user);
  return n;
}
