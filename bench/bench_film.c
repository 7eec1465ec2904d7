/* Film accumulation throughput (samples/s) per filter and evaluation mode on each device, against
 * the single-thread host reference, with the film's peak memory per pixel. */
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "bench.h"
#include "film_internal.h"

#define FILM_W 1280
#define FILM_H 720
#define FILM_RADIUS 2.0f

typedef struct run {
  clr_film film;
  const clr_film_sample *samples;
  cl_mem buffer; /* device copy of samples, or NULL for host samples */
  size_t count;
  int reference;
} run;

static int run_once(void *user) {
  run *r = user;
  clr_result res = r->reference ? film_add_samples_reference(r->film, r->samples, r->count)
                   : r->buffer  ? film_add_samples_buffer(r->film, r->buffer, r->count)
                                : film_add_samples(r->film, r->samples, r->count);
  if (res != CLR_SUCCESS) fprintf(stderr, "bench: %s\n", clr_last_error_message());
  return res == CLR_SUCCESS;
}

static uint32_t rng_next(uint32_t *s) {
  *s ^= *s << 13;
  *s ^= *s >> 17;
  *s ^= *s << 5;
  return *s;
}

/* `spp` random samples per pixel, uniform over the film's sample bounds, in random order. */
static clr_film_sample *random_samples(clr_film film, size_t count) {
  clr_film_sample *s = malloc(count * sizeof *s);
  if (!s) return NULL;
  clr_bounds2i b = film_sample_bounds(film);
  float w = (float)(b.x1 - b.x0), h = (float)(b.y1 - b.y0);
  uint32_t st = 12345u;
  for (size_t i = 0; i < count; ++i) {
    s[i].x = (float)b.x0 + (float)(rng_next(&st) >> 8) * 0x1p-24f * w;
    s[i].y = (float)b.y0 + (float)(rng_next(&st) >> 8) * 0x1p-24f * h;
    s[i].r = (float)(rng_next(&st) >> 8) * 0x1p-24f;
    s[i].g = (float)(rng_next(&st) >> 8) * 0x1p-24f;
    s[i].b = (float)(rng_next(&st) >> 8) * 0x1p-24f;
    s[i].weight = 1.0f;
  }
  return s;
}

static clr_film make_film(clr_context ctx, int type, int use_table) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = FILM_W;
  d.y_resolution = FILM_H;
  clr_filter_desc_init(&d.filter, (clr_filter_type)type);
  d.filter.radius[0] = d.filter.radius[1] = FILM_RADIUS;
  d.filter.use_table = use_table;
  clr_film film = NULL;
  return film_create(ctx, &d, &film) == CLR_SUCCESS ? film : NULL;
}

/* The film's memory: its sums per pixel and the accumulation's scratch (bounded by the chunk);
 * and the host threads it binned with. */
typedef struct film_memory {
  double sums_bytes_per_pixel, scratch_mib;
  int bin_threads;
} film_memory;

/* This process's CPU time (every thread's, PoCL's workers included) in seconds. */
static double process_cpu_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* CLR_BENCH_FILM_THREADS, when set, the film's host binning threads (0 = automatic). */
static int bench_bin_threads(void) {
  const char *env = getenv("CLR_BENCH_FILM_THREADS");
  return env ? atoi(env) : 0;
}

/* Samples per second of one path (the median run; *timing gets every run's spread); *mem gets
 * the film's peak memory, *cpu_ns the process's CPU nanoseconds per sample over all its runs (the
 * warm-up included; less disturbed by load than samples/s). */
static double rate(clr_context ctx, int type, int use_table, int path, size_t count, int reps,
                   const clr_film_sample *samples, film_memory *mem, double *cpu_ns,
                   bench_timing *timing) {
  run r = {make_film(ctx, type, use_table), samples, NULL, count, path == 2};
  if (!r.film) return -1;
  if (film_set_bin_threads(r.film, bench_bin_threads()) != CLR_SUCCESS) {
    film_release(r.film);
    return -1;
  }
  if (path == 1) {
    cl_int err;
    r.buffer = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              count * sizeof *samples, (void *)samples, &err);
    if (err != CL_SUCCESS) {
      film_release(r.film);
      return -1;
    }
  }
  double cpu0 = process_cpu_s();
  double t = bench_time(reps, run_once, &r, timing) ? timing->median : -1;
  *cpu_ns = 1e9 * (process_cpu_s() - cpu0) / ((double)count * (timing->reps + 1));
  if (mem) {
    mem->sums_bytes_per_pixel = (double)clr_film_sums_bytes(r.film) / ((double)FILM_W * FILM_H);
    mem->scratch_mib = (double)clr_film_scratch_bytes(r.film) / (1024.0 * 1024.0);
    mem->bin_threads = clr_film_host_threads(r.film);
  }
  if (r.buffer) clReleaseMemObject(r.buffer);
  film_release(r.film);
  return t > 0 ? (double)count / t : -1;
}

/* Filters measured: box, triangle and mitchell (the target case), all radius FILM_RADIUS. */
#define FILTER_COUNT 3
static const int filter_types[FILTER_COUNT] = {CLR_FILTER_BOX, CLR_FILTER_TRIANGLE,
                                               CLR_FILTER_MITCHELL};
