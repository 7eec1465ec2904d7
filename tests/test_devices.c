/* Every kernel on every OpenCL implementation the test suite knows, in both kernel shapes, against
 * the host reference: bit-identical sample values and indices (each sampler, each seeding mode,
 * the halton/sobol large-index and past-the-tables paths) and film sums (every filter, exact and
 * table).
 *
 * Any other device the machine's own ICDs list (a vendor GPU driver) runs the same checks in
 * both shapes (test_other_devices).
 *
 * Each (implementation, shape) runs as a child process of this program (`test_devices --child`)
 * with its own environment:
 *   - PoCL: the machine's default ICDs, CLRENDER_DEVICE naming PoCL's platform, an empty kernel
 *     cache of its own and no program binary cache, so every kernel compiles and a build warning
 *     on its stderr fails the test;
 *   - Oclgrind: OCL_ICD_VENDORS pointing at a folder this test writes in the build tree with one
 *     .icd naming liboclgrind-rt-icd.so, so Oclgrind (which presents itself as a GPU) is never
 *     registered for anything else on the machine. Oclgrind exits 0 even when it finds invalid
 *     memory accesses, data races or API misuse and only reports them: its log (OCLGRIND_LOG)
 *     and the child's stderr must be free of any diagnostic (build warnings included). Its
 *     uninitialized-value plugin is not used: it stops at LLVM's `freeze` instruction.
 * Sizes are small: Oclgrind interprets every instruction. */
#define _DEFAULT_SOURCE
#define _XOPEN_SOURCE 700 /* nftw */
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>
#include "clrender.h"
#include "clr_internal.h"
#include "film_internal.h"
#include "xorshift_test_random.h"
#include "sample_batch_test_util.h"

#ifndef CLR_OCLGRIND_ICD
#define CLR_OCLGRIND_ICD ""
#endif

/* ---- Child: one implementation, one shape. ---- */

static clr_context ctx;
static int failures;

#define CHECK(cond, ...)                          \
  do {                                            \
    if (!(cond)) {                                \
      printf("FAIL %s:%d: ", __FILE__, __LINE__); \
      printf(__VA_ARGS__);                        \
      printf("\n");                               \
      ++failures;                                 \
    }                                             \
  } while (0)

static const clr_sample_request camera10[] = {{2, 0}, {1, 0}, {2, 0}, {1, 0}, {2, 0}, {2, 0}};
static const clr_sample_request with_arrays[] = {{2, 0}, {1, 0}, {2, 0}, {1, 5}, {2, 0},
                                                 {2, 7}, {1, 0}, {1, 0}, {1, 0}, {2, 0},
                                                 {2, 0}, {2, 3}, {1, 0}};
/* with_arrays with skipped requests: time, lens, the 2D array of 7, a stream and a fallback. */
#define SKIP CLR_SAMPLE_REQUEST_SKIPPED
static const clr_sample_request with_skips[] = {
    {2, 0},        {1 | SKIP, 0}, {2 | SKIP, 0}, {1, 5},        {2, 0}, {2 | SKIP, 7}, {1, 0},
    {1 | SKIP, 0}, {1, 0},        {2, 0},        {2 | SKIP, 0}, {2, 3}, {1, 0}};

