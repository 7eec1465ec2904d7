/* OpenCL runtime: device enumeration and choice, context and queue, the program cache with
 * build options made in one place, and shared constant buffers. */
#include <stdarg.h>
#include <ctype.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "embedded_kernels.h"
#include "program_cache.h"
#include "clrender/kernels.h"

#define MAX_PROGRAMS 64
#define MAX_SHARED 16
#define MAX_DEVICES 64

typedef struct cached_program {
  char name[64];
  char defines[512];
  cl_program program;
} cached_program;

typedef struct shared_buffer {
  char key[64];
  cl_mem buffer;
} shared_buffer;

struct clr_context_t {
  atomic_int refcount;
  cl_platform_id platform;
  cl_device_id device;
  cl_context cl;
  cl_command_queue queue;
  char device_name[300];
  int is_gpu;
  int correctly_rounded_divide;
  int unified_memory;             /* CL_DEVICE_HOST_UNIFIED_MEMORY: constant tables used in place */
  int fp64;                       /* CL_DEVICE_DOUBLE_FP_CONFIG is not 0 (cl_khr_fp64) */
  clr_kernel_shape default_shape; /* the device's (or CLRENDER_KERNELS's) shape */
  _Atomic int shape;              /* the shape in use */
  size_t max_group;               /* CL_DEVICE_MAX_WORK_GROUP_SIZE, capped by item sizes[0] */
  cl_ulong local_mem;             /* CL_DEVICE_LOCAL_MEM_SIZE */
  clr_error_callback callback;
  void *callback_user;
  pthread_mutex_t lock;
  cached_program programs[MAX_PROGRAMS];
  int program_count;
  shared_buffer shared[MAX_SHARED];
  int shared_count;
};

clr_result clr_fail(clr_context ctx, clr_result code, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  const char *message = clr_error_vrecord(fmt, args);
  va_end(args);
  if (ctx && ctx->callback) ctx->callback(ctx->callback_user, code, message);
  return code;
}

void clr_context_desc_init(clr_context_desc *desc) {
  if (!desc) return;
  memset(desc, 0, sizeof *desc);
  desc->struct_size = sizeof *desc;
}

typedef struct device_entry {
  cl_platform_id platform;
  cl_device_id device;
  clr_device_info info;
} device_entry;

static clr_result enumerate_devices(device_entry *entries, int capacity, int *count) {
  cl_uint nplatforms = 0;
  *count = 0;
  cl_int err = clGetPlatformIDs(0, NULL, &nplatforms);
  if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || nplatforms == 0)
    return clr_fail(NULL, CLR_ERROR_NO_DEVICE,
                    "no OpenCL platform found (install pocl-opencl-icd for the CPU device)");
  CLR_CL_CHECK_ERR(NULL, err, "clGetPlatformIDs");
  cl_platform_id platforms[16];
  if (nplatforms > 16) nplatforms = 16;
  CLR_CL_CHECK(NULL, clGetPlatformIDs(nplatforms, platforms, NULL));
  int n = 0;
  for (cl_uint p = 0; p < nplatforms; ++p) {
    cl_uint ndev = 0;
    err = clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 0, NULL, &ndev);
    if (err == CL_DEVICE_NOT_FOUND || ndev == 0) continue;
    CLR_CL_CHECK_ERR(NULL, err, "clGetDeviceIDs");
    cl_device_id devices[MAX_DEVICES];
    if (ndev > MAX_DEVICES) ndev = MAX_DEVICES;
    CLR_CL_CHECK(NULL, clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, ndev, devices, NULL));
    for (cl_uint d = 0; d < ndev; ++d, ++n) {
      if (n >= capacity) continue;
      device_entry *e = &entries[n];
      memset(e, 0, sizeof *e);
      e->platform = platforms[p];
      e->device = devices[d];
      e->info.index = n;
      cl_device_type type = 0;
      cl_uint units = 0;
      cl_ulong mem = 0;
      CLR_CL_CHECK(
          NULL, clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof e->info.platform_name - 1,
                                  e->info.platform_name, NULL));
      CLR_CL_CHECK(NULL, clGetDeviceInfo(devices[d], CL_DEVICE_NAME, sizeof e->info.device_name - 1,
                                         e->info.device_name, NULL));
      CLR_CL_CHECK(NULL,
                   clGetDeviceInfo(devices[d], CL_DEVICE_VERSION, sizeof e->info.device_version - 1,
                                   e->info.device_version, NULL));
      CLR_CL_CHECK(NULL,
                   clGetDeviceInfo(devices[d], CL_DRIVER_VERSION, sizeof e->info.driver_version - 1,
                                   e->info.driver_version, NULL));
      CLR_CL_CHECK(NULL, clGetDeviceInfo(devices[d], CL_DEVICE_TYPE, sizeof type, &type, NULL));
      CLR_CL_CHECK(NULL, clGetDeviceInfo(devices[d], CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units,
                                         &units, NULL));
      CLR_CL_CHECK(NULL,
                   clGetDeviceInfo(devices[d], CL_DEVICE_GLOBAL_MEM_SIZE, sizeof mem, &mem, NULL));
      e->info.is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
      e->info.compute_units = units;
      e->info.global_memory_bytes = mem;
    }
  }
  *count = n;
  if (n == 0) return clr_fail(NULL, CLR_ERROR_NO_DEVICE, "no OpenCL device found on any platform");
  return CLR_SUCCESS;
}

