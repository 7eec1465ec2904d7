/* The OpenCL side of a render (context, film, sampler and the sampler's kernel program), set up
 * while a helper thread does other work (the scene build): loading the OpenCL implementation and
 * building or loading the program is most of a small render's fixed cost. */
#ifndef CLR_DEVICE_SETUP_H
#define CLR_DEVICE_SETUP_H

#include "clrender/film.h"
#include "clrender/sampler.h"

typedef struct clr_device_setup {
  clr_context ctx;
  clr_film film;
  clr_sampler sampler;
} clr_device_setup;

/* Work done on the helper thread; reports failures through the last-error message. */
typedef clr_result (*clr_setup_work_fn)(void *user);

/* Creates the context (kernel shape `kernels` unless NULL), film and sampler on the calling thread
 * (PoCL's LLVM leaves per-thread state, an alternate signal stack, that must not meet a thread's
 * exit) and builds the sampler's program, while work(user) runs on a helper thread. The work's
 * failure is reported first, with its message, as when the two ran one after the other; on any
 * failure nothing is left in *s. */
clr_result clr_device_setup_run(clr_device_setup *s, const clr_context_desc *context_desc,
                                const char *kernels, const clr_film_desc *film_desc,
                                const clr_sampler_desc *sampler_desc, clr_setup_work_fn work,
                                void *user);
/* Whether `device` (a --device value) names the host reference ("host"): then the setup makes
 * no context (ctx stays NULL), a host film and a host sampler, and the render draws its samples
 * from the host reference generator (the device's bits) without loading OpenCL. */
int clr_device_is_host(const char *device);
/* Releases the sampler, film and context (any of them may be NULL). */
void clr_device_setup_release(clr_device_setup *s);

#endif
