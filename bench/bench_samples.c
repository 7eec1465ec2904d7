/* Sample generation throughput (values/s) per sampler on each device, against the host reference;
 * halton, sobol and stratified also with pbrt-v4's logic (--seeding pbrt-v4). */
#include <stdlib.h>
#include <string.h>
#include "bench.h"

static const clr_sample_request layout[] = {{2, 0}, {1, 0}, {2, 0}, {1, 0}, {2, 0}, {2, 0}};
#define LAYOUT_VALUES 10

typedef struct run {
  clr_sampler sampler;
  clr_sample_batch batch;
  clr_sample_output out;
  int reference;
} run;

static int run_once(void *user) {
  run *r = user;
  clr_result res = r->reference ? clr_sampler_generate_reference(r->sampler, &r->batch, &r->out)
                                : clr_sampler_generate(r->sampler, &r->batch, &r->out);
  if (res != CLR_SUCCESS) fprintf(stderr, "bench: %s\n", clr_last_error_message());
  return res == CLR_SUCCESS;
}

static void setup_run(run *r, clr_sampler s, int side) {
  memset(r, 0, sizeof *r);
  r->sampler = s;
  clr_sample_batch_init(&r->batch);
  r->batch.pixels = (clr_bounds2i){0, 0, side, side};
  r->batch.requests = layout;
  r->batch.request_count = 6;
  clr_sample_output_init(&r->out);
}

/* A bench line's sampler: a type and a seeding (CLR_SEEDING_PBRT_V4, or the default). */
typedef struct sampler_case {
  clr_sampler_type type;
  int v4;
} sampler_case;

static void case_desc(sampler_case c, clr_sampler_desc *d) {
  clr_sampler_desc_init(d, c.type);
  if (c.v4) d->seeding = CLR_SEEDING_PBRT_V4;
  d->film.x_resolution = d->film.y_resolution = 512;
}

/* Values per second of the single-thread host reference on a smaller batch. */
static double reference_rate(sampler_case c, const bench_options *o) {
  int side = o->quick ? 32 : 64;
  clr_sampler_desc d;
  case_desc(c, &d);
  clr_sampler s = NULL;
  if (clr_sampler_create(NULL, &d, &s) != CLR_SUCCESS) return -1;
  run r;
  setup_run(&r, s, side);
  r.reference = 1;
  size_t values = (size_t)side * side * clr_sampler_spp(s) * LAYOUT_VALUES;
  r.out.host_values = malloc(values * sizeof(float));
  double t = r.out.host_values ? bench_median(bench_reps(o, 1, 3), run_once, &r) : -1;
  free(r.out.host_values);
  clr_sampler_release(s);
  return t > 0 ? (double)values / t : -1;
}

/* The device's timing of `*value_count` values; 0 on failure. */
static int device_timing(clr_context ctx, sampler_case c, const bench_options *o, bench_timing *t,
                         double *value_count) {
  int side = o->quick ? 128 : 512;
  clr_sampler_desc d;
  case_desc(c, &d);
  clr_sampler s = NULL;
  if (clr_sampler_create(ctx, &d, &s) != CLR_SUCCESS) return 0;
  run r;
  setup_run(&r, s, side);
  size_t values = (size_t)side * side * clr_sampler_spp(s) * LAYOUT_VALUES;
  *value_count = (double)values;
  cl_int err;
  r.out.device_values = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_WRITE,
                                       values * sizeof(float), NULL, &err);
  int ok = err == CL_SUCCESS && bench_time(bench_reps(o, 2, 5), run_once, &r, t) && t->min > 0;
  if (err == CL_SUCCESS) clReleaseMemObject(r.out.device_values);
  clr_sampler_release(s);
  return ok;
}

/* Whether CLR_BENCH_SAMPLERS (comma-separated sampler names; unset: every sampler) names t. */
static int sampler_wanted(clr_sampler_type t) {
  const char *list = getenv("CLR_BENCH_SAMPLERS"), *name = clr_sampler_type_name(t);
  if (!list) return 1;
  size_t n = strlen(name);
  for (const char *at = list; (at = strstr(at, name)) != NULL; at += n)
    if ((at == list || at[-1] == ',') && (at[n] == ',' || at[n] == '\0')) return 1;
  return 0;
}

/* Every sampler with its default seeding, then pbrt-v4's halton, sobol and stratified: how many
 * cases (at most `most`). */
static int sampler_cases(sampler_case *cases, int most) {
  static const clr_sampler_type v4[] = {CLR_SAMPLER_HALTON, CLR_SAMPLER_SOBOL,
                                        CLR_SAMPLER_STRATIFIED};
  int n = 0;
  for (int t = 0; t < bench_sampler_count() && n < most; ++t)
    cases[n++] = (sampler_case){(clr_sampler_type)t, 0};
  for (int k = 0; k < 3 && n < most; ++k) cases[n++] = (sampler_case){v4[k], 1};
  return n;
}

void bench_samples(const bench_options *o, const clr_device_info *devices, int device_count) {
  enum { MAX_CASES = 64 };
  sampler_case cases[MAX_CASES];
  int count = sampler_cases(cases, MAX_CASES);
  double baseline[MAX_CASES];
  for (int c = 0; c < count; ++c)
    baseline[c] = sampler_wanted(cases[c].type) ? reference_rate(cases[c], o) : -1;
  for (int i = 0; i < device_count; ++i) {
    clr_context ctx = bench_open_device(o, devices, i, "samples");
    if (!ctx) continue;
    for (int c = 0; c < count; ++c) {
      if (!sampler_wanted(cases[c].type)) continue;
      bench_timing timing;
      double values = 0;
      int ok = device_timing(ctx, cases[c], o, &timing, &values);
      double rate = ok ? values / timing.median : -1;
      printf("{\"bench\":\"samples\",");
      bench_json_device(ctx);
      printf(",\"sampler\":\"%s\"", clr_sampler_type_name(cases[c].type));
      if (cases[c].v4) printf(",\"seeding\":\"pbrt-v4\"");
      printf(",\"layout_values\":%d", LAYOUT_VALUES);
      if (!ok) {
        printf(",\"error\":");
        bench_json_escape(stdout, clr_last_error_message());
      } else {
        printf(
            ",\"values_per_s\":%.4g,\"baseline\":\"host reference, 1 thread\","
            "\"baseline_values_per_s\":%.4g,\"ratio\":%.2f",
            rate, baseline[c], baseline[c] > 0 ? rate / baseline[c] : 0.0);
        bench_json_spread("values_per_s", values, &timing);
      }
      printf("}\n");
      fflush(stdout);
    }
    clr_context_release(ctx);
  }
}
