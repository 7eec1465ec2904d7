/* On-disk cache of built OpenCL program binaries (clCreateProgramWithBinary), so a render skips
 * the implementation's front end (PoCL preprocesses the whole source with clang to hash it for
 * its own cache). Best effort: any problem (no folder, a corrupt, truncated or foreign file, a
 * binary the implementation refuses) falls back to building from source, and nothing here
 * records an error. */
#ifndef CLR_PROGRAM_CACHE_H
#define CLR_PROGRAM_CACHE_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/opencl.h"

/* What a cached binary must match: device and implementation, clrender version, program name,
 * build options and the source's length and two hashes. */
typedef struct clr_program_key {
  char identity[2048];
  char file_name[40]; /* the identity's hash: "p-<16 hex>.bin" */
} clr_program_key;

/* The cache folder: $CLRENDER_CACHE_DIR, else $XDG_CACHE_HOME/clrender, else
 * $HOME/.cache/clrender; 0 when the cache is off (CLRENDER_PROGRAM_CACHE=0, off or no) or no
 * folder is known. */
int clr_program_cache_dir(char *out, size_t size);

void clr_program_key_make(clr_program_key *key, cl_platform_id platform, cl_device_id device,
                          const char *program_name, const char *source, size_t length,
                          const char *options);

/* A program created from the cached binary and built with `options`, or NULL. */
cl_program clr_program_cache_load(const clr_program_key *key, cl_context cl, cl_device_id device,
                                  const char *options);

/* Writes the built program's binary (temporary file in the folder, renamed when complete). */
void clr_program_cache_store(const clr_program_key *key, cl_program program);

#endif
