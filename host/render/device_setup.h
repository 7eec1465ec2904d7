/* The OpenCL side of a render (context, film, sampler and the sampler's kernel program), set up on
 * its own thread while the main thread builds the scene: loading the OpenCL implementation and
 * building or loading the program is most of a small render's fixed cost. */
#ifndef CLR_DEVICE_SETUP_H
#define CLR_DEVICE_SETUP_H

#include <pthread.h>
#include "clrender/film.h"
#include "clrender/sampler.h"

typedef struct clr_device_setup {
  /* inputs, copied by clr_device_setup_start */
  clr_context_desc context_desc;
  const char *kernels; /* kernel shape name or NULL (caller keeps it alive) */
  clr_film_desc film_desc;
  clr_sampler_desc sampler_desc;
  /* outputs, read after clr_device_setup_finish */
  clr_context ctx;
  clr_film film;
  clr_sampler sampler;
  clr_result result;
  char message[1024]; /* the failing call's last-error message */
  pthread_t thread, tables_thread;
  int threaded;        /* the setup thread started (otherwise the work ran inline) */
  int tables_threaded; /* the host tables thread started (otherwise the setup builds them) */
} clr_device_setup;

/* Starts creating the context, film and sampler and building the sampler's program. */
void clr_device_setup_start(clr_device_setup *s, const clr_context_desc *context_desc,
                            const char *kernels, const clr_film_desc *film_desc,
                            const clr_sampler_desc *sampler_desc);
/* Waits for the setup; on failure sets the last-error message and releases what was made. */
clr_result clr_device_setup_finish(clr_device_setup *s);
/* Releases the sampler, film and context (any of them may be NULL). */
void clr_device_setup_release(clr_device_setup *s);

#endif