static const char *filter_name(int type) {
  return type == CLR_FILTER_BOX ? "box" : type == CLR_FILTER_TRIANGLE ? "triangle" : "mitchell";
}

/* CLR_BENCH_FILM_FILTER (box, triangle, mitchell) and CLR_BENCH_FILM_MODE (exact, table), when
 * set, keep only the cases they name (shorter profiles and side-by-side runs). */
static int case_selected(int type, int use_table) {
  const char *filter = getenv("CLR_BENCH_FILM_FILTER"), *mode = getenv("CLR_BENCH_FILM_MODE");
  return (!filter || strcmp(filter, filter_name(type)) == 0) &&
         (!mode || strcmp(mode, use_table ? "table" : "exact") == 0);
}

/* CLR_BENCH_FILM_INPUT (host, device_buffer), when set, keeps only that input path. */
static int input_selected(int path) {
  const char *input = getenv("CLR_BENCH_FILM_INPUT");
  if (input && strcmp(input, "host") != 0 && strcmp(input, "device_buffer") != 0) {
    if (path == 0)
      fprintf(stderr,
              "bench film: CLR_BENCH_FILM_INPUT=%s: expected host or device_buffer; "
              "running both\n",
              input);
    return 1;
  }
  return !input || strcmp(input, path ? "device_buffer" : "host") == 0;
}

void bench_film(const bench_options *o, const clr_device_info *devices, int device_count) {
  const char *env = getenv("CLR_BENCH_FILM_SPP");
  size_t spp = env ? (size_t)atoi(env) : o->quick ? 2 : 16;
  if (spp < 1) spp = 1;
  size_t count = spp * FILM_W * FILM_H, ref_count = (size_t)FILM_W * FILM_H;
  int reps = bench_reps(o, 1, 3);
  clr_context host_ctx = NULL; /* the reference runs on the host; a film needs a context */
  if (clr_context_create(NULL, &host_ctx) != CLR_SUCCESS) {
    fprintf(stderr, "bench film: %s\n", clr_last_error_message());
    return;
  }
  clr_film tmp = make_film(host_ctx, CLR_FILTER_BOX, 1);
  clr_film_sample *samples = tmp ? random_samples(tmp, count) : NULL;
  film_release(tmp);
  if (!samples) {
    fprintf(stderr, "bench film: no memory for %zu samples\n", count);
    clr_context_release(host_ctx);
    return;
  }
  double baseline[FILTER_COUNT][2], baseline_cpu_ns[FILTER_COUNT][2];
  bench_timing baseline_timing = {0, 0, 0, reps};
  for (int t = 0; t < FILTER_COUNT; ++t)
    for (int m = 0; m < 2; ++m)
      baseline[t][m] = case_selected(filter_types[t], m)
                           ? rate(host_ctx, filter_types[t], m, 2, ref_count, reps, samples, NULL,
                                  &baseline_cpu_ns[t][m], &baseline_timing)
                           : -1;
  for (int i = 0; i < device_count; ++i) {
    clr_context ctx = bench_open_device(o, devices, i, "film");
    if (!ctx) continue;
    for (int t = 0; t < FILTER_COUNT; ++t)
      for (int m = 0; m < 2; ++m)
        for (int path = 0; path < 2 && case_selected(filter_types[t], m); ++path) {
          if (!input_selected(path)) continue;
          film_memory mem = {0, 0, 0};
          double cpu_ns = 0;
          bench_timing timing = {0, 0, 0, reps};
          double v =
              rate(ctx, filter_types[t], m, path, count, reps, samples, &mem, &cpu_ns, &timing);
          printf("{\"bench\":\"film\",");
          bench_json_device(ctx);
          printf(
              ",\"filter\":\"%s\",\"radius\":%g,\"mode\":\"%s\",\"input\":\"%s\","
              "\"resolution\":\"%dx%d\",\"spp\":%zu",
              filter_name(filter_types[t]), (double)FILM_RADIUS, m ? "table" : "exact",
              path ? "device_buffer" : "host", FILM_W, FILM_H, spp);
          if (v < 0) {
            printf(",\"error\":");
            bench_json_escape(stdout, clr_last_error_message());
          } else {
            printf(
                ",\"samples_per_s\":%.4g,\"cpu_ns_per_sample\":%.1f,\"bin_threads\":%d,"
                "\"film_bytes_per_pixel\":%.1f,\"scratch_mib\":%.1f,"
                "\"baseline\":\"host reference, 1 thread\",\"baseline_samples_per_s\":%.4g,"
                "\"baseline_cpu_ns_per_sample\":%.1f,\"ratio\":%.2f",
                v, cpu_ns, mem.bin_threads, mem.sums_bytes_per_pixel, mem.scratch_mib,
                baseline[t][m], baseline_cpu_ns[t][m],
                baseline[t][m] > 0 ? v / baseline[t][m] : 0.0);
            bench_json_spread("samples_per_s", (double)count, &timing);
          }
          printf("}\n");
          fflush(stdout);
        }
    clr_context_release(ctx);
  }
  free(samples);
  clr_context_release(host_ctx);
}
