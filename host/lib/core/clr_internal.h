/* Internal helpers shared by the library's host code: error reporting and OpenCL checks. */
#ifndef CLR_INTERNAL_H
#define CLR_INTERNAL_H

#include <stdarg.h>
#include "clrender/context.h"

/* Formats a message into this thread's last error (arguments may point into it); returns it. */
const char *clr_error_vrecord(const char *fmt, va_list args);
/* Records `code` with a printf-style message as this thread's last error, calls the context's
 * error callback (ctx may be NULL) and returns `code`. */
clr_result clr_fail(clr_context ctx, clr_result code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Size-tagged descs: `full` (sizeof full_size) holds the defaults from the desc's _init; the
 * caller's `given` desc may come from an older, smaller header: the bytes its struct_size covers
 * replace the defaults. CLR_ERROR_INVALID_ARGUMENT naming `what` for a struct_size that is too
 * small, too large or not a multiple of 4. full's struct_size stays sizeof. */
clr_result clr_desc_adopt(void *full, size_t full_size, const void *given, const char *what);
/* Clears this thread's last error message. */
void clr_clear_error(void);

/* Name of an OpenCL error code, e.g. "CL_OUT_OF_RESOURCES". */
const char *clr_cl_error_name(cl_int err);

/* Checks an OpenCL call returning cl_int; on failure returns CLR_ERROR_OPENCL naming the call. */
#define CLR_CL_CHECK(ctx, call)                                             \
  do {                                                                      \
    cl_int clr_cl_err_ = (call);                                            \
    if (clr_cl_err_ != CL_SUCCESS)                                          \
      return clr_fail((ctx), CLR_ERROR_OPENCL, "%s failed: %s (%d)", #call, \
                      clr_cl_error_name(clr_cl_err_), (int)clr_cl_err_);    \
  } while (0)

/* Same, for calls that report through an errcode_ret argument already stored in `err`. */
#define CLR_CL_CHECK_ERR(ctx, err, what)                                     \
  do {                                                                       \
    if ((err) != CL_SUCCESS)                                                 \
      return clr_fail((ctx), CLR_ERROR_OPENCL, "%s failed: %s (%d)", (what), \
                      clr_cl_error_name(err), (int)(err));                   \
  } while (0)

#define CLR_CHECK(expr)                       \
  do {                                        \
    clr_result clr_r_ = (expr);               \
    if (clr_r_ != CLR_SUCCESS) return clr_r_; \
  } while (0)

/* Returns the program built from embedded entry file `name` with the build options
 * `defines` (e.g. "-DCLR_FILTER=3", may be NULL) for this context; built once and cached. The
 * context owns the program. A build failure returns CLR_ERROR_KERNEL_BUILD with the device's
 * build log in the message. */
clr_result clr_context_program(clr_context ctx, const char *name, const char *defines,
                               cl_program *program);
/* Creates a kernel from a cached program; the caller releases it. */
clr_result clr_context_kernel(clr_context ctx, const char *program_name, const char *defines,
                              const char *kernel_name, cl_kernel *kernel);

/* Device copy of a constant table shared by every user of a context (created on first use from
 * `data`, owned by the context, keyed by `key`); `data` must live, unchanged, as long as the
 * context (devices with host-unified memory use it in place). */
clr_result clr_context_shared_buffer(clr_context ctx, const char *key, const void *data,
                                     size_t bytes, cl_mem *buffer);

/* Whether this context launches the portable kernels (else the SIMD ones); see kernels.h. */
int clr_context_portable(clr_context ctx);
/* CL_DEVICE_HOST_UNIFIED_MEMORY of the context's device (a CPU device such as PoCL's). */
int clr_context_unified_memory(clr_context ctx);
/* Whether the context's device computes in double (cl_khr_fp64). */
int clr_context_fp64(clr_context ctx);
/* CL_DEVICE_LOCAL_MEM_SIZE of the context's device. */
cl_ulong clr_context_local_mem(clr_context ctx);
/* A work-group size for `kernel` on the context's device: `wanted` capped by the device's and the
 * kernel's limits (CL_DEVICE_MAX_WORK_GROUP_SIZE, CL_DEVICE_MAX_WORK_ITEM_SIZES[0],
 * CL_KERNEL_WORK_GROUP_SIZE), rounded down to CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE when
 * larger than it; at least 1. */
size_t clr_context_group_size(clr_context ctx, cl_kernel kernel, size_t wanted);
/* Enqueues `items` work-items of a 1D kernel in groups of clr_context_group_size(wanted_group),
 * padded to whole groups (kernels clamp or skip ids past `items`). */
clr_result clr_context_launch(clr_context ctx, cl_kernel kernel, size_t items, size_t wanted_group,
                              const char *name);

#endif
