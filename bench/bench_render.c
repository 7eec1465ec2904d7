/* End-to-end render benchmark: the bundled scenes per sampler, and pbrt-v3's comparison case
 * (256x256 Cornell box, ambientocclusion, 16 spp, 2 threads, halton and sobol). One JSON object
 * per render with the phase breakdown. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "renderer.h"
#include "scene_parser.h"

#ifndef CLR_SOURCE_DIR
#define CLR_SOURCE_DIR "."
#endif

static char *read_text(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *t = malloc((size_t)n + 1);
  if (t && fread(t, 1, (size_t)n, f) != (size_t)n) {
    free(t);
    t = NULL;
  }
  if (t) t[n] = 0;
  fclose(f);
  return t;
}

/* Replaces the scene's Integrator line (one line starting with "Integrator") by `integrator`. */
static char *with_integrator(const char *text, const char *integrator) {
  const char *at = strstr(text, "\nIntegrator");
  if (!at) return NULL;
  const char *eol = strchr(at + 1, '\n');
  size_t head = (size_t)(at + 1 - text), n = strlen(text) + strlen(integrator) + 2;
  char *out = malloc(n);
  if (!out) return NULL;
  snprintf(out, n, "%.*s%s%s", (int)head, text, integrator, eol ? eol : "\n");
  return out;
}

/* The device (index string) and kernel shape of the current pass. */
static const char *pass_device;
static clr_kernel_shape pass_shape;
static char pass_device_name[300];

static void run(const char *label, const char *text, const char *path, const char *sampler, int spp,
                int nthreads, int xres) {
  clr_scene_desc *desc = NULL;
  clr_parse_options po;
  clr_parse_options_init(&po);
  po.warn = NULL;
  if (clr_scene_parse_string(text, path, &po, &desc) != CLR_SUCCESS) {
    fprintf(stderr, "bench_render: %s\n", clr_last_error_message());
    return;
  }
  clr_render_options o;
  clr_render_options_init(&o);
  o.quiet = 1;
  o.sampler = sampler;
  o.spp = spp;
  o.nthreads = nthreads;
  o.xresolution = o.yresolution = xres;
  o.outfile = "/tmp/clrender_bench_render.exr";
  o.device = pass_device;
  o.kernels = clr_kernel_shape_name(pass_shape);
  clr_render_stats st;
  clr_render_stats_init(&st);
  double t0 = bench_now();
  clr_result r = clr_render_desc(desc, &o, &st, 1, NULL);
  double wall = bench_now() - t0;
  clr_scene_desc_free(desc);
  remove("/tmp/clrender_bench_render.exr");
  remove("/tmp/clrender_bench_render.png");
  if (r != CLR_SUCCESS) {
    fprintf(stderr, "bench_render: %s: %s\n", label, clr_last_error_message());
    return;
  }
  char json[2048];
  clr_render_stats_json(&st, json, sizeof json);
  printf("{\"bench\":\"render\",\"device\":");
  bench_json_escape(stdout, pass_device_name);
  printf(",\"kernels\":\"%s\",\"case\":", clr_kernel_shape_name(pass_shape));
  bench_json_escape(stdout, label);
  printf(",\"wall_seconds\":%.4f,\"stats\":%s}\n", wall, json);
  fflush(stdout);
}

static void render_cases(const bench_options *o);

void bench_render(const bench_options *o, const clr_device_info *devices, int device_count) {
  for (int i = 0; i < device_count; ++i) {
    clr_context ctx = bench_open_device(o, devices, i, "render");
    if (!ctx) continue;
    char index[16];
    snprintf(index, sizeof index, "%d", i);
    pass_device = index;
    pass_shape = clr_context_kernel_shape(ctx);
    snprintf(pass_device_name, sizeof pass_device_name, "%s", clr_context_device_name(ctx));
    clr_context_release(ctx);
    render_cases(o);
  }
}

static void render_cases(const bench_options *o) {
  static const char *samplers[] = {"random", "stratified", "halton", "sobol"};
  static const char *scenes[] = {"scenes/cornell-box.pbrt", "scenes/checkerboard.pbrt",
                                 "scenes/killeroo-simple/killeroo-simple.pbrt"};
  char path[1024];
  for (int s = 0; s < 3; ++s) {
    snprintf(path, sizeof path, "%s/%s", CLR_SOURCE_DIR, scenes[s]);
    char *text = read_text(path);
    if (!text) {
      fprintf(stderr, "bench_render: cannot read %s\n", path);
      continue;
    }
    int killeroo = s == 2;
    for (int k = 0; k < 4; ++k) {
      char label[256];
      snprintf(label, sizeof label, "%s %s", scenes[s], samplers[k]);
      run(label, text, path, samplers[k], (o->quick || killeroo) ? 4 : 0, 0,
          killeroo ? (o->quick ? 128 : 350) : (o->quick ? 128 : 0));
    }
    if (s == 0) {
      const char *ao[2] = {"Integrator \"ambientocclusion\" \"integer nsamples\" [64]",
                           "Integrator \"ambientocclusion\" \"integer nsamples\" [1]"};
      for (int a = 0; a < 2; ++a) {
        char *t = with_integrator(text, ao[a]);
        for (int k = 2; t && k < 4; ++k) {
          char label[256];
          snprintf(label, sizeof label,
                   "cornell-box 256x256 ambientocclusion nsamples %d, 16 spp, 2 threads, %s",
                   a == 0 ? 64 : 1, samplers[k]);
          run(label, t, path, samplers[k], 16, 2, o->quick ? 128 : 256);
        }
        free(t);
      }
    }
    free(text);
  }
}
