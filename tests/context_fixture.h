/* The cmocka group fixture of the tests that share one context on the default device. */
#ifndef CLR_CONTEXT_FIXTURE_H
#define CLR_CONTEXT_FIXTURE_H

#include "clrender.h"

static clr_context ctx;

static int setup(void **state) {
  (void)state;
  return clr_context_create(NULL, &ctx) == CLR_SUCCESS ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  clr_context_release(ctx);
  return 0;
}

#endif
