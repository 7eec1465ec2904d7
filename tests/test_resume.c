/* Resumable and time-bounded renders (issue #13): an 8-spp image resumed to 16 spp equals a
 * 16-spp render within the merge tolerance (1e-5 relative to the larger of the pixel and the
 * image mean); --time-limit 0 renders exactly one pass and records it; a render interrupted
 * (SIGINT) after a checkpoint keeps whole passes and resumes to the full render; images of
 * another render are refused with a message naming the difference. No timing: the interrupt
 * arrives while the CLI is stopped by tests/fault_preload.c in its checkpoint write. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <glob.h>
#include "exr_io.h"
#include "hardening_util.h"
#include "resume.h"
#include <string.h>

#define SCENE CLR_SOURCE_DIR "/scenes/cornell-box.pbrt"

static char dir[] = CLR_BINARY_DIR "/clr_resume_XXXXXX";
static char log_path[sizeof dir + 16];

/* Runs `clrender render SCENE <common flags> ARGS...` (NULL-terminated); returns the exit
 * status; with `stop` the child stops itself before each rename and *pid_out gets its pid. */
static pid_t start(const char *const *args, int stop) {
  pid_t pid = fork();
  if (pid != 0) return pid;
  if (stop) hu_stop_before_commit();
  FILE *f = freopen(log_path, "w", stderr);
  if (!f) _exit(126);
  char *argv[40];
  int n = 0;
  const char *common[] = {"clrender",     "render", SCENE, "--nthreads", "2",  "--quiet",
                          "--cropwindow", "0.3",    "0.7", "0.3",        "0.7"};
  for (size_t i = 0; i < sizeof common / sizeof common[0]; ++i) argv[n++] = (char *)common[i];
  for (int i = 0; args[i]; ++i) argv[n++] = (char *)args[i];
  argv[n] = NULL;
  execv(CLR_CLI_PATH, argv);
  _exit(127);
}

static int render(const char *const *args) {
  pid_t pid = start(args, 0);
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status));
  return WEXITSTATUS(status);
}

static void in_dir(char *buf, size_t size, const char *name) {
  snprintf(buf, size, "%s/%s", dir, name);
}

static int log_contains(const char *needle) {
  FILE *f = fopen(log_path, "r");
  char text[4096] = {0};
  size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
  if (f) fclose(f);
  text[n] = 0;
  if (!strstr(text, needle)) printf("log lacks \"%s\":\n%s\n", needle, text);
  return strstr(text, needle) != NULL;
}

static int32_t int_attr(const char *path, const char *name) {
  clr_exr_image *im = NULL;
  assert_int_equal(clr_exr_read(path, &im), CLR_SUCCESS);
  int32_t v = -1;
  assert_true(clr_exr_image_int_attr(im, name, &v));
  clr_exr_image_free(im);
  return v;
}

/* R, G, B of b equal a's within 1e-5 relative to max(|pixel|, image mean). */
static void assert_close_images(const char *a_path, const char *b_path) {
  clr_exr_image *a = NULL, *b = NULL;
  assert_int_equal(clr_exr_read(a_path, &a), CLR_SUCCESS);
  assert_int_equal(clr_exr_read(b_path, &b), CLR_SUCCESS);
  assert_int_equal(a->width, b->width);
  assert_int_equal(a->height, b->height);
  size_t n = (size_t)a->width * (size_t)a->height;
  const char *names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    const float *pa = clr_exr_image_channel(a, names[c]), *pb = clr_exr_image_channel(b, names[c]);
    assert_non_null(pa);
    assert_non_null(pb);
    double mean = 0.0;
    for (size_t i = 0; i < n; ++i) mean += fabs((double)pa[i]) / (double)n;
    assert_true(mean > 0.0);
    for (size_t i = 0; i < n; ++i) {
      double ref = fabs((double)pa[i]) > mean ? fabs((double)pa[i]) : mean;
      if (fabs((double)pa[i] - (double)pb[i]) > 1e-5 * ref)
        fail_msg("%s pixel %zu: %.9g vs %.9g", names[c], i, (double)pa[i], (double)pb[i]);
    }
  }
  clr_exr_image_free(a);
  clr_exr_image_free(b);
}

