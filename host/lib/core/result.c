/* Result codes, their message table and the per-thread last error message. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "clr_internal.h"

static _Thread_local char last_error[4096];

const char *clr_result_string(clr_result result) {
  switch (result) {
#define CLR_RESULT_CASE(name, message) \
  case name:                           \
    return message;
    CLR_RESULT_MAP(CLR_RESULT_CASE)
#undef CLR_RESULT_CASE
    default:
      return "unknown result code";
  }
}

const char *clr_result_name(clr_result result) {
  switch (result) {
#define CLR_RESULT_CASE(name, message) \
  case name:                           \
    return #name;
    CLR_RESULT_MAP(CLR_RESULT_CASE)
#undef CLR_RESULT_CASE
    default:
      return "CLR_RESULT_UNKNOWN";
  }
}

const char *clr_last_error_message(void) { return last_error; }

void clr_clear_error(void) { last_error[0] = 0; }

const char *clr_error_vrecord(const char *fmt, va_list args) {
  char message[sizeof last_error]; /* formatted apart: the arguments may point into last_error */
  vsnprintf(message, sizeof message, fmt, args);
  memcpy(last_error, message, sizeof message);
  return last_error;
}

clr_result clr_set_last_error(clr_result code, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  clr_error_vrecord(fmt, args);
  va_end(args);
  return code;
}

const char *clr_cl_error_name(cl_int err) {
  switch (err) {
#define E(x) \
  case x:    \
    return #x;
    /* clang-format off */
    E(CL_SUCCESS) E(CL_DEVICE_NOT_FOUND) E(CL_DEVICE_NOT_AVAILABLE)
    E(CL_COMPILER_NOT_AVAILABLE) E(CL_MEM_OBJECT_ALLOCATION_FAILURE) E(CL_OUT_OF_RESOURCES)
    E(CL_OUT_OF_HOST_MEMORY) E(CL_PROFILING_INFO_NOT_AVAILABLE) E(CL_MEM_COPY_OVERLAP)
    E(CL_IMAGE_FORMAT_MISMATCH) E(CL_IMAGE_FORMAT_NOT_SUPPORTED) E(CL_BUILD_PROGRAM_FAILURE)
    E(CL_MAP_FAILURE) E(CL_MISALIGNED_SUB_BUFFER_OFFSET) E(CL_COMPILE_PROGRAM_FAILURE)
    E(CL_LINKER_NOT_AVAILABLE) E(CL_LINK_PROGRAM_FAILURE) E(CL_INVALID_VALUE)
    E(CL_INVALID_DEVICE_TYPE) E(CL_INVALID_PLATFORM) E(CL_INVALID_DEVICE)
    E(CL_INVALID_CONTEXT) E(CL_INVALID_QUEUE_PROPERTIES) E(CL_INVALID_COMMAND_QUEUE)
    E(CL_INVALID_HOST_PTR) E(CL_INVALID_MEM_OBJECT) E(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
    E(CL_INVALID_IMAGE_SIZE) E(CL_INVALID_SAMPLER) E(CL_INVALID_BINARY)
    E(CL_INVALID_BUILD_OPTIONS) E(CL_INVALID_PROGRAM) E(CL_INVALID_PROGRAM_EXECUTABLE)
    E(CL_INVALID_KERNEL_NAME) E(CL_INVALID_KERNEL_DEFINITION) E(CL_INVALID_KERNEL)
    E(CL_INVALID_ARG_INDEX) E(CL_INVALID_ARG_VALUE) E(CL_INVALID_ARG_SIZE)
    E(CL_INVALID_KERNEL_ARGS) E(CL_INVALID_WORK_DIMENSION) E(CL_INVALID_WORK_GROUP_SIZE)
    E(CL_INVALID_WORK_ITEM_SIZE) E(CL_INVALID_GLOBAL_OFFSET) E(CL_INVALID_EVENT_WAIT_LIST)
    E(CL_INVALID_EVENT) E(CL_INVALID_OPERATION) E(CL_INVALID_BUFFER_SIZE)
    E(CL_INVALID_GLOBAL_WORK_SIZE) E(CL_INVALID_PROPERTY) E(CL_INVALID_COMPILER_OPTIONS)
    E(CL_INVALID_LINKER_OPTIONS) E(CL_INVALID_DEVICE_PARTITION_COUNT)
    /* clang-format on */
#undef E
                                                                    default
        : return "unknown OpenCL error";
  }
}
