/* Atomic file output: write "path.tmp-XXXXXX" beside path, rename it onto path on success. */
#ifndef CLR_ATOMIC_FILE_H
#define CLR_ATOMIC_FILE_H

#include <stdint.h>
#include <stdio.h>
#include "clrender/result.h"

typedef struct clr_atomic_file {
  char *path;      /* final destination */
  char *temp_path; /* "path.tmp-XXXXXX", removed unless committed */
  int fd;          /* open temp file, -1 once closed or handed to `stream` */
  FILE *stream;    /* set by clr_atomic_file_stream, owns the descriptor */
} clr_atomic_file;

/* Creates the temporary file next to `path` (mode 0666 minus umask). An existing `path` must be
 * a regular, writable file: a directory, symbolic link, device, FIFO, socket or read-only file is
 * refused (commit checks again before the rename). On failure returns CLR_ERROR_IO naming the
 * path and leaves nothing behind; `file` is then safe to abort. */
clr_result clr_atomic_file_open(clr_atomic_file *file, const char *path);

/* A stdio stream over the temporary file (created once; the atomic file keeps ownership). */
clr_result clr_atomic_file_stream(clr_atomic_file *file, FILE **stream);

/* Writes `size` bytes at byte `offset` of the temporary file (positioned write, no stream). */
clr_result clr_atomic_file_pwrite(clr_atomic_file *file, const void *data, uint64_t size,
                                  uint64_t offset);

/* Flushes, syncs and closes the temporary file, checks `path` again (see clr_atomic_file_open),
 * then renames the temporary file onto it. On any failure the temporary file is removed and
 * CLR_ERROR_IO is returned. Frees the file's memory either way. */
clr_result clr_atomic_file_commit(clr_atomic_file *file);

/* Closes and removes the temporary file and frees the file's memory (no-op after commit). */
void clr_atomic_file_abort(clr_atomic_file *file);

/* Checks that `path` could be written: an existing `path` is a regular writable file (see
 * clr_atomic_file_open), its directory exists and a file can be created there (a temporary file
 * is created and removed). CLR_ERROR_IO naming the path otherwise. */
clr_result clr_check_writable(const char *path);

#endif
