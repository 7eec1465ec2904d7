/* `clrender render SCENE.pbrt`: renders a pbrt-v3 scene to EXR + PNG. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "cli.h"
#include "cli_args.h"
#include "clrender.h"
#include "distributed.h"
#include "render.h"

static volatile sig_atomic_t render_cancel;
static volatile sig_atomic_t render_signal; /* the SIGINT/SIGTERM received, 0 if none */
static void on_signal(int sig) {
  render_signal = sig;
  render_cancel = 1;
}

static int cancel_on_signal(void *user, int32_t tiles_done, int32_t tiles_total) {
  (void)user;
  (void)tiles_done;
  (void)tiles_total;
  return render_cancel != 0;
}

static void usage(FILE *f) {
  fprintf(
      f,
      "usage: clrender render SCENE.pbrt [options]\n"
      "Renders a pbrt-v3 scene: writes the Film's filename (.exr, .pfm or .png) and a PNG preview\n"
      "with the same name. Flags override the scene file; \"--flag=value\" works as\n"
      "\"--flag value\".\n"
      "  --spp N                 samples per pixel\n"
      "  --nthreads N            worker threads (default and 0: all cores)\n"
      "  --outfile F             output image by extension: .exr or .pfm (with a PNG preview\n"
      "                          beside it) or .png; overrides the scene's Film filename\n"
      "  --cropwindow x0 x1 y0 y1  render only this part of the film (NDC, [0,1])\n"
      "  --seed N                seed of the per-pixel sample streams (default 0)\n"
      "  --seeding pbrt-v3|pbrt-v4|pixel  sample stream seeding (default pixel: crops render\n"
      "                          exactly the samples of the full frame; pbrt-v3: per-16x16-tile\n"
      "                          streams; pbrt-v4: pbrt-v4's samplers and camera sample\n"
      "                          sequence for every name)\n"
      "  --randomization R       pbrt-v4 halton, sobol, paddedsobol, zsobol: none |\n"
      "                          permutedigits | fastowen | owen\n"
      "  --device D              OpenCL device index or name (see clrender devices); under\n"
      "                          mpirun a comma list names one per local rank (wrapping);\n"
      "                          host: the kernels' C build on this CPU (same image, OpenCL\n"
      "                          never loaded: least memory and start-up, slower sampling)\n"
      "  --kernels SHAPE         simd | portable | auto (default auto: simd on PoCL CPU\n"
      "                          devices, portable elsewhere; same image either way)\n"
      "  --sampler NAME          random, stratified, halton, sobol, 02sequence\n"
      "                          (lowdiscrepancy), maxmindist, independent, paddedsobol, zsobol,\n"
      "                          pmj02bn\n"
      "  --filter NAME           box, triangle, gaussian, mitchell, sinc, blackmanharris,\n"
      "                          catmullrom (default parameters)\n"
      "  --tile-size N           render tile side in pixels (default 16)\n"
      "  --resume IMAGE.exr      continue that image (written by clrender with its sums, same\n"
      "                          scene, sampler, integrator, seed, film) up to --spp: the\n"
      "                          samples it lacks, exactly those a longer render draws\n"
      "  --time-limit SECONDS    stop after the pass that reaches this time (0: one pass); the\n"
      "                          image records the spp reached (clrender.spp) and is resumable\n"
      "  --checkpoint SECONDS    rewrite the image (atomically) after each pass once this long\n"
      "                          has passed since the last write (0: every pass)\n"
      "  --pass-spp N            samples per pixel per pass (default spp / 8, at least 1)\n"
      "  --noise-threshold E     adaptive sampling: after each pair of passes, pixels whose\n"
      "                          A/B error estimate is below E receive no more passes\n"
      "  --error-map FILE.exr    with --noise-threshold: write the per-pixel estimates\n"
      "  --quiet                 no warnings, no progress bar\n"
      "  --stats                 print timings and counts as JSON on stderr\n"
      "  --reference-samples     generate samples with the single-thread host reference\n"
      "                          (the kernels' bits, slower: for comparisons)\n"
      "  --help                  this text\n"
      "Exit status: 0 ok, 1 scene or render error (nothing written), 2 usage error,\n"
      "130 (SIGINT) or 143 (SIGTERM): interrupted; the tiles in flight are finished and\n"
      "a valid partial image is written (EXR attribute clrender.partial = 1).\n"
      "Distributed: \"mpirun -np N clrender render SCENE.pbrt ...\" shares the frame between N\n"
      "ranks (each with --nthreads threads); rank 0 writes the image, bit-identical to a\n"
      "single-process render, with per-rank figures (EXR attributes clrender.mpi.*). A failing\n"
      "rank ends the whole job with a non-zero status and nothing written.\n");
}