/* Device and host values (and indices) of one batch: returns whether they are identical. */
static int compare_batch(clr_sampler s, const char *what, clr_bounds2i px, int first, int count,
                         const clr_sample_request *req, int nreq) {
  int32_t per = 0;
  if (clr_sample_layout_values(req, nreq, &per) != CLR_SUCCESS) return 0;
  size_t spp = (size_t)(count ? count : clr_sampler_spp(s));
  size_t items = (size_t)(px.x1 - px.x0) * (size_t)(px.y1 - px.y0) * spp;
  size_t n = items * (size_t)per;
  float *dev = malloc(n * sizeof(float)), *ref = malloc(n * sizeof(float));
  uint64_t *di = malloc(items * sizeof(uint64_t)), *ri = malloc(items * sizeof(uint64_t));
  int ok = dev && ref && di && ri;
  if (ok) {
    /* Different fill patterns: values the kernels leave unwritten would differ. */
    memset(dev, 0xa5, n * sizeof(float));
    memset(ref, 0x5a, n * sizeof(float));
    clr_sample_batch b = sample_batch(px, first, count, req, nreq);
    clr_sample_output out;
    clr_sample_output_init(&out);
    out.host_values = dev;
    out.host_indices = di;
    clr_result r = clr_sampler_generate(s, &b, &out);
    CHECK(r == CLR_SUCCESS, "%s: device: %s", what, clr_last_error_message());
    out.host_values = ref;
    out.host_indices = ri;
    clr_result rr = clr_sampler_generate_reference(s, &b, &out);
    CHECK(rr == CLR_SUCCESS, "%s: reference: %s", what, clr_last_error_message());
    ok = r == CLR_SUCCESS && rr == CLR_SUCCESS;
    size_t bad = 0;
    for (size_t i = 0; ok && i < n; ++i)
      if (memcmp(&dev[i], &ref[i], 4) != 0 && bad++ < 3)
        printf("  %s: value %zu device %.9g (0x%08x) reference %.9g\n", what, i, (double)dev[i],
               (unsigned)*(uint32_t *)&dev[i], (double)ref[i]);
    if (ok) CHECK(bad == 0, "%s: %zu of %zu values differ", what, bad, n);
    if (ok) CHECK(memcmp(di, ri, items * sizeof(uint64_t)) == 0, "%s: indices differ", what);
    ok = ok && bad == 0;
  }
  free(dev);
  free(ref);
  free(di);
  free(ri);
  return ok;
}

static clr_sampler make_sampler(clr_sampler_type type, clr_seeding seeding, int res, int spp) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.seeding = seeding;
  d.pixel_samples = spp;
  if (type == CLR_SAMPLER_STRATIFIED) d.x_samples = d.y_samples = 2;
  d.film.x_resolution = d.film.y_resolution = res;
  d.film.filter_radius[0] = d.film.filter_radius[1] = 1.5f;
  clr_sampler s = NULL;
  clr_result r = clr_sampler_create(ctx, &d, &s);
  CHECK(r == CLR_SUCCESS, "clr_sampler_create: %s", clr_last_error_message());
  return r == CLR_SUCCESS ? s : NULL;
}

/* pbrt-v4's samplers' per-item and per-pixel kernels serve both shapes: on Oclgrind (slow) they
 * run in the portable context only (check_v4_lanes runs the SIMD ones there). */
static int v4_here(void) {
  return !strstr(clr_context_device_name(ctx), "Oclgrind") ||
         clr_context_kernel_shape(ctx) == CLR_KERNELS_PORTABLE;
}

/* pbrt-v4's own samplers run pbrt-v4's algorithm under every seeding (tested once); 02sequence and
 * maxmindist have no pbrt-v4 version. */
static int seeding_applies(int type, int seeding) {
  if ((type >= CLR_SAMPLER_INDEPENDENT || seeding == CLR_SEEDING_PBRT_V4) && !v4_here()) return 0;
  if (type >= CLR_SAMPLER_INDEPENDENT) return seeding == CLR_SEEDING_PBRT_V4;
  return seeding != CLR_SEEDING_PBRT_V4 ||
         (type != CLR_SAMPLER_ZEROTWO && type != CLR_SAMPLER_MAXMINDIST);
}

