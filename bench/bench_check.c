/* Simulators (Oclgrind) in the benchmark: no timing, a correctness check against the host
 * reference instead (small sizes), and the gfx90a kernel resources from the portability test. */
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "film_internal.h"

#ifndef CLR_BINARY_DIR
#define CLR_BINARY_DIR "."
#endif

static const clr_sample_request layout[] = {{2, 0}, {1, 0}, {2, 0}, {1, 3}, {2, 0}, {2, 2}};

/* Device vs host values of a 5x3-pixel batch, 4 spp: 1 identical, 0 different, -1 failed. */
static int check_sampler(clr_context ctx, clr_sampler_type type, clr_seeding seeding) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.pixel_samples = 4;
  if (type == CLR_SAMPLER_STRATIFIED) d.x_samples = d.y_samples = 2;
  d.seeding = seeding;
  d.film.x_resolution = d.film.y_resolution = 16;
  clr_sampler s = NULL;
  if (clr_sampler_create(ctx, &d, &s) != CLR_SUCCESS) return -1;
  int32_t per = 0;
  clr_sample_layout_values(layout, 6, &per);
  size_t n = 5 * 3 * 4 * (size_t)per;
  float *a = calloc(n, sizeof(float)), *b = calloc(n, sizeof(float));
  clr_sample_batch batch;
  clr_sample_batch_init(&batch);
  batch.pixels = (clr_bounds2i){2, 3, 7, 6};
  batch.requests = layout;
  batch.request_count = 6;
  clr_sample_output out;
  clr_sample_output_init(&out);
  int result = -1;
  if (a && b) {
    out.host_values = a;
    clr_result r = clr_sampler_generate(s, &batch, &out);
    out.host_values = b;
    if (r == CLR_SUCCESS && clr_sampler_generate_reference(s, &batch, &out) == CLR_SUCCESS)
      result = memcmp(a, b, n * sizeof(float)) == 0;
  }
  free(a);
  free(b);
  clr_sampler_release(s);
  return result;
}

/* Device vs host film sums for one filter on a 24x16 film: 1 identical, 0 different, -1 failed. */
static int check_film(clr_context ctx, clr_filter_type type, int table) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = 24;
  d.y_resolution = 16;
  clr_filter_desc_init(&d.filter, type);
  d.filter.use_table = table;
  clr_film dev = NULL, ref = NULL;
  if (film_create(ctx, &d, &dev) != CLR_SUCCESS) return -1;
  if (film_create(ctx, &d, &ref) != CLR_SUCCESS) {
    film_release(dev);
    return -1;
  }
  enum { N = 500, PIXELS = 24 * 16 };
  clr_film_sample samples[N];
  uint32_t st = 99u;
  for (int i = 0; i < N; ++i) {
    float v[6];
    for (int c = 0; c < 6; ++c) {
      st ^= st << 13;
      st ^= st >> 17;
      st ^= st << 5;
      v[c] = (float)(st >> 8) * 0x1p-24f;
    }
    samples[i] =
        (clr_film_sample){v[0] * 26.0f - 1.0f, v[1] * 18.0f - 1.0f, v[2], v[3], v[4], 0.5f + v[5]};
  }
  static double a[PIXELS * 4], b[PIXELS * 4];
  int result = -1;
  if (film_add_samples(dev, samples, N) == CLR_SUCCESS &&
      film_add_samples_reference(ref, samples, N) == CLR_SUCCESS &&
      film_get_sums(dev, a, a + 3 * PIXELS, NULL) == CLR_SUCCESS &&
      film_get_sums(ref, b, b + 3 * PIXELS, NULL) == CLR_SUCCESS)
    result = memcmp(a, b, sizeof a) == 0;
  film_release(dev);
  film_release(ref);
  return result;
}

static void print_check(const char *bench, clr_context ctx, const char *what, int result) {
  printf("{\"bench\":\"%s\",", bench);
  bench_json_device(ctx);
  printf(",\"case\":\"%s\",\"check\":\"%s\",\"timing\":\"skipped: simulator\"}\n", what,
         result > 0    ? "identical to the host reference"
         : result == 0 ? "DIFFERENT from the host reference"
                       : "failed");
  fflush(stdout);
}

void bench_check(const char *bench, clr_context ctx) {
  char what[96];
  if (strcmp(bench, "samples") == 0) {
    for (int t = 0; t <= CLR_SAMPLER_MAXMINDIST; ++t)
      for (int seeding = 0; seeding < 2; ++seeding) {
        snprintf(what, sizeof what, "%s, %s seeding", clr_sampler_type_name((clr_sampler_type)t),
                 seeding ? "pixel" : "pbrt-v3");
        print_check(bench, ctx, what,
                    check_sampler(ctx, (clr_sampler_type)t, (clr_seeding)seeding));
      }
  } else if (strcmp(bench, "film") == 0) {
    for (int type = 0; type < CLR_FILTER_TYPE_COUNT; ++type)
      for (int table = 0; table < 2; ++table) {
        snprintf(what, sizeof what, "%s %s", clr_filter_type_name((clr_filter_type)type),
                 table ? "table" : "exact");
        print_check(bench, ctx, what, check_film(ctx, (clr_filter_type)type, table));
      }
  } else {
    printf("{\"bench\":\"%s\",", bench);
    bench_json_device(ctx);
    printf(",\"timing\":\"skipped: simulator (samples and film are checked)\"}\n");
  }
}

void bench_kernel_resources(void) {
  char path[4096];
  snprintf(path, sizeof path, "%s/tests/kernel-resources.jsonl", CLR_BINARY_DIR);
  FILE *f = fopen(path, "r");
  if (!f) {
    printf(
        "{\"bench\":\"kernel_resources\",\"error\":\"%s missing: run test_kernel_portability "
        "(ctest -R kernel_portability)\"}\n",
        path);
    return;
  }
  char line[2048];
  while (fgets(line, sizeof line, f)) {
    if (line[0] != '{') continue;
    printf("{\"bench\":\"kernel_resources\",%s", line + 1);
  }
  fclose(f);
  fflush(stdout);
}
