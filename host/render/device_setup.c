/* Context, film and sampler made beside a helper thread's work (the scene build). */
#include "device_setup.h"
#include <pthread.h>
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

int clr_device_is_host(const char *device) { return device && strcmp(device, "host") == 0; }

/* The host reference: no context, a host film and sampler (nothing loads OpenCL). */
static clr_result setup_host(clr_device_setup *s, const clr_film_desc *film_desc,
                             const clr_sampler_desc *sampler_desc) {
  clr_result r = film_create(NULL, film_desc, &s->film);
  if (r == CLR_SUCCESS) r = clr_sampler_create(NULL, sampler_desc, &s->sampler);
  if (r == CLR_SUCCESS) r = warm_sampler(s->sampler, 1);
  return r;
}

static clr_result setup(clr_device_setup *s, const clr_context_desc *context_desc,
                        const char *kernels, const clr_film_desc *film_desc,
                        const clr_sampler_desc *sampler_desc) {
  if (clr_device_is_host(context_desc->device)) return setup_host(s, film_desc, sampler_desc);
  clr_result r = clr_context_create(context_desc, &s->ctx);
  if (r == CLR_SUCCESS && kernels) {
    clr_kernel_shape shape;
    r = clr_kernel_shape_from_name(kernels, &shape);
    if (r == CLR_SUCCESS) r = clr_context_set_kernel_shape(s->ctx, shape);
  }
  if (r == CLR_SUCCESS) r = film_create(s->ctx, film_desc, &s->film);
  if (r == CLR_SUCCESS) r = clr_sampler_create(s->ctx, sampler_desc, &s->sampler);
  if (r == CLR_SUCCESS) r = warm_sampler(s->sampler, 0);
  return r;
}

/* A helper thread's job: the caller's work, or the sampler's host tables. */
typedef struct helper {
  clr_setup_work_fn work;
  void *user;
  const clr_sampler_desc *tables_of; /* build this sampler's host tables instead of work */
  clr_result result;
  char message[1024];
  pthread_t thread;
  int started;
} helper;

static void *helper_main(void *arg) {
  helper *h = arg;
  if (h->tables_of) { /* errors are left to the device setup, which meets them again */
    clr_sampler host = NULL;
    if (clr_sampler_create(NULL, h->tables_of, &host) == CLR_SUCCESS) warm_sampler(host, 1);
    if (host) clr_sampler_release(host);
    return NULL;
  }
  h->result = h->work(h->user);
  if (h->result != CLR_SUCCESS)
    snprintf(h->message, sizeof h->message, "%s", clr_last_error_message());
  return NULL;
}

clr_result clr_device_setup_run(clr_device_setup *s, const clr_context_desc *context_desc,
                                const char *kernels, const clr_film_desc *film_desc,
                                const clr_sampler_desc *sampler_desc, clr_setup_work_fn work,
                                void *user) {
  memset(s, 0, sizeof *s);
  helper job, tables;
  memset(&job, 0, sizeof job);
  memset(&tables, 0, sizeof tables);
  job.work = work;
  job.user = user;
  /* A host-only sampler builds Halton's smallest table set beside the setup (larger layouts build
   * a larger set on first use; halton_tables.c). */
  tables.tables_of = sampler_desc;
  if (sampler_desc->type == CLR_SAMPLER_HALTON && !clr_device_is_host(context_desc->device))
    tables.started = pthread_create(&tables.thread, NULL, helper_main, &tables) == 0;
  job.started = pthread_create(&job.thread, NULL, helper_main, &job) == 0;
  clr_result r = setup(s, context_desc, kernels, film_desc, sampler_desc);
  char message[1024] = "";
  if (r != CLR_SUCCESS) snprintf(message, sizeof message, "%s", clr_last_error_message());
  if (job.started)
    pthread_join(job.thread, NULL);
  else
    helper_main(&job);
  if (tables.started) pthread_join(tables.thread, NULL);
  if (job.result == CLR_SUCCESS && r == CLR_SUCCESS) return CLR_SUCCESS;
  clr_device_setup_release(s);
  if (job.result != CLR_SUCCESS) return clr_set_last_error(job.result, "%s", job.message);
  return clr_set_last_error(r, "%s", message);
}

void clr_device_setup_release(clr_device_setup *s) {
  if (s->sampler) clr_sampler_release(s->sampler);
  if (s->film) film_release(s->film);
  if (s->ctx) clr_context_release(s->ctx);
  s->sampler = NULL;
  s->film = NULL;
  s->ctx = NULL;
}