static void check_samplers(void) {
  static const char *seedings[] = {"pbrt-v3", "pixel", "pbrt-v4"};
  for (int t = 0; t < CLR_SAMPLER_TYPE_COUNT; ++t)
    for (int seeding = 0; seeding < 3; ++seeding) {
      if (!seeding_applies(t, seeding)) continue;
      clr_sampler s = make_sampler((clr_sampler_type)t, (clr_seeding)seeding, 20, 4);
      if (!s) continue;
      char what[96];
      /* A batch away from the origin (offsets, a partial pbrt-v3 tile) and a width that is
       * not a multiple of 8 (the SIMD kernels' padding lanes). */
      clr_bounds2i px = {3, 14, 12, 19};
      snprintf(what, sizeof what, "%s/%s camera", clr_sampler_type_name((clr_sampler_type)t),
               seedings[seeding]);
      int ok = compare_batch(s, what, px, 0, 0, camera10, 6);
      snprintf(what, sizeof what, "%s/%s arrays", clr_sampler_type_name((clr_sampler_type)t),
               seedings[seeding]);
      ok &= compare_batch(s, what, (clr_bounds2i){0, 0, 5, 3}, 1, 2, with_arrays,
                          (int)(sizeof with_arrays / sizeof with_arrays[0]));
      ok &= compare_batch(s, what, (clr_bounds2i){0, 0, 5, 3}, 1, 2, with_skips,
                          (int)(sizeof with_skips / sizeof with_skips[0]));
      printf("%-40s %s\n", what, ok ? "identical" : "DIFFERENT");
      clr_sampler_release(s);
    }
}

/* A pbrt-v4-seeded sampler of `type` (40x24 film) against the reference: samples first ..
 * first + count - 1 (all for count 0) of pixels px with the camera layout, reported as
 * "<sampler> <label> <randomization>". */
static void check_v4_case(clr_sampler_type type, clr_randomization randomization, uint32_t seed,
                          int spp, clr_bounds2i px, int first, int count, const char *label) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.seeding = CLR_SEEDING_PBRT_V4;
  d.randomization = randomization;
  d.seed = seed;
  d.pixel_samples = spp;
  d.film.x_resolution = 40;
  d.film.y_resolution = 24;
  clr_sampler s = NULL;
  CHECK(clr_sampler_create(ctx, &d, &s) == CLR_SUCCESS, "create: %s", clr_last_error_message());
  if (!s) return;
  char what[96];
  snprintf(what, sizeof what, "%s %s %s", clr_sampler_type_name(type), label,
           clr_randomization_name(randomization));
  int ok = compare_batch(s, what, px, first, count, camera10, 6);
  printf("%-40s %s\n", what, ok ? "identical" : "DIFFERENT");
  clr_sampler_release(s);
}

/* pbrt-v4's randomizations of halton, sobol, paddedsobol and zsobol (the camera layout). */
static void check_v4_randomizations(void) {
  if (!v4_here()) return;
  static const clr_sampler_type types[] = {CLR_SAMPLER_HALTON, CLR_SAMPLER_SOBOL,
                                           CLR_SAMPLER_PADDEDSOBOL, CLR_SAMPLER_ZSOBOL};
  for (int t = 0; t < 4; ++t)
    for (int r = CLR_RANDOMIZATION_NONE; r <= CLR_RANDOMIZATION_OWEN; ++r)
      if (types[t] != CLR_SAMPLER_HALTON || r != CLR_RANDOMIZATION_FASTOWEN)
        check_v4_case(types[t], (clr_randomization)r, 5, 8, (clr_bounds2i){31, 17, 34, 19}, 3, 3,
                      "pbrt-v4");
}

/* The SIMD kernels of zsobol, paddedsobol and pmj02bn (8 pixels per work-item) and of pbrt-v4's
 * sobol, independent, stratified and halton (8 items) on every device, Oclgrind's SIMD context
 * included: every randomizer (the default for independent, stratified and pmj02bn), spp 8 and 2
 * (zsobol: odd powers of two) or 5 (paddedsobol: cycle walks; the others), a batch of 18 pixels
 * (padding lanes). */
