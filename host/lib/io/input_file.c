/* Input files from untrusted sources: regular files only, size known up front. */
#define _POSIX_C_SOURCE 200809L
#include "input_file.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "clr_internal.h"

static clr_result check_stat(const struct stat *st, const char *path, const char *what) {
  if (S_ISDIR(st->st_mode))
    return clr_fail(NULL, CLR_ERROR_IO, "cannot read %s '%s': is a directory", what, path);
  if (!S_ISREG(st->st_mode))
    return clr_fail(NULL, CLR_ERROR_IO,
                    "cannot read %s '%s': is not a regular file (a device, FIFO or socket)", what,
                    path);
  return CLR_SUCCESS;
}

clr_result clr_input_file_open(const char *path, const char *what, FILE **stream, uint64_t *size) {
  if (!path || !what || !stream || !size)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_input_file_open: NULL argument");
  *stream = NULL;
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0)
    return clr_fail(NULL, CLR_ERROR_IO, "cannot open %s '%s': %s", what, path, strerror(errno));
  struct stat st;
  clr_result r = fstat(fd, &st) == 0 ? check_stat(&st, path, what)
                                     : clr_fail(NULL, CLR_ERROR_IO, "cannot stat %s '%s': %s", what,
                                                path, strerror(errno));
  int flags = fcntl(fd, F_GETFL);
  if (r == CLR_SUCCESS && (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0))
    r = clr_fail(NULL, CLR_ERROR_IO, "cannot read %s '%s': %s", what, path, strerror(errno));
  FILE *f = r == CLR_SUCCESS ? fdopen(fd, "rb") : NULL;
  if (r == CLR_SUCCESS && !f)
    r = clr_fail(NULL, CLR_ERROR_IO, "cannot read %s '%s': %s", what, path, strerror(errno));
  if (r != CLR_SUCCESS) {
    close(fd);
    return r;
  }
  *stream = f;
  *size = (uint64_t)st.st_size;
  return CLR_SUCCESS;
}

clr_result clr_input_file_check(const char *path, const char *what, uint64_t *size) {
  if (!path || !what || !size)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_input_file_check: NULL argument");
  struct stat st;
  if (stat(path, &st) != 0)
    return clr_fail(NULL, CLR_ERROR_IO, "cannot open %s '%s': %s", what, path, strerror(errno));
  CLR_CHECK(check_stat(&st, path, what));
  *size = (uint64_t)st.st_size;
  return CLR_SUCCESS;
}

int clr_input_file_exists(const char *path) {
  struct stat st;
  return path && lstat(path, &st) == 0;
}
