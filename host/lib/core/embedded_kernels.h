/* Kernel sources embedded at build time by tools/embed_kernels.c. */
#ifndef CLR_EMBEDDED_KERNELS_H
#define CLR_EMBEDDED_KERNELS_H
#include <stddef.h>

typedef struct clr_embedded_kernel {
  const char *name;   /* entry file name, e.g. "sampler_kernels.cl" */
  const char *source; /* with its local includes inlined */
  size_t length;
} clr_embedded_kernel;

extern const clr_embedded_kernel clr_embedded_kernels[];
extern const int clr_embedded_kernel_count;

#endif
