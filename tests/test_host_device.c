/* `--device host` (clr_render_options.device = "host"): renders with the C build of the kernels
 * never load OpenCL and give the default device's images bit for bit, for every sampler kind,
 * each integrator, one and two threads, passes and adaptive sampling. */
#define _GNU_SOURCE
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
#include "cornell_test_scene.h"
#include "scene_test_util.h"

static const char *box_body = CORNELL_CAMERA
    "Film \"image\" \"integer xresolution\" [24] \"integer yresolution\" [20]\n"
    "PixelFilter \"mitchell\"\nWorldBegin\n" CORNELL_LIGHT_FLOOR_AND_BACK_WALL
    "Shape \"sphere\" \"float radius\" [100]\nWorldEnd\n";

static clr_render_image render(const char *sampler, int spp, const char *integrator,
                               const clr_render_options *opts) {
  char text[4096];
  snprintf(text, sizeof text, "Sampler \"%s\" \"integer pixelsamples\" [%d]\nIntegrator %s\n%s",
           sampler, spp, integrator, box_body);
  return stu_render_image(text, "test.pbrt", opts, NULL);
}

static int maps_mention(const char *what) {
  FILE *f = fopen("/proc/self/maps", "r");
  assert_non_null(f);
  char line[4096];
  int found = 0;
  while (fgets(line, sizeof line, f)) found |= strstr(line, what) != NULL;
  fclose(f);
  return found;
}

/* Runs first, before any test of this process loads an OpenCL implementation. */
static void test_host_never_loads_opencl(void **state) {
  (void)state;
  clr_render_options o;
  clr_render_options_init(&o);
  o.device = "host";
  o.nthreads = 2;
  clr_render_image im = render("halton", 4, "\"path\" \"integer maxdepth\" [3]", &o);
  assert_true(im.width == 24 && im.height == 20);
  free(im.rgb);
  assert_false(maps_mention("libpocl"));
  assert_false(maps_mention("libLLVM"));
  assert_false(maps_mention("libclang"));
}

static void assert_same_image(const char *sampler, int spp, const char *integrator,
                              clr_render_options *o) {
  o->device = NULL;
  clr_render_image dev = render(sampler, spp, integrator, o);
  o->device = "host";
  clr_render_image host = render(sampler, spp, integrator, o);
  assert_true(dev.width == host.width && dev.height == host.height);
  size_t bytes = (size_t)dev.width * (size_t)dev.height * 3 * sizeof(float);
  if (memcmp(dev.rgb, host.rgb, bytes) != 0)
    fail_msg("%s %d spp, %s: host and device images differ", sampler, spp, integrator);
  free(dev.rgb);
  free(host.rgb);
}

static void test_host_matches_device(void **state) {
  (void)state;
  const char *samplers[] = {"halton", "sobol", "stratified", "random", "02sequence", "zsobol"};
  const char *integrators[] = {"\"ambientocclusion\" \"integer nsamples\" [2]",
                               "\"directlighting\"", "\"path\" \"integer maxdepth\" [3]"};
  clr_render_options o;
  clr_render_options_init(&o);
  for (size_t s = 0; s < sizeof samplers / sizeof samplers[0]; ++s)
    for (size_t i = 0; i < sizeof integrators / sizeof integrators[0]; ++i) {
      o.nthreads = 1 + (int)((s + i) % 2);
      assert_same_image(samplers[s], 4, integrators[i], &o);
    }
}

static void test_host_passes_and_adaptive(void **state) {
  (void)state;
  clr_render_options o;
  clr_render_options_init(&o);
  o.nthreads = 2;
  o.pass_spp = 2;
  assert_same_image("sobol", 8, "\"path\" \"integer maxdepth\" [3]", &o);
  o.noise_threshold = 0.05f;
  assert_same_image("halton", 8, "\"path\" \"integer maxdepth\" [3]", &o);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_host_never_loads_opencl),
      cmocka_unit_test(test_host_matches_device),
      cmocka_unit_test(test_host_passes_and_adaptive),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