static int parse_int(const char *s, long lo, long hi, long *out) {
  char *end;
  long v = strtol(s, &end, 10);
  if (!*s || *end || v < lo || v > hi) return 0;
  *out = v;
  return 1;
}

static int parse_float(const char *s, float *out) {
  char *end;
  float v = strtof(s, &end);
  if (!*s || *end) return 0;
  *out = v;
  return 1;
}

/* --device "A,B,C" under mpirun: the entry of this node-local rank, wrapping; malloc'ed. */
static char *device_for_rank(const char *list, int local_rank) {
  int count = 1;
  for (const char *p = list; *p; ++p) count += *p == ',';
  const char *start = list;
  for (int k = local_rank % count; k > 0; --k) start = strchr(start, ',') + 1;
  const char *end = strchr(start, ',');
  size_t n = end ? (size_t)(end - start) : strlen(start);
  char *s = malloc(n + 1);
  if (s) {
    memcpy(s, start, n);
    s[n] = 0;
  }
  return s;
}

static int render_command(int argc, char **argv, clr_dist *dist) {
  clr_render_options o;
  clr_render_options_init(&o);
  const char *scene = NULL;
  int stats = 0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    long v;
#define NEED(n) \
  if (i + (n) >= argc) goto bad
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(a, "--spp") == 0) {
      NEED(1);
      if (!parse_int(argv[++i], 1, 1 << 24, &v)) goto bad;
      o.spp = (int32_t)v;
    } else if (strcmp(a, "--nthreads") == 0) {
      NEED(1);
      if (!parse_int(argv[++i], 0, 4096, &v)) goto bad; /* 0: every core, as pbrt-v3 */
      o.nthreads = (int32_t)v;
    } else if (strcmp(a, "--tile-size") == 0) {
      NEED(1);
      if (!parse_int(argv[++i], 1, 4096, &v)) goto bad;
      o.tile_size = (int32_t)v;
    } else if (strcmp(a, "--seed") == 0) {
      NEED(1);
      if (!parse_int(argv[++i], 0, 0xffffffffL, &v)) goto bad;
      o.seed = (uint32_t)v;
    } else if (strcmp(a, "--outfile") == 0) {
      NEED(1);
      o.outfile = argv[++i];
    } else if (strcmp(a, "--device") == 0) {
      NEED(1);
      o.device = argv[++i];
      if (!cli_device_list_ok(o.device)) {
        fprintf(stderr, "clrender render: \"--device\" \"%s\": empty entry in the device list\n",
                o.device);
        usage(stderr);
        return 2;
      }
    } else if (strcmp(a, "--kernels") == 0) {
      NEED(1);
      o.kernels = argv[++i];
      clr_kernel_shape shape;
      if (clr_kernel_shape_from_name(o.kernels, &shape) != CLR_SUCCESS) goto bad;
    } else if (strcmp(a, "--sampler") == 0) {
      NEED(1);
      o.sampler = argv[++i];
      clr_sampler_type t;
      if (clr_sampler_type_from_name(o.sampler, &t) != CLR_SUCCESS) goto bad;
    } else if (strcmp(a, "--filter") == 0) {
      NEED(1);
      o.filter = argv[++i];
      clr_filter_type ft;
      if (clr_filter_type_from_name(o.filter, &ft) != CLR_SUCCESS) goto bad;
    } else if (strcmp(a, "--seeding") == 0) {
      NEED(1);
      ++i;
      if (strcmp(argv[i], "pbrt-v3") == 0)
        o.seeding = CLR_SEEDING_PBRT_V3;
      else if (strcmp(argv[i], "pixel") == 0)
        o.seeding = CLR_SEEDING_PIXEL;
      else if (strcmp(argv[i], "pbrt-v4") == 0)
        o.seeding = CLR_SEEDING_PBRT_V4;
      else
        goto bad;
    } else if (strcmp(a, "--randomization") == 0) {
      NEED(1);
      if (clr_randomization_from_name(argv[++i], &o.randomization) != CLR_SUCCESS) goto bad;
    } else if (strcmp(a, "--cropwindow") == 0) {
      NEED(4);
      for (int k = 0; k < 4; ++k)
        if (!parse_float(argv[++i], &o.crop_window[k]) ||
            !(o.crop_window[k] >= 0.0f && o.crop_window[k] <= 1.0f))
          goto bad;
      if (!(o.crop_window[0] < o.crop_window[1] && o.crop_window[2] < o.crop_window[3])) goto bad;
      o.crop_given = 1;
    } else if (strcmp(a, "--resume") == 0) {
      NEED(1);
      o.resume = argv[++i];
    } else if (strcmp(a, "--time-limit") == 0 || strcmp(a, "--checkpoint") == 0) {
      NEED(1);
      float seconds = 0.0f;
      if (!parse_float(argv[++i], &seconds) || !(seconds >= 0.0f && seconds <= 1e9f)) goto bad;
      *(a[2] == 't' ? &o.time_limit : &o.checkpoint) = seconds;
    } else if (strcmp(a, "--noise-threshold") == 0) {
      NEED(1);
      if (!parse_float(argv[++i], &o.noise_threshold) ||
          !(o.noise_threshold > 0.0f && o.noise_threshold < 1e30f))
        goto bad;
    } else if (strcmp(a, "--error-map") == 0) {
      NEED(1);
      o.error_map = argv[++i];
    } else if (strcmp(a, "--pass-spp") == 0) {
      NEED(1);
      if (!parse_int(argv[++i], 1, 1 << 24, &v)) goto bad;
      o.pass_spp = (int32_t)v;
    } else if (strcmp(a, "--quiet") == 0) {
      o.quiet = 1;
    } else if (strcmp(a, "--reference-samples") == 0) {
      o.reference_samples = 1;
    } else if (strcmp(a, "--stats") == 0) {
      stats = 1;
    } else if (a[0] == '-' && a[1]) {
      fprintf(stderr, "clrender render: unknown option \"%s\"\n", a);
      usage(stderr);
      return 2;
    } else if (!scene) {
      scene = a;
    } else {
      goto bad;
    }