static void check_v4_lanes(void) {
  if (clr_context_kernel_shape(ctx) != CLR_KERNELS_SIMD) return;
  static const clr_sampler_type types[] = {
      CLR_SAMPLER_ZSOBOL,     CLR_SAMPLER_PADDEDSOBOL, CLR_SAMPLER_SOBOL, CLR_SAMPLER_INDEPENDENT,
      CLR_SAMPLER_STRATIFIED, CLR_SAMPLER_PMJ02BN,     CLR_SAMPLER_HALTON};
  for (int t = 0; t < 7; ++t) {
    if (types[t] == CLR_SAMPLER_INDEPENDENT || types[t] == CLR_SAMPLER_STRATIFIED ||
        types[t] == CLR_SAMPLER_PMJ02BN) {
      check_v4_case(types[t], CLR_RANDOMIZATION_DEFAULT, 3, 5, (clr_bounds2i){3, 2, 12, 4}, 0, 0,
                    "lanes");
      continue;
    }
    for (int r = CLR_RANDOMIZATION_NONE; r <= CLR_RANDOMIZATION_OWEN; ++r)
      if (types[t] != CLR_SAMPLER_HALTON || r != CLR_RANDOMIZATION_FASTOWEN)
        check_v4_case(types[t], (clr_randomization)r, 3,
                      t                             ? 5
                      : r == CLR_RANDOMIZATION_OWEN ? 2
                                                    : 8,
                      (clr_bounds2i){3, 2, 12, 4}, 0, 0, "lanes");
  }
}

/* The global samplers' other paths: indices past 2^32 (halton), more than 32 index bits (sobol),
 * halton reversals past 2^32, values past the tables (hash fallback), halton's pair tables with
 * the 8 lanes of a work-item in one pixel (the bench's case). */
static void check_global_paths(void) {
  static clr_sample_request many[601];
  for (int i = 0; i < 601; ++i) many[i] = (clr_sample_request){2, 0};
  static const clr_sample_request arrays[] = {{2, 0}, {1, 0}, {2, 3}, {1, 2}};
  struct {
    clr_sampler_type type;
    int spp, first, count;
    const clr_sample_request *req;
    int nreq;
    const char *what;
  } cases[] = {
      {CLR_SAMPLER_HALTON, 1 << 18, (1 << 18) - 2, 2, camera10, 6, "halton indices > 2^32"},
      {CLR_SAMPLER_HALTON, 4096, 4094, 2, many, 201, "halton 3-digit reversals"},
      {CLR_SAMPLER_HALTON, 4096, 200, 3, arrays, 4, "halton arrays, large spp"},
      {CLR_SAMPLER_HALTON, 16, 0, 1, many, 601, "halton past 1000 primes"},
      {CLR_SAMPLER_HALTON, 16, 0, 16, camera10, 6, "halton pair tables, one pixel"},
      {CLR_SAMPLER_SOBOL, 1 << 16, (1 << 16) - 2, 2, camera10, 6, "sobol 36-bit indices"},
      {CLR_SAMPLER_SOBOL, 1 << 16, 100, 2, arrays, 4, "sobol arrays, large spp"},
      {CLR_SAMPLER_SOBOL, 16, 0, 1, many, 601, "sobol past 1024 dimensions"},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    clr_sampler_desc d;
    clr_sampler_desc_init(&d, cases[c].type);
    d.pixel_samples = cases[c].spp;
    d.film.x_resolution = d.film.y_resolution = 512;
    clr_sampler s = NULL;
    clr_result r = clr_sampler_create(ctx, &d, &s);
    CHECK(r == CLR_SUCCESS, "%s: %s", cases[c].what, clr_last_error_message());
    if (r != CLR_SUCCESS) continue;
    int ok = compare_batch(s, cases[c].what, (clr_bounds2i){300, 301, 303, 302}, cases[c].first,
                           cases[c].count, cases[c].req, cases[c].nreq);
    printf("%-40s %s\n", cases[c].what, ok ? "identical" : "DIFFERENT");
    clr_sampler_release(s);
  }
}

