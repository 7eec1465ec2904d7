/* Atomic file output: a uniquely named temporary beside the target, renamed onto it on success. */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include "clr_internal.h"

#define CLR_TEMP_SUFFIX ".tmp-XXXXXX"
#define CLR_TEMP_ATTEMPTS 100

static atomic_uint temp_counter;

static char *copy_string(const char *s) {
  size_t n = strlen(s) + 1;
  char *copy = malloc(n);
  if (copy) memcpy(copy, s, n);
  return copy;
}

/* Replaces the trailing "XXXXXX" of `name` with letters and digits mixed from the process id, a
 * counter and the clock, so parallel writers (threads or processes) pick different names. */
static void fill_random_suffix(char *name) {
  static const char alphabet[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  struct timespec now = {0, 0};
  clock_gettime(CLOCK_REALTIME, &now);
  uint64_t v = (uint64_t)getpid() * 0x9E3779B97F4A7C15ull;
  v ^= (uint64_t)atomic_fetch_add(&temp_counter, 1u) * 0xBF58476D1CE4E5B9ull;
  v ^= (uint64_t)now.tv_nsec * 0x94D049BB133111EBull + (uint64_t)now.tv_sec;
  v ^= v >> 31;
  char *x = name + strlen(name) - 6;
  for (int i = 0; i < 6; ++i, v /= 62) x[i] = alphabet[v % 62];
}

/* Refuses an existing `path` that is not a regular file the user may replace: a directory, a
 * symbolic link (its target is never replaced), a device, FIFO or socket, or a read-only file
 * (no write bit, or not writable for this user). A name that does not exist yet is fine. */
static clr_result check_target(const char *path) {
  struct stat st;
  if (lstat(path, &st) != 0) {
    if (errno == ENOENT) return CLR_SUCCESS;
    return clr_fail(NULL, CLR_ERROR_IO, "cannot write '%s': %s", path, strerror(errno));
  }
  if (S_ISDIR(st.st_mode))
    return clr_fail(NULL, CLR_ERROR_IO, "cannot write '%s': it is a directory", path);
  if (S_ISLNK(st.st_mode))
    return clr_fail(NULL, CLR_ERROR_IO,
                    "cannot write '%s': it is a symbolic link (only regular files are replaced)",
                    path);
  if (!S_ISREG(st.st_mode))
    return clr_fail(NULL, CLR_ERROR_IO,
                    "cannot write '%s': it is not a regular file (a device, FIFO or socket)", path);
  if (!(st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) || access(path, W_OK) != 0)
    return clr_fail(NULL, CLR_ERROR_IO, "cannot write '%s': the existing file is read-only", path);
  return CLR_SUCCESS;
}

clr_result clr_atomic_file_open(clr_atomic_file *file, const char *path) {
  if (!file) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_atomic_file_open: file is NULL");
  memset(file, 0, sizeof *file);
  file->fd = -1;
  if (!path) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_atomic_file_open: path is NULL");
  if (!path[0]) return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT, "output path is empty");
  CLR_CHECK(check_target(path));
  file->path = copy_string(path);
  file->temp_path = malloc(strlen(path) + sizeof CLR_TEMP_SUFFIX);
  if (!file->path || !file->temp_path) {
    clr_atomic_file_abort(file);
    return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "out of memory opening '%s'", path);
  }
  int err = EEXIST;
  for (int attempt = 0; attempt < CLR_TEMP_ATTEMPTS && err == EEXIST; ++attempt) {
    strcpy(file->temp_path, path);
    strcat(file->temp_path, CLR_TEMP_SUFFIX);
    fill_random_suffix(file->temp_path);
    file->fd = open(file->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    err = file->fd < 0 ? errno : 0;
  }
  if (file->fd < 0) {
    clr_fail(NULL, CLR_ERROR_IO, "cannot create '%s' (temporary file '%s'): %s", path,
             file->temp_path, strerror(err));
    free(file->temp_path); /* nothing was created: abort must not unlink */
    file->temp_path = NULL;
    clr_atomic_file_abort(file);
    return CLR_ERROR_IO;
  }
  return CLR_SUCCESS;
}