/* 8 spp resumed to 16 equals 16; flag and value (or NULL) go to every render. */
static void resumed_equals_full_with(const char *sampler, const char *flag, const char *value) {
  char part[sizeof dir + 16], resumed[sizeof dir + 16], full[sizeof dir + 16];
  in_dir(part, sizeof part, "s8.exr");
  in_dir(resumed, sizeof resumed, "s8to16.exr");
  in_dir(full, sizeof full, "s16.exr");
  const char *a[] = {"--sampler", sampler, "--spp", "8", "--outfile", part, flag, value, NULL};
  const char *b[] = {"--sampler", sampler, "--spp", "16",  "--outfile", resumed,
                     "--resume",  part,    flag,    value, NULL};
  const char *c[] = {"--sampler", sampler, "--spp", "16", "--outfile", full, flag, value, NULL};
  assert_int_equal(render(a), 0);
  assert_int_equal(render(b), 0);
  assert_int_equal(render(c), 0);
  assert_int_equal(int_attr(resumed, "clrender.spp"), 16);
  assert_int_equal(int_attr(resumed, "clrender.samples"), int_attr(full, "clrender.samples"));
  assert_close_images(full, resumed);
}

static void resumed_equals_full(const char *sampler) {
  resumed_equals_full_with(sampler, NULL, NULL);
}

static void test_halton_8_resumed_to_16_equals_16(void **state) {
  (void)state;
  resumed_equals_full("halton");
}

static void test_sobol_8_resumed_to_16_equals_16(void **state) {
  (void)state;
  resumed_equals_full("sobol");
}

/* pbrt-v4's independent sampler draws sample i of a pixel whatever the total spp. */
static void test_pbrt_v4_independent_8_resumed_to_16_equals_16(void **state) {
  (void)state;
  resumed_equals_full_with("independent", "--seeding", "pbrt-v4");
}

/* Another randomization draws other samples: refused, naming it. */
static void test_resume_refuses_another_randomization(void **state) {
  (void)state;
  char part[sizeof dir + 16], resumed[sizeof dir + 16];
  in_dir(part, sizeof part, "owen8.exr");
  in_dir(resumed, sizeof resumed, "owen8to16.exr");
  const char *a[] = {"--sampler",       "sobol", "--seeding", "pbrt-v4",
                     "--randomization", "owen",  "--spp",     "8",
                     "--outfile",       part,    NULL};
  const char *b[] = {"--sampler", "sobol", "--seeding", "pbrt-v4",   "--randomization",
                     "fastowen",  "--spp", "16",        "--outfile", resumed,
                     "--resume",  part,    NULL};
  assert_int_equal(render(a), 0);
  assert_int_equal(render(b), 1);
  assert_true(log_contains("randomization \"owen\""));
}

/* --time-limit 0: one pass of --pass-spp samples, recorded; resumed to the full spp. A pixel
 * sampler (stratified) resumes only to the total it was started for. */
static void test_time_limit_zero_renders_one_resumable_pass(void **state) {
  (void)state;
  char one[sizeof dir + 16], resumed[sizeof dir + 16], full[sizeof dir + 16];
  in_dir(one, sizeof one, "one.exr");
  in_dir(resumed, sizeof resumed, "one_resumed.exr");
  in_dir(full, sizeof full, "strat16.exr");
  const char *a[] = {"--sampler",    "stratified", "--spp",     "16", "--pass-spp", "4",
                     "--time-limit", "0",          "--outfile", one,  NULL};
  assert_int_equal(render(a), 0);
  assert_int_equal(int_attr(one, "clrender.spp"), 4);
  assert_int_equal(int_attr(one, "clrender.partial"), 0);
  const char *wrong[] = {"--sampler", "stratified", "--spp", "32", "--outfile",
                         resumed,     "--resume",   one,     NULL};
  assert_int_equal(render(wrong), 1);
  assert_true(log_contains("depend on the total spp"));
  const char *b[] = {"--sampler", "stratified", "--spp", "16", "--outfile",
                     resumed,     "--resume",   one,     NULL};
  const char *c[] = {"--sampler", "stratified", "--spp", "16", "--outfile", full, NULL};
  assert_int_equal(render(b), 0);
  assert_int_equal(render(c), 0);
  assert_close_images(full, resumed);
}