static clr_film make_film(int type, int table, int tile) {
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = 21;
  d.y_resolution = 13;
  clr_filter_desc_init(&d.filter, (clr_filter_type)type);
  d.filter.use_table = table;
  d.accumulation_tile_size = tile;
  clr_film film = NULL;
  clr_result r = film_create(ctx, &d, &film);
  CHECK(r == CLR_SUCCESS, "film_create: %s", clr_last_error_message());
  return r == CLR_SUCCESS ? film : NULL;
}

static int film_sums(clr_film film, double **out, size_t *n) {
  clr_bounds2i b = film_pixel_bounds(film);
  *n = (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0) * 7;
  *out = malloc(*n * sizeof(double));
  if (!*out) return 0;
  size_t px = *n / 7;
  return film_get_sums(film, *out, *out + 3 * px, *out + 4 * px) == CLR_SUCCESS;
}

static void check_film(void) {
  const size_t n = 600;
  clr_film_sample *samples = malloc(n * sizeof *samples);
  if (!samples) return;
  for (int type = 0; type < CLR_FILTER_TYPE_COUNT; ++type)
    for (int table = 0; table < 2; ++table) {
      clr_film ref = make_film(type, table, 16);
      if (!ref) continue;
      clr_bounds2i sb = film_sample_bounds(ref);
      rng_state = 77u + (uint32_t)(type * 2 + table);
      float w = (float)(sb.x1 - sb.x0) + 2.0f, h = (float)(sb.y1 - sb.y0) + 2.0f;
      for (size_t i = 0; i < n; ++i) {
        samples[i].x = (float)sb.x0 - 1.0f + rnd() * w;
        samples[i].y = (float)sb.y0 - 1.0f + rnd() * h;
        samples[i].r = rnd() * 4.0f;
        samples[i].g = rnd();
        samples[i].b = rnd() * 0.25f;
        samples[i].weight = 0.5f + rnd();
      }
      CHECK(film_add_samples_reference(ref, samples, n) == CLR_SUCCESS, "reference: %s",
            clr_last_error_message());
      double *expect = NULL;
      size_t count = 0;
      CHECK(film_sums(ref, &expect, &count), "film_get_sums (reference)");
      double total = 0;
      for (size_t i = 0; expect && i < count / 7; ++i) total += expect[3 * (count / 7) + i];
      CHECK(total > 0, "no filter weight");
      char what[96];
      snprintf(what, sizeof what, "film %s %s", clr_filter_type_name((clr_filter_type)type),
               table ? "table" : "exact");
      int ok = expect != NULL;
      /* Tile sizes 16 and 4 from host samples; 16 from a device buffer of samples. */
      static const int tiles[] = {16, 4, 16};
      for (int t = 0; t < 3 && expect; ++t) {
        clr_film film = make_film(type, table, tiles[t]);
        if (!film) {
          ok = 0;
          continue;
        }
        clr_result r;
        if (t < 2) {
          r = film_add_samples(film, samples, n);
        } else {
          cl_int err = CL_SUCCESS;
          cl_mem buf =
              clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                             n * sizeof *samples, samples, &err);
          r = err == CL_SUCCESS ? film_add_samples_buffer(film, buf, n) : CLR_ERROR_OPENCL;
          if (err == CL_SUCCESS) clReleaseMemObject(buf);
        }
        CHECK(r == CLR_SUCCESS, "%s: film_add_samples: %s", what, clr_last_error_message());
        double *got = NULL;
        size_t gn = 0;
        int same = r == CLR_SUCCESS && film_sums(film, &got, &gn) && gn == count &&
                   memcmp(got, expect, count * sizeof(double)) == 0;
        CHECK(same, "%s, tile %d: sums differ from the reference", what, tiles[t]);
        CHECK(film_sample_count(film) == film_sample_count(ref), "%s: accepted counts differ",
              what);
        ok &= same;
        free(got);
        film_release(film);
      }
      printf("%-40s %s\n", what, ok ? "identical" : "DIFFERENT");
      free(expect);
      film_release(ref);
    }
  free(samples);
}

