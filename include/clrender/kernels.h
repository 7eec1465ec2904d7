/* clrender kernel shapes: the same results (the host reference's bits) from two shapes of
 * OpenCL kernels, chosen per context.
 *   CLR_KERNELS_SIMD      8 batch items or pixels per work-item in OpenCL vector types; fastest
 *                         on PoCL's CPU devices, where it is the default.
 *   CLR_KERNELS_PORTABLE  one work-item per sample vector or pixel, scalar OpenCL C 1.2 with
 *                         small private state; the default on every other device (GPUs,
 *                         accelerators, other CPU implementations).
 * The environment variable CLRENDER_KERNELS=simd|portable overrides the automatic choice for
 * every context created while it is set; clr_context_set_kernel_shape overrides both. */
#ifndef CLRENDER_KERNELS_H
#define CLRENDER_KERNELS_H

#include "clrender/context.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum clr_kernel_shape {
  CLR_KERNELS_AUTO = 0, /* the device's default (or CLRENDER_KERNELS) */
  CLR_KERNELS_SIMD = 1,
  CLR_KERNELS_PORTABLE = 2
} clr_kernel_shape;

/* "auto", "simd" or "portable" (case-insensitive); anything else -> CLR_ERROR_INVALID_ARGUMENT
 * naming it. */
CLR_API clr_result clr_kernel_shape_from_name(const char *name, clr_kernel_shape *out);
/* "auto", "simd", "portable" ("unknown" otherwise). */
CLR_API const char *clr_kernel_shape_name(clr_kernel_shape shape);
/* Chooses the shape of the kernels this context's samplers and films launch from now on
 * (CLR_KERNELS_AUTO: back to the device's default). */
CLR_API clr_result clr_context_set_kernel_shape(clr_context ctx, clr_kernel_shape shape);
/* The shape in use: CLR_KERNELS_SIMD or CLR_KERNELS_PORTABLE. */
CLR_API clr_kernel_shape clr_context_kernel_shape(clr_context ctx);

#ifdef __cplusplus
}
#endif
#endif