/* Copies the complete temporary file "OUT.tmp-XXXXXX" of a stopped writer to `to`. */
static void copy_temporary(const char *out, const char *to) {
  char pattern[sizeof dir + 32];
  snprintf(pattern, sizeof pattern, "%s.tmp-*", out);
  glob_t g;
  assert_int_equal(glob(pattern, 0, NULL, &g), 0);
  assert_int_equal(g.gl_pathc, 1);
  FILE *in = fopen(g.gl_pathv[0], "rb"), *o = fopen(to, "wb");
  assert_non_null(in);
  assert_non_null(o);
  char buf[1 << 14];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, in)) > 0) assert_int_equal(fwrite(buf, 1, n, o), n);
  fclose(in);
  assert_int_equal(fclose(o), 0);
  globfree(&g);
}

/* SIGINT while the first checkpoint is being written: the render drops the pass in flight,
 * writes the whole passes (partial, resumable) and exits 130; resuming gives the full image. */
static void test_interrupted_checkpointed_render_resumes(void **state) {
  (void)state;
  char cut[sizeof dir + 16], resumed[sizeof dir + 16], full[sizeof dir + 16], ckpt[sizeof dir + 16];
  in_dir(cut, sizeof cut, "cut.exr");
  in_dir(ckpt, sizeof ckpt, "checkpoint.exr");
  in_dir(resumed, sizeof resumed, "cut_resumed.exr");
  in_dir(full, sizeof full, "h16.exr");
  const char *a[] = {"--spp", "16", "--pass-spp", "4", "--checkpoint", "0", "--outfile", cut, NULL};
  pid_t pid = start(a, 1);
  int status = 0, stops = 0;
  for (;;) {
    assert_int_equal(waitpid(pid, &status, WUNTRACED), pid);
    if (!WIFSTOPPED(status)) break;
    if (stops++ == 0) { /* in the first checkpoint: keep a copy of it, then interrupt */
      copy_temporary(cut, ckpt);
      assert_int_equal(kill(pid, SIGINT), 0);
    }
    assert_int_equal(kill(pid, SIGCONT), 0);
  }
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 130);
  assert_int_equal(stops, 4); /* checkpoint EXR + PNG, final EXR + PNG */
  assert_int_equal(int_attr(cut, "clrender.partial"), 1);
  int32_t spp = int_attr(cut, "clrender.spp");
  assert_true(spp == 4 || spp == 8); /* the checkpointed pass, maybe the next one too */
  const char *b[] = {"--spp", "16", "--outfile", resumed, "--resume", cut, NULL};
  const char *c[] = {"--spp", "16", "--outfile", full, NULL};
  assert_int_equal(render(b), 0);
  assert_int_equal(render(c), 0);
  assert_close_images(full, resumed);
  assert_int_equal(int_attr(ckpt, "clrender.spp"), 4); /* a checkpoint resumes as well */
  const char *d[] = {"--spp", "16", "--outfile", resumed, "--resume", ckpt, NULL};
  assert_int_equal(render(d), 0);
  assert_close_images(full, resumed);
}

/* Adaptive sampling: the same pixels converge for 1 and 2 threads (bit-identical images), fewer
 * samples than uniform sampling are taken, an error map is written; a threshold every pixel
 * meets stops at the first estimate, at 16 spp (the samples of a 16-spp render). */