/* A deliberately invalid launch (writes past a 16-word buffer) for the test that proves Oclgrind's
 * reports reach the checks. */
static int run_invalid_child(void) {
  if (clr_context_create(NULL, &ctx) != CLR_SUCCESS) return 1;
  cl_int err = CL_SUCCESS;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_WRITE, 16 * sizeof(cl_uint),
                              NULL, &err);
  cl_kernel k = NULL;
  if (err != CL_SUCCESS ||
      clr_context_kernel(ctx, "selftest_kernels.cl", NULL, "clr_selftest_fill", &k) != CLR_SUCCESS)
    return 1;
  cl_uint value = 7;
  size_t global = 32;
  clSetKernelArg(k, 0, sizeof buf, &buf);
  clSetKernelArg(k, 1, sizeof value, &value);
  clEnqueueNDRangeKernel(clr_context_cl_queue(ctx), k, 1, NULL, &global, NULL, 0, NULL, NULL);
  clFinish(clr_context_cl_queue(ctx));
  clReleaseKernel(k);
  clReleaseMemObject(buf);
  clr_context_release(ctx);
  return 0;
}

static int run_child(void) {
  setvbuf(stdout, NULL, _IOLBF, 0);
  clr_result r = clr_context_create(NULL, &ctx);
  if (r != CLR_SUCCESS) {
    printf("FAIL: clr_context_create: %s\n", clr_last_error_message());
    return 1;
  }
  const char *expect_device = getenv("CLR_TEST_EXPECT_DEVICE");
  const char *expect_shape = getenv("CLRENDER_KERNELS");
  printf("device: %s, kernels: %s\n", clr_context_device_name(ctx),
         clr_kernel_shape_name(clr_context_kernel_shape(ctx)));
  CHECK(!expect_device || strstr(clr_context_device_name(ctx), expect_device),
        "device %s is not %s", clr_context_device_name(ctx), expect_device);
  CHECK(!expect_shape ||
            strcmp(clr_kernel_shape_name(clr_context_kernel_shape(ctx)), expect_shape) == 0,
        "kernel shape %s, expected %s", clr_kernel_shape_name(clr_context_kernel_shape(ctx)),
        expect_shape);
  check_samplers();
  check_v4_randomizations();
  check_v4_lanes();
  check_global_paths();
  check_film();
  clr_context_release(ctx);
  printf("%d failure(s)\n", failures);
  return failures ? 1 : 0;
}

/* ---- Parent: the cmocka tests, one child per implementation and shape. ---- */

static char self_path[4096];

static char *read_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t cap = 4096, len = 0;
  char *text = malloc(cap);
  size_t got;
  while (text && (got = fread(text + len, 1, cap - len - 1, f)) > 0) {
    len += got;
    if (cap - len < 2) {
      char *bigger = realloc(text, cap * 2);
      if (!bigger) {
        free(text);
        text = NULL;
        break;
      }
      text = bigger;
      cap *= 2;
    }
  }
  fclose(f);
  if (text) text[len] = 0;
  return text;
}

/* Runs `test_devices --child` with the given environment additions (NULL-terminated name, value
 * pairs); its stderr goes to err_path. Returns the exit status (-1: did not run). */
static int run_child_process(const char *const *env, const char *err_path, const char *mode) {
  fflush(stdout);
  pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    for (int i = 0; env[i]; i += 2) setenv(env[i], env[i + 1], 1);
    int fd = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 2);
      close(fd);
    }
    execl(self_path, self_path, mode, (char *)NULL);
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status)
                           : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

/* Fails on any Oclgrind report or fatal error text. */
static void assert_no_diagnostics(const char *what, const char *path) {
  char *text = read_file(path);
  if (!text) return; /* never written: nothing reported */
  size_t len = strlen(text);
  if (len) fprintf(stderr, "%s (%s):\n%s\n", what, path, text);
  free(text);
  assert_int_equal(len, 0);
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw) {
  (void)st, (void)flag, (void)ftw;
  return remove(path);
}

