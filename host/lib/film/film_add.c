/* film_add_samples and its variants: check the arguments, cut the samples into chunks, take each
 * chunk's float sums from the accumulator and add them into the film's double sums. */
#include <pthread.h>
#include "clr_internal.h"
#include "film_internal.h"

static clr_result check_add_args(clr_film film, const void *samples, size_t count, const char *fn) {
  if (!film || !samples)
    return clr_fail(film ? film->ctx : NULL, CLR_ERROR_NULL_POINTER, "%s: %s is NULL", fn,
                    !film ? "film" : "samples");
  if (count == 0) return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "%s: count is 0", fn);
  if (count > UINT32_MAX)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "%s: count %zu exceeds %u", fn, count,
                    UINT32_MAX);
  return CLR_SUCCESS;
}

static size_t chunk_length(size_t count, size_t at) {
  return count - at < CLR_FILM_CHUNK_SAMPLES ? count - at : CLR_FILM_CHUNK_SAMPLES;
}

/* One chunk through the accumulator (kernels, or the host reference) into the double sums.
 * Caller holds the film's lock. */
static clr_result add_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                            int reference) {
  clr_film_chunk_sums chunk;
  clr_result r = clr_film_accumulate_chunk(film, samples, count, reference, &chunk);
  if (r == CLR_SUCCESS && chunk.sums)
    clr_film_add_block(film, chunk.block, chunk.sums, reference ? 1 : clr_film_host_threads(film));
  clr_result released = clr_film_chunk_sums_release(film, &chunk);
  return r != CLR_SUCCESS ? r : released;
}

static clr_result add_host_samples(clr_film film, const clr_film_sample *samples, size_t count,
                                   int reference, const char *fn) {
  clr_clear_error();
  CLR_CHECK(check_add_args(film, samples, count, fn));
  pthread_mutex_lock(&film->lock);
  clr_result r = CLR_SUCCESS;
  if (!reference && film->ctx)
    r = clr_film_accumulate_overlapped(film, samples, count);
  else
    for (size_t at = 0; at < count && r == CLR_SUCCESS; at += CLR_FILM_CHUNK_SAMPLES)
      r = add_chunk(film, samples + at, chunk_length(count, at), reference);
  pthread_mutex_unlock(&film->lock);
  return r;
}

clr_result film_add_samples(clr_film film, const clr_film_sample *samples, size_t count) {
  return add_host_samples(film, samples, count, 0, "film_add_samples");
}

clr_result film_add_samples_reference(clr_film film, const clr_film_sample *samples, size_t count) {
  return add_host_samples(film, samples, count, 1, "film_add_samples_reference");
}

clr_result film_add_samples_buffer(clr_film film, cl_mem samples, size_t count) {
  clr_clear_error();
  CLR_CHECK(check_add_args(film, samples, count, "film_add_samples_buffer"));
  if (!film->ctx)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "film_add_samples_buffer: the film has no OpenCL context (film_create(NULL))");
  size_t size = 0;
  CLR_CL_CHECK(film->ctx, clGetMemObjectInfo(samples, CL_MEM_SIZE, sizeof size, &size, NULL));
  if (size / sizeof(clr_film_sample) < count)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_add_samples_buffer: buffer of %zu bytes holds fewer than %zu samples",
                    size, count);
  pthread_mutex_lock(&film->lock);
  clr_result r = clr_film_open_device_sums(film);
  cl_command_queue q = clr_context_cl_queue(film->ctx);
  for (size_t at = 0; at < count && r == CLR_SUCCESS; at += CLR_FILM_CHUNK_SAMPLES) {
    size_t n = chunk_length(count, at);
    cl_int err = CL_SUCCESS;
    clr_film_sample *host = clEnqueueMapBuffer(q, samples, CL_TRUE, CL_MAP_READ, at * sizeof *host,
                                               n * sizeof *host, 0, NULL, NULL, &err);
    if (err != CL_SUCCESS) {
      r = clr_fail(film->ctx, CLR_ERROR_OPENCL,
                   "film_add_samples_buffer: clEnqueueMapBuffer "
                   "failed: %s (%d)",
                   clr_cl_error_name(err), (int)err);
      break;
    }
    r = add_chunk(film, host, n, 0);
    err = clEnqueueUnmapMemObject(q, samples, host, 0, NULL, NULL);
    if (err != CL_SUCCESS && r == CLR_SUCCESS)
      r = clr_fail(film->ctx, CLR_ERROR_OPENCL,
                   "film_add_samples_buffer: clEnqueueUnmapMemObject "
                   "failed: %s (%d)",
                   clr_cl_error_name(err), (int)err);
  }
  clr_result closed = clr_film_close_device_sums(film);
  pthread_mutex_unlock(&film->lock);
  return r != CLR_SUCCESS ? r : closed;
}
