/* clrender OpenCL context: platform/device choice, command queue, program cache.
 *
 * Thread safety: every call here is thread-safe. A context may be shared by any number of
 * samplers and films on any threads (its program cache and shared buffers are locked); the
 * OpenCL objects it hands out stay owned by it.
 * Lifetime: create -> reference count 1; retain/release count (atomically); the last release
 * finishes the queue and frees everything. Samplers and films retain their context.
 * NULL: retain/release ignore NULL; accessors return "", 0 or NULL for a NULL context; a NULL desc in
 * clr_context_create means the defaults; other NULL pointers return CLR_ERROR_NULL_POINTER. */
#ifndef CLRENDER_CONTEXT_H
#define CLRENDER_CONTEXT_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/opencl.h"
#include "clrender/export.h"
#include "clrender/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct clr_context_t *clr_context;

typedef void (*clr_error_callback)(void *user, clr_result code, const char *message);

typedef struct clr_context_desc {
  size_t struct_size; /* sizeof(clr_context_desc): set by clr_context_desc_init */
  /* Device selector: NULL or "" picks the default (env CLRENDER_DEVICE if set, else the first GPU,
   * else the first CPU device); a decimal number is an index in clr_device_list order; anything
   * else is a case-insensitive substring of "platform name: device name". */
  const char *device;
  clr_error_callback error_callback; /* optional, called on every failing call on this context */
  void *error_user;
} clr_context_desc;

CLR_API void clr_context_desc_init(clr_context_desc *desc);
CLR_API clr_result clr_context_create(const clr_context_desc *desc, clr_context *out);
CLR_API void clr_context_retain(clr_context ctx);
CLR_API void clr_context_release(clr_context ctx);

/* Description of the chosen device, e.g. "Portable Computing Language: pthread-haswell".
 * Owned by the context, valid until its last release. */
CLR_API const char *clr_context_device_name(clr_context ctx);
CLR_API int clr_context_device_is_gpu(clr_context ctx);
CLR_API cl_context clr_context_cl_context(clr_context ctx);
CLR_API cl_command_queue clr_context_cl_queue(clr_context ctx);
CLR_API cl_device_id clr_context_cl_device(clr_context ctx);

typedef struct clr_device_info {
  int index; /* index for the device selector */
  char platform_name[128];
  char device_name[128];
  char device_version[128];
  char driver_version[64];
  int is_gpu;
  unsigned compute_units;
  uint64_t global_memory_bytes;
} clr_device_info;

/* Fills up to `capacity` entries (all platforms, all devices, in selector order); *count gets the
 * total number of devices. */
CLR_API clr_result clr_device_list(clr_device_info *infos, int capacity, int *count);

#ifdef __cplusplus
}
#endif
#endif