static void test_adaptive_sampling_is_deterministic(void **state) {
  (void)state;
  char one[sizeof dir + 16], two[sizeof dir + 16], map[sizeof dir + 16], all[sizeof dir + 16],
      four[sizeof dir + 16], uniform[sizeof dir + 16];
  in_dir(one, sizeof one, "ad1.exr");
  in_dir(two, sizeof two, "ad2.exr");
  in_dir(map, sizeof map, "err.exr");
  in_dir(all, sizeof all, "adall.exr");
  in_dir(four, sizeof four, "u16.exr");
  in_dir(uniform, sizeof uniform, "u32.exr");
  const char *a[] = {"--spp",      "32",        "--pass-spp", "2",           "--noise-threshold",
                     "0.2",        "--outfile", one,          "--error-map", map,
                     "--nthreads", "1",         NULL};
  const char *b[] = {"--spp", "32",        "--pass-spp", "2", "--noise-threshold",
                     "0.2",   "--outfile", two,          NULL};
  const char *u[] = {"--spp", "32", "--outfile", uniform, NULL};
  assert_int_equal(render(a), 0);
  assert_int_equal(render(b), 0);
  assert_int_equal(render(u), 0);
  clr_exr_image *x = NULL, *y = NULL;
  assert_int_equal(clr_exr_read(one, &x), CLR_SUCCESS);
  assert_int_equal(clr_exr_read(two, &y), CLR_SUCCESS);
  assert_int_equal(x->channel_count, y->channel_count);
  size_t n = (size_t)x->width * (size_t)x->height;
  for (int c = 0; c < x->channel_count; ++c)
    assert_memory_equal(x->channels[c], y->channels[c], n * sizeof(float));
  clr_exr_image_free(x);
  clr_exr_image_free(y);
  int32_t adaptive = int_attr(one, "clrender.samples"),
          full = int_attr(uniform, "clrender.samples");
  assert_true(adaptive < full);
  assert_true(adaptive >= full / 2); /* at least 16 spp everywhere */
  clr_exr_image *em = NULL;
  assert_int_equal(clr_exr_read(map, &em), CLR_SUCCESS);
  const float *e = clr_exr_image_channel(em, "R");
  assert_non_null(e);
  int below = 0;
  for (size_t i = 0; i < (size_t)em->width * (size_t)em->height; ++i) {
    assert_true(e[i] >= 0.0f && isfinite(e[i]));
    below += e[i] < 0.2f;
  }
  assert_true(below > 0);
  clr_exr_image_free(em);
  const char *c[] = {"--spp", "32",        "--pass-spp", "2", "--noise-threshold",
                     "1e9",   "--outfile", all,          NULL};
  const char *d[] = {"--spp", "16", "--outfile", four, NULL};
  assert_int_equal(render(c), 0);
  assert_int_equal(render(d), 0);
  assert_int_equal(int_attr(all, "clrender.samples"), int_attr(four, "clrender.samples"));
  assert_close_images(four, all);
}

/* Another seed, an image that already has the spp asked for, a missing file: refused. */
static void test_resume_refuses_other_renders(void **state) {
  (void)state;
  char base[sizeof dir + 16], out[sizeof dir + 16];
  in_dir(base, sizeof base, "base.exr");
  in_dir(out, sizeof out, "refused.exr");
  const char *a[] = {"--spp", "4", "--outfile", base, NULL};
  assert_int_equal(render(a), 0);
  const char *seed[] = {"--spp", "8", "--seed", "7", "--outfile", out, "--resume", base, NULL};
  assert_int_equal(render(seed), 1);
  assert_true(log_contains("seed \"0\", this render has \"7\""));
  const char *same[] = {"--spp", "4", "--outfile", out, "--resume", base, NULL};
  assert_int_equal(render(same), 1);
  assert_true(log_contains("already holds 4 spp"));
  const char *filter[] = {"--spp", "8",        "--filter", "gaussian", "--outfile",
                          out,     "--resume", base,       NULL};
  assert_int_equal(render(filter), 1);
  assert_true(log_contains("is not this one"));
  char missing[sizeof dir + 16];
  in_dir(missing, sizeof missing, "none.exr");
  const char *none[] = {"--spp", "8", "--outfile", out, "--resume", missing, NULL};
  assert_int_equal(render(none), 1);
  struct stat st;
  assert_int_not_equal(stat(out, &st), 0);
}

/* The values clr_resume_check reads from an 8-of-16-spp sobol image (clr_resume_attributes'
 * order), and the identity of the render that continues it. */
typedef char resume_values[11][CLR_RESUME_VALUE];
static void sobol_8_of_16(resume_values values, clr_resume_identity *now) {
  const char *recorded[] = {
      "sobol", "path", "0123456789abcdef",   "0", "pixel", "default", "8", "16",
      "0",     "1",    "camera 0, values 53"};
  assert_int_equal(clr_resume_attribute_count, 11);
  memset(values, 0, sizeof(resume_values));
  for (int k = 0; k < 11; ++k) snprintf(values[k], CLR_RESUME_VALUE, "%s", recorded[k]);
  *now = (clr_resume_identity){.sampler = "sobol",
                               .integrator = "path",
                               .scene = "0123456789abcdef",
                               .seeding = "pixel",
                               .randomization = "default",
                               .spp_target = 16,
                               .global_sampler = 1};
  snprintf(now->seed, sizeof now->seed, "0");
  snprintf(now->layout, sizeof now->layout, "camera 0, values 53");
}

