/* Benchmark harness: each section measures on every OpenCL device against a single-thread host
 * baseline measured in the same run, and prints JSON Lines. */
#ifndef CLR_BENCH_H
#define CLR_BENCH_H

#include <stdio.h>
#include "clrender.h"

typedef struct bench_options {
  int quick;               /* smaller problems, fewer repetitions */
  const char *only_device; /* NULL: every device */
} bench_options;

double bench_now(void);
/* Median seconds of `reps` runs of fn(user) after one warm-up run; negative on failure. */
double bench_median(int reps, int (*fn)(void *user), void *user);
void bench_json_escape(FILE *f, const char *s);
/* Context on device i, or NULL when --device excludes it or it fails to open (then a JSON line
 * with the error is printed for section `bench` and the caller skips the device). */
clr_context bench_open_device(const bench_options *o, const clr_device_info *devices, int i,
                              const char *bench);

void bench_samples(const bench_options *o, const clr_device_info *devices, int device_count);
void bench_render(const bench_options *o, const clr_device_info *devices, int device_count);
/* Embree packet vs single-ray tracing on the host (--only tracer). */
void bench_tracer(const bench_options *o);
/* Film accumulation samples/s per filter and evaluation mode (--only film). */
void bench_film(const bench_options *o, const clr_device_info *devices, int device_count);

#endif
