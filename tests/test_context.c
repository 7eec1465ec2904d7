/* OpenCL runtime: device listing and selection, embedded programs, build-log reporting. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clr_internal.h"
#include "clrender.h"

static void test_result_strings(void **state) {
  (void)state;
  assert_string_equal(clr_result_name(CLR_ERROR_INVALID_SPP), "CLR_ERROR_INVALID_SPP");
  assert_string_equal(clr_result_string(CLR_SUCCESS), "success");
  assert_string_equal(clr_result_string((clr_result)9999), "unknown result code");
  for (int r = 0; r < CLR_RESULT_COUNT; ++r) assert_true(strlen(clr_result_string(r)) > 3);
}

static void test_device_list(void **state) {
  (void)state;
  clr_device_info infos[8];
  int count = 0;
  assert_int_equal(clr_device_list(infos, 8, &count), CLR_SUCCESS);
  assert_true(count >= 1);
  assert_int_equal(infos[0].index, 0);
  assert_true(strlen(infos[0].device_name) > 0);
  assert_true(infos[0].compute_units >= 1);
  assert_int_equal(clr_device_list(infos, 8, NULL), CLR_ERROR_NULL_POINTER);
}

static int callback_calls;
static void count_errors(void *user, clr_result code, const char *message) {
  (void)user;
  (void)message;
  if (code != CLR_SUCCESS) ++callback_calls;
}

static void test_device_selection(void **state) {
  (void)state;
  clr_context_desc desc;
  clr_context_desc_init(&desc);
  clr_context ctx = NULL;
  desc.device = "0";
  assert_int_equal(clr_context_create(&desc, &ctx), CLR_SUCCESS);
  char name[300];
  snprintf(name, sizeof name, "%s", clr_context_device_name(ctx));
  clr_context_release(ctx);
  /* A substring of the device's name picks the same device, whatever the case. */
  const char *colon = strstr(name, ": ");
  assert_non_null(colon);
  char sub[8] = {0};
  for (int i = 0; i < 6 && colon[2 + i]; ++i) sub[i] = (char)((i % 2) ? colon[2 + i] : toupper(colon[2 + i]));
  desc.device = sub;
  assert_int_equal(clr_context_create(&desc, &ctx), CLR_SUCCESS);
  clr_context_release(ctx);
  desc.device = "no-such-device-xyz";
  assert_int_equal(clr_context_create(&desc, &ctx), CLR_ERROR_NO_DEVICE);
  assert_null(ctx);
  assert_non_null(strstr(clr_last_error_message(), "no-such-device-xyz"));
  desc.device = "97";
  assert_int_equal(clr_context_create(&desc, &ctx), CLR_ERROR_NO_DEVICE);
  desc.struct_size = 3;
  assert_int_equal(clr_context_create(&desc, &ctx), CLR_ERROR_INVALID_ARGUMENT);
}

static void test_embedded_program_runs(void **state) {
  (void)state;
  clr_context ctx = NULL;
  assert_int_equal(clr_context_create(NULL, &ctx), CLR_SUCCESS);
  cl_kernel k = NULL;
  assert_int_equal(clr_context_kernel(ctx, "selftest_kernels.cl", NULL, "clr_selftest_fill", &k),
                   CLR_SUCCESS);
  cl_int err = 0;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_WRITE_ONLY, 64 * 4, NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  cl_uint value = 1000;
  assert_int_equal(clSetKernelArg(k, 0, sizeof buf, &buf), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 1, sizeof value, &value), CL_SUCCESS);
  size_t global = 64;
  assert_int_equal(clEnqueueNDRangeKernel(clr_context_cl_queue(ctx), k, 1, NULL, &global, NULL, 0,
                                          NULL, NULL),
                   CL_SUCCESS);
  cl_uint out[64];
  assert_int_equal(clEnqueueReadBuffer(clr_context_cl_queue(ctx), buf, CL_TRUE, 0, sizeof out, out,
                                       0, NULL, NULL),
                   CL_SUCCESS);
  for (int i = 0; i < 64; ++i) assert_int_equal(out[i], 1000 + i);
  clReleaseMemObject(buf);
  clReleaseKernel(k);
  clr_context_release(ctx);
}

static void test_build_failure_reports_log(void **state) {
  (void)state;
  clr_context_desc desc;
  clr_context_desc_init(&desc);
  desc.error_callback = count_errors;
  clr_context ctx = NULL;
  assert_int_equal(clr_context_create(&desc, &ctx), CLR_SUCCESS);
  cl_program p = NULL;
  callback_calls = 0;
  assert_int_equal(clr_context_program(ctx, "selftest_kernels.cl", "-DCLR_SELFTEST_BREAK", &p),
                   CLR_ERROR_KERNEL_BUILD);
  assert_int_equal(callback_calls, 1);
  const char *msg = clr_last_error_message();
  assert_non_null(strstr(msg, "build log"));
  assert_non_null(strstr(msg, "selftest_kernels.cl:6"));
  assert_int_equal(clr_context_program(ctx, "missing.cl", NULL, &p), CLR_ERROR_INTERNAL);
  clr_context_release(ctx);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_result_strings),
      cmocka_unit_test(test_device_list),
      cmocka_unit_test(test_device_selection),
      cmocka_unit_test(test_embedded_program_runs),
      cmocka_unit_test(test_build_failure_reports_log),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
