/* Benchmark harness: each section measures on every OpenCL device against a single-thread host
 * baseline measured in the same run, and prints JSON Lines. */
#ifndef CLR_BENCH_H
#define CLR_BENCH_H

#include <stdio.h>
#include "clrender.h"

typedef struct bench_options {
  int quick;               /* smaller problems, fewer repetitions */
  const char *only_device; /* NULL: every device */
  clr_kernel_shape shape;  /* kernel shape of this pass (each JSON line names it) */
  const char *out_dir;     /* figures of the quality section; NULL: build/bench-quality */
  int reps;                /* timed runs per figure (--reps); 0: the section's default */
} bench_options;

/* Timed runs of one figure: median, fastest and slowest run in seconds. */
typedef struct bench_timing {
  double median, min, max;
  int reps;
} bench_timing;

#define BENCH_MAX_REPS 64

double bench_now(void);
/* o->reps when --reps was given, else the section's default (its quick one under --quick). */
int bench_reps(const bench_options *o, int quick_default, int full_default);
/* Times `reps` runs of fn(user) after one warm-up run; 0 on failure (then *t is unset). */
int bench_time(int reps, int (*fn)(void *user), void *user, bench_timing *t);
/* Median seconds of `reps` runs of fn(user) after one warm-up run; negative on failure. */
double bench_median(int reps, int (*fn)(void *user), void *user);
/* Prints ,"reps":N,"<name>_min":..,"<name>_max":.. for a rate of `work` units per second. */
void bench_json_spread(const char *name, double work, const bench_timing *t);
void bench_json_escape(FILE *f, const char *s);
/* Context on device i with the pass's kernel shape, or NULL when --device excludes it or it fails
 * to open (then a JSON line with the error is printed for section `bench` and the caller skips the
 * device). Simulators (Oclgrind) are not timed: for them this runs the section's correctness
 * check against the host reference, prints it and returns NULL. */
clr_context bench_open_device(const bench_options *o, const clr_device_info *devices, int i,
                              const char *bench);

/* Prints "device":"...","kernels":"..." for ctx. */
void bench_json_device(clr_context ctx);
/* Whether device i is a simulator, checked for correctness but never timed. */
int bench_is_simulator(const clr_device_info *device);
/* The section's correctness check on a simulator (bench_check.c): JSON Lines. */
void bench_check(const char *bench, clr_context ctx);
/* Per-kernel registers, spills and private bytes for gfx90a from the portability test's output. */
void bench_kernel_resources(void);

/* The library's samplers are the types 0 .. count-1 (those clr_sampler_type_name knows), so
 * samplers added to the library join every section that loops over them. */
int bench_sampler_count(void);

void bench_samples(const bench_options *o, const clr_device_info *devices, int device_count);
void bench_render(const bench_options *o, const clr_device_info *devices, int device_count);
/* Embree packet vs single-ray tracing on the host (--only tracer). */
void bench_tracer(const bench_options *o);
/* Film accumulation samples/s per filter and evaluation mode (--only film). */
void bench_film(const bench_options *o, const clr_device_info *devices, int device_count);

/* Sample quality: RMSE vs spp and convergence slopes per sampler, spectra, PNG figures in
 * o->out_dir (--only quality). Returns 0 when the figures' folder cannot be made. */
int bench_quality(const bench_options *o);

#endif