/* An empty folder at `path` (a previous run's contents removed). */
static void make_empty_dir(const char *path) {
  if (access(path, F_OK) == 0)
    assert_int_equal(nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS), 0);
  assert_int_equal(mkdir(path, 0755), 0);
}

/* Writes the private ICD folder naming only Oclgrind into `icd_dir`. */
static void write_oclgrind_icd(const char *icd_dir) {
  char icd[4300];
  mkdir(icd_dir, 0755);
  snprintf(icd, sizeof icd, "%s/oclgrind.icd", icd_dir);
  if (!*CLR_OCLGRIND_ICD || access(CLR_OCLGRIND_ICD, R_OK) != 0)
    fail_msg(
        "Oclgrind's ICD library (liboclgrind-rt-icd.so) was not found at configure time "
        "(\"%s\"): install Debian's oclgrind (scripts/install-deps.sh) and re-run cmake",
        CLR_OCLGRIND_ICD);
  FILE *f = fopen(icd, "w");
  assert_non_null(f);
  fprintf(f, "%s\n", CLR_OCLGRIND_ICD);
  fclose(f);
}

static void run_on(const char *implementation, const char *shape) {
  char dir[4096], err_path[4200], log_path[4200];
  snprintf(dir, sizeof dir, "%s/tests/devices", CLR_BINARY_DIR);
  mkdir(dir, 0755);
  snprintf(err_path, sizeof err_path, "%s/%s-%s.stderr", dir, implementation, shape);
  snprintf(log_path, sizeof log_path, "%s/%s-%s.oclgrind.log", dir, implementation, shape);
  remove(log_path);
  printf("== %s, %s kernels\n", implementation, shape);
  int status;
  if (strcmp(implementation, "oclgrind") == 0) {
    /* The private ICD folder: only Oclgrind, only for this child. */
    char icd_dir[4200];
    snprintf(icd_dir, sizeof icd_dir, "%s/oclgrind-icd", dir);
    write_oclgrind_icd(icd_dir);
    const char *env[] = {
        "OCL_ICD_VENDORS", icd_dir, "OPENCL_VENDOR_PATH", icd_dir, "CLRENDER_DEVICE", "Oclgrind",
        "CLR_TEST_EXPECT_DEVICE", "Oclgrind", "CLRENDER_KERNELS", shape, "OCLGRIND_CHECK_API", "1",
        "OCLGRIND_DATA_RACES", "1", "OCLGRIND_LOG", log_path, "OCLGRIND_NUM_THREADS", "1",
        /* Fewer work-items per group than the kernels' usual 64: launches must
                          * take their sizes from the device. */
        "OCLGRIND_MAX_WGSIZE", "16", NULL};
    status = run_child_process(env, err_path, "--child");
    assert_no_diagnostics("Oclgrind log", log_path);
  } else {
    /* Kernels compiled afresh (empty PoCL cache, no program binaries), so their build warnings
     * reach stderr on every machine, not only where the caches are cold. */
    char pocl_cache[4200];
    snprintf(pocl_cache, sizeof pocl_cache, "%s/pocl-cache-%s", dir, shape);
    make_empty_dir(pocl_cache);
    const char *env[] = {"CLRENDER_DEVICE",
                         "Portable Computing Language",
                         "CLR_TEST_EXPECT_DEVICE",
                         "Portable Computing Language",
                         "CLRENDER_KERNELS",
                         shape,
                         "POCL_CACHE_DIR",
                         pocl_cache,
                         "CLRENDER_PROGRAM_CACHE",
                         "0",
                         NULL};
    status = run_child_process(env, err_path, "--child");
  }
  assert_no_diagnostics("child stderr", err_path);
  assert_int_equal(status, 0);
}

