/* SIGINT/SIGTERM during `clrender render`: the render stops after the tiles in flight and writes
 * a valid EXR marked clrender.partial = 1 (and its PNG preview). */
#define _DEFAULT_SOURCE
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>
#include "exr_io.h"

static void interrupt_with(int sig) {
  char dir[] = "/tmp/clr_interrupt_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char exr[256], png[256];
  snprintf(exr, sizeof exr, "%s/partial.exr", dir);
  snprintf(png, sizeof png, "%s/partial.png", dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    execl(CLR_CLI_PATH, "clrender", "render", CLR_SOURCE_DIR "/scenes/cornell-box.pbrt", "--spp",
          "1024", "--tile-size", "8", "--quiet", "--outfile", exr, (char *)NULL);
    _exit(127);
  }
  struct timespec wait = {1, 500000000};
  nanosleep(&wait, NULL);
  assert_int_equal(kill(pid, sig), 0);
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status));
  clr_exr_image *im = NULL;
  assert_int_equal(clr_exr_read(exr, &im), CLR_SUCCESS);
  int32_t partial = 0;
  assert_true(clr_exr_image_int_attr(im, "clrender.partial", &partial));
  assert_int_equal(partial, 1);
  assert_non_null(clr_exr_image_channel(im, "R"));
  clr_exr_image_free(im);
  struct stat st;
  assert_int_equal(stat(png, &st), 0);
  unlink(exr);
  unlink(png);
  rmdir(dir);
}

static void test_sigint_writes_partial_image(void **state) {
  (void)state;
  interrupt_with(SIGINT);
}

static void test_sigterm_writes_partial_image(void **state) {
  (void)state;
  interrupt_with(SIGTERM);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sigint_writes_partial_image),
      cmocka_unit_test(test_sigterm_writes_partial_image),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