clr_result clr_device_list(clr_device_info *infos, int capacity, int *count) {
  if (!count) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_device_list: count is NULL");
  if (capacity < 0 || (capacity > 0 && !infos))
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT, "clr_device_list: bad capacity %d", capacity);
  device_entry entries[MAX_DEVICES];
  CLR_CHECK(enumerate_devices(entries, MAX_DEVICES, count));
  for (int i = 0; i < *count && i < capacity && i < MAX_DEVICES; ++i) infos[i] = entries[i].info;
  return CLR_SUCCESS;
}

static int contains_nocase(const char *hay, const char *needle) {
  size_t n = strlen(needle);
  for (; *hay; ++hay) {
    size_t i = 0;
    while (i < n && hay[i] && tolower((unsigned char)hay[i]) == tolower((unsigned char)needle[i]))
      ++i;
    if (i == n) return 1;
  }
  return n == 0;
}

static int is_decimal(const char *s) {
  if (!*s) return 0;
  for (; *s; ++s)
    if (!isdigit((unsigned char)*s)) return 0;
  return 1;
}

static clr_result choose_device(const char *selector, const device_entry *entries, int count,
                                int *chosen) {
  if (selector && *selector) {
    if (is_decimal(selector)) {
      long idx = strtol(selector, NULL, 10);
      if (idx < 0 || idx >= count)
        return clr_fail(NULL, CLR_ERROR_NO_DEVICE,
                        "device index %s out of range: %d device(s) (see `clrender devices`)",
                        selector, count);
      *chosen = (int)idx;
      return CLR_SUCCESS;
    }
    for (int i = 0; i < count; ++i) {
      char full[300];
      snprintf(full, sizeof full, "%s: %s", entries[i].info.platform_name,
               entries[i].info.device_name);
      if (contains_nocase(full, selector)) {
        *chosen = i;
        return CLR_SUCCESS;
      }
    }
    return clr_fail(NULL, CLR_ERROR_NO_DEVICE,
                    "no OpenCL device matches \"%s\" (see `clrender devices`)", selector);
  }
  for (int i = 0; i < count; ++i)
    if (entries[i].info.is_gpu) {
      *chosen = i;
      return CLR_SUCCESS;
    }
  *chosen = 0;
  return CLR_SUCCESS;
}

static int has_word(const char *list, const char *word) {
  size_t n = strlen(word);
  for (const char *at = strstr(list, word); at; at = strstr(at + 1, word))
    if ((at == list || at[-1] == ' ') && (at[n] == ' ' || at[n] == 0)) return 1;
  return 0;
}

