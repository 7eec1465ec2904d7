/* clrender end-to-end rendering of pbrt-v3 scene files: Embree tracing on the host, sample
 * vectors from the sampler kernels, reconstruction by the film, EXR + PNG output. */
#ifndef CLRENDER_RENDER_H
#define CLRENDER_RENDER_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/result.h"
#include "clrender/sampler.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Called on the thread running clr_render_file before the first tile and after each merged tile
 * (possibly more often, with the same counts): return non-zero to stop after the tiles in
 * flight; the image is then written and marked partial. Must be cheap. */
typedef int (*clr_render_progress_fn)(void *user, int32_t tiles_done, int32_t tiles_total);

enum { CLR_LAZY_SAMPLES_AUTO = 0, CLR_LAZY_SAMPLES_OFF = 1, CLR_LAZY_SAMPLES_ALWAYS = 2 };

typedef struct clr_render_options {
  size_t struct_size;   /* sizeof(clr_render_options), set by clr_render_options_init */
  int32_t nthreads;     /* worker threads; 0: every core */
  int32_t spp;          /* samples per pixel override; 0: the scene's */
  int32_t tile_size;    /* render tile side in pixels (16); never changes the image beyond
                              float rounding of the film sums */
  uint32_t seed;        /* mixed into CLR_SEEDING_PIXEL streams (0) */
  clr_seeding seeding;  /* CLR_SEEDING_PIXEL (default), CLR_SEEDING_PBRT_V3 or _PBRT_V4 */
  const char *sampler;  /* sampler name override or NULL */
  const char *filter;   /* filter name override (clr_filter_type_from_name names) or NULL */
  int32_t crop_given;   /* 1: crop_window overrides the Film's "cropwindow" */
  float crop_window[4]; /* x0 x1 y0 y1 in [0,1] */
  int32_t xresolution, yresolution; /* overrides when > 0 */
  const char *outfile; /* output by extension: .exr or .pfm (PNG preview beside it), .png;
                              overrides the Film's "filename" */
  const char *device;  /* OpenCL device selector (see clr_context_desc) or NULL; "host": the
                          host reference build of the kernels, OpenCL never loaded */
  int32_t quiet;       /* 1: no warnings on stderr */
  int32_t progress;    /* 1: progress bar on stderr */
  clr_render_progress_fn progress_callback; /* optional: progress and cancellation */
  void *progress_user;
  int32_t reference_samples;       /* 1: samples from the single-thread host reference generator
                                (the device's bits, slower: for comparisons) */
  const char *kernels;             /* kernel shape: "simd", "portable" or NULL/"auto" (the device's
                              default or CLRENDER_KERNELS; see clrender/kernels.h) */
  clr_randomization randomization; /* pbrt-v4 samplers: overrides the Sampler's
                                      "randomization" unless CLR_RANDOMIZATION_DEFAULT */
  /* Passes (any of the four below set): the frame renders in passes of pass_spp samples per
   * pixel (all tiles of samples [s, s + pass_spp)), each merged whole into the image, so an
   * interrupted or time-limited render records whole passes and can be resumed. */
  const char *resume;    /* continue this EXR (clrender-written, with sums) up to spp, or NULL */
  double time_limit;     /* seconds (from the first pass); stop after the pass that reaches it;
                            < 0 (default): none; 0: exactly one pass */
  double checkpoint;     /* seconds; rewrite the image after each pass when this long has passed
                            since the last write; < 0 (default): none; 0: after every pass */
  int32_t pass_spp;      /* samples per pixel per pass; 0 (default): max(1, spp / 8) */
  float noise_threshold; /* > 0: adaptive sampling (passes): a pixel whose A/B error estimate
                            falls below it stops receiving passes; 0 (default): off */
  const char *error_map; /* with noise_threshold: write the estimates to this EXR, or NULL */
  const char *scene_id;  /* recorded as clrender.scene and checked by resume; clr_render_file
                            sets the scene file's content hash when NULL */
  /* Path tracing with halton or sobol may generate only the camera's and the first bounces'
   * values of each sample vector up front and fetch a deeper bounce's values on the host for the
   * paths that reach it (the same values: the image is identical). CLR_LAZY_SAMPLES_AUTO
   * (default): per band, by the measured costs and path survival; _OFF: every vector whole;
   * _ALWAYS: the first bounce up front, deeper ones fetched (tests). */
  int32_t lazy_samples;
} clr_render_options;

typedef struct clr_render_stats {
  size_t struct_size; /* sizeof(clr_render_stats), set by clr_render_stats_init */
  double seconds_total, seconds_parse, seconds_build;
  double seconds_render; /* wall time of the tile loop */
  /* phase breakdown; worker phases are summed over threads (CPU seconds) */
  double seconds_sample_generation, seconds_tracing, seconds_shading, seconds_reconstruction,
      seconds_merge, seconds_output;
  double seconds_device_wait; /* the OpenCL setup's time past the scene build (overlapped) */
  uint64_t rays, samples, dropped_samples;
  int32_t tiles_done, tiles_total, threads, spp, partial;
  int32_t spp_target; /* the spp asked for; spp: the spp the image holds (whole passes) */
  int32_t passes;     /* passes rendered (1 without pass mode) */
  char sampler[32], integrator[32];
  char exr_path[1024], png_path[1024];
  char pfm_path[1024]; /* the PFM written (an output name ending in .pfm), else "" */
} clr_render_stats;

void clr_render_options_init(clr_render_options *options);
void clr_render_stats_init(clr_render_stats *stats);

/* Parses, builds and renders the scene and writes the image. Scene errors (syntax, missing
 * files, bad meshes) fail before anything is written, with clr_last_error_message() naming the
 * file and line. CLR_ERROR_INTERRUPTED is not returned for a cancelled render: the partial
 * image is written and stats->partial set. options and stats may be NULL. */
clr_result clr_render_file(const char *scene_path, const clr_render_options *options,
                           clr_render_stats *stats);

/* The stats as one JSON object (no newline) into buf; returns the length it needs. */
int clr_render_stats_json(const clr_render_stats *stats, char *buf, size_t size);

#ifdef __cplusplus
}
#endif
#endif
