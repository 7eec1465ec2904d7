/* clrender result codes: a fixed-size (int32_t) code with a table of messages (X-macro), and the
 * per-thread detailed message of the last failure.
 *
 * Stability: the codes' values never change; new codes are only appended before
 * CLR_RESULT_COUNT. Thread safety: every call here is thread-safe; the last-error message is
 * per thread. */
#ifndef CLRENDER_RESULT_H
#define CLRENDER_RESULT_H

#include <stdint.h>
#include "clrender/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CLR_RESULT_MAP(X)                                                            \
  X(CLR_SUCCESS, "success")                                                          \
  X(CLR_ERROR_INVALID_ARGUMENT, "invalid argument")                                  \
  X(CLR_ERROR_NULL_POINTER, "a required pointer argument is NULL")                   \
  X(CLR_ERROR_OUT_OF_MEMORY, "out of host memory")                                   \
  X(CLR_ERROR_OPENCL, "an OpenCL call failed")                                       \
  X(CLR_ERROR_NO_DEVICE, "no matching OpenCL device")                                \
  X(CLR_ERROR_KERNEL_BUILD, "an OpenCL program failed to build")                     \
  X(CLR_ERROR_INVALID_SAMPLER, "unknown sampler name")                               \
  X(CLR_ERROR_INVALID_SPP, "samples per pixel must be positive")                     \
  X(CLR_ERROR_INVALID_RESOLUTION, "resolution must be positive and within limits")   \
  X(CLR_ERROR_INVALID_DIMENSIONS, "sampler dimensions must be positive")             \
  X(CLR_ERROR_INVALID_REQUESTS, "invalid sample request layout")                     \
  X(CLR_ERROR_REQUEST_TOO_LARGE, "sample request exceeds the supported size")        \
  X(CLR_ERROR_INVALID_PIXEL_RANGE, "pixel range outside the sample bounds or empty") \
  X(CLR_ERROR_INVALID_FILTER, "unknown filter name or bad filter parameter")         \
  X(CLR_ERROR_INVALID_RADIUS, "filter radius must be positive and finite")           \
  X(CLR_ERROR_INVALID_CROP_WINDOW, "crop window must lie in [0,1] and be non-empty") \
  X(CLR_ERROR_INVALID_FILM, "invalid film or incompatible films")                    \
  X(CLR_ERROR_INVALID_TILE, "invalid film tile")                                     \
  X(CLR_ERROR_IO, "file input/output failed")                                        \
  X(CLR_ERROR_FILE_FORMAT, "malformed or unsupported file")                          \
  X(CLR_ERROR_PARSE, "scene file syntax error")                                      \
  X(CLR_ERROR_SCENE, "invalid scene description")                                    \
  X(CLR_ERROR_EMBREE, "an Embree call failed")                                       \
  X(CLR_ERROR_OPENEXR, "an OpenEXR call failed")                                     \
  X(CLR_ERROR_PNG, "a libpng call failed")                                           \
  X(CLR_ERROR_INTERRUPTED, "interrupted")                                            \
  X(CLR_ERROR_INTERNAL, "internal error")

/* Every call that can fail returns a clr_result: CLR_SUCCESS (0) or one of the codes below. */
typedef int32_t clr_result;

enum clr_result_code {
#define CLR_RESULT_ENUM(name, message) name,
  CLR_RESULT_MAP(CLR_RESULT_ENUM)
#undef CLR_RESULT_ENUM
      CLR_RESULT_COUNT
};

/* Static description of a result code ("unknown result code" for out-of-range values). */
CLR_API const char *clr_result_string(clr_result result);
/* Name of the enumerator, e.g. "CLR_ERROR_INVALID_SPP". */
CLR_API const char *clr_result_name(clr_result result);
/* Detailed message of the last failing clrender call on this thread ("" if none). It names the
 * call, parameter or file and the offending value. */
CLR_API const char *clr_last_error_message(void);
/* Records a printf-style message as this thread's last error and returns `code`: for layers
 * built on clrender (the renderer) that report through the same channel. The arguments may
 * include clr_last_error_message() itself (the message is formatted before it is stored). */
CLR_API clr_result clr_set_last_error(clr_result code, const char *fmt, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#ifdef __cplusplus
}
#endif
#endif