/* Kernel shape named by CLRENDER_KERNELS, or the device's: SIMD on PoCL's CPU devices (whose
 * vectoriser the SIMD kernels are written for), portable everywhere else. */
static clr_result default_kernel_shape(const device_entry *e, cl_device_type type,
                                       clr_kernel_shape *shape) {
  const char *env = getenv("CLRENDER_KERNELS");
  *shape = CLR_KERNELS_AUTO;
  if (env && *env) {
    if (clr_kernel_shape_from_name(env, shape) != CLR_SUCCESS)
      return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                      "CLRENDER_KERNELS=%s: expected simd, portable or auto", env);
  }
  if (*shape == CLR_KERNELS_AUTO)
    *shape = (contains_nocase(e->info.platform_name, "Portable Computing Language") &&
              (type & CL_DEVICE_TYPE_CPU))
                 ? CLR_KERNELS_SIMD
                 : CLR_KERNELS_PORTABLE;
  return CLR_SUCCESS;
}

/* What the kernels need from a device, and the limits launches obey. The kernels use no double
 * (devices without cl_khr_fp64 run them) but do use 64-bit integers, which the embedded profile
 * makes optional (cles_khr_int64). */
static clr_result query_device(clr_context ctx, const device_entry *e) {
  char profile[64] = "", extensions[8192] = "";
  cl_device_type type = 0;
  size_t items[3] = {0, 0, 0}, max_group = 0;
  cl_uint dims = 0;
  cl_bool available = CL_TRUE, compiler = CL_TRUE;
  CLR_CL_CHECK(NULL,
               clGetDeviceInfo(ctx->device, CL_DEVICE_PROFILE, sizeof profile - 1, profile, NULL));
  if (clGetDeviceInfo(ctx->device, CL_DEVICE_EXTENSIONS, sizeof extensions - 1, extensions, NULL) !=
      CL_SUCCESS)
    extensions[0] = 0;
  CLR_CL_CHECK(NULL, clGetDeviceInfo(ctx->device, CL_DEVICE_TYPE, sizeof type, &type, NULL));
  CLR_CL_CHECK(NULL, clGetDeviceInfo(ctx->device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof max_group,
                                     &max_group, NULL));
  CLR_CL_CHECK(NULL, clGetDeviceInfo(ctx->device, CL_DEVICE_MAX_WORK_ITEM_DIMENSIONS, sizeof dims,
                                     &dims, NULL));
  if (dims >= 1 && dims <= 3)
    CLR_CL_CHECK(NULL, clGetDeviceInfo(ctx->device, CL_DEVICE_MAX_WORK_ITEM_SIZES,
                                       sizeof(size_t) * dims, items, NULL));
  CLR_CL_CHECK(NULL, clGetDeviceInfo(ctx->device, CL_DEVICE_LOCAL_MEM_SIZE, sizeof ctx->local_mem,
                                     &ctx->local_mem, NULL));
  clGetDeviceInfo(ctx->device, CL_DEVICE_AVAILABLE, sizeof available, &available, NULL);
  clGetDeviceInfo(ctx->device, CL_DEVICE_COMPILER_AVAILABLE, sizeof compiler, &compiler, NULL);
  if (!available)
    return clr_fail(NULL, CLR_ERROR_NO_DEVICE, "%s: the device is not available", ctx->device_name);
  if (!compiler)
    return clr_fail(NULL, CLR_ERROR_NO_DEVICE,
                    "%s: the device has no OpenCL C compiler (the kernels are built from source)",
                    ctx->device_name);
  if (strstr(profile, "EMBEDDED") && !has_word(extensions, "cles_khr_int64"))
    return clr_fail(NULL, CLR_ERROR_NO_DEVICE,
                    "%s: EMBEDDED_PROFILE device without cles_khr_int64: the kernels need 64-bit "
                    "integers (long, ulong)",
                    ctx->device_name);
  if (items[0] && items[0] < max_group) max_group = items[0];
  ctx->max_group = max_group ? max_group : 1;
  CLR_CHECK(default_kernel_shape(e, type, &ctx->default_shape));
  atomic_init(&ctx->shape, (int)ctx->default_shape);
  return CLR_SUCCESS;
}

