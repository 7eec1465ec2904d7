/* Reading input files named by a scene: regular files only, bounded size. */
#define _POSIX_C_SOURCE 200809L
#include "render_input.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

clr_result clr_read_input_file(const char *path, const char *context, uint64_t max_bytes,
                               char **data, size_t *size) {
  const char *ctx = context ? context : "";
  const char *sep = context ? ": " : "";
  if (!path || !data || !size)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "%s%sclr_read_input_file: NULL argument", ctx,
                              sep);
  *data = NULL;
  *size = 0;
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0)
    return clr_set_last_error(CLR_ERROR_IO, "%s%scannot open '%s': %s", ctx, sep, path,
                              strerror(errno));
  struct stat st;
  clr_result r = CLR_SUCCESS;
  if (fstat(fd, &st) != 0)
    r = clr_set_last_error(CLR_ERROR_IO, "%s%scannot read '%s': %s", ctx, sep, path,
                           strerror(errno));
  else if (S_ISDIR(st.st_mode))
    r = clr_set_last_error(CLR_ERROR_IO, "%s%scannot read '%s': is a directory", ctx, sep, path);
  else if (!S_ISREG(st.st_mode))
    r = clr_set_last_error(CLR_ERROR_IO,
                           "%s%scannot read '%s': is not a regular file (a device, FIFO or "
                           "socket)",
                           ctx, sep, path);
  else if ((uint64_t)st.st_size > max_bytes || (uint64_t)st.st_size >= SIZE_MAX)
    r = clr_set_last_error(CLR_ERROR_FILE_FORMAT,
                           "%s%s'%s' is too large (%llu bytes, at most %llu)", ctx, sep, path,
                           (unsigned long long)st.st_size, (unsigned long long)max_bytes);
  size_t want = r == CLR_SUCCESS ? (size_t)st.st_size : 0, got = 0;
  char *buffer = r == CLR_SUCCESS ? malloc(want + 1) : NULL;
  if (r == CLR_SUCCESS && !buffer)
    r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "%s%sout of memory reading '%s' (%zu bytes)",
                           ctx, sep, path, want);
  while (r == CLR_SUCCESS && got < want) { /* at most the size seen: a growing file stops there */
    ssize_t n = read(fd, buffer + got, want - got);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n < 0)
      r = clr_set_last_error(CLR_ERROR_IO, "%s%scannot read '%s': %s", ctx, sep, path,
                             strerror(errno));
    else if (n == 0)
      break; /* shrank while reading: keep what is there */
    else
      got += (size_t)n;
  }
  close(fd);
  if (r != CLR_SUCCESS) {
    free(buffer);
    return r;
  }
  buffer[got] = 0;
  *data = buffer;
  *size = got;
  return CLR_SUCCESS;
}