/* An image whose sample vectors were laid out otherwise (another maxdepth, or written by a
 * clrender whose integrator drew other dimensions) is refused, naming both layouts. */
static void test_resume_refuses_another_sample_layout(void **state) {
  (void)state;
  resume_values values;
  clr_resume_identity now;
  sobol_8_of_16(values, &now);
  int32_t done = 0;
  assert_int_equal(clr_resume_check("a.exr", &values[0][0], &now, &done), CLR_SUCCESS);
  assert_int_equal(done, 8);
  snprintf(now.layout, sizeof now.layout, "camera 0, values 45");
  assert_int_equal(clr_resume_check("a.exr", &values[0][0], &now, &done),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(
      strstr(clr_last_error_message(),
             "sample layout \"camera 0, values 53\", this render has \"camera 0, values 45\""));
  values[10][0] = 0; /* an image from before the layout was recorded */
  assert_int_equal(clr_resume_check("a.exr", &values[0][0], &now, &done),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "sample layout \"(not recorded)\""));
}

/* The recorded counts come from an untrusted file: anything but a plain count (a flag: 0 or 1)
 * is refused, naming the attribute and its text. */
static void test_resume_refuses_bad_recorded_counts(void **state) {
  (void)state;
  resume_values values;
  clr_resume_identity now;
  static const struct {
    int attribute;
    const char *text, *message;
  } bad[] = {
      {6, "8x", "clrender.spp attribute is \"8x\", not a whole number"},
      {6, "99999999999", "clrender.spp attribute is \"99999999999\""},
      {6, "1e30", "clrender.spp attribute is \"1e30\""},
      {6, "-3", "clrender.spp attribute is \"-3\""},
      {6, " 8", "clrender.spp attribute is \" 8\""},
      {6, "", "clrender.spp attribute is \"\""},
      {7, "16.5", "clrender.spp_target attribute is \"16.5\""},
      {8, "2", "clrender.partial attribute is \"2\", not 0 or 1"},
      {9, "yes", "clrender.whole_passes attribute is \"yes\", not 0 or 1"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    sobol_8_of_16(values, &now);
    int32_t done = -1;
    assert_int_equal(clr_resume_check("a.exr", &values[0][0], &now, &done), CLR_SUCCESS);
    assert_int_equal(done, 8);
    snprintf(values[bad[i].attribute], CLR_RESUME_VALUE, "%s", bad[i].text);
    done = -1;
    assert_int_equal(clr_resume_check("a.exr", &values[0][0], &now, &done),
                     CLR_ERROR_INVALID_ARGUMENT);
    assert_int_equal(done, -1);
    if (!strstr(clr_last_error_message(), bad[i].message))
      fail_msg("%s: got \"%s\"", bad[i].text, clr_last_error_message());
  }
  sobol_8_of_16(values, &now);
  values[9][0] = 0; /* no clrender.whole_passes: refused for that reason */
  int32_t done = -1;
  assert_int_equal(clr_resume_check("a.exr", &values[0][0], &now, &done),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "no clrender.whole_passes attribute"));
}

int main(void) {
  if (!mkdtemp(dir)) return 1;
  snprintf(log_path, sizeof log_path, "%s/log.txt", dir);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_halton_8_resumed_to_16_equals_16),
      cmocka_unit_test(test_sobol_8_resumed_to_16_equals_16),
      cmocka_unit_test(test_pbrt_v4_independent_8_resumed_to_16_equals_16),
      cmocka_unit_test(test_resume_refuses_another_randomization),
      cmocka_unit_test(test_time_limit_zero_renders_one_resumable_pass),
      cmocka_unit_test(test_interrupted_checkpointed_render_resumes),
      cmocka_unit_test(test_resume_refuses_other_renders),
      cmocka_unit_test(test_resume_refuses_another_sample_layout),
      cmocka_unit_test(test_resume_refuses_bad_recorded_counts),
      cmocka_unit_test(test_adaptive_sampling_is_deterministic),
  };
  int failed = cmocka_run_group_tests(tests, NULL, NULL);
  char cmd[sizeof dir + 16];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (failed == 0 && system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return failed;
}
