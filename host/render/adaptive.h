/* Adaptive sampling (--noise-threshold): the passes alternate between two half films A (even
 * passes) and B (odd passes); after each pair a pixel's error estimate is
 *   e = (|A.r - B.r| + |A.g - B.g| + |A.b - B.b|) / (1e-4 + sqrt(I.r + I.g + I.b)), I = (A + B) / 2
 * (the A/B estimator of Cycles and LuxCore), and a pixel whose e falls below the threshold stops
 * receiving passes. Everything is computed from the films, so the pixels sampled depend only on
 * the seed and the passes, never on threads or ranks (under MPI rank 0 decides and shares). */
#ifndef CLR_ADAPTIVE_H
#define CLR_ADAPTIVE_H

#include <stdint.h>
#include "clrender/film.h"

/* No pixel stops before it has this many samples (8 per half): earlier estimates are too noisy
 * (pixels whose few samples happen to agree would stop at once). */
#define CLR_ADAPTIVE_MIN_SPP 16

typedef struct clr_adaptive {
  clr_film half[2];    /* A: even passes, B: odd passes */
  uint8_t *active;     /* per film pixel: 1 while sampled */
  float *error;        /* per film pixel: the last estimate (INFINITY before the first) */
  clr_bounds2i bounds; /* the film's pixel bounds */
  int32_t width, height;
  float threshold;
  int64_t active_count;
} clr_adaptive;

clr_result clr_adaptive_init(clr_adaptive *ad, clr_context ctx, clr_film film, float threshold);
void clr_adaptive_free(clr_adaptive *ad);
/* 1 when the samples of sample pixel (x, y) are rendered: the nearest film pixel is active (or
 * ad is NULL). */
int clr_adaptive_pixel_active(const clr_adaptive *ad, int32_t x, int32_t y);
/* The active sample pixels of `pixels` (all of them when ad is NULL). */
int64_t clr_adaptive_count_active(const clr_adaptive *ad, clr_bounds2i pixels);
/* The next run of active sample pixels of row y in [x, x1), bridging gaps shorter than `gap`:
 * *start = its first pixel (x1 when none), returns one past its last. */
int clr_adaptive_next_run(const clr_adaptive *ad, int32_t y, int32_t x, int32_t x1, int32_t gap,
                          int32_t *start);
/* Adds pass number `pass` (from 0) into its half film. */
clr_result clr_adaptive_add_pass(clr_adaptive *ad, clr_film pass, int32_t pass_index);
/* After an odd pass: new estimates, and pixels below the threshold leave the active set. */
clr_result clr_adaptive_update(clr_adaptive *ad);
/* The estimates as an EXR (R = G = B = e; 0 where never estimated) of the film's geometry. */
clr_result clr_adaptive_write_error_map(const clr_adaptive *ad, clr_context ctx, clr_film film,
                                        const char *path);

#endif