/* The checks above can only pass for the right reason if Oclgrind's reports reach them: an
 * out-of-bounds write must show up in its log while the process still exits 0. */
static void test_oclgrind_reports_reach_the_test(void **state) {
  (void)state;
  char dir[4096], icd_dir[4200], log_path[4200], err_path[4200];
  snprintf(dir, sizeof dir, "%s/tests/devices", CLR_BINARY_DIR);
  mkdir(dir, 0755);
  snprintf(icd_dir, sizeof icd_dir, "%s/oclgrind-icd", dir);
  snprintf(log_path, sizeof log_path, "%s/invalid.oclgrind.log", dir);
  snprintf(err_path, sizeof err_path, "%s/invalid.stderr", dir);
  remove(log_path);
  write_oclgrind_icd(icd_dir);
  const char *env[] = {"OCL_ICD_VENDORS", icd_dir,           "OPENCL_VENDOR_PATH",
                       icd_dir,           "CLRENDER_DEVICE", "Oclgrind",
                       "OCLGRIND_LOG",    log_path,          NULL};
  assert_int_equal(run_child_process(env, err_path, "--invalid-child"), 0);
  char *log = read_file(log_path);
  assert_non_null(log);
  assert_non_null(strstr(log, "Invalid write"));
  free(log);
}

/* Every other device of the machine's own ICDs (a vendor GPU driver, another CPU runtime), in
 * both shapes: none on a machine with PoCL only. */
static void test_other_devices(void **state) {
  (void)state;
  clr_device_info infos[64];
  int count = 0;
  assert_int_equal(clr_device_list(infos, 64, &count), CLR_SUCCESS);
  int others = 0;
  for (int i = 0; i < count && i < 64; ++i) {
    if (strstr(infos[i].platform_name, "Portable Computing Language")) continue;
    ++others;
    for (int k = 0; k < 2; ++k) {
      const char *shape = k ? "simd" : "portable";
      char index[16], dir[4096], err_path[4300];
      snprintf(index, sizeof index, "%d", i);
      snprintf(dir, sizeof dir, "%s/tests/devices", CLR_BINARY_DIR);
      mkdir(dir, 0755);
      snprintf(err_path, sizeof err_path, "%s/device%d-%s.stderr", dir, i, shape);
      printf("== %s: %s, %s kernels\n", infos[i].platform_name, infos[i].device_name, shape);
      const char *env[] = {"CLRENDER_DEVICE", index, "CLRENDER_KERNELS", shape, NULL};
      int status = run_child_process(env, err_path, "--child");
      assert_no_diagnostics("child stderr", err_path);
      assert_int_equal(status, 0);
    }
  }
  printf("%d device(s) besides PoCL\n", others);
}

static void test_pocl_simd(void **state) {
  (void)state;
  run_on("pocl", "simd");
}

static void test_pocl_portable(void **state) {
  (void)state;
  run_on("pocl", "portable");
}

static void test_oclgrind_simd(void **state) {
  (void)state;
  run_on("oclgrind", "simd");
}

static void test_oclgrind_portable(void **state) {
  (void)state;
  run_on("oclgrind", "portable");
}

int main(int argc, char **argv) {
  if (argc > 1 && strcmp(argv[1], "--child") == 0) return run_child();
  if (argc > 1 && strcmp(argv[1], "--invalid-child") == 0) return run_invalid_child();
  ssize_t n = readlink("/proc/self/exe", self_path, sizeof self_path - 1);
  if (n <= 0)
    snprintf(self_path, sizeof self_path, "%s", argv[0]);
  else
    self_path[n] = 0;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_oclgrind_reports_reach_the_test),
      cmocka_unit_test(test_pocl_simd),
      cmocka_unit_test(test_pocl_portable),
      cmocka_unit_test(test_oclgrind_simd),
      cmocka_unit_test(test_oclgrind_portable),
      cmocka_unit_test(test_other_devices),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
