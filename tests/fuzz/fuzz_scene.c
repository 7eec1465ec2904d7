/* Fuzz target: pbrt-v3 scene text -> tokenizer + parser (clr_scene_parse_string) -> film
 * settings -> scene build (Embree geometry, PLY/loopsubdiv meshes, textures, lights) ->
 * integrator, as clrender render does before it opens the OpenCL device. */
#include <string.h>
#include "fuzz_common.h"
#include "integrator.h"
#include "loop_subdiv.h"
#include "render_scene.h"
#include "scene_parser.h"

/* Relative Include/plymesh/imagemap paths resolve in tests/fuzz/scene-files: mesh.ply and
 * texture.png are there, anything else is missing. */
#define FUZZ_SCENE_PATH CLR_FUZZ_DIR "/scene-files/scene.pbrt"

static int mentions(const uint8_t *data, size_t size, const char *s) {
  size_t n = strlen(s);
  for (size_t i = 0; i + n <= size; ++i)
    if (memcmp(data + i, s, n) == 0) return 1;
  return 0;
}

/* loopsubdiv turns a few bytes of input into millions of triangles (up to the library's
 * CLR_LOOP_MAX_TRIANGLES per shape, tens of seconds under ASan each). Scenes whose accepted
 * loopsubdiv shapes add up to more than this budget are parsed but not built, so one input stays
 * well under a second; shapes over the library's limit still go through it (they are refused up
 * front). */
#define FUZZ_SUBDIVIDED_TRIANGLE_BUDGET (1 << 18)
#define FUZZ_LIBRARY_SUBDIVISION_LIMIT CLR_LOOP_MAX_TRIANGLES

static int within_budget(const clr_scene_desc *desc) {
  int64_t total = 0;
  for (int i = 0; i < desc->shape_count; ++i) {
    const clr_shape_desc *sd = &desc->shapes[i];
    if (strcmp(sd->type, "loopsubdiv") != 0) continue;
    int count = 0;
    clr_params_find_ints(&sd->params, "indices", &count);
    int levels = clr_params_find_int(&sd->params, "nlevels", 3);
    int64_t triangles = count > 3 ? count / 3 : 1; /* no "indices": one triangle, as pbrt-v3 */
    for (int l = 0; l < levels && triangles <= FUZZ_LIBRARY_SUBDIVISION_LIMIT; ++l) triangles *= 4;
    if (triangles <= FUZZ_LIBRARY_SUBDIVISION_LIMIT) total += triangles;
  }
  return total <= FUZZ_SUBDIVIDED_TRIANGLE_BUDGET;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  /* Device and kernel files block or never end (issue #8, reading them is refused elsewhere);
   * keep the fuzzer on the parser rather than on the machine's files. */
  if (mentions(data, size, "dev/") || mentions(data, size, "/dev") ||
      mentions(data, size, "proc/") || mentions(data, size, "/proc") ||
      mentions(data, size, "sys/") || mentions(data, size, "/sys"))
    return 0;
  char *text = malloc(size + 1);
  if (!text) return 0;
  memcpy(text, data, size);
  text[size] = 0;
  clr_parse_options po;
  clr_parse_options_init(&po);
  po.warn = fuzz_ignore_warning;
  clr_scene_desc *desc = NULL;
  /* The parser takes a NUL-terminated string: text after an embedded NUL is not seen. */
  clr_result r = clr_scene_parse_string(text, FUZZ_SCENE_PATH, &po, &desc);
  fuzz_report("parse", r);
  if (r == CLR_SUCCESS && desc && !within_budget(desc)) {
    if (fuzz_verbose()) fprintf(stderr, "  not built: loopsubdiv over the fuzzing budget\n");
  } else if (r == CLR_SUCCESS && desc) {
    clr_render_settings settings;
    clr_render_settings_from_desc(desc, &settings);
    clr_render_scene *scene = NULL;
    r = clr_render_scene_build(desc, fuzz_ignore_warning, NULL, &scene);
    fuzz_report("build", r);
    if (r == CLR_SUCCESS) {
      clr_integrator integ;
      r = clr_integrator_create(desc, scene, fuzz_ignore_warning, NULL, &integ);
      fuzz_report("integrator", r);
      if (r == CLR_SUCCESS) {
        clr_scene_desc_report_unused(desc, fuzz_ignore_warning, NULL);
        if (settings.x_resolution > 0 && settings.y_resolution > 0)
          clr_render_scene_set_film(scene, settings.x_resolution, settings.y_resolution);
        clr_integrator_free(&integ);
      }
      clr_render_scene_free(scene);
    }
  }
  clr_scene_desc_free(desc);
  free(text);
  return 0;
}
