/* The two kernel shapes behind one interface (clrender/kernels.h): names, the per-context choice,
 * CLRENDER_KERNELS, and the same bits from both in a render and from `clrender samples`. */
#define _DEFAULT_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "clr_internal.h"
#include "renderer.h"
#include "scene_parser.h"
#include "scene_test_util.h"

static void test_names(void **state) {
  (void)state;
  clr_kernel_shape shape;
  assert_int_equal(clr_kernel_shape_from_name("portable", &shape), CLR_SUCCESS);
  assert_int_equal(shape, CLR_KERNELS_PORTABLE);
  assert_int_equal(clr_kernel_shape_from_name("SIMD", &shape), CLR_SUCCESS);
  assert_int_equal(shape, CLR_KERNELS_SIMD);
  assert_int_equal(clr_kernel_shape_from_name("auto", &shape), CLR_SUCCESS);
  assert_int_equal(shape, CLR_KERNELS_AUTO);
  assert_int_equal(clr_kernel_shape_from_name("gpu", &shape), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "\"gpu\""));
  assert_int_equal(clr_kernel_shape_from_name("simdx", &shape), CLR_ERROR_INVALID_ARGUMENT);
  assert_string_equal(clr_kernel_shape_name(CLR_KERNELS_PORTABLE), "portable");
  assert_string_equal(clr_kernel_shape_name(CLR_KERNELS_SIMD), "simd");
}

/* The automatic choice, the override and the environment variable. */
static void test_context_choice(void **state) {
  (void)state;
  unsetenv("CLRENDER_KERNELS");
  clr_context ctx = NULL;
  assert_int_equal(clr_context_create(NULL, &ctx), CLR_SUCCESS);
  clr_kernel_shape automatic = clr_context_kernel_shape(ctx);
  int pocl_cpu = strstr(clr_context_device_name(ctx), "Portable Computing Language") &&
                 !clr_context_device_is_gpu(ctx);
  assert_int_equal(automatic, pocl_cpu ? CLR_KERNELS_SIMD : CLR_KERNELS_PORTABLE);
  assert_int_equal(clr_context_set_kernel_shape(ctx, CLR_KERNELS_PORTABLE), CLR_SUCCESS);
  assert_int_equal(clr_context_kernel_shape(ctx), CLR_KERNELS_PORTABLE);
  assert_int_equal(clr_context_set_kernel_shape(ctx, CLR_KERNELS_AUTO), CLR_SUCCESS);
  assert_int_equal(clr_context_kernel_shape(ctx), automatic);
  assert_int_equal(clr_context_set_kernel_shape(ctx, (clr_kernel_shape)9),
                   CLR_ERROR_INVALID_ARGUMENT);
  clr_context_release(ctx);

  setenv("CLRENDER_KERNELS", "portable", 1);
  assert_int_equal(clr_context_create(NULL, &ctx), CLR_SUCCESS);
  assert_int_equal(clr_context_kernel_shape(ctx), CLR_KERNELS_PORTABLE);
  clr_context_release(ctx);
  setenv("CLRENDER_KERNELS", "vector", 1);
  assert_int_equal(clr_context_create(NULL, &ctx), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "CLRENDER_KERNELS=vector"));
  unsetenv("CLRENDER_KERNELS");
}

/* Work-group sizes come from the device and the kernel, never above their limits. */
static void test_group_sizes_from_the_device(void **state) {
  (void)state;
  clr_context ctx = NULL;
  assert_int_equal(clr_context_create(NULL, &ctx), CLR_SUCCESS);
  cl_kernel k = NULL;
  assert_int_equal(clr_context_kernel(ctx, "selftest_kernels.cl", NULL, "clr_selftest_fill", &k),
                   CLR_SUCCESS);
  cl_device_id dev = clr_context_cl_device(ctx);
  size_t kmax = 0, dmax = 0, multiple = 0, items[3] = {0, 0, 0};
  assert_int_equal(
      clGetKernelWorkGroupInfo(k, dev, CL_KERNEL_WORK_GROUP_SIZE, sizeof kmax, &kmax, NULL),
      CL_SUCCESS);
  assert_int_equal(clGetKernelWorkGroupInfo(k, dev, CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE,
                                            sizeof multiple, &multiple, NULL),
                   CL_SUCCESS);
  assert_int_equal(clGetDeviceInfo(dev, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof dmax, &dmax, NULL),
                   CL_SUCCESS);
  assert_int_equal(clGetDeviceInfo(dev, CL_DEVICE_MAX_WORK_ITEM_SIZES, sizeof items, items, NULL),
                   CL_SUCCESS);
  size_t most = clr_context_group_size(ctx, k, (size_t)1 << 30);
  assert_true(most >= 1 && most <= kmax && most <= dmax && most <= items[0]);
  assert_int_equal(clr_context_group_size(ctx, k, 0), 1);
  assert_int_equal(clr_context_group_size(ctx, k, 1), 1);
  if (multiple > 1 && multiple + multiple / 2 <= most)
    assert_int_equal(clr_context_group_size(ctx, k, multiple + multiple / 2), multiple);
  /* A launch of a count that is no multiple of the group. */
  cl_int err = CL_SUCCESS;
  size_t group = clr_context_group_size(ctx, k, 64), n = 1000;
  size_t padded = (n + group - 1) / group * group;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_WRITE,
                              padded * sizeof(cl_uint), NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  cl_uint value = 5;
  assert_int_equal(clSetKernelArg(k, 0, sizeof buf, &buf), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 1, sizeof value, &value), CL_SUCCESS);
  assert_int_equal(clr_context_launch(ctx, k, n, 64, "clr_selftest_fill"), CLR_SUCCESS);
  cl_uint *out = malloc(padded * sizeof(cl_uint));
  assert_int_equal(clEnqueueReadBuffer(clr_context_cl_queue(ctx), buf, CL_TRUE, 0,
                                       padded * sizeof(cl_uint), out, 0, NULL, NULL),
                   CL_SUCCESS);
  for (size_t i = 0; i < n; ++i) assert_int_equal(out[i], 5 + i);
  free(out);
  clReleaseMemObject(buf);
  clReleaseKernel(k);
  clr_context_release(ctx);
}