clr_result clr_context_create(const clr_context_desc *desc, clr_context *out) {
  clr_clear_error();
  if (!out) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_context_create: out is NULL");
  *out = NULL;
  clr_context_desc full;
  clr_context_desc_init(&full);
  if (desc) CLR_CHECK(clr_desc_adopt(&full, sizeof full, desc, "clr_context_create: desc"));
  desc = &full;
  const char *selector = desc->device;
  if (!selector || !*selector) selector = getenv("CLRENDER_DEVICE");

  device_entry entries[MAX_DEVICES];
  int count = 0;
  CLR_CHECK(enumerate_devices(entries, MAX_DEVICES, &count));
  if (count > MAX_DEVICES) count = MAX_DEVICES;
  int chosen = 0;
  CLR_CHECK(choose_device(selector, entries, count, &chosen));

  clr_context ctx = calloc(1, sizeof *ctx);
  if (!ctx) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "clr_context_create: out of memory");
  atomic_init(&ctx->refcount, 1);
  ctx->platform = entries[chosen].platform;
  ctx->device = entries[chosen].device;
  ctx->is_gpu = entries[chosen].info.is_gpu;
  ctx->callback = desc->error_callback;
  ctx->callback_user = desc->error_user;
  snprintf(ctx->device_name, sizeof ctx->device_name, "%s: %s", entries[chosen].info.platform_name,
           entries[chosen].info.device_name);
  pthread_mutex_init(&ctx->lock, NULL);

  cl_device_fp_config fp = 0;
  if (clGetDeviceInfo(ctx->device, CL_DEVICE_SINGLE_FP_CONFIG, sizeof fp, &fp, NULL) == CL_SUCCESS)
    ctx->correctly_rounded_divide = (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
  cl_bool unified = CL_FALSE;
  if (clGetDeviceInfo(ctx->device, CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof unified, &unified, NULL) ==
      CL_SUCCESS)
    ctx->unified_memory = unified == CL_TRUE;
  cl_device_fp_config fp64 = 0;
  if (clGetDeviceInfo(ctx->device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64, &fp64, NULL) ==
      CL_SUCCESS)
    ctx->fp64 = fp64 != 0;
  clr_result dr = query_device(ctx, &entries[chosen]);
  if (dr != CLR_SUCCESS) {
    clr_context_release(ctx);
    return dr;
  }

  cl_int err = CL_SUCCESS;
  cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)ctx->platform, 0};
  ctx->cl = clCreateContext(props, 1, &ctx->device, NULL, NULL, &err);
  if (err != CL_SUCCESS) {
    clr_result r = clr_fail(NULL, CLR_ERROR_OPENCL, "clCreateContext failed for %s: %s (%d)",
                            ctx->device_name, clr_cl_error_name(err), (int)err);
    clr_context_release(ctx);
    return r;
  }
  ctx->queue = clCreateCommandQueue(ctx->cl, ctx->device, 0, &err);
  if (err != CL_SUCCESS) {
    clr_result r = clr_fail(NULL, CLR_ERROR_OPENCL, "clCreateCommandQueue failed for %s: %s (%d)",
                            ctx->device_name, clr_cl_error_name(err), (int)err);
    clr_context_release(ctx);
    return r;
  }
  *out = ctx;
  return CLR_SUCCESS;
}

void clr_context_retain(clr_context ctx) {
  if (ctx) atomic_fetch_add(&ctx->refcount, 1);
}

