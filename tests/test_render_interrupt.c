/* SIGINT/SIGTERM during `clrender render`: the render stops after the tiles in flight, writes
 * a valid EXR marked clrender.partial = 1 (and its PNG preview) and exits with 128 + the signal
 * (130, 143). The signal is sent only once the render has visibly started: the CLI's stderr is a
 * pseudo-terminal, so it draws its progress bar, and the test waits for the first one (no sleep
 * racing the render). */
#define _GNU_SOURCE
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>
#include "exr_io.h"

/* Reads the pseudo-terminal until `needle` has appeared (1) or it closes / 120 s pass (0). */
static int wait_for_output(int fd, const char *needle) {
  char seen[8192];
  size_t len = 0;
  for (;;) {
    struct pollfd p = {fd, POLLIN, 0};
    if (poll(&p, 1, 120000) <= 0) return 0;
    char buf[512];
    ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return 0;
    for (ssize_t i = 0; i < n; ++i) {
      if (len + 1 == sizeof seen) { /* keep the tail */
        memmove(seen, seen + sizeof seen / 2, sizeof seen / 2);
        len = sizeof seen / 2 - 1;
      }
      seen[len++] = buf[i];
    }
    seen[len] = 0;
    if (strstr(seen, needle)) return 1;
  }
}

/* Reads until the other side closes, so the child never blocks writing its stderr. */
static void drain(int fd) {
  char buf[512];
  for (;;) {
    ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
  }
}

static void interrupt_with(int sig) {
  char dir[] = CLR_BINARY_DIR "/clr_interrupt_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char exr[sizeof dir + 16], png[sizeof dir + 16];
  snprintf(exr, sizeof exr, "%s/partial.exr", dir);
  snprintf(png, sizeof png, "%s/partial.png", dir);
  int master = posix_openpt(O_RDWR | O_NOCTTY);
  assert_true(master >= 0);
  assert_int_equal(grantpt(master), 0);
  assert_int_equal(unlockpt(master), 0);
  const char *slave_name = ptsname(master);
  assert_non_null(slave_name);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    int slave = open(slave_name, O_RDWR | O_NOCTTY);
    if (slave < 0) _exit(126);
    dup2(slave, STDERR_FILENO);
    close(slave);
    close(master);
    execl(CLR_CLI_PATH, "clrender", "render", CLR_SOURCE_DIR "/scenes/cornell-box.pbrt", "--spp",
          "1024", "--tile-size", "8", "--outfile", exr, (char *)NULL);
    _exit(127);
  }
  int started = wait_for_output(master, " tiles "); /* the first progress bar */
  assert_int_equal(kill(pid, sig), 0);
  assert_true(started);
  drain(master);
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  close(master);
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 128 + sig); /* 130 for SIGINT, 143 for SIGTERM */
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