#undef NEED
    continue;
  bad:
    fprintf(stderr, "clrender render: bad or missing value for \"%s\"\n", a);
    usage(stderr);
    return 2;
  }
  if (!scene) {
    fprintf(stderr, "clrender render: no scene file given\n");
    usage(stderr);
    return 2;
  }
  if (o.error_map && o.noise_threshold <= 0.0f) {
    fprintf(stderr, "clrender render: --error-map needs --noise-threshold\n");
    usage(stderr);
    return 2;
  }
  char *device = NULL;
  if (o.device && strchr(o.device, ',')) {
    device = device_for_rank(o.device, clr_dist_local_rank(dist));
    if (!device) {
      fprintf(stderr, "clrender: out of memory\n");
      return 1;
    }
    o.device = device;
  }
  int root = clr_dist_rank(dist) == 0;
  if (!root) o.quiet = 1; /* rank 0 speaks for the job */
  o.progress = !o.quiet && isatty(STDERR_FILENO);
  o.progress_callback = cancel_on_signal;
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  clr_render_stats st;
  clr_render_stats_init(&st);
  clr_result r = clr_render_file(scene, &o, &st);
  free(device);
  int interrupted = render_signal; /* 128 + signal, as a shell reports a killed command */
  if (r != CLR_SUCCESS) {
    if (dist)
      fprintf(stderr, "clrender: rank %d of %d: %s\n", clr_dist_rank(dist), clr_dist_size(dist),
              clr_last_error_message());
    else
      fprintf(stderr, "clrender: %s\n", clr_last_error_message());
    return interrupted ? 128 + interrupted : 1;
  }
  if (!root) return 0;
  if (stats) {
    char buf[2048];
    clr_render_stats_json(&st, buf, sizeof buf);
    fprintf(stderr, "%s\n", buf);
  }
  if (!o.quiet) {
    const char *main_image = st.exr_path[0] ? st.exr_path : st.pfm_path;
    fprintf(stderr, "clrender: wrote %s%s%s%s\n", main_image, main_image[0] ? " and " : "",
            st.png_path, st.partial ? " (partial)" : "");
    if (st.dropped_samples)
      fprintf(stderr, "clrender: %llu samples with NaN/Inf/negative radiance dropped\n",
              (unsigned long long)st.dropped_samples);
  }
  if (interrupted) {
    fprintf(stderr, "clrender: interrupted by %s: the image is partial\n",
            interrupted == SIGINT ? "SIGINT" : "SIGTERM");
    return 128 + interrupted;
  }
  return 0;
}

int cli_render(int argc, char **argv) {
  if (clr_dist_init(&argc, &argv) != 0) {
    fprintf(stderr, "clrender: MPI_Init failed\n");
    return 1;
  }
  int status = render_command(argc, argv, clr_dist_world());
  clr_dist_finalize(status); /* a failed rank aborts the job: no rank waits for it */
  return status;
}
