/* The sampler tests' batch: `count` samples from sample `first` (count 0: all spp) of every pixel
 * in `pixels`, laid out by the `nreq` requests. */
#ifndef CLR_SAMPLE_BATCH_TEST_UTIL_H
#define CLR_SAMPLE_BATCH_TEST_UTIL_H

#include "clrender.h"

static inline clr_sample_batch sample_batch(clr_bounds2i pixels, int first, int count,
                                            const clr_sample_request *req, int nreq) {
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = pixels;
  b.first_sample = first, b.sample_count = count; /* the samples of each pixel */
  b.requests = req, b.request_count = nreq;       /* their layout */
  return b;
}

#endif
