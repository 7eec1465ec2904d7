/* `clrender samples` and `clrender devices` as a user runs them: CSV rows and values, the plot,
 * and bad flags (usage, exit status 2, nothing written). */
#define _DEFAULT_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

/* Runs `clrender ARGS`, capturing stdout into buf; returns the exit status. */
static int run(const char *args, char *buf, size_t size) {
  char cmd[2048];
  snprintf(cmd, sizeof cmd, "%s %s 2>/dev/null", CLR_CLI_PATH, args);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t n = fread(buf, 1, size - 1, p);
  buf[n] = 0;
  int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static int count_lines(const char *s) {
  int n = 0;
  for (; *s; ++s) n += *s == '\n';
  return n;
}

static void test_csv_rows_and_header(void **state) {
  (void)state;
  static char out[1 << 20];
  assert_int_equal(run("samples --sampler sobol --spp 16 --res 16x16 --pixels 2,3,4,5 "
                       "--requests 2,1,2,1,2,2",
                       out, sizeof out),
                   0);
  const char *header = "px,py,sample,global_index,v0,v1,v2,v3,v4,v5,v6,v7,v8,v9\n";
  assert_true(strncmp(out, header, strlen(header)) == 0);
  assert_int_equal(count_lines(out), 1 + 4 * 16);
  /* Every row: pixel inside the range, film offset in [0,1), a global index. */
  char *line = strchr(out, '\n') + 1;
  for (int r = 0; r < 64; ++r) {
    int px, py, s;
    unsigned long long idx;
    double v0, v1;
    assert_int_equal(sscanf(line, "%d,%d,%d,%llu,%lf,%lf", &px, &py, &s, &idx, &v0, &v1), 6);
    assert_true(px >= 2 && px < 4 && py >= 3 && py < 5 && s >= 0 && s < 16);
    assert_true(v0 >= 0 && v0 < 1 && v1 >= 0 && v1 < 1);
    line = strchr(line, '\n') + 1;
  }
  /* Samplers without a global index leave the column empty. */
  assert_int_equal(run("samples --sampler stratified --spp 4 --pixel 0,0", out, sizeof out), 0);
  assert_non_null(strstr(out, "\n0,0,0,,"));
  assert_int_equal(count_lines(out), 5);
  /* Device and host reference print the same text. */
  static char ref[1 << 20];
  const char *args = "samples --sampler halton --pixels 0,0,3,2 --requests 2,1,2,2:3";
  assert_int_equal(run(args, out, sizeof out), 0);
  char ref_args[256];
  snprintf(ref_args, sizeof ref_args, "%s --reference", args);
  assert_int_equal(run(ref_args, ref, sizeof ref), 0);
  assert_string_equal(out, ref);
}

/* Values of row "px,py,sample,," (no global index) as floats; returns how many were read. */
static int row_values(const char *out, const char *prefix, float *v, int most) {
  const char *row = strstr(out, prefix);
  if (!row) return 0;
  row += strlen(prefix);
  int n = 0;
  while (n < most && *row && *row != '\n') {
    char *end = NULL;
    v[n++] = strtof(row, &end);
    row = *end == ',' ? end + 1 : end;
  }
  return n;
}

/* --seeding pbrt-v4, --randomization, --seed and a wavelength-first layout reach the sampler:
 * values pinned from pbrt-v4 (as in test_pbrt_v4_samplers). */
static void test_pbrt_v4_flags(void **state) {
  (void)state;
  static char out[1 << 16];
  float v[8];
  assert_int_equal(run("samples --sampler sobol --seeding pbrt-v4 --randomization owen --seed 7 "
                       "--spp 16 --res 1280x720 --pixel 100,200 --requests 2,1,2,1 --reference",
                       out, sizeof out),
                   0);
  assert_int_equal(row_values(out, "\n100,200,3,,", v, 8), 6);
  const float sobol[6] = {0x1.006p-2f,    0x1.0aap-2f,    0x1.ff6e8cp-1f,
                          0x1.4a9eaap-1f, 0x1.459408p-1f, 0x1.2cfb12p-1f};
  for (int k = 0; k < 6; ++k) assert_true(v[k] == sobol[k]);
  assert_int_equal(run("samples --sampler zsobol --seed 5 --spp 16 --pixel 3,5 --requests 1,2,1,2",
                       out, sizeof out),
                   0);
  assert_int_equal(row_values(out, "\n3,5,1,,", v, 8), 6);
  const float zsobol[6] = {0x1.9f4136p-2f, 0x1.872b46p-1f, 0x1.619128p-1f,
                           0x1.a00504p-2f, 0x1.6aec3ap-2f, 0x1.ab9fdap-1f};
  for (int k = 0; k < 6; ++k) assert_true(v[k] == zsobol[k]);
  assert_int_equal(run("samples --sampler zsobol --randomization fast-owen", out, sizeof out), 2);
  assert_int_equal(run("samples --sampler maxmindist --seeding pbrt-v4", out, sizeof out), 2);
  assert_int_equal(run("samples --sampler halton --randomization owen", out, sizeof out), 2);
}

static void test_plot_png(void **state) {
  (void)state;
  char path[] = CLR_BINARY_DIR "/clr_plot_XXXXXX.png";
  int fd = mkstemps(path, 4);
  assert_true(fd >= 0);
  close(fd);
  char args[512], out[256];
  snprintf(args, sizeof args, "samples --sampler random --pixels 0,0,4,4 --plot %s --proj 0,1",
           path);
  assert_int_equal(run(args, out, sizeof out), 0);
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  unsigned char sig[8];
  assert_int_equal(fread(sig, 1, 8, f), 8);
  fclose(f);
  assert_memory_equal(sig, "\x89PNG\r\n\x1a\n", 8);
  unlink(path);
}

static void test_bad_flags_exit_2(void **state) {
  (void)state;
  static char out[1 << 16];
  const char *bad[] = {
      "samples",
      "samples --sampler zeroTwo",
      "samples --sampler sobol --spp 0",
      "samples --sampler sobol --spp -3",
      "samples --sampler sobol --spp many",
      "samples --sampler sobol --res 0x16",
      "samples --sampler sobol --res 16",
      "samples --sampler sobol --filter-radius -1",
      "samples --sampler sobol --requests 1,2",
      "samples --sampler sobol --requests 2,3",
      "samples --sampler sobol --requests 2,2:999999",
      "samples --sampler sobol --pixels 0,0,999,999",
      "samples --sampler sobol --pixel 1",
      "samples --sampler sobol --seeding tiles",
      "samples --sampler stratified --dimensions 0",
      "samples --sampler sobol --frobnicate 1",
      "samples --sampler sobol --proj 0,12 --plot " CLR_BINARY_DIR "/clr_never_written.png",
      "nonsense-command",
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    int status = run(bad[i], out, sizeof out);
    if (status != 2) fail_msg("\"%s\" exited %d, expected 2", bad[i], status);
    assert_int_equal(out[0], 0); /* nothing on stdout */
  }
  assert_int_not_equal(access(CLR_BINARY_DIR "/clr_never_written.png", F_OK), 0);
}

static void test_devices_lists_default(void **state) {
  (void)state;
  static char out[1 << 16];
  assert_int_equal(run("devices", out, sizeof out), 0);
  assert_non_null(strstr(out, "* 0"));
  assert_int_equal(run("samples --sampler sobol --device no-such-device", out, sizeof out), 1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_csv_rows_and_header),
      cmocka_unit_test(test_pbrt_v4_flags),
      cmocka_unit_test(test_plot_png),
      cmocka_unit_test(test_bad_flags_exit_2),
      cmocka_unit_test(test_devices_lists_default),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
