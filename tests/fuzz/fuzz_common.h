/* Helpers shared by the fuzz targets: the input as a file for readers that take a path. */
#ifndef CLR_FUZZ_COMMON_H
#define CLR_FUZZ_COMMON_H

#ifndef _GNU_SOURCE
#define _GNU_SOURCE
#endif
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include "clrender/context.h"
#include "clrender/result.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* An in-memory regular file (memfd) holding the input, reachable as /proc/self/fd/N; falls back
 * to an unlinked file in the build tree. One per target, rewritten for every input. */
typedef struct fuzz_file {
  int fd;
  char path[64];
} fuzz_file;

static inline const char *fuzz_file_write(fuzz_file *f, const uint8_t *data, size_t size) {
  if (f->fd <= 0) {
    f->fd = memfd_create("clr-fuzz-input", 0);
    if (f->fd < 0) {
      char tmp[] = CLR_FUZZ_WORK_DIR "/clr-fuzz-input-XXXXXX";
      f->fd = mkstemp(tmp);
      if (f->fd >= 0) unlink(tmp);
    }
    if (f->fd < 0) {
      perror("fuzz: cannot create the input file");
      abort();
    }
    snprintf(f->path, sizeof f->path, "/proc/self/fd/%d", f->fd);
  }
  if (ftruncate(f->fd, 0) != 0) abort();
  size_t done = 0;
  while (done < size) {
    ssize_t n = pwrite(f->fd, data + done, size - done, (off_t)done);
    if (n <= 0) abort();
    done += (size_t)n;
  }
  return f->path;
}

/* With CLR_FUZZ_VERBOSE=1 in the environment, the targets print why an input was refused
 * (clr_last_error_message()) and every warning: handy when writing seeds. */
static inline int fuzz_verbose(void) {
  static int verbose = -1;
  if (verbose < 0)
    verbose = getenv("CLR_FUZZ_VERBOSE") && strcmp(getenv("CLR_FUZZ_VERBOSE"), "1") == 0;
  return verbose;
}

static inline void fuzz_report(const char *step, clr_result r) {
  if (fuzz_verbose() && r != CLR_SUCCESS)
    fprintf(stderr, "  %s: %s\n", step, clr_last_error_message());
}

static inline void fuzz_ignore_warning(void *user, const char *message) {
  (void)user;
  if (fuzz_verbose()) fprintf(stderr, "  warning: %s\n", message);
}

/* The input as a stream of bytes; zeros once it is used up (the differential targets). */
typedef struct fuzz_reader {
  const uint8_t *p;
  size_t n;
} fuzz_reader;

static inline uint8_t fuzz_next(fuzz_reader *r) {
  if (!r->n) return 0;
  --r->n;
  return *r->p++;
}

/* The default OpenCL device's context for a differential target's whole run; aborts, naming the
 * target, when there is none. */
static inline clr_context fuzz_device_context(const char *target) {
  clr_context ctx = NULL;
  if (clr_context_create(NULL, &ctx) != CLR_SUCCESS) {
    fprintf(stderr, "%s: no OpenCL device: %s\n", target, clr_last_error_message());
    abort();
  }
  return ctx;
}

#endif
