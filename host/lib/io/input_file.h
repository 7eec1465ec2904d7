/* Input files from untrusted sources: only regular files are read (never a directory, device,
 * FIFO or socket), and their size is known before any reader trusts a header. */
#ifndef CLR_INPUT_FILE_H
#define CLR_INPUT_FILE_H

#include <stdint.h>
#include <stdio.h>
#include "clrender/result.h"

/* Opens `path` for reading without blocking (a FIFO never stalls the caller), checks it is a
 * regular file and returns a stdio stream and its size. `what` names the file kind in messages
 * ("PNG", "EXR"): "cannot read PNG 'x': is a directory" / "...: is not a regular file (a
 * device, FIFO or socket)" with CLR_ERROR_IO. */
clr_result clr_input_file_open(const char *path, const char *what, FILE **stream, uint64_t *size);

/* Same checks without keeping the file open (for readers that open the path themselves). */
clr_result clr_input_file_check(const char *path, const char *what, uint64_t *size);

/* Whether anything exists at `path` (lstat succeeds). */
int clr_input_file_exists(const char *path);

#endif
