/* clrender_bench: loops over every OpenCL platform and device and runs each benchmark section. */
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "bench.h"

double bench_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int bench_reps(const bench_options *o, int quick_default, int full_default) {
  return o->reps > 0 ? o->reps : o->quick ? quick_default : full_default;
}

int bench_time(int reps, int (*fn)(void *user), void *user, bench_timing *t) {
  double times[BENCH_MAX_REPS];
  if (reps < 1) reps = 1;
  if (reps > BENCH_MAX_REPS) reps = BENCH_MAX_REPS;
  if (!fn(user)) return 0;
  for (int i = 0; i < reps; ++i) {
    double t0 = bench_now();
    if (!fn(user)) return 0;
    times[i] = bench_now() - t0;
  }
  qsort(times, (size_t)reps, sizeof times[0], cmp_double);
  *t = (bench_timing){times[reps / 2], times[0], times[reps - 1], reps};
  return 1;
}

double bench_median(int reps, int (*fn)(void *user), void *user) {
  bench_timing t;
  return bench_time(reps, fn, user, &t) ? t.median : -1.0;
}

void bench_json_spread(const char *name, double work, const bench_timing *t) {
  printf(",\"reps\":%d,\"%s_min\":%.4g,\"%s_max\":%.4g", t->reps, name, work / t->max, name,
         work / t->min);
}

void bench_json_escape(FILE *f, const char *s) {
  fputc('"', f);
  for (; *s; ++s) {
    if (*s == '"' || *s == '\\') fputc('\\', f);
    if ((unsigned char)*s < 32) continue;
    fputc(*s, f);
  }
  fputc('"', f);
}

clr_context bench_open_device(const bench_options *o, const clr_device_info *devices, int i,
                              const char *bench) {
  char index[16];
  snprintf(index, sizeof index, "%d", i);
  if (o->only_device && !strstr(devices[i].device_name, o->only_device) &&
      strcmp(o->only_device, index) != 0)
    return NULL;
  clr_context_desc cd;
  clr_context_desc_init(&cd);
  cd.device = index;
  clr_context ctx = NULL;
  if (clr_context_create(&cd, &ctx) == CLR_SUCCESS &&
      clr_context_set_kernel_shape(ctx, o->shape) == CLR_SUCCESS) {
    if (!bench_is_simulator(&devices[i])) return ctx;
    bench_check(bench, ctx);
    clr_context_release(ctx);
    return NULL;
  }
  clr_context_release(ctx);
  printf("{\"bench\":\"%s\",\"device\":", bench);
  bench_json_escape(stdout, devices[i].device_name);
  printf(",\"error\":");
  bench_json_escape(stdout, clr_last_error_message());
  printf("}\n");
  return NULL;
}

void bench_json_device(clr_context ctx) {
  printf("\"device\":");
  bench_json_escape(stdout, clr_context_device_name(ctx));
  printf(",\"kernels\":\"%s\"", clr_kernel_shape_name(clr_context_kernel_shape(ctx)));
}

int bench_sampler_count(void) {
  int n = 0;
  for (;; ++n) {
    const char *name = clr_sampler_type_name((clr_sampler_type)n);
    if (!name || strcmp(name, "unknown") == 0 || n >= 1024) return n;
  }
}

int bench_is_simulator(const clr_device_info *device) {
  return strstr(device->platform_name, "Oclgrind") != NULL ||
         strstr(device->device_name, "Oclgrind") != NULL;
}

static void usage(void) {
  fprintf(stderr,
          "usage: clrender_bench [--quick] [--device INDEX|NAME] "
          "[--only samples|film|tracer|render|kernels|quality] [--kernels simd|portable|both]\n"
          "                      [--reps N] [--out-dir DIR]\n"
          "Prints one JSON object per line: each device's figure (per kernel shape, both\n"
          "by default) and the single-thread host reference measured in the same run, with\n"
          "their ratio. --reps N (1-64): timed runs per samples, film or tracer figure after\n"
          "a warm-up run (the median; _min and _max: the slowest and fastest run's rates).\n"
          "Simulators (Oclgrind) are checked against the host reference, not timed.\n"
          "`tracer`: Embree packets against single rays on the host. `kernels`: gfx90a\n"
          "registers, spills and private bytes per kernel (from test_kernel_portability).\n"
          "`quality` (only with --only): RMSE vs spp and convergence slope of every sampler\n"
          "(analytic integrands, a checkerboard render), spectra; PNG figures in --out-dir\n"
          "(default build/bench-quality).\n");
}

int main(int argc, char **argv) {
  bench_options o = {0, NULL, CLR_KERNELS_AUTO, NULL, 0};
  const char *only = NULL, *kernels = "both";
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--quick") == 0)
      o.quick = 1;
    else if (strcmp(argv[i], "--device") == 0 && i + 1 < argc)
      o.only_device = argv[++i];
    else if (strcmp(argv[i], "--only") == 0 && i + 1 < argc)
      only = argv[++i];
    else if (strcmp(argv[i], "--kernels") == 0 && i + 1 < argc)
      kernels = argv[++i];
    else if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc) {
      char *end = NULL;
      long reps = strtol(argv[++i], &end, 10);
      if (end == argv[i] || *end != '\0' || reps < 1 || reps > BENCH_MAX_REPS) {
        fprintf(stderr, "clrender_bench: --reps %s: expected a whole number from 1 to %d\n",
                argv[i], BENCH_MAX_REPS);
        return 2;
      }
      o.reps = (int)reps;
    } else if (strcmp(argv[i], "--out-dir") == 0 && i + 1 < argc && argv[i + 1][0])
      o.out_dir = argv[++i];
    else {
      usage();
      return 2;
    }
  }
  static const char *const sections[] = {"samples", "film",    "tracer",
                                         "render",  "kernels", "quality"};
  int known = !only;
  for (int s = 0; s < 6; ++s) known |= only && strcmp(only, sections[s]) == 0;
  if (!known) {
    fprintf(stderr, "clrender_bench: --only %s: unknown section\n", only);
    usage();
    return 2;
  }
  /* quality's figures do not depend on the device (host reference samples, the default device
   * for the renders): it runs only when asked for */
  if (only && strcmp(only, "quality") == 0) return bench_quality(&o) ? 0 : 1;
  clr_device_info devices[64];
  int count = 0;
  if (clr_device_list(devices, 64, &count) != CLR_SUCCESS) {
    fprintf(stderr, "clrender_bench: %s\n", clr_last_error_message());
    return 1;
  }
  if (count > 64) count = 64;
  clr_kernel_shape shapes[2] = {CLR_KERNELS_SIMD, CLR_KERNELS_PORTABLE};
  int nshapes = 2;
  if (strcmp(kernels, "both") != 0) {
    if (clr_kernel_shape_from_name(kernels, &shapes[0]) != CLR_SUCCESS) {
      usage();
      return 2;
    }
    nshapes = 1;
  }
  if (!only || strcmp(only, "kernels") == 0) bench_kernel_resources();
  if (!only || strcmp(only, "tracer") == 0) bench_tracer(&o);
  for (int k = 0; k < nshapes; ++k) {
    o.shape = shapes[k];
    if (!only || strcmp(only, "samples") == 0) bench_samples(&o, devices, count);
    if (!only || strcmp(only, "film") == 0) bench_film(&o, devices, count);
    if (!only || strcmp(only, "render") == 0) bench_render(&o, devices, count);
  }
  return 0;
}