static clr_render_image render(const char *kernels) {
  const char *scene =
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n"
      "Film \"image\" \"integer xresolution\" [20] \"integer yresolution\" [12]\n"
      "PixelFilter \"gaussian\"\n"
      "Sampler \"sobol\" \"integer pixelsamples\" [4]\n"
      "Integrator \"ambientocclusion\" \"integer nsamples\" [2]\n"
      "WorldBegin\nShape \"sphere\" \"float radius\" [1]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 -1  10 -10 -1  10 10 -1  -10 10 -1]\nWorldEnd\n";
  clr_render_options o;
  clr_render_options_init(&o);
  o.nthreads = 2;
  o.kernels = kernels;
  return stu_render_image(scene, "shapes.pbrt", &o, NULL);
}

static void test_render_same_bits(void **state) {
  (void)state;
  clr_render_image simd = render("simd"), portable = render("portable");
  assert_int_equal(simd.width * simd.height, portable.width * portable.height);
  double sum = 0;
  for (int i = 0; i < simd.width * simd.height * 3; ++i) sum += simd.rgb[i];
  assert_true(sum > 0);
  assert_memory_equal(simd.rgb, portable.rgb,
                      sizeof(float) * 3 * (size_t)(simd.width * simd.height));
  free(simd.rgb);
  free(portable.rgb);
}

#ifdef CLR_CLI_PATH
static size_t run(const char *args, char *buf, size_t size) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s %s 2>&1", CLR_CLI_PATH, args);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t n = fread(buf, 1, size - 1, p);
  buf[n] = 0;
  int status = pclose(p);
  return status == 0 ? n : 0;
}

static void test_cli_samples_same_output(void **state) {
  (void)state;
  static char a[1 << 18], b[1 << 18], c[1 << 18];
  static const char *samplers[] = {"random", "stratified", "halton",
                                   "sobol",  "02sequence", "maxmindist"};
  for (int s = 0; s < 6; ++s) {
    char args[256];
    snprintf(args, sizeof args,
             "samples --sampler %s --spp 4 --res 16x16 --pixels 1,2,7,5 --requests 2,1,2,2:3 "
             "--kernels ",
             samplers[s]);
    char with[300];
    snprintf(with, sizeof with, "%ssimd", args);
    assert_true(run(with, a, sizeof a) > 0);
    snprintf(with, sizeof with, "%sportable", args);
    assert_true(run(with, b, sizeof b) > 0);
    assert_string_equal(a, b);
    snprintf(with, sizeof with,
             "samples --sampler %s --spp 4 --res 16x16 --pixels 1,2,7,5 --requests 2,1,2,2:3 "
             "--reference",
             samplers[s]);
    assert_true(run(with, c, sizeof c) > 0);
    assert_string_equal(a, c);
  }
  assert_true(run("devices", a, sizeof a) > 0);
  assert_true(strstr(a, ", kernels simd]") || strstr(a, ", kernels portable]"));
  assert_int_equal(run("samples --sampler sobol --kernels wide", a, sizeof a), 0);
  assert_non_null(strstr(a, "--kernels"));
}
#endif

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_names),
      cmocka_unit_test(test_context_choice),
      cmocka_unit_test(test_group_sizes_from_the_device),
      cmocka_unit_test(test_render_same_bits),
#ifdef CLR_CLI_PATH
      cmocka_unit_test(test_cli_samples_same_output),
#endif
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
