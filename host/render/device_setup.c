/* Context, film and sampler made on a helper thread, overlapping the scene build. */
#include "device_setup.h"
#include <stdio.h>
#include <string.h>
#include "clrender/kernels.h"

/* Generates one sample of the first sample pixel: on the device, so the sampler's kernel program
 * (the same build defines as the render's batches: they depend on the sampler and the film, not
 * on the batch) is built or loaded from the implementation's cache now; with the host reference,
 * so the sampler's process-wide tables (Halton's permutations) are built. */
static clr_result warm_sampler(clr_sampler sampler, int reference) {
  clr_sample_request film_offset = {2, 0};
  clr_sample_batch batch;
  clr_sample_batch_init(&batch);
  clr_bounds2i b = clr_sampler_sample_bounds(sampler);
  batch.pixels = (clr_bounds2i){b.x0, b.y0, b.x0 + 1, b.y0 + 1};
  batch.sample_count = 1;
  batch.requests = &film_offset;
  batch.request_count = 1;
  float values[2];
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = values;
  return reference ? clr_sampler_generate_reference(sampler, &batch, &out)
                   : clr_sampler_generate(sampler, &batch, &out);
}

static clr_result setup(clr_device_setup *s) {
  clr_result r = clr_context_create(&s->context_desc, &s->ctx);
  if (r == CLR_SUCCESS && s->kernels) {
    clr_kernel_shape shape;
    r = clr_kernel_shape_from_name(s->kernels, &shape);
    if (r == CLR_SUCCESS) r = clr_context_set_kernel_shape(s->ctx, shape);
  }
  if (r == CLR_SUCCESS) r = film_create(s->ctx, &s->film_desc, &s->film);
  if (r == CLR_SUCCESS) r = clr_sampler_create(s->ctx, &s->sampler_desc, &s->sampler);
  if (r == CLR_SUCCESS) r = warm_sampler(s->sampler, 0);
  return r;
}

static void *setup_main(void *arg) {
  clr_device_setup *s = arg;
  s->result = setup(s);
  if (s->result != CLR_SUCCESS)
    snprintf(s->message, sizeof s->message, "%s", clr_last_error_message());
  return NULL;
}

/* Builds the sampler's tables through a host-only sampler while the OpenCL implementation loads
 * (Halton's take a fifth of the setup thread's time, profile 2026-11-30); errors are left to the
 * setup thread, which meets them again. */
static void *tables_main(void *arg) {
  clr_device_setup *s = arg;
  clr_sampler host = NULL;
  if (clr_sampler_create(NULL, &s->sampler_desc, &host) == CLR_SUCCESS) warm_sampler(host, 1);
  if (host) clr_sampler_release(host);
  return NULL;
}

void clr_device_setup_start(clr_device_setup *s, const clr_context_desc *context_desc,
                            const char *kernels, const clr_film_desc *film_desc,
                            const clr_sampler_desc *sampler_desc) {
  memset(s, 0, sizeof *s);
  s->context_desc = *context_desc;
  s->kernels = kernels;
  s->film_desc = *film_desc;
  s->sampler_desc = *sampler_desc;
  s->threaded = pthread_create(&s->thread, NULL, setup_main, s) == 0;
  if (!s->threaded) setup_main(s);
  /* Only Halton's tables are worth it (the host reference of any global sampler builds them). */
  if (sampler_desc->type == CLR_SAMPLER_HALTON)
    s->tables_threaded = pthread_create(&s->tables_thread, NULL, tables_main, s) == 0;
}

clr_result clr_device_setup_finish(clr_device_setup *s) {
  if (s->threaded) pthread_join(s->thread, NULL);
  if (s->tables_threaded) pthread_join(s->tables_thread, NULL);
  s->threaded = s->tables_threaded = 0;
  if (s->result == CLR_SUCCESS) return CLR_SUCCESS;
  clr_device_setup_release(s);
  return clr_set_last_error(s->result, "%s", s->message);
}

void clr_device_setup_release(clr_device_setup *s) {
  if (s->sampler) clr_sampler_release(s->sampler);
  if (s->film) film_release(s->film);
  if (s->ctx) clr_context_release(s->ctx);
  s->sampler = NULL;
  s->film = NULL;
  s->ctx = NULL;
}
