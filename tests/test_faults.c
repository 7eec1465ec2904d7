/* Fault tests (issue #8): kill -9 during the write, two renders writing the same output at once,
 * a full disk. Outputs are written to "NAME.tmp-XXXXXX" beside NAME and renamed, so a killed
 * writer never leaves a file at the output name (its obviously named temporary file stays).
 * The moment of the write is reached without timing: the LD_PRELOAD shim tests/fault_preload.c
 * makes the CLI stop itself (SIGSTOP) with its temporary file complete and nothing renamed, and
 * the test waits for that stop with waitpid(WUNTRACED). */
#define _GNU_SOURCE
#include <glob.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/mount.h>
#include <cmocka.h>
#include "clrender.h"
#include "exr_io.h"
#include "hardening_util.h"

#define SCENE_TEXT(res)                                                               \
  "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n"           \
  "Film \"image\" \"integer xresolution\" [" res "] \"integer yresolution\" [" res    \
  "]\n"                                                                               \
  "Sampler \"random\" \"integer pixelsamples\" [2]\nPixelFilter \"gaussian\"\n"       \
  "Integrator \"ambientocclusion\" \"integer nsamples\" [1]\n"                        \
  "WorldBegin\nShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" " \
  "[-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nShape \"sphere\"\nWorldEnd\n"

/* Starts `clrender render s.pbrt --quiet --outfile OUT [--seed SEED]` in `dir`; with `stop`,
 * the child stops itself before each rename. */
static pid_t start_render(const char *dir, const char *out, const char *seed, int stop) {
  pid_t pid = fork();
  if (pid != 0) return pid;
  if (chdir(dir) != 0) _exit(126);
  if (stop) hu_stop_before_commit();
  int null = open("/dev/null", O_RDWR);
  dup2(null, 0);
  dup2(null, 1);
  execl(CLR_CLI_PATH, "clrender", "render", "s.pbrt", "--quiet", "--nthreads", "1", "--outfile",
        out, "--seed", seed, (char *)NULL);
  _exit(127);
}

/* Waits until the child stops (1) or exits (0, status in *status). */
static int wait_stopped(pid_t pid, int *status) {
  int st = 0;
  assert_int_equal(waitpid(pid, &st, WUNTRACED), pid);
  if (status) *status = st;
  return WIFSTOPPED(st);
}

static int count_matches(const char *pattern) {
  glob_t g;
  int n = glob(pattern, 0, NULL, &g) == 0 ? (int)g.gl_pathc : 0;
  if (n) globfree(&g);
  return n;
}

static void assert_complete_exr(const char *path, int32_t expected_samples) {
  clr_exr_image *im = NULL;
  assert_int_equal(clr_exr_read(path, &im), CLR_SUCCESS);
  int32_t partial = -1, samples = -1;
  assert_true(clr_exr_image_int_attr(im, "clrender.partial", &partial));
  assert_true(clr_exr_image_int_attr(im, "clrender.samples", &samples));
  assert_int_equal(partial, 0);
  assert_int_equal(samples, expected_samples);
  assert_non_null(clr_exr_image_channel(im, "R"));
  assert_non_null(clr_exr_image_channel(im, "sum.R"));
  clr_exr_image_free(im);
}

static void test_kill9_during_write(void **state) {
  (void)state;
  const char *dir = hu_workdir("kill9", 0);
  char path[600];
  snprintf(path, sizeof path, "%s/s.pbrt", dir);
  assert_true(hu_write_file(path, SCENE_TEXT("8"), strlen(SCENE_TEXT("8"))));
  /* an existing image at the output name must survive untouched */
  snprintf(path, sizeof path, "%s/old.exr", dir);
  assert_true(hu_write_file(path, "previous image", 14));
  const char *outs[2] = {"new.exr", "old.exr"};
  for (int k = 0; k < 2; ++k) {
    pid_t pid = start_render(dir, outs[k], "0", 1);
    assert_true(pid > 0);
    assert_true(wait_stopped(pid, NULL)); /* stopped with the EXR written, not renamed */
    char pattern[700], out[700];
    snprintf(pattern, sizeof pattern, "%s/%s.tmp-??????", dir, outs[k]);
    snprintf(out, sizeof out, "%s/%s", dir, outs[k]);
    assert_int_equal(count_matches(pattern), 1);
    assert_int_equal(kill(pid, SIGKILL), 0);
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    /* nothing at the output name (or the old file, unchanged); the temporary file is left,
     * named NAME.tmp-XXXXXX beside it */
    size_t size = 0;
    char *content = hu_read_file(out, &size);
    if (k == 0) {
      assert_null(content);
    } else {
      assert_non_null(content);
      assert_int_equal(size, 14);
      assert_memory_equal(content, "previous image", 14);
    }
    free(content);
    assert_int_equal(count_matches(pattern), 1);
    char png[700];
    snprintf(png, sizeof png, "%s/%.3s.png", dir, outs[k]);
    assert_int_equal(access(png, F_OK), -1); /* the preview comes after the EXR */
  }
  /* the next run to the same name succeeds beside the leftover */
  pid_t pid = start_render(dir, "new.exr", "0", 0);
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  snprintf(path, sizeof path, "%s/new.exr", dir);
  assert_complete_exr(path, 12 * 12 * 2); /* sample bounds: 8 + 2 x gaussian radius 2 */
  hu_sh("rm -rf '%s'", dir);
}

/* Two renders to one output: both are held with complete temporary files, then released
 * together, twice (EXR, then PNG). The result is one complete image, no temporary files. */
static void test_two_renders_same_output(void **state) {
  (void)state;
  const char *dir = hu_workdir("two_renders", 0);
  char path[600];
  snprintf(path, sizeof path, "%s/s.pbrt", dir);
  assert_true(hu_write_file(path, SCENE_TEXT("16"), strlen(SCENE_TEXT("16"))));
  pid_t a = start_render(dir, "same.exr", "1", 1), b = start_render(dir, "same.exr", "2", 1);
  assert_true(a > 0 && b > 0);
  for (int round = 0; round < 2; ++round) { /* EXR commit, then PNG commit */
    assert_true(wait_stopped(a, NULL));
    assert_true(wait_stopped(b, NULL));
    char pattern[700];
    snprintf(pattern, sizeof pattern, "%s/same.%s.tmp-??????", dir, round ? "png" : "exr");
    assert_int_equal(count_matches(pattern), 2); /* two distinct temporary names */
    assert_int_equal(kill(a, SIGCONT), 0);
    assert_int_equal(kill(b, SIGCONT), 0);
  }
  int sa = 0, sb = 0;
  assert_int_equal(waitpid(a, &sa, 0), a);
  assert_int_equal(waitpid(b, &sb, 0), b);
  assert_true(WIFEXITED(sa) && WEXITSTATUS(sa) == 0);
  assert_true(WIFEXITED(sb) && WEXITSTATUS(sb) == 0);
  snprintf(path, sizeof path, "%s/same.exr", dir);
  assert_complete_exr(path, 20 * 20 * 2);
  snprintf(path, sizeof path, "%s/same.png", dir);
  clr_image im;
  assert_int_equal(clr_image_read(path, &im), CLR_SUCCESS);
  assert_int_equal(im.width, 16);
  clr_image_free(&im);
  snprintf(path, sizeof path, "%s/*.tmp-*", dir);
  assert_int_equal(count_matches(path), 0);
  hu_sh("rm -rf '%s'", dir);
}

/* A 16 KiB tmpfs: the EXR with its sums (~60 KiB of noisy planes) does not fit. Exit 1 naming the error, nothing at the
 * output name, the old file beside it untouched, no temporary file left. */
static void test_full_disk(void **state) {
  (void)state;
  const char *dir = hu_workdir("full_disk", 0);
  char mnt[600], path[700];
  snprintf(mnt, sizeof mnt, "%s/mnt", dir);
  assert_int_equal(mkdir(mnt, 0777), 0);
  if (geteuid() != 0 || mount("tmpfs", mnt, "tmpfs", 0, "size=16k") != 0) {
    printf("skipped: mounting a small tmpfs needs root and mount(2) (%s)\n", strerror(errno));
    hu_sh("rm -rf '%s'", dir);
    skip();
  }
  snprintf(path, sizeof path, "%s/s.pbrt", dir);
  assert_true(hu_write_file(path, SCENE_TEXT("64"), strlen(SCENE_TEXT("64"))));
  snprintf(path, sizeof path, "%s/old.exr", mnt);
  assert_true(hu_write_file(path, "previous image", 14));
  char *before = hu_snapshot(mnt);
  char err[700];
  snprintf(err, sizeof err, "%s/stderr.txt", dir);
  char *argv[] = {"clrender", "render", "s.pbrt", "--quiet", "--outfile", "mnt/o.exr", NULL};
  int status = hu_run_cli(dir, argv, err);
  char *after = hu_snapshot(mnt);
  char *msg = hu_read_file(err, NULL);
  umount(mnt);
  assert_int_equal(status, 1);
  assert_non_null(msg);
  assert_non_null(strstr(msg, "mnt/o.exr"));
  assert_non_null(strstr(msg, "No space left on device"));
  assert_string_equal(before, after); /* no o.exr, no temporary file, old.exr unchanged */
  free(before);
  free(after);
  free(msg);
  hu_sh("rm -rf '%s'", dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_kill9_during_write),
      cmocka_unit_test(test_two_renders_same_output),
      cmocka_unit_test(test_full_disk),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
