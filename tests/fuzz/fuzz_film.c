/* Fuzz target, differential: film_add_samples on the default OpenCL device (PoCL: the SIMD or the
 * portable kernels, any binning thread count, work-group size and accumulation tile size) must
 * give the host film (no context: the kernels' C build) the same counts and the same double sums,
 * bit for bit, for any film, filter and samples (NaN, Inf, negative, outside, on pixel and
 * radius boundaries, raw float bits), in one call or two, from host memory or a device buffer.
 * A difference aborts, so libFuzzer reports it with the input. The input's layout:
 * fuzz_film_input.h. */
#include "clrender.h"
#include "film_internal.h"
#include "fuzz_film_input.h"

static clr_context ctx;

static void fail(const char *what) {
  fprintf(stderr, "fuzz_film: the device film and the host film differ: %s\n", what);
  abort();
}

/* film_add_samples_buffer from a device copy of the samples (none for none). */
static clr_result add_from_buffer(clr_film film, const clr_film_sample *s, size_t n) {
  if (!n) return film_add_samples(film, s, n);
  cl_int err = CL_SUCCESS;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              n * sizeof *s, (void *)s, &err);
  if (err != CL_SUCCESS) fail("clCreateBuffer");
  clr_result r = film_add_samples_buffer(film, buf, n);
  clReleaseMemObject(buf);
  return r;
}

/* Adds the same samples to both films; both calls succeed or fail alike. */
static void add_both(clr_film dev, clr_film host, const clr_film_sample *s, size_t n,
                     int from_buffer) {
  clr_result a = from_buffer ? add_from_buffer(dev, s, n) : film_add_samples(dev, s, n);
  fuzz_report("film_add_samples (device)", a);
  clr_result b = film_add_samples(host, s, n);
  fuzz_report("film_add_samples (host)", b);
  if (a != b) fail("one call failed");
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  ctx = fuzz_device_context("fuzz_film");
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_reader r = {data, size};
  fuzz_film_input in;
  fuzz_read_film(&r, &in);
  clr_film dev = NULL, host = NULL;
  if (!fuzz_create_films(ctx, &in.desc, &dev, &host)) return 0;
  if (clr_context_set_kernel_shape(
          ctx, (in.flags & FUZZ_FLAG_PORTABLE) ? CLR_KERNELS_PORTABLE : CLR_KERNELS_SIMD) !=
          CLR_SUCCESS ||
      film_set_bin_threads(dev, in.threads) != CLR_SUCCESS ||
      film_set_group_size(dev, in.group) != CLR_SUCCESS)
    fail(clr_last_error_message());
  size_t n = 0;
  clr_film_sample *samples = fuzz_read_samples(&r, &in, &n);
  size_t first = fuzz_first_call(&in, n);
  const int from_buffer = (in.flags & FUZZ_FLAG_BUFFER) != 0;
  add_both(dev, host, samples, first, from_buffer);
  if (first < n) add_both(dev, host, samples + first, n - first, from_buffer);
  const char *differ = fuzz_films_differ(dev, host);
  if (differ) fail(differ);
  free(samples);
  film_release(dev);
  film_release(host);
  return 0;
}
