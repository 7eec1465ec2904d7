/* The renderer tests' shared steps: parse a scene text as if it were the file `path` (relative
 * file names resolve beside it) and render it (with default options, or given ones); all assert success and
 * print the library's message first when they fail. Include after cmocka.h. */
#ifndef CLR_SCENE_TEST_UTIL_H
#define CLR_SCENE_TEST_UTIL_H

#include <stdio.h>
#include <string.h>
#include "render_scene.h"
#include "renderer.h"
#include "scene_parser.h"

static inline clr_scene_desc *stu_parse(const char *text, const char *path) {
  clr_scene_desc *desc = NULL;
  clr_parse_options po;
  clr_parse_options_init(&po);
  clr_result r = clr_scene_parse_string(text, path, &po, &desc);
  if (r != CLR_SUCCESS) fprintf(stderr, "%s\n", clr_last_error_message());
  assert_int_equal(r, CLR_SUCCESS);
  return desc;
}

/* The scene built from the text (free it and *desc, the parsed text). */
static inline clr_render_scene *stu_build(const char *text, const char *path,
                                          clr_scene_desc **desc) {
  *desc = stu_parse(text, path);
  clr_render_scene *scene = NULL;
  clr_result r = clr_render_scene_build(*desc, NULL, NULL, &scene);
  if (r != CLR_SUCCESS) fprintf(stderr, "%s\n", clr_last_error_message());
  assert_int_equal(r, CLR_SUCCESS);
  return scene;
}

/* The image (free its rgb) rendered with `opts` (the defaults when NULL; always quiet), the
 * statistics in *stats when it is not NULL. */
static inline clr_render_image stu_render_image(const char *text, const char *path,
                                                const clr_render_options *opts,
                                                clr_render_stats *stats) {
  clr_scene_desc *desc = stu_parse(text, path);
  clr_render_options o;
  clr_render_options_init(&o);
  if (opts) o = *opts;
  o.quiet = 1;
  clr_render_image im;
  memset(&im, 0, sizeof im);
  clr_result r = clr_render_desc(desc, &o, stats, 0, &im);
  if (r != CLR_SUCCESS) fprintf(stderr, "%s\n", clr_last_error_message());
  assert_int_equal(r, CLR_SUCCESS);
  clr_scene_desc_free(desc);
  return im;
}

/* The image's rgb (free it), its size in *w, *h. */
static inline float *stu_render(const char *text, const char *path, int *w, int *h) {
  clr_render_image im = stu_render_image(text, path, NULL, NULL);
  *w = im.width;
  *h = im.height;
  return im.rgb;
}

#endif