void clr_context_release(clr_context ctx) {
  if (!ctx || atomic_fetch_sub(&ctx->refcount, 1) != 1) return;
  if (ctx->queue) clFinish(ctx->queue);
  for (int i = 0; i < ctx->program_count; ++i) clReleaseProgram(ctx->programs[i].program);
  for (int i = 0; i < ctx->shared_count; ++i) clReleaseMemObject(ctx->shared[i].buffer);
  if (ctx->queue) clReleaseCommandQueue(ctx->queue);
  if (ctx->cl) clReleaseContext(ctx->cl);
  pthread_mutex_destroy(&ctx->lock);
  free(ctx);
}

const char *clr_context_device_name(clr_context ctx) { return ctx ? ctx->device_name : ""; }
int clr_context_device_is_gpu(clr_context ctx) { return ctx ? ctx->is_gpu : 0; }
cl_context clr_context_cl_context(clr_context ctx) { return ctx ? ctx->cl : NULL; }
cl_command_queue clr_context_cl_queue(clr_context ctx) { return ctx ? ctx->queue : NULL; }
cl_device_id clr_context_cl_device(clr_context ctx) { return ctx ? ctx->device : NULL; }

clr_result clr_kernel_shape_from_name(const char *name, clr_kernel_shape *out) {
  if (!name || !out)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_kernel_shape_from_name: NULL argument");
  static const char *const names[] = {"auto", "simd", "portable"};
  for (int i = 0; i < 3; ++i)
    if (strlen(name) == strlen(names[i]) && contains_nocase(name, names[i])) {
      *out = (clr_kernel_shape)i;
      return CLR_SUCCESS;
    }
  return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                  "unknown kernel shape \"%s\" (expected simd, portable or auto)", name);
}

const char *clr_kernel_shape_name(clr_kernel_shape shape) {
  switch (shape) {
    case CLR_KERNELS_AUTO:
      return "auto";
    case CLR_KERNELS_SIMD:
      return "simd";
    case CLR_KERNELS_PORTABLE:
      return "portable";
  }
  return "unknown";
}

clr_result clr_context_set_kernel_shape(clr_context ctx, clr_kernel_shape shape) {
  if (!ctx)
    return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "clr_context_set_kernel_shape: ctx is NULL");
  if (shape != CLR_KERNELS_AUTO && shape != CLR_KERNELS_SIMD && shape != CLR_KERNELS_PORTABLE)
    return clr_fail(ctx, CLR_ERROR_INVALID_ARGUMENT, "clr_context_set_kernel_shape: bad shape %d",
                    (int)shape);
  atomic_store(&ctx->shape, (int)(shape == CLR_KERNELS_AUTO ? ctx->default_shape : shape));
  return CLR_SUCCESS;
}

clr_kernel_shape clr_context_kernel_shape(clr_context ctx) {
  return ctx ? (clr_kernel_shape)atomic_load(&ctx->shape) : CLR_KERNELS_PORTABLE;
}

int clr_context_portable(clr_context ctx) {
  return clr_context_kernel_shape(ctx) == CLR_KERNELS_PORTABLE;
}

int clr_context_unified_memory(clr_context ctx) { return ctx ? ctx->unified_memory : 0; }

int clr_context_fp64(clr_context ctx) { return ctx ? ctx->fp64 : 0; }

cl_ulong clr_context_local_mem(clr_context ctx) { return ctx ? ctx->local_mem : 0; }

size_t clr_context_group_size(clr_context ctx, cl_kernel kernel, size_t wanted) {
  size_t g = wanted ? wanted : 1, kmax = 0, multiple = 0;
  if (g > ctx->max_group) g = ctx->max_group;
  if (clGetKernelWorkGroupInfo(kernel, ctx->device, CL_KERNEL_WORK_GROUP_SIZE, sizeof kmax, &kmax,
                               NULL) == CL_SUCCESS &&
      kmax && g > kmax)
    g = kmax;
  if (clGetKernelWorkGroupInfo(kernel, ctx->device, CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE,
                               sizeof multiple, &multiple, NULL) == CL_SUCCESS &&
      multiple > 1 && g > multiple)
    g = g / multiple * multiple;
  return g ? g : 1;
}

