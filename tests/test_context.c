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
  for (int i = 0; i < 6 && colon[2 + i]; ++i)
    sub[i] = (char)((i % 2) ? colon[2 + i] : toupper(colon[2 + i]));
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
  assert_int_equal(
      clEnqueueNDRangeKernel(clr_context_cl_queue(ctx), k, 1, NULL, &global, NULL, 0, NULL, NULL),
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

/* The result type is a fixed 32 bits with stable values; the version query matches the headers;
 * a message may quote the previous one. */
static void test_result_version_messages(void **state) {
  (void)state;
  assert_int_equal(sizeof(clr_result), 4);
  assert_int_equal(CLR_SUCCESS, 0);
  assert_int_equal(CLR_ERROR_INVALID_ARGUMENT, 1);
  assert_int_equal(CLR_ERROR_IO, 19);
  assert_int_equal(CLR_ERROR_INTERNAL, 27);
  assert_int_equal(CLR_RESULT_COUNT, 28);
  assert_string_equal(clr_result_name(CLR_ERROR_IO), "CLR_ERROR_IO");
  assert_string_equal(clr_result_string(CLR_RESULT_COUNT), "unknown result code");
  assert_string_equal(clr_version(), CLR_VERSION_STRING);
  assert_int_equal(clr_version_number(), CLR_VERSION_NUMBER);
  assert_int_equal(CLR_VERSION_NUMBER,
                   CLR_VERSION_MAJOR * 10000 + CLR_VERSION_MINOR * 100 + CLR_VERSION_PATCH);
  assert_int_equal(clr_set_last_error(CLR_ERROR_IO, "inner reason %d", 7), CLR_ERROR_IO);
  clr_set_last_error(CLR_ERROR_SCENE, "x.pbrt:8: Shape \"plymesh\": %s", clr_last_error_message());
  assert_string_equal(clr_last_error_message(), "x.pbrt:8: Shape \"plymesh\": inner reason 7");
}

/* A sampler without a context is host-only: the reference works, the device call refuses. */
static void test_null_context_sampler(void **state) {
  (void)state;
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, CLR_SAMPLER_SOBOL);
  d.film.x_resolution = d.film.y_resolution = 4;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  const clr_sample_request req = {2, 0};
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = (clr_bounds2i){0, 0, 1, 1};
  b.requests = &req;
  b.request_count = 1;
  float values[2 * 16];
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = values;
  assert_int_equal(clr_sampler_generate_reference(s, &b, &out), CLR_SUCCESS);
  assert_true(values[0] == 0.0f && values[1] == 0.0f); /* Sobol sample 0 of pixel (0,0) */
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "without a context"));
  clr_sampler_release(s);
  clr_sampler_release(NULL);
  assert_int_equal(clr_sampler_create(NULL, NULL, &s), CLR_ERROR_NULL_POINTER);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_result_version_messages),
      cmocka_unit_test(test_null_context_sampler),
      cmocka_unit_test(test_result_strings),
      cmocka_unit_test(test_device_list),
      cmocka_unit_test(test_device_selection),
      cmocka_unit_test(test_embedded_program_runs),
      cmocka_unit_test(test_build_failure_reports_log),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
