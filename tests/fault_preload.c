/* LD_PRELOAD shim for the fault tests: with CLR_FAULT_STOP_BEFORE_COMMIT=1 the process stops
 * itself (SIGSTOP) when it syncs one of clrender's temporary outputs ("NAME.tmp-XXXXXX"): the
 * file is complete and nothing is renamed yet, so a test can kill or race it at exactly that
 * point without timing. The library itself has no test switch. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int is_temporary_output(int fd) {
  char link[64], target[4096];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  ssize_t n = readlink(link, target, sizeof target - 1);
  if (n <= 0) return 0;
  target[n] = 0;
  return strstr(target, ".tmp-") != NULL;
}

int fsync(int fd) {
  int (*real_fsync)(int) = (int (*)(int))dlsym(RTLD_NEXT, "fsync");
  const char *stop = getenv("CLR_FAULT_STOP_BEFORE_COMMIT");
  if (stop && stop[0] == '1' && is_temporary_output(fd)) raise(SIGSTOP);
  return real_fsync ? real_fsync(fd) : -1;
}
