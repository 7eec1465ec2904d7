/* Reading input files named by a scene (scene, Include, PLY): regular files only, bounded size. */
#ifndef CLR_RENDER_INPUT_H
#define CLR_RENDER_INPUT_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/result.h"

/* Largest scene or Include file read (1 GiB). */
#define CLR_SCENE_MAX_FILE_BYTES ((uint64_t)1 << 30)
/* Largest PLY file read (4 GiB). */
#define CLR_PLY_MAX_FILE_BYTES ((uint64_t)4 << 30)

/* Reads the whole of `path` into a new NUL-terminated buffer (*size bytes without the NUL; free
 * with free()). The file must be a regular file (opened without blocking, so a FIFO never
 * stalls) of at most `max_bytes`. On failure returns, with "<context>: " before the message
 * (context may be NULL):
 *   CLR_ERROR_IO  "cannot open 'P': <reason>", "cannot read 'P': is a directory",
 *                 "cannot read 'P': is not a regular file (a device, FIFO or socket)",
 *                 "cannot read 'P': <reason>";
 *   CLR_ERROR_FILE_FORMAT  "'P' is too large (N bytes, at most M)";
 *   CLR_ERROR_OUT_OF_MEMORY. */
clr_result clr_read_input_file(const char *path, const char *context, uint64_t max_bytes,
                               char **data, size_t *size);

#endif