clr_result clr_context_launch(clr_context ctx, cl_kernel kernel, size_t items, size_t wanted_group,
                              const char *name) {
  if (items == 0) return CLR_SUCCESS;
  size_t local = clr_context_group_size(ctx, kernel, wanted_group);
  size_t global = (items + local - 1) / local * local;
  cl_int err = clEnqueueNDRangeKernel(ctx->queue, kernel, 1, NULL, &global, &local, 0, NULL, NULL);
  if (err != CL_SUCCESS)
    return clr_fail(
        ctx, CLR_ERROR_OPENCL,
        "clEnqueueNDRangeKernel(%s, %zu work-items, groups of %zu) failed on %s: %s (%d)", name,
        items, local, ctx->device_name, clr_cl_error_name(err), (int)err);
  return CLR_SUCCESS;
}

static const clr_embedded_kernel *find_embedded(const char *name) {
  for (int i = 0; i < clr_embedded_kernel_count; ++i)
    if (strcmp(clr_embedded_kernels[i].name, name) == 0) return &clr_embedded_kernels[i];
  return NULL;
}

/* The one place where build options are made: language version, exact arithmetic, specialisation. */
static void make_build_options(const clr_context ctx, const char *defines, char *out, size_t size) {
  snprintf(out, size, "-cl-std=CL1.2 -DCLR_OPENCL=1%s %s",
           ctx->correctly_rounded_divide ? " -cl-fp32-correctly-rounded-divide-sqrt" : "",
           defines ? defines : "");
}

static clr_result build_program(clr_context ctx, const clr_embedded_kernel *src,
                                const char *defines, cl_program *out) {
  cl_int err = CL_SUCCESS;
  const char *text = src->source;
  size_t length = src->length;
  char options[1024];
  make_build_options(ctx, defines, options, sizeof options);
  clr_program_key key;
  clr_program_key_make(&key, ctx->platform, ctx->device, src->name, text, length, options);
  *out = clr_program_cache_load(&key, ctx->cl, ctx->device, options);
  if (*out) return CLR_SUCCESS;
  cl_program program = clCreateProgramWithSource(ctx->cl, 1, &text, &length, &err);
  CLR_CL_CHECK_ERR(ctx, err, "clCreateProgramWithSource");
  err = clBuildProgram(program, 1, &ctx->device, options, NULL, NULL);
  if (err != CL_SUCCESS) {
    size_t log_size = 0;
    clGetProgramBuildInfo(program, ctx->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &log_size);
    char *log = malloc(log_size + 1);
    if (log) {
      log[0] = 0;
      if (clGetProgramBuildInfo(program, ctx->device, CL_PROGRAM_BUILD_LOG, log_size, log, NULL) !=
          CL_SUCCESS)
        log[0] = 0;
      log[log_size] = 0;
    }
    clr_result r = clr_fail(ctx, CLR_ERROR_KERNEL_BUILD,
                            "clBuildProgram failed for %s (options \"%s\") on %s: %s (%d)\n"
                            "build log:\n%s",
                            src->name, options, ctx->device_name, clr_cl_error_name(err), (int)err,
                            log ? log : "(no memory for the log)");
    free(log);
    clReleaseProgram(program);
    return r;
  }
  clr_program_cache_store(&key, program);
  *out = program;
  return CLR_SUCCESS;
}

