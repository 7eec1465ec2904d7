/* clrender result codes: one fixed-size enum with a table of messages (X-macro). */
#ifndef CLRENDER_RESULT_H
#define CLRENDER_RESULT_H

#ifdef __cplusplus
extern "C" {
#endif

#define CLR_RESULT_MAP(X)                                                              \
  X(CLR_SUCCESS, "success")                                                            \
  X(CLR_ERROR_INVALID_ARGUMENT, "invalid argument")                                    \
  X(CLR_ERROR_NULL_POINTER, "a required pointer argument is NULL")                    \
  X(CLR_ERROR_OUT_OF_MEMORY, "out of host memory")                                     \
  X(CLR_ERROR_OPENCL, "an OpenCL call failed")                                         \
  X(CLR_ERROR_NO_DEVICE, "no matching OpenCL device")                                  \
  X(CLR_ERROR_KERNEL_BUILD, "an OpenCL program failed to build")                       \
  X(CLR_ERROR_INVALID_SAMPLER, "unknown sampler name")                                 \
  X(CLR_ERROR_INVALID_SPP, "samples per pixel must be positive")                       \
  X(CLR_ERROR_INVALID_RESOLUTION, "resolution must be positive and within limits")     \
  X(CLR_ERROR_INVALID_DIMENSIONS, "sampler dimensions must be positive")               \
  X(CLR_ERROR_INVALID_REQUESTS, "invalid sample request layout")                       \
  X(CLR_ERROR_REQUEST_TOO_LARGE, "sample request exceeds the supported size")          \
  X(CLR_ERROR_INVALID_PIXEL_RANGE, "pixel range outside the sample bounds or empty")   \
  X(CLR_ERROR_INVALID_FILTER, "unknown filter name or bad filter parameter")           \
  X(CLR_ERROR_INVALID_RADIUS, "filter radius must be positive and finite")             \
  X(CLR_ERROR_INVALID_CROP_WINDOW, "crop window must lie in [0,1] and be non-empty")   \
  X(CLR_ERROR_INVALID_FILM, "invalid film or incompatible films")                      \
  X(CLR_ERROR_INVALID_TILE, "invalid film tile")                                       \
  X(CLR_ERROR_IO, "file input/output failed")                                          \
  X(CLR_ERROR_FILE_FORMAT, "malformed or unsupported file")                            \
  X(CLR_ERROR_PARSE, "scene file syntax error")                                        \
  X(CLR_ERROR_SCENE, "invalid scene description")                                      \
  X(CLR_ERROR_EMBREE, "an Embree call failed")                                         \
  X(CLR_ERROR_OPENEXR, "an OpenEXR call failed")                                       \
  X(CLR_ERROR_PNG, "a libpng call failed")                                             \
  X(CLR_ERROR_INTERRUPTED, "interrupted")                                              \
  X(CLR_ERROR_INTERNAL, "internal error")

typedef enum clr_result {
#define CLR_RESULT_ENUM(name, message) name,
  CLR_RESULT_MAP(CLR_RESULT_ENUM)
#undef CLR_RESULT_ENUM
  CLR_RESULT_COUNT
} clr_result;

/* Static description of a result code ("unknown result code" for out-of-range values). */
const char *clr_result_string(clr_result result);
/* Name of the enumerator, e.g. "CLR_ERROR_INVALID_SPP". */
const char *clr_result_name(clr_result result);
/* Detailed message of the last failing clrender call on this thread ("" if none). It names the
 * call, parameter or file and the offending value. */
const char *clr_last_error_message(void);

#ifdef __cplusplus
}
#endif
#endif