clr_result clr_atomic_file_stream(clr_atomic_file *file, FILE **stream) {
  if (!file || !stream)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_atomic_file_stream: NULL argument");
  if (!file->stream) {
    if (file->fd < 0)
      return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT, "clr_atomic_file_stream: file is closed");
    file->stream = fdopen(file->fd, "wb");
    if (!file->stream)
      return clr_fail(NULL, CLR_ERROR_IO, "fdopen failed for '%s': %s", file->temp_path,
                      strerror(errno));
    file->fd = -1;
  }
  *stream = file->stream;
  return CLR_SUCCESS;
}

clr_result clr_atomic_file_pwrite(clr_atomic_file *file, const void *data, uint64_t size,
                                  uint64_t offset) {
  if (!file || (!data && size))
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_atomic_file_pwrite: NULL argument");
  if (file->fd < 0)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT, "clr_atomic_file_pwrite: no descriptor");
  const unsigned char *bytes = data;
  while (size > 0) {
    size_t chunk = size > (1u << 30) ? (size_t)(1u << 30) : (size_t)size;
    ssize_t written = pwrite(file->fd, bytes, chunk, (off_t)offset);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0)
      return clr_fail(NULL, CLR_ERROR_IO, "write to '%s' failed: %s", file->temp_path,
                      written < 0 ? strerror(errno) : "no progress");
    bytes += written;
    offset += (uint64_t)written;
    size -= (uint64_t)written;
  }
  return CLR_SUCCESS;
}

/* Flushes, syncs and closes whatever the file holds open; returns 0 or the first errno. */
static int close_temp(clr_atomic_file *file, int sync) {
  int err = 0;
  if (file->stream) {
    if (sync && fflush(file->stream) != 0) err = errno;
    if (sync && !err && fsync(fileno(file->stream)) != 0) err = errno;
    if (fclose(file->stream) != 0 && !err) err = errno;
    file->stream = NULL;
  }
  if (file->fd >= 0) {
    if (sync && fsync(file->fd) != 0) err = errno;
    if (close(file->fd) != 0 && !err) err = errno;
    file->fd = -1;
  }
  return err;
}

static void free_names(clr_atomic_file *file) {
  free(file->path);
  free(file->temp_path);
  file->path = NULL;
  file->temp_path = NULL;
}

clr_result clr_atomic_file_commit(clr_atomic_file *file) {
  if (!file || !file->temp_path)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT, "clr_atomic_file_commit: file not open");
  int err = close_temp(file, 1);
  if (err) {
    clr_fail(NULL, CLR_ERROR_IO, "writing '%s' failed: %s", file->path, strerror(err));
    clr_atomic_file_abort(file);
    return CLR_ERROR_IO;
  }
  /* The target may have changed since the open: check it again right before replacing it. */
  if (check_target(file->path) != CLR_SUCCESS) {
    clr_atomic_file_abort(file);
    return CLR_ERROR_IO;
  }
  if (rename(file->temp_path, file->path) != 0) {
    clr_fail(NULL, CLR_ERROR_IO, "cannot rename '%s' to '%s': %s", file->temp_path, file->path,
             strerror(errno));
    clr_atomic_file_abort(file);
    return CLR_ERROR_IO;
  }
  free_names(file);
  return CLR_SUCCESS;
}

void clr_atomic_file_abort(clr_atomic_file *file) {
  if (!file) return;
  close_temp(file, 0);
  if (file->temp_path) unlink(file->temp_path);
  free_names(file);
}

clr_result clr_check_writable(const char *path) {
  clr_atomic_file probe;
  CLR_CHECK(clr_atomic_file_open(&probe, path));
  clr_atomic_file_abort(&probe);
  return CLR_SUCCESS;
}