clr_result clr_context_program(clr_context ctx, const char *name, const char *defines,
                               cl_program *program) {
  if (!ctx || !name || !program)
    return clr_fail(ctx, CLR_ERROR_NULL_POINTER, "clr_context_program: NULL argument");
  if (!defines) defines = "";
  if (strlen(name) >= sizeof ctx->programs[0].name ||
      strlen(defines) >= sizeof ctx->programs[0].defines)
    return clr_fail(ctx, CLR_ERROR_INTERNAL, "clr_context_program: name or defines too long");
  const clr_embedded_kernel *src = find_embedded(name);
  if (!src) return clr_fail(ctx, CLR_ERROR_INTERNAL, "no embedded kernel file named %s", name);
  pthread_mutex_lock(&ctx->lock);
  for (int i = 0; i < ctx->program_count; ++i) {
    if (strcmp(ctx->programs[i].name, name) == 0 &&
        strcmp(ctx->programs[i].defines, defines) == 0) {
      *program = ctx->programs[i].program;
      pthread_mutex_unlock(&ctx->lock);
      return CLR_SUCCESS;
    }
  }
  clr_result r = CLR_SUCCESS;
  if (ctx->program_count == MAX_PROGRAMS) {
    r = clr_fail(ctx, CLR_ERROR_INTERNAL, "program cache full (%d programs)", MAX_PROGRAMS);
  } else {
    r = build_program(ctx, src, defines, program);
    if (r == CLR_SUCCESS) {
      cached_program *c = &ctx->programs[ctx->program_count++];
      snprintf(c->name, sizeof c->name, "%s", name);
      snprintf(c->defines, sizeof c->defines, "%s", defines);
      c->program = *program;
    }
  }
  pthread_mutex_unlock(&ctx->lock);
  return r;
}

clr_result clr_context_kernel(clr_context ctx, const char *program_name, const char *defines,
                              const char *kernel_name, cl_kernel *kernel) {
  cl_program program = NULL;
  CLR_CHECK(clr_context_program(ctx, program_name, defines, &program));
  cl_int err = CL_SUCCESS;
  *kernel = clCreateKernel(program, kernel_name, &err);
  if (err != CL_SUCCESS)
    return clr_fail(ctx, CLR_ERROR_OPENCL, "clCreateKernel(%s in %s) failed: %s (%d)", kernel_name,
                    program_name, clr_cl_error_name(err), (int)err);
  return CLR_SUCCESS;
}

clr_result clr_context_shared_buffer(clr_context ctx, const char *key, const void *data,
                                     size_t bytes, cl_mem *buffer) {
  if (!ctx || !key || !data || !buffer || bytes == 0)
    return clr_fail(ctx, CLR_ERROR_NULL_POINTER, "clr_context_shared_buffer: bad argument");
  pthread_mutex_lock(&ctx->lock);
  for (int i = 0; i < ctx->shared_count; ++i) {
    if (strcmp(ctx->shared[i].key, key) == 0) {
      *buffer = ctx->shared[i].buffer;
      pthread_mutex_unlock(&ctx->lock);
      return CLR_SUCCESS;
    }
  }
  clr_result r = CLR_SUCCESS;
  if (ctx->shared_count == MAX_SHARED || strlen(key) >= sizeof ctx->shared[0].key) {
    r = clr_fail(ctx, CLR_ERROR_INTERNAL, "shared buffer table full or key %s too long", key);
  } else {
    cl_int err = CL_SUCCESS;
    /* The tables live as long as the process and never change: a device sharing the host's
     * memory reads them in place (PoCL: no second copy of Halton's 7.9 MB permutations). */
    cl_mem_flags where = ctx->unified_memory ? CL_MEM_USE_HOST_PTR : CL_MEM_COPY_HOST_PTR;
    cl_mem mem = clCreateBuffer(ctx->cl, CL_MEM_READ_ONLY | where, bytes, (void *)data, &err);
    if (err != CL_SUCCESS) {
      r = clr_fail(ctx, CLR_ERROR_OPENCL, "clCreateBuffer(%s, %zu bytes) failed: %s (%d)", key,
                   bytes, clr_cl_error_name(err), (int)err);
    } else {
      shared_buffer *s = &ctx->shared[ctx->shared_count++];
      snprintf(s->key, sizeof s->key, "%s", key);
      s->buffer = mem;
      *buffer = mem;
    }
  }
  pthread_mutex_unlock(&ctx->lock);
  return r;
}
