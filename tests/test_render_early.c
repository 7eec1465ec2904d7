/* The early start (renderer.c): bands shaded on the scene-build thread with the host reference's
 * samples while the device is set up give the same image, counts and rays as a render without
 * it; a device failure after an early start is reported with its message, nothing left. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "renderer.h"
#include "scene_parser.h"

/* A small Cornell-like box: 40 x 36 pixels, 8-pixel tiles (one band per tile row). */
static const char *box_head =
    "LookAt 278 273 -800  278 273 0  0 1 0\nCamera \"perspective\" \"float fov\" [39.3]\n"
    "Film \"image\" \"integer xresolution\" [40] \"integer yresolution\" [36]\n";
static const char *box_world =
    "WorldBegin\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [17 12 4]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
    "\"point P\" [343 548.7 227  343 548.7 332  213 548.7 332  213 548.7 227]\nAttributeEnd\n"
    "Material \"matte\" \"rgb Kd\" [0.7 0.6 0.5]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 6 4 6 7]\n"
    "\"point P\" [0 0 0  0 0 559  556 0 559  556 0 0  0 0 559  0 548 559  556 548 559  556 0 559]\n"
    "Shape \"sphere\" \"float radius\" [100]\nWorldEnd\n";

static clr_scene_desc *parse_box(const char *sampler, const char *filter, const char *integrator) {
  char text[4096];
  snprintf(text, sizeof text, "%sSampler \"%s\" \"integer pixelsamples\" [4]\n%s\n%s\n%s", box_head,
           sampler, filter, integrator, box_world);
  clr_scene_desc *desc = NULL;
  clr_parse_options po;
  clr_parse_options_init(&po);
  assert_int_equal(clr_scene_parse_string(text, "test.pbrt", &po, &desc), CLR_SUCCESS);
  return desc;
}

static clr_render_image render(const clr_scene_desc *desc, int early, int threads,
                               clr_render_stats *st) {
  clr_render_options o;
  clr_render_options_init(&o);
  o.quiet = 1;
  o.tile_size = 8;
  o.nthreads = threads;
  o.early_start = early;
  o.lazy_samples = CLR_LAZY_SAMPLES_OFF;
  clr_render_image im;
  memset(&im, 0, sizeof im);
  clr_render_stats_init(st);
  clr_result r = clr_render_desc(desc, &o, st, 0, &im);
  if (r != CLR_SUCCESS) fprintf(stderr, "%s\n", clr_last_error_message());
  assert_int_equal(r, CLR_SUCCESS);
  return im;
}

/* Early start forced (the first band and half the second on the host) and off: the same bits,
 * samples and rays, for AO, direct lighting and path tracing, halton and sobol, box and
 * triangle filters (tiles overlapping: the merge order matters), 1 and 2 threads. */
static void test_early_start_same_image(void **state) {
  (void)state;
  const char *samplers[2] = {"halton", "sobol"};
  const char *filters[2] = {"PixelFilter \"box\"", "PixelFilter \"triangle\""};
  const char *integrators[3] = {"Integrator \"ambientocclusion\"", "Integrator \"directlighting\"",
                                "Integrator \"path\" \"integer maxdepth\" [3]"};
  for (int s = 0; s < 2; ++s)
    for (int f = 0; f < 2; ++f)
      for (int i = 0; i < 3; ++i) {
        clr_scene_desc *desc = parse_box(samplers[s], filters[f], integrators[i]);
        clr_render_stats off_st, early_st;
        clr_render_image off = render(desc, CLR_EARLY_START_OFF, 2, &off_st);
        for (int threads = 1; threads <= 2; ++threads) {
          clr_render_image early = render(desc, CLR_EARLY_START_ALWAYS, threads, &early_st);
          assert_int_equal(early.width, off.width);
          assert_int_equal(early.height, off.height);
          assert_memory_equal(early.rgb, off.rgb,
                              (size_t)off.width * (size_t)off.height * 3 * sizeof(float));
          assert_int_equal(early_st.samples, off_st.samples);
          assert_int_equal(early_st.rays, off_st.rays);
          assert_int_equal(early_st.tiles_done, off_st.tiles_done);
          assert_int_equal(early_st.partial, 0);
          free(early.rgb);
        }
        free(off.rgb);
        clr_scene_desc_free(desc);
      }
}

/* A device that cannot be set up after the first band was shaded early: its error, no image
 * (the early tiles, scene and film are freed: the ASan build checks for leaks). */
static void test_early_start_device_failure(void **state) {
  (void)state;
  clr_scene_desc *desc =
      parse_box("halton", "PixelFilter \"box\"", "Integrator \"directlighting\"");
  for (int early = CLR_EARLY_START_AUTO; early <= CLR_EARLY_START_ALWAYS; ++early) {
    clr_render_options o;
    clr_render_options_init(&o);
    o.quiet = 1;
    o.tile_size = 8;
    o.early_start = early;
    o.device = "no-such-device-here";
    clr_render_image im;
    memset(&im, 0, sizeof im);
    assert_int_not_equal(clr_render_desc(desc, &o, NULL, 0, &im), CLR_SUCCESS);
    assert_non_null(strstr(clr_last_error_message(), "no-such-device-here"));
    assert_null(im.rgb);
  }
  clr_scene_desc_free(desc);
}

/* An early_start outside auto/off/always is refused, naming the field and value. */
static void test_early_start_option_checked(void **state) {
  (void)state;
  clr_scene_desc *desc =
      parse_box("halton", "PixelFilter \"box\"", "Integrator \"directlighting\"");
  clr_render_options o;
  clr_render_options_init(&o);
  o.quiet = 1;
  o.early_start = 3;
  assert_int_equal(clr_render_desc(desc, &o, NULL, 0, NULL), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "early_start 3"));
  clr_scene_desc_free(desc);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_early_start_same_image),
      cmocka_unit_test(test_early_start_device_failure),
      cmocka_unit_test(test_early_start_option_checked),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
