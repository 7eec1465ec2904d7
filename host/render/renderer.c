#define _POSIX_C_SOURCE 200809L /* pthread_getcpuclockid */
/* Render loop: tiles over the sample bounds; the main thread generates each tile's sample
 * vectors on the OpenCL device and merges finished film tiles strictly in tile order, worker
 * threads trace and shade tiles and filter their samples into film tiles. The image is thus
 * bit-identical whatever the thread count and scheduling. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "render_error.h"
#include "device_setup.h"
#include "clrender/film.h"
#include "clrender/kernels.h"
#include "adaptive.h"
#include "camera_sample.h"
#include "cost_fit.h"
#include "distributed.h"
#include "integrator.h"
#include "pfm_output.h"
#include "pcg32.h"
#include "render_scene.h"
#include "resume.h"
#include "renderer.h"
#include "scene_parser.h"

#define CHUNK_SAMPLES 256

void clr_render_options_init(clr_render_options *o) {
  if (!o) return;
  memset(o, 0, sizeof *o);
  o->struct_size = sizeof *o;
  o->tile_size = 16;
  o->seeding = CLR_SEEDING_PIXEL;
  o->time_limit = -1.0;
  o->checkpoint = -1.0;
}

void clr_render_stats_init(clr_render_stats *s) {
  if (!s) return;
  memset(s, 0, sizeof *s);
  s->struct_size = sizeof *s;
}

/* Seconds of a clock (CLOCK_MONOTONIC, CLOCK_PROCESS_CPUTIME_ID, CLOCK_THREAD_CPUTIME_ID, a
 * thread's); 0 when it can't be read. */
static double clock_seconds(clockid_t clock) {
  struct timespec ts;
  if (clock_gettime(clock, &ts) != 0) return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double now_seconds(void) { return clock_seconds(CLOCK_MONOTONIC); }

typedef struct warn_sink {
  int quiet;
} warn_sink;
static void warn_print(void *user, const char *msg) {
  const warn_sink *w = user;
  if (!w || !w->quiet) fprintf(stderr, "clrender: warning: %s\n", msg);
}

/* ---------- configuration from the scene and the options ---------- */

static clr_result sampler_from_desc(const clr_scene_desc *d, const clr_render_options *o,
                                    clr_warn_fn warn, void *wu, clr_sampler_desc *sd) {
  const clr_param_list *p = &d->sampler.params;
  const char *name = o->sampler ? o->sampler : (d->sampler.type ? d->sampler.type : "halton");
  clr_sampler_type type;
  if (strcmp(name, "zerotwosequence") == 0) {
    if (warn) {
      char m[256];
      snprintf(m, sizeof m, "sampler \"%s\" not supported: using \"sobol\"", name);
      warn(wu, m);
    }
    type = CLR_SAMPLER_SOBOL;
  } else if (clr_sampler_type_from_name(name, &type) != CLR_SUCCESS) {
    return clr_set_last_error(CLR_ERROR_INVALID_SAMPLER, "%s:%d: unknown sampler \"%s\"",
                              o->sampler ? "--sampler" : (p->file ? p->file : "?"), p->line, name);
  }
  clr_sampler_desc_init(sd, type);
  int same = !o->sampler || (d->sampler.type && strcmp(d->sampler.type, name) == 0);
  if (same) {
    sd->pixel_samples = clr_params_find_int(p, "pixelsamples", sd->pixel_samples);
    sd->x_samples = clr_params_find_int(p, "xsamples", sd->x_samples);
    sd->y_samples = clr_params_find_int(p, "ysamples", sd->y_samples);
    sd->jitter = clr_params_find_bool(p, "jitter", sd->jitter != 0);
    sd->dimensions = clr_params_find_int(p, "dimensions", sd->dimensions);
    sd->sample_pixel_center = clr_params_find_bool(p, "samplepixelcenter", false);
    const char *r = clr_params_find_string(p, "randomization", NULL);
    if (r && clr_randomization_from_name(r, &sd->randomization) != CLR_SUCCESS)
      return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                                "%s:%d: unknown randomization \"%s\" (expected none, "
                                "permutedigits, fastowen or owen)",
                                p->file ? p->file : "?", p->line, r);
  }
  if (o->spp > 0) {
    sd->pixel_samples = o->spp;
    int x = (int)sqrt((double)o->spp);
    if (x < 1) x = 1;
    sd->x_samples = x;
    sd->y_samples = (o->spp + x - 1) / x;
  }
  if (type == CLR_SAMPLER_ZEROTWO && sd->pixel_samples > 0 &&
      (sd->pixel_samples & (sd->pixel_samples - 1)) != 0 && warn) {
    int32_t up = 1;
    while (up < sd->pixel_samples && up < (1 << 30)) up <<= 1;
    char m[128]; /* pbrt-v3's ZeroTwoSequenceSampler warning */
    snprintf(m, sizeof m, "Pixel samples being rounded up to power of 2 (from %d to %d).",
             (int)sd->pixel_samples, (int)up);
    warn(wu, m);
  }
  if (type == CLR_SAMPLER_MAXMINDIST && sd->pixel_samples > 0 && sd->pixel_samples < (1 << 17) &&
      (sd->pixel_samples & (sd->pixel_samples - 1)) != 0 && warn) {
    int32_t up = 1;
    while (up < sd->pixel_samples) up <<= 1;
    char m[128]; /* pbrt-v3's MaxMinDistSampler warning */
    snprintf(m, sizeof m, "Non power-of-two sample count rounded up to %d for MaxMinDistSampler.",
             (int)up);
    warn(wu, m);
  }
  sd->seeding = o->seeding;
  /* pbrt-v4: the Sampler's "seed" defaults to --seed */
  sd->seed = same ? (uint32_t)clr_params_find_int(p, "seed", (int)o->seed) : o->seed;
  if (o->randomization != CLR_RANDOMIZATION_DEFAULT) sd->randomization = o->randomization;
  return CLR_SUCCESS;
}

static clr_result filter_from_desc(const clr_scene_desc *d, const clr_render_options *o,
                                   clr_warn_fn warn, void *wu, clr_filter_desc *fd) {
  const char *scene_name = d->filter.type ? d->filter.type : "box";
  const char *name = o->filter ? o->filter : scene_name;
  const clr_param_list *p = &d->filter.params;
  clr_filter_type type;
  if (clr_filter_type_from_name(name, &type) != CLR_SUCCESS) {
    if (o->filter)
      return clr_set_last_error(CLR_ERROR_INVALID_FILTER, "--filter: unknown filter \"%s\"", name);
    if (warn) {
      char m[512];
      snprintf(m, sizeof m, "%s:%d: filter \"%s\" not supported: using \"box\"",
               p->file ? p->file : "?", p->line, name);
      warn(wu, m);
    }
    type = CLR_FILTER_BOX;
    name = "box";
  }
  clr_filter_desc_init(fd, type);
  if (strcmp(name, scene_name) == 0) { /* the scene's own parameters apply to its filter only */
    fd->radius[0] = clr_params_find_float(p, "xwidth", fd->radius[0]);
    fd->radius[1] = clr_params_find_float(p, "ywidth", fd->radius[1]);
    fd->alpha = clr_params_find_float(p, "alpha", fd->alpha);
    fd->b = clr_params_find_float(p, "B", fd->b);
    fd->c = clr_params_find_float(p, "C", fd->c);
    fd->tau = clr_params_find_float(p, "tau", fd->tau);
  }
  return CLR_SUCCESS;
}

/* pbrt-v3 warns when the Sobol sampler rounds its pixel samples up to a power of two; the
 * stratified sampler's x * y grid for --spp is reported the same way. */
static void warn_spp_rounding(const clr_scene_desc *d, const clr_render_options *o,
                              const clr_sampler_desc *sd, int32_t spp, clr_warn_fn warn, void *wu) {
  int32_t asked = o->spp > 0 ? o->spp : sd->pixel_samples;
  if (!warn) return;
  if (sd->type == CLR_SAMPLER_STRATIFIED ? (o->spp <= 0 || spp == o->spp) : spp == asked) return;
  if (sd->type == CLR_SAMPLER_ZEROTWO || sd->type == CLR_SAMPLER_MAXMINDIST) return; /* warned */
  char where[600], m[800];
  const clr_param_list *p = &d->sampler.params;
  if (o->spp > 0)
    snprintf(where, sizeof where, "--spp %d", (int)o->spp);
  else
    snprintf(where, sizeof where, "%s:%d", p->file ? p->file : "<scene>", p->line);
  if (sd->type == CLR_SAMPLER_SOBOL)
    snprintf(m, sizeof m,
             "%s: non power-of-two sample count rounded up to %d for the sobol sampler", where,
             (int)spp);
  else
    snprintf(m, sizeof m, "%s: the %s sampler renders %d samples per pixel", where,
             clr_sampler_type_name(sd->type), (int)spp);
  warn(wu, m);
}

/* ---------- scene values checked before any work ---------- */

/* Line of parameter `name` in `p` (any type), else the directive's line. */
static int param_line(const clr_param_list *p, const char *name) {
  for (int i = 0; i < p->count; ++i)
    if (strcmp(p->items[i].name, name) == 0) return p->items[i].line;
  return p->line;
}

static const char *param_file(const clr_param_list *p) { return p->file ? p->file : "<scene>"; }

/* The sampler's name, seeding and randomization go together (pbrt-v4's randomizations, no
 * pbrt-v4 02sequence): the library's message, located at the Sampler directive or the flags. */
static clr_result check_sampler_kind(const clr_sampler_desc *sd, const clr_render_options *o,
                                     const clr_param_list *sampler) {
  clr_sampler_desc probe = *sd;
  probe.pixel_samples = 1;
  probe.x_samples = probe.y_samples = 1;
  probe.film.x_resolution = probe.film.y_resolution = 1;
  probe.film.crop_window[0] = probe.film.crop_window[2] = 0.0f;
  probe.film.crop_window[1] = probe.film.crop_window[3] = 1.0f;
  clr_sampler s = NULL;
  clr_result r = clr_sampler_create(NULL, &probe, &s);
  clr_sampler_release(s);
  if (r == CLR_SUCCESS) return CLR_SUCCESS;
  char why[512]; /* the message lives in the buffer clr_set_last_error writes */
  snprintf(why, sizeof why, "%s", clr_last_error_message());
  if (o->sampler || o->randomization != CLR_RANDOMIZATION_DEFAULT)
    return clr_set_last_error(r, "render options: %s", why);
  return clr_set_last_error(r, "%s:%d: Sampler: %s", param_file(sampler),
                            param_line(sampler, "randomization"), why);
}

/* Semantic errors the later stages would report without a location: every message here starts
 * with the scene's FILE:LINE (or the flag that set the value). */
static clr_result check_scene_values(const clr_scene_desc *d, const clr_render_options *o,
                                     const clr_render_settings *settings,
                                     const clr_sampler_desc *sd, const clr_filter_desc *fd) {
  const clr_param_list *film = &d->film.params, *sampler = &d->sampler.params,
                       *filter = &d->filter.params;
  int n = 0;
  if (clr_params_find_floats(film, "cropwindow", &n) && n != 4)
    return clr_set_last_error(CLR_ERROR_INVALID_CROP_WINDOW,
                              "%s:%d: Film: \"cropwindow\" needs 4 values (x0 x1 y0 y1), got %d",
                              param_file(film), param_line(film, "cropwindow"), n);
  const char *res_names[2] = {"xresolution", "yresolution"};
  int32_t res[2] = {settings->x_resolution, settings->y_resolution};
  int32_t flag[2] = {o->xresolution, o->yresolution};
  for (int k = 0; k < 2; ++k)
    if (res[k] <= 0 || res[k] > CLR_FILM_MAX_SIDE ||
        (int64_t)res[0] * res[1] > (int64_t)CLR_FILM_MAX_PIXELS) {
      if (flag[k] > 0)
        return clr_set_last_error(CLR_ERROR_INVALID_RESOLUTION,
                                  "render options: %s %d x %d is outside 1..%d (at most %d pixels)",
                                  res_names[k], (int)res[0], (int)res[1], (int)CLR_FILM_MAX_SIDE,
                                  (int)CLR_FILM_MAX_PIXELS);
      return clr_set_last_error(CLR_ERROR_INVALID_RESOLUTION,
                                "%s:%d: Film: \"%s\" %d (resolution %d x %d) must be in 1..%d, at "
                                "most %d pixels",
                                param_file(film), param_line(film, res_names[k]), res_names[k],
                                (int)res[k], (int)res[0], (int)res[1], (int)CLR_FILM_MAX_SIDE,
                                (int)CLR_FILM_MAX_PIXELS);
    }
  if (o->spp <= 0) {
    const char *bad = NULL;
    int value = 0;
    if (sd->type == CLR_SAMPLER_STRATIFIED) {
      if (sd->x_samples <= 0)
        bad = "xsamples", value = sd->x_samples;
      else if (sd->y_samples <= 0)
        bad = "ysamples", value = sd->y_samples;
      else if (sd->dimensions <= 0)
        bad = "dimensions", value = sd->dimensions;
    } else if (sd->pixel_samples <= 0) {
      bad = "pixelsamples", value = sd->pixel_samples;
    }
    if (bad)
      return clr_set_last_error(CLR_ERROR_INVALID_SPP,
                                "%s:%d: Sampler \"%s\": \"%s\" must be "
                                "positive, got %d",
                                param_file(sampler), param_line(sampler, bad),
                                clr_sampler_type_name(sd->type), bad, value);
  }
  CLR_CHECK(check_sampler_kind(sd, o, sampler));
  for (int k = 0; k < 2; ++k)
    if (!(fd->radius[k] > 0.0f && fd->radius[k] <= CLR_FILM_MAX_FILTER_RADIUS)) {
      const char *name = k ? "ywidth" : "xwidth";
      if (o->filter)
        return clr_set_last_error(CLR_ERROR_INVALID_RADIUS, "--filter %s: %s %g must be in (0, %g]",
                                  o->filter, name, (double)fd->radius[k],
                                  (double)CLR_FILM_MAX_FILTER_RADIUS);
      return clr_set_last_error(
          CLR_ERROR_INVALID_RADIUS, "%s:%d: PixelFilter \"%s\": \"%s\" must be in (0, %g], got %g",
          param_file(filter), param_line(filter, name), clr_filter_type_name(fd->type), name,
          (double)CLR_FILM_MAX_FILTER_RADIUS, (double)fd->radius[k]);
    }
  return CLR_SUCCESS;
}

/* ---------- tiles ---------- */

/* Sample values of one generation call: consecutive tiles of one tile row, so the values are
 * those of the band's pixel rectangle (row-major pixels, samples, values). */
/* Floats per batch, at least one tile. The bands (2 + threads / tiles per band of them, each also
 * mirrored in a device buffer) held 32 MiB each before; at 4 MiB the sample generation time is
 * unchanged (docs/performance.md). */
#define BATCH_VALUES_BUDGET ((size_t)1 << 20)

enum { TILE_PENDING, TILE_READY, TILE_BUSY, TILE_DONE, TILE_MERGED };

typedef struct sample_band {
  float *values;
  size_t values_cap;
  /* the generated prefix of each vector (the whole layout, or choose_prefix's): requests,
   * values and path bounces; deeper bounces' values are fetched */
  int32_t requests, stride, path_bounces;
  clr_bounds2i pixels; /* the band's pixel rectangle */
  int unfinished;      /* tiles of the band not yet shaded; the band is free at 0 */
  int in_use;
} sample_band;

typedef struct tile_info {
  int state;
  int index; /* in the frame's tile grid (tiles[] is in this process's claim order) */
  int band;
  clr_bounds2i pixels;
  clr_film_tile film_tile;
  clr_result result;
} tile_info;

typedef struct render_job {
  const clr_render_scene *scene;
  const clr_integrator *integrator;
  clr_sampler sampler;
  int lazy; /* bands may hold a prefix of the layout (lazy_allowed), 2: always the same */
  /* choose_prefix's figures: samples shaded and their vertices per bounce, the CPU cost of
   * generated values (each band's values against the process's CPU seconds during its
   * generation less the workers', the first band left out: its calls start cold) and of fetched
   * values (the workers' thread CPU seconds in sampled fetches, values of those calls) */
  uint64_t seen_samples, seen_vertices[CLR_COUNTED_BOUNCES];
  clr_cost_fit gen_fit;
  int gen_bands;
  double fetch_cpu_s;
  uint64_t fetch_cpu_values;
  double fetch_value_s;     /* the workers' wall seconds in fetches (--stats) */
  clr_sample_fetch fetch;   /* the layout prepared for fetches (lazy), or NULL */
  clockid_t *worker_clocks; /* the workers' CPU clocks, for the generation's CPU */
  int nworker_clocks;
  clr_film film;
  int spp;                  /* samples per pixel of this pass */
  int first_sample;         /* the pass's first sample index */
  int host_samples;         /* options->reference_samples: host reference generator (comparison) */
  clr_camera_layout camera; /* pbrt-v3's or pbrt-v4's camera sample (camera_sample.h) */
  int cancelled;            /* the progress callback asked to stop */
  uint32_t seed;
  clr_bounds2i region;          /* the sample pixels rendered (render_region) */
  clr_dist *dist;               /* MPI ranks sharing the frame, or NULL */
  const clr_adaptive *adaptive; /* pixels still sampled (--noise-threshold), or NULL: all */
  int next_band;                /* the next band to claim when alone */
  tile_info *tiles;
  sample_band *bands;
  int nbands;
  int next_take, ready_end; /* tiles [next_take, ready_end) wait for a worker, in tile order */
  int busy;                 /* tiles being shaded */
  pthread_mutex_t mutex;
  pthread_cond_t cond;
  int stop;
  /* per-thread phase sums, merged under the mutex */
  double trace_s, shade_s, recon_s;
  uint64_t rays;
  uint64_t rays_sent; /* of them, reported to rank 0 with earlier passes */
} render_job;

/* A worker's buffers, reused from tile to tile. */
typedef struct worker_buffers {
  clr_film_sample *fs;
  size_t fs_cap;
  clr_ray rays[CHUNK_SAMPLES];
  clr_ray_differential diffs[CHUNK_SAMPLES];
  uint64_t keys[CHUNK_SAMPLES];
  float L[3 * CHUNK_SAMPLES], weights[CHUNK_SAMPLES];
  clr_sample_point points[CHUNK_SAMPLES]; /* the chunk's pixels and samples */
  const render_job *job;                  /* for fetch_values */
  double fetch_s;                         /* in fetch_values */
  uint64_t calls;                         /* fetch_values calls, the CPU-timed ones sampled */
  double fetch_cpu_s, clock_cost_s;       /* the sampled calls' CPU; one pair of clock reads */
  uint64_t fetch_cpu_values;              /* values of the sampled calls */
} worker_buffers;

static uint64_t sample_key(uint32_t seed, int px, int py, int s) {
  return clr_mix64(((uint64_t)seed << 32) ^
                   clr_mix64(((uint64_t)(uint32_t)px << 32) | (uint32_t)py)) +
         (uint64_t)s * 0x9E3779B97F4A7C15ull;
}

/* clr_fetch_values_fn of the renderer: values of the chunk's samples past the generated prefix,
 * computed on the host (clr_sampler_generate_at: the generated values' bits). */
static clr_result fetch_values(void *user, const int32_t *samples, int32_t n, int32_t first_value,
                               int32_t value_count, float *out) {
  worker_buffers *b = user;
  clr_sample_point pts[CHUNK_SAMPLES];
  double t0 = now_seconds();
  /* one call in 16, chosen by a hash (not a stride that could follow the bounces' cycle), is
   * timed in thread CPU: a clock read is a system call (~0.3-1.7 us here) */
  int timed = (clr_mix64(++b->calls) & 15) == 0;
  double c0 = timed ? clock_seconds(CLOCK_THREAD_CPUTIME_ID) : 0.0;
  for (int32_t j = 0; j < n; ++j) pts[j] = b->points[samples[j]];
  clr_result r = clr_sample_fetch_values(b->job->fetch, pts, n, first_value, value_count, out);
  if (timed) {
    double c = clock_seconds(CLOCK_THREAD_CPUTIME_ID) - c0 - b->clock_cost_s;
    b->fetch_cpu_s += c > 0.0 ? c : 0.0;
    b->fetch_cpu_values += (uint64_t)n * (uint64_t)value_count;
  }
  b->fetch_s += now_seconds() - t0;
  return r;
}

/* Traces and shades `n` consecutive samples of pixel row py starting at column px0, sample s0;
 * values: their sample vectors; fs: their film samples. */
static clr_result shade_run(render_job *job, const sample_band *band, worker_buffers *b,
                            clr_integrator_scratch *scratch, clr_integrator_counters *counters,
                            int px0, int py, int s0, int n, const float *values,
                            clr_film_sample *fs) {
  const clr_integrator *it = job->integrator;
  int spp = job->spp;
  float cam[7][CHUNK_SAMPLES];
  clr_camera_samples cs = {cam[0], cam[1], cam[2], cam[3], cam[4], cam[5], cam[6]};
  clr_camera_samples_from_values(&job->camera, values + it->camera_offset, (size_t)band->stride,
                                 px0, py, s0, spp, n, &cs);
  clr_render_scene_camera_rays(job->scene, &cs, n, b->rays, b->diffs, b->weights);
  for (int k = 0, px = px0, s = s0; k < n; ++k) {
    fs[k].x = cs.pixel_x[k];
    fs[k].y = cs.pixel_y[k];
    b->keys[k] = sample_key(job->seed, px, py, job->first_sample + s);
    b->points[k].x = px;
    b->points[k].y = py;
    b->points[k].sample = job->first_sample + s;
    if (++s == spp) {
      s = 0;
      ++px;
    }
  }
  clr_integrator_values sv = clr_integrator_values_whole(it, values);
  if (band->stride != it->values_per_sample) {
    sv.stride = band->stride;
    sv.path_bounces = band->path_bounces;
    sv.fetch = fetch_values;
    sv.fetch_user = b;
  }
  CLR_CHECK(clr_integrator_li(it, job->scene, scratch, b->rays, b->diffs, &sv, b->keys, n, b->L,
                              counters));
  for (int k = 0; k < n; ++k) {
    fs[k].r = b->L[3 * k];
    fs[k].g = b->L[3 * k + 1];
    fs[k].b = b->L[3 * k + 2];
    fs[k].weight = b->weights[k];
  }
  return CLR_SUCCESS;
}

/* Traces, shades and filters one tile's samples (read from its band) into a new film tile. */
static clr_result shade_tile(render_job *job, tile_info *tile, worker_buffers *b,
                             clr_integrator_scratch *scratch, clr_integrator_counters *counters,
                             double *recon_s) {
  const sample_band *band = &job->bands[tile->band];
  size_t vps = (size_t)band->stride, spp = (size_t)job->spp;
  int w = tile->pixels.x1 - tile->pixels.x0, h = tile->pixels.y1 - tile->pixels.y0;
  int band_w = band->pixels.x1 - band->pixels.x0;
  size_t row = (size_t)w * spp, total = row * (size_t)h;
  if (total > b->fs_cap) {
    clr_film_sample *fs = realloc(b->fs, total * sizeof *fs);
    if (!fs) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "render tile");
    b->fs = fs;
    b->fs_cap = total;
  }
  size_t filled = 0;
  for (int py = tile->pixels.y0; py < tile->pixels.y1; ++py)
    for (int x = tile->pixels.x0, xe; x < tile->pixels.x1; x = xe) { /* runs of active pixels */
      int on = clr_adaptive_pixel_active(job->adaptive, x, py);
      for (xe = x + 1;
           xe < tile->pixels.x1 && clr_adaptive_pixel_active(job->adaptive, xe, py) == on;)
        ++xe;
      if (!on) continue;
      size_t first =
          ((size_t)(py - band->pixels.y0) * (size_t)band_w + (size_t)(x - band->pixels.x0)) * spp;
      size_t run = (size_t)(xe - x) * spp;
      for (size_t base = 0; base < run; base += CHUNK_SAMPLES) {
        int n = (int)(run - base < CHUNK_SAMPLES ? run - base : CHUNK_SAMPLES);
        CLR_CHECK(shade_run(job, band, b, scratch, counters, x + (int)(base / spp), py,
                            (int)(base % spp), n, band->values + (first + base) * vps,
                            b->fs + filled + base));
      }
      filled += run;
    }
  (void)row;
  double t0 = now_seconds();
  clr_result r = film_get_tile(job->film, tile->pixels, &tile->film_tile);
  if (r == CLR_SUCCESS && filled) r = film_tile_add_samples(tile->film_tile, b->fs, filled);
  *recon_s += now_seconds() - t0;
  return r;
}

/* Adds a worker's path figures since its last report to the job's (under the job's mutex);
 * returns its fetch seconds. */
static double report_tile_figures(render_job *job, clr_integrator_counters *c, worker_buffers *b) {
  job->seen_samples += c->samples;
  for (int k = 0; k < CLR_COUNTED_BOUNCES; ++k) job->seen_vertices[k] += c->bounce_vertices[k];
  job->fetch_value_s += b->fetch_s;
  job->fetch_cpu_s += b->fetch_cpu_s;
  job->fetch_cpu_values += b->fetch_cpu_values;
  double fetch = b->fetch_s;
  c->samples = 0;
  memset(c->bounce_vertices, 0, sizeof c->bounce_vertices);
  b->fetch_s = b->fetch_cpu_s = 0.0;
  b->fetch_cpu_values = 0;
  return fetch;
}

/* The thread CPU seconds of a pair of back-to-back clock reads (least of 8), taken off each
 * timed fetch. */
static double thread_clock_cost(void) {
  double least = 1.0;
  for (int i = 0; i < 8; ++i) {
    double a = clock_seconds(CLOCK_THREAD_CPUTIME_ID),
           d = clock_seconds(CLOCK_THREAD_CPUTIME_ID) - a;
    if (d < least) least = d;
  }
  return least;
}

static void *worker_main(void *arg) {
  render_job *job = arg;
  clr_integrator_scratch *scratch = clr_integrator_scratch_create();
  worker_buffers *buffers = calloc(1, sizeof *buffers);
  if (buffers) {
    buffers->job = job;
    buffers->clock_cost_s = thread_clock_cost();
  }
  clr_integrator_counters counters;
  memset(&counters, 0, sizeof counters);
  double busy = 0.0, recon = 0.0, fetch = 0.0;
  pthread_mutex_lock(&job->mutex);
  for (;;) {
    if (job->next_take == job->ready_end) { /* the lowest READY tile keeps merges flowing */
      if (job->stop) break;
      pthread_cond_wait(&job->cond, &job->mutex);
      continue;
    }
    tile_info *tile = &job->tiles[job->next_take++];
    tile->state = TILE_BUSY;
    job->busy++;
    pthread_mutex_unlock(&job->mutex);
    double t0 = now_seconds();
    clr_result r = scratch && buffers
                       ? shade_tile(job, tile, buffers, scratch, &counters, &recon)
                       : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "render worker");
    busy += now_seconds() - t0;
    pthread_mutex_lock(&job->mutex);
    tile->result = r;
    tile->state = TILE_DONE;
    job->busy--;
    if (--job->bands[tile->band].unfinished == 0) job->bands[tile->band].in_use = 0;
    if (buffers) fetch += report_tile_figures(job, &counters, buffers);
    pthread_cond_broadcast(&job->cond);
  }
  job->trace_s += counters.trace_seconds;
  job->recon_s += recon;
  job->shade_s += busy - counters.trace_seconds - recon - fetch;
  job->rays += counters.rays;
  pthread_mutex_unlock(&job->mutex);
  if (buffers) free(buffers->fs);
  free(buffers);
  clr_integrator_scratch_free(scratch);
  return NULL;
}

static int default_threads(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

/* Seconds left: the rate of the tiles merged after the first one times the tiles left. The time
 * to the first merge (first band generated, pipeline filling) is paid once and is not counted:
 * it made the estimate 20 % high a quarter of the way through a Cornell box render. */
double clr_progress_eta(int done, int total, double elapsed, double first_elapsed) {
  if (done >= total) return 0.0;
  if (done < 2) return done ? elapsed * (double)(total - done) / (double)done : 0.0;
  return (elapsed - first_elapsed) * (double)(total - done) / (double)(done - 1);
}

static void progress_bar(int done, int total, double elapsed, double first_elapsed) {
  int width = 30, filled = total ? done * width / total : width;
  char bar[64];
  for (int i = 0; i < width; ++i) bar[i] = i < filled ? '=' : ' ';
  bar[width] = 0;
  double eta = clr_progress_eta(done, total, elapsed, first_elapsed);
  fprintf(stderr, "\r[%s] %d/%d tiles  %.1fs elapsed  ~%.1fs left ", bar, done, total, elapsed,
          eta);
  if (done == total) fputc('\n', stderr);
  fflush(stderr);
}

/* Tile grid over the sample bounds and the bands generation works in. */
typedef struct tile_grid {
  clr_bounds2i bounds;
  int size, ntx, nty, ntiles;
  int band_tiles; /* tiles per band (the last band of a row may have fewer) */
} tile_grid;

static clr_bounds2i tile_pixels(const tile_grid *g, int tile) {
  int tx = tile % g->ntx, ty = tile / g->ntx, ts = g->size;
  clr_bounds2i px = {g->bounds.x0 + tx * ts, g->bounds.y0 + ty * ts, g->bounds.x0 + (tx + 1) * ts,
                     g->bounds.y0 + (ty + 1) * ts};
  if (px.x1 > g->bounds.x1) px.x1 = g->bounds.x1;
  if (px.y1 > g->bounds.y1) px.y1 = g->bounds.y1;
  return px;
}

/* Bands split each tile row into runs of band_tiles tiles (the last may be shorter). */
static int bands_per_row(const tile_grid *g) {
  return (g->ntx + g->band_tiles - 1) / g->band_tiles;
}

static clr_result generate_rect(const render_job *job, clr_sampler sampler, clr_sample_batch *batch,
                                clr_bounds2i px, float *values) {
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = values;
  batch->pixels = px;
  return job->host_samples ? clr_sampler_generate_reference(sampler, batch, &out)
                           : clr_sampler_generate(sampler, batch, &out);
}

/* The band's sample values (row-major over px): all of them, or with adaptive sampling only the
 * runs of active pixels when fewer than half are active (per-pixel streams make a pixel's values
 * the same in any batch). */
static clr_result generate_values(const render_job *job, clr_sampler sampler,
                                  clr_sample_batch *batch, clr_bounds2i px, int32_t stride,
                                  float *values) {
  int64_t active = clr_adaptive_count_active(job->adaptive, px);
  int64_t w = px.x1 - px.x0, all = w * (px.y1 - px.y0);
  if (active == all) return generate_rect(job, sampler, batch, px, values);
  if (active == 0) return CLR_SUCCESS; /* no sample of the band is shaded */
  if (active * 2 > all) return generate_rect(job, sampler, batch, px, values);
  size_t per_pixel = (size_t)job->spp * (size_t)stride;
  for (int y = px.y0; y < px.y1; ++y)
    for (int x = px.x0, xe; x < px.x1; x = xe) {
      xe = clr_adaptive_next_run(job->adaptive, y, x, px.x1, 16, &x);
      if (x >= px.x1) break;
      clr_bounds2i run = {x, y, xe, y + 1};
      CLR_CHECK(generate_rect(
          job, sampler, batch, run,
          values + ((size_t)(y - px.y0) * (size_t)w + (size_t)(x - px.x0)) * per_pixel));
    }
  return CLR_SUCCESS;
}

/* The workers' CPU seconds so far (their thread clocks). */
static double workers_clock_seconds(const render_job *job) {
  double sum = 0.0;
  for (int i = 0; i < job->nworker_clocks; ++i) sum += clock_seconds(job->worker_clocks[i]);
  return sum;
}

/* Generates band `index` of the grid into band slot `bi` with the layout's prefix holding
 * `bounces` path bounces (or the whole layout), its tiles at tiles[pos...]; returns its tile
 * count in *count. */
static clr_result generate_band(render_job *job, clr_sampler sampler, clr_sample_batch *batch,
                                const tile_grid *g, int index, int pos, int bi, int32_t bounces,
                                int *count) {
  sample_band *band = &job->bands[bi];
  const clr_integrator *it = job->integrator;
  band->requests = it->request_count;
  band->stride = it->values_per_sample;
  band->path_bounces = it->path_bounces_in_layout;
  if (bounces < it->path_bounces_in_layout) {
    band->requests = clr_integrator_path_prefix(it, bounces, &band->stride);
    band->path_bounces = bounces;
  }
  int bpr = bands_per_row(g);
  int first = (index / bpr) * g->ntx + (index % bpr) * g->band_tiles;
  int row_left = g->ntx - first % g->ntx;
  int n = row_left < g->band_tiles ? row_left : g->band_tiles;
  clr_bounds2i a = tile_pixels(g, first), z = tile_pixels(g, first + n - 1);
  clr_bounds2i px = {a.x0, a.y0, z.x1, a.y1};
  size_t need =
      (size_t)(px.x1 - px.x0) * (size_t)(px.y1 - px.y0) * (size_t)job->spp * (size_t)band->stride;
  if (need > band->values_cap) {
    free(band->values);
    band->values = malloc(need * sizeof *band->values);
    band->values_cap = band->values ? need : 0;
    if (!band->values)
      return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "sample values (%zu floats)", need);
  }
  batch->first_sample = job->first_sample;
  batch->sample_count = job->spp;
  batch->request_count = band->requests;
  /* PoCL's threads run the kernel beside the workers: its CPU is the process's less theirs */
  double p0 = clock_seconds(CLOCK_PROCESS_CPUTIME_ID), w0 = workers_clock_seconds(job);
  CLR_CHECK(generate_values(job, sampler, batch, px, band->stride, band->values));
  double gen = workers_clock_seconds(job) - w0;
  gen = clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - p0 - gen;
  if (job->gen_bands++ > 0) clr_cost_fit_add(&job->gen_fit, (double)need, gen > 0.0 ? gen : 0.0);
  band->pixels = px;
  for (int k = 0; k < n; ++k) {
    job->tiles[pos + k].index = first + k;
    job->tiles[pos + k].band = bi;
    job->tiles[pos + k].pixels = tile_pixels(g, first + k);
  }
  *count = n;
  return CLR_SUCCESS;
}

static int free_band(const render_job *job) {
  for (int i = 0; i < job->nbands; ++i)
    if (!job->bands[i].in_use) return i;
  return -1;
}

/* The next band this process renders: the next in order when alone, else one claimed from the
 * ranks' shared counter; -1 when none is left. */
static clr_result claim_band(render_job *job, const tile_grid *g, int *band) {
  if (job->dist) return clr_dist_claim_band(job->dist, band);
  int total = bands_per_row(g) * g->nty;
  *band = job->next_band < total ? job->next_band++ : -1;
  return CLR_SUCCESS;
}

/* A finished tile goes into the film, or to rank 0 when ranks share the frame. */
static clr_result commit_tile(render_job *job, tile_info *m) {
  if (job->dist) return clr_dist_keep_tile(job->dist, m->index, m->film_tile);
  return film_merge_tile(job->film, m->film_tile);
}

/* The path bounces whose values the next band generates up front (path_bounces_in_layout: the
 * whole layout). Values are the same either way, so this chooses speed only: a deeper bounce's
 * values are fetched on the host when the fraction of samples reaching it, times a fetched
 * value's cost, is below a generated value's (each measured so far in this render; the first
 * bands explore with one bounce up front). A generated value's cost is the slope of the bands'
 * CPU seconds against their values: the average would count each launch's fixed cost (0.7 ms a
 * band measured on a 2-core AVX2 EPYC) as values' cost, several times the kernel's on a machine
 * where the kernel is fast. Bounce 0 is always generated. */
static int32_t choose_prefix(const render_job *job) {
  int32_t all = job->integrator->path_bounces_in_layout;
  if (!job->lazy) return all;
  if (job->lazy == 2) return 1;
  double gen = clr_cost_fit_per_unit(&job->gen_fit);
  if (!job->seen_samples || !(gen > 0.0) || !job->fetch_cpu_values) return 1;
  double ratio = gen / (job->fetch_cpu_s / (double)job->fetch_cpu_values);
  for (int32_t b = 1; b < all; ++b) {
    uint64_t v = job->seen_vertices[b < CLR_COUNTED_BOUNCES ? b : CLR_COUNTED_BOUNCES - 1];
    if ((double)v < ratio * (double)job->seen_samples) return b;
  }
  return all;
}

/* Main thread: generates bands ahead of the workers and merges finished tiles in claim order
 * (tile order when alone). */
static clr_result run_pipeline(render_job *job, clr_sampler sampler, const tile_grid *g,
                               const clr_render_options *o, clr_render_stats *st) {
  clr_sample_batch batch;
  clr_sample_batch_init(&batch);
  batch.requests = job->integrator->requests;
  int next_gen = 0, next_merge = 0, claims_done = 0;
  clr_result r = CLR_SUCCESS;
  double t_start = now_seconds(), t_first = 0.0;
  pthread_mutex_lock(&job->mutex);
  while (r == CLR_SUCCESS && next_merge < g->ntiles) {
    if (!job->cancelled && o->progress_callback)
      job->cancelled = o->progress_callback(o->progress_user, next_merge, g->ntiles) != 0;
    int cancelled = job->cancelled;
    int bi = free_band(job);
    if (!cancelled && !claims_done && bi >= 0) {
      job->bands[bi].in_use = 1;
      int32_t bounces = choose_prefix(job); /* the workers' figures, read under the mutex */
      pthread_mutex_unlock(&job->mutex);
      int n = 0, index = -1;
      double t0 = now_seconds();
      r = claim_band(job, g, &index);
      if (r == CLR_SUCCESS && index >= 0)
        r = generate_band(job, sampler, &batch, g, index, next_gen, bi, bounces, &n);
      st->seconds_sample_generation += now_seconds() - t0;
      pthread_mutex_lock(&job->mutex);
      if (r != CLR_SUCCESS || index < 0) {
        job->bands[bi].in_use = 0;
        claims_done = index < 0;
        if (r != CLR_SUCCESS) break;
        continue;
      }
      job->bands[bi].unfinished = n;
      for (int t = next_gen; t < next_gen + n; ++t) job->tiles[t].state = TILE_READY;
      next_gen += n;
      job->ready_end = next_gen;
      pthread_cond_broadcast(&job->cond);
      continue;
    }
    tile_info *m = &job->tiles[next_merge];
    if (next_merge >= next_gen || m->state != TILE_DONE) {
      if (next_merge >= next_gen) break; /* cancelled or every claim made, nothing in flight */
      pthread_cond_wait(&job->cond, &job->mutex);
      continue;
    }
    pthread_mutex_unlock(&job->mutex);
    r = m->result;
    if (r == CLR_SUCCESS) {
      double t0 = now_seconds();
      r = commit_tile(job, m);
      st->seconds_merge += now_seconds() - t0;
    }
    film_tile_release(m->film_tile);
    m->film_tile = NULL;
    pthread_mutex_lock(&job->mutex);
    m->state = TILE_MERGED;
    ++next_merge;
    st->tiles_done = next_merge;
    if (next_merge == 1) t_first = now_seconds() - t_start;
    if (o->progress) progress_bar(next_merge, g->ntiles, now_seconds() - t_start, t_first);
  }
  /* stop the workers; wait for tiles in flight when failing */
  job->ready_end = job->next_take;
  while (job->busy) pthread_cond_wait(&job->cond, &job->mutex);
  job->stop = 1;
  pthread_cond_broadcast(&job->cond);
  pthread_mutex_unlock(&job->mutex);
  return r;
}

/* Sends this rank's tiles and figures to rank 0, which merges the frame; on rank 0 the stats then
 * count every rank's tiles and rays. */
static clr_result finish_distributed_frame(render_job *job, clr_result r, double seconds,
                                           clr_render_stats *st) {
  clr_dist_rank_stats mine = {0, job->rays - job->rays_sent, (uint64_t)st->tiles_done, seconds, 0.0,
                              0};
  job->rays_sent = job->rays;              /* job->rays counts every pass */
  for (int i = 0; i < st->tiles_done; ++i) /* the samples shaded: active pixels only */
    mine.samples += (uint64_t)clr_adaptive_count_active(job->adaptive, job->tiles[i].pixels) *
                    (uint64_t)job->spp;
  int32_t missing = 0;
  r = clr_dist_end_frame(job->dist, job->film, r, &mine, &missing);
  if (r != CLR_SUCCESS) return r; /* the job ends: the CLI aborts every rank */
  clr_dist_share(job->dist, &missing);
  st->tiles_done = st->tiles_total - missing;
  st->partial = missing > 0;
  return r;
}

/* The integrator's layout prepared once for the workers' fetches (lazy sample vectors). */
static clr_result prepare_fetch(render_job *job) {
  job->fetch = NULL;
  if (!job->lazy) return CLR_SUCCESS;
  const clr_integrator *it = job->integrator;
  return clr_sample_fetch_create(job->sampler, it->requests, it->request_count, &job->fetch);
}

/* Runs the tile pipeline; *partial set when cancelled. */
static clr_result render_tiles(render_job *job, clr_sampler sampler, const clr_render_options *o,
                               int nthreads, clr_render_stats *st) {
  tile_grid g;
  (void)sampler;
  job->next_take = job->ready_end = job->busy = job->stop = job->next_band = 0;
  st->tiles_done = 0;
  g.bounds = job->region;
  g.size = o->tile_size > 0 ? o->tile_size : 16;
  g.ntx = (g.bounds.x1 - g.bounds.x0 + g.size - 1) / g.size;
  g.nty = (g.bounds.y1 - g.bounds.y0 + g.size - 1) / g.size;
  g.ntiles = g.ntx * g.nty;
  size_t tile_values = (size_t)g.size * (size_t)g.size * (size_t)job->spp *
                       (size_t)job->integrator->values_per_sample;
  size_t fit = BATCH_VALUES_BUDGET / (tile_values ? tile_values : 1);
  g.band_tiles = fit < 1 ? 1 : fit > (size_t)g.ntx ? g.ntx : (int)fit;
  st->tiles_total = g.ntiles;
  /* one band being generated, enough being shaded to keep every worker busy */
  job->nbands = 2 + (nthreads + g.band_tiles - 1) / g.band_tiles;
  job->tiles = calloc((size_t)(g.ntiles ? g.ntiles : 1), sizeof *job->tiles);
  job->bands = calloc((size_t)job->nbands, sizeof *job->bands);
  pthread_t *threads = calloc((size_t)nthreads, sizeof *threads);
  job->worker_clocks = calloc((size_t)nthreads, sizeof *job->worker_clocks);
  job->nworker_clocks = 0;
  if (!job->tiles || !job->bands || !threads || !job->worker_clocks) {
    free(job->tiles);
    free(job->bands);
    free(threads);
    free(job->worker_clocks);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "render tiles");
  }
  clr_result rf = prepare_fetch(job);
  if (rf != CLR_SUCCESS) {
    free(job->tiles);
    free(job->bands);
    free(threads);
    free(job->worker_clocks);
    return rf;
  }
  if (job->dist) {
    clr_result rb = clr_dist_begin_frame(job->dist, bands_per_row(&g) * g.nty, g.ntiles);
    if (rb != CLR_SUCCESS) {
      free(job->tiles);
      free(job->bands);
      free(threads);
      free(job->worker_clocks);
      clr_sample_fetch_release(job->fetch);
      job->fetch = NULL;
      return rb;
    }
  }
  double t_loop = now_seconds();
  pthread_mutex_init(&job->mutex, NULL);
  pthread_cond_init(&job->cond, NULL);
  int started = 0;
  for (; started < nthreads; ++started)
    if (pthread_create(&threads[started], NULL, worker_main, job) != 0) break;
  for (int i = 0; i < started; ++i) /* no band yet: the workers wait, nobody reads the clocks */
    if (pthread_getcpuclockid(threads[i], &job->worker_clocks[job->nworker_clocks]) == 0)
      ++job->nworker_clocks;
  clr_result r = started ? run_pipeline(job, sampler, &g, o, st)
                         : clr_set_last_error(CLR_ERROR_INTERNAL, "pthread_create failed");
  if (!started) job->stop = 1;
  for (int i = 0; i < started; ++i) pthread_join(threads[i], NULL);
  for (int i = 0; i < g.ntiles; ++i)
    if (job->tiles[i].film_tile) film_tile_release(job->tiles[i].film_tile);
  st->partial = st->tiles_done < g.ntiles;
  if (job->dist) r = finish_distributed_frame(job, r, now_seconds() - t_loop, st);
  for (int i = 0; i < job->nbands; ++i) free(job->bands[i].values);
  if (o->progress && st->tiles_done < g.ntiles) fputc('\n', stderr);
  pthread_cond_destroy(&job->cond);
  pthread_mutex_destroy(&job->mutex);
  free(job->tiles);
  free(job->bands);
  free(threads);
  free(job->worker_clocks);
  job->worker_clocks = NULL;
  job->nworker_clocks = 0;
  clr_sample_fetch_release(job->fetch);
  job->fetch = NULL;
  return r;
}

/* ---------- passes, output ---------- */

/* What the image header records besides the film: the render's identity, for --resume. */
typedef struct output_info {
  const clr_render_options *o;
  clr_render_stats *st;
  clr_resume_identity id;
  int whole_passes; /* the image holds whole passes of every pixel */
} output_info;

/* Writes the EXR (with the identity attributes), the PFM when rgb is given, and the preview. */
static clr_result write_image(clr_film film, const output_info *oi, const float *rgb, int w,
                              int h) {
  clr_render_stats *st = oi->st;
  clr_film_write_options wo;
  clr_film_write_options_init(&wo);
  wo.sampler = st->sampler;
  wo.spp = st->spp;
  wo.render_time_s = st->seconds_render;
  wo.partial = st->partial;
  char target[16], whole[4];
  snprintf(target, sizeof target, "%d", (int)st->spp_target);
  snprintf(whole, sizeof whole, "%d", oi->whole_passes);
  const char *keys[16] = {
      "integrator",          "clrender.seed",         "clrender.seeding",       "clrender.scene",
      "clrender.spp_target", "clrender.whole_passes", "clrender.randomization", "clrender.layout"};
  const char *vals[16] = {st->integrator, oi->id.seed, oi->id.seeding,       oi->id.scene,
                          target,         whole,       oi->id.randomization, oi->id.layout};
  wo.metadata_keys = keys;
  wo.metadata_values = vals;
  int n = 8;
  char threshold[32];
  if (oi->o->noise_threshold > 0.0f) {
    snprintf(threshold, sizeof threshold, "%.9g", (double)oi->o->noise_threshold);
    keys[n] = "clrender.noise_threshold";
    vals[n++] = threshold;
  }
  wo.metadata_count = n + clr_dist_metadata(clr_dist_world(), keys + n, vals + n, 16 - n);
  clr_result r = CLR_SUCCESS;
  if (st->exr_path[0]) r = film_write(film, st->exr_path, &wo);
  if (r == CLR_SUCCESS && rgb && st->pfm_path[0]) r = clr_write_pfm(st->pfm_path, rgb, w, h);
  if (r == CLR_SUCCESS) r = film_write_png(film, st->png_path, 1.0f);
  return r;
}

static int pass_mode(const clr_render_options *o) {
  return o->resume || o->time_limit >= 0.0 || o->checkpoint >= 0.0 || o->pass_spp > 0 ||
         o->noise_threshold > 0.0f;
}

/* After pass `index` (from 0) of an adaptive render, with spp_done samples per pixel: the pass
 * goes into its half film; after each pair, from CLR_ADAPTIVE_MIN_SPP on, rank 0 updates the
 * active pixels and shares them. *done: no pixel is left. */
static clr_result adapt(clr_adaptive *ad, clr_film pass, int index, int spp_done, clr_dist *dist,
                        int *done) {
  clr_result r = clr_adaptive_add_pass(ad, pass, index);
  if (r != CLR_SUCCESS || (index & 1) == 0 || spp_done < CLR_ADAPTIVE_MIN_SPP) return r;
  if (clr_dist_rank(dist) == 0) r = clr_adaptive_update(ad);
  if (r != CLR_SUCCESS) return r;
  if (dist) clr_dist_share_bytes(dist, ad->active, (size_t)ad->width * (size_t)ad->height);
  int64_t left = 0;
  for (size_t i = 0; i < (size_t)ad->width * (size_t)ad->height; ++i) left += ad->active[i];
  ad->active_count = left;
  *done = left == 0;
  return CLR_SUCCESS;
}

/* --resume: rank 0 adds the image's sums into `film` after checking it is this render's; every
 * rank gets the spp it holds. */
static clr_result load_resumed(clr_film film, const char *path, const clr_resume_identity *id,
                               int32_t *spp_done) {
  clr_dist *dist = clr_dist_world();
  clr_result r = CLR_SUCCESS;
  int32_t done = -1;
  if (clr_dist_rank(dist) == 0) { /* the sums merged first: a refused image fails the render */
    int32_t n = clr_resume_attribute_count;
    char *values = calloc((size_t)n, CLR_RESUME_VALUE);
    r = values ? film_merge_file(film, path, n, clr_resume_attributes, values, CLR_RESUME_VALUE)
               : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "resume");
    if (r == CLR_SUCCESS) r = clr_resume_check(path, values, id, &done);
    free(values);
  }
  if (dist) clr_dist_share(dist, &done);
  if (r == CLR_SUCCESS && done < 0)
    r = clr_set_last_error(CLR_ERROR_IO, "--resume %s: rank 0 could not resume it", path);
  *spp_done = done;
  return r;
}

/* Renders samples [spp_done, spp_target) in passes, each into a pass film merged whole into
 * `film`; stops early at the time limit or when cancelled (the unfinished pass is dropped).
 * Checkpoints rewrite the image (rank 0) when `oi` is given. */
static clr_result render_passes(render_job *job, clr_sampler sampler, clr_context ctx,
                                clr_film film, int spp_done, const clr_render_options *o,
                                int nthreads, clr_render_stats *st, const output_info *oi) {
  int total = st->spp_target, step = o->pass_spp > 0 ? o->pass_spp : total / 8;
  if (step < 1) step = 1;
  double t0 = now_seconds(), last_write = t0;
  clr_result r = CLR_SUCCESS;
  st->spp = spp_done;
  int32_t stop = spp_done >= total;
  clr_adaptive ad;
  memset(&ad, 0, sizeof ad);
  if (o->noise_threshold > 0.0f) {
    r = clr_adaptive_init(&ad, ctx, film, o->noise_threshold);
    job->adaptive = &ad;
  }
  while (r == CLR_SUCCESS && !stop) {
    clr_film pass = NULL;
    r = film_create(ctx, film_get_desc(film), &pass);
    if (r != CLR_SUCCESS) break;
    job->film = pass;
    job->first_sample = spp_done;
    job->spp = step < total - spp_done ? step : total - spp_done;
    r = render_tiles(job, sampler, o, nthreads, st);
    int converged = 0;
    if (r == CLR_SUCCESS && !st->partial) r = film_merge_film(film, pass);
    if (r == CLR_SUCCESS && !st->partial && job->adaptive)
      r = adapt(&ad, pass, st->passes, spp_done + job->spp, job->dist, &converged);
    film_release(pass);
    if (r == CLR_SUCCESS && !st->partial) {
      spp_done += job->spp;
      st->spp = spp_done;
      st->passes++;
    }
    double now = now_seconds();
    stop = r != CLR_SUCCESS || st->partial || spp_done >= total || converged ||
           (o->time_limit >= 0.0 && now - t0 >= o->time_limit);
    if (job->dist) clr_dist_share(job->dist, &stop); /* rank 0's clock and film decide */
    if (!stop && oi && o->checkpoint >= 0.0 && now - last_write >= o->checkpoint) {
      st->seconds_render = now - t0;
      r = write_image(film, oi, NULL, 0, 0);
      last_write = now_seconds();
    }
  }
  if (r == CLR_SUCCESS && job->adaptive && o->error_map && oi && clr_dist_rank(job->dist) == 0)
    r = clr_adaptive_write_error_map(&ad, ctx, film, o->error_map);
  job->adaptive = NULL;
  clr_adaptive_free(&ad);
  return r;
}

/* The sample pixels to render. pbrt-v3 renders the crop's sample bounds (GetSampleBounds), which
 * miss a sample exactly at distance `radius` past the crop's last pixel centre (Halton and Sobol
 * put every pixel's sample 0 at offset 0; a box filter of radius 0.5 reaches the pixel above it).
 * With per-pixel seeding the samples of a pixel do not depend on the crop, so a crop renders every
 * sample pixel whose samples can reach its pixels, [floor(x0 + 0.5 - r), floor(x1 - 0.5 + r) + 1),
 * clipped to the full frame's sample bounds: exactly the samples the full render filters into the
 * crop's pixels, and crops merge into the full image. pbrt-v3 seeding keeps pbrt-v3's bounds. */
static clr_bounds2i render_region(clr_sampler sampler, const clr_sampler_desc *sd) {
  clr_bounds2i sb = clr_sampler_sample_bounds(sampler);
  if (sd->seeding == CLR_SEEDING_PBRT_V3) return sb;
  clr_bounds2i pb = clr_sampler_pixel_bounds(sampler), r;
  float rx = sd->film.filter_radius[0], ry = sd->film.filter_radius[1];
  r.x0 = (int32_t)floorf((float)pb.x0 + 0.5f - rx);
  r.y0 = (int32_t)floorf((float)pb.y0 + 0.5f - ry);
  r.x1 = (int32_t)floorf((float)pb.x1 - 0.5f + rx) + 1;
  r.y1 = (int32_t)floorf((float)pb.y1 - 0.5f + ry) + 1;
  /* the full frame's sample bounds (film_geometry.c's formula over the uncropped pixels) */
  clr_bounds2i full = {(int32_t)floorf(0.5f - rx), (int32_t)floorf(0.5f - ry),
                       (int32_t)ceilf((float)sd->film.x_resolution - 0.5f + rx),
                       (int32_t)ceilf((float)sd->film.y_resolution - 0.5f + ry)};
  if (r.x0 < full.x0) r.x0 = full.x0;
  if (r.y0 < full.y0) r.y0 = full.y0;
  if (r.x1 > full.x1) r.x1 = full.x1;
  if (r.y1 > full.y1) r.y1 = full.y1;
  return r;
}

/* ---------- output paths ---------- */

static int has_suffix(const char *s, const char *suffix) {
  size_t a = strlen(s), b = strlen(suffix);
  if (a < b) return 0;
  for (size_t i = 0; i < b; ++i) {
    char c = s[a - b + i];
    if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
    if (c != suffix[i]) return 0;
  }
  return 1;
}

/* The image format by the name's extension, as pbrt-v3: ".exr" (with a PNG preview beside it),
 * ".pfm" (with the preview too), ".png" (alone); any other name is an error naming it. */
static clr_result output_paths(const char *path, clr_render_stats *st) {
  if (strlen(path) + 8 >= sizeof st->exr_path)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "output path too long: %s", path);
  st->exr_path[0] = st->pfm_path[0] = 0;
  if (has_suffix(path, ".png")) {
    snprintf(st->png_path, sizeof st->png_path, "%s", path);
    return CLR_SUCCESS;
  }
  int exr = has_suffix(path, ".exr"), pfm = has_suffix(path, ".pfm");
  if (!exr && !pfm) {
    CLR_CHECK(film_check_output_path(path)); /* a device or directory is reported as such */
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (dot && (!slash || dot > slash))
      return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                                "output \"%s\": unknown image extension \"%s\" (clrender writes "
                                ".exr, .png and .pfm)",
                                path, dot);
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "output \"%s\" has no image extension (clrender writes .exr, .png "
                              "and .pfm)",
                              path);
  }
  snprintf(exr ? st->exr_path : st->pfm_path, sizeof st->exr_path, "%s", path);
  snprintf(st->png_path, sizeof st->png_path, "%.*s.png", (int)(strlen(path) - 4), path);
  return CLR_SUCCESS;
}

/* ---------- entry points ---------- */

/* Whether bands may hold a prefix of the layout: path tracing with a sampler whose values are a
 * function of (pixel, sample, dimension) and a layout without arrays (so that a prefix of the
 * layout has the same values as the whole layout). */
static int lazy_allowed(const render_job *job, const clr_render_options *o) {
  const clr_integrator *it = job->integrator;
  if (o->lazy_samples == CLR_LAZY_SAMPLES_OFF || it->type != CLR_INTEGRATOR_PATH ||
      it->path_bounces_in_layout < 2 || !clr_sampler_has_global_index(job->sampler))
    return 0;
  for (int32_t i = 0; i < it->request_count; ++i)
    if (it->requests[i].array_size) return 0;
  return o->lazy_samples == CLR_LAZY_SAMPLES_ALWAYS ? 2 : 1;
}

/* The scene and its integrator, built beside the device setup. */
typedef struct scene_build_job {
  const clr_scene_desc *d;
  clr_warn_fn warn;
  void *wu;
  clr_sampler_type sampler_type;
  int pbrt_v4;             /* pbrt-v4's camera layout (clr_integrator_create_layout) */
  clr_render_scene *scene; /* NULL unless both were made */
  clr_integrator integ;
  double seconds;
} scene_build_job;

static clr_result build_scene(void *user) {
  scene_build_job *b = user;
  double t0 = now_seconds();
  clr_render_scene *scene = NULL;
  CLR_CHECK(clr_render_scene_build(b->d, b->warn, b->wu, &scene));
  clr_result r = clr_integrator_create_layout(b->d, scene, b->sampler_type, b->pbrt_v4, b->warn,
                                              b->wu, &b->integ);
  if (r != CLR_SUCCESS) {
    clr_render_scene_free(scene);
    return r;
  }
  b->scene = scene;
  b->seconds = now_seconds() - t0;
  return CLR_SUCCESS;
}

clr_result clr_render_desc(const clr_scene_desc *d, const clr_render_options *opts,
                           clr_render_stats *stats, int write_files, clr_render_image *image) {
  clr_render_options defaults;
  clr_render_options_init(&defaults);
  const clr_render_options *o = opts ? opts : &defaults;
  if (o->struct_size != sizeof *o)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "clr_render_options.struct_size %zu, expected %zu", o->struct_size,
                              sizeof *o);
  if (o->lazy_samples < CLR_LAZY_SAMPLES_AUTO || o->lazy_samples > CLR_LAZY_SAMPLES_ALWAYS)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "clr_render_options.lazy_samples %d (auto 0, off 1, always 2)",
                              (int)o->lazy_samples);
  clr_render_stats local;
  clr_render_stats_init(&local);
  clr_render_stats *st = &local;
  double t_begin = now_seconds();
  warn_sink sink = {o->quiet};
  clr_warn_fn warn = warn_print;
  void *wu = &sink;

  clr_render_settings settings;
  clr_render_settings_from_desc(d, &settings);
  if (o->crop_given) memcpy(settings.crop_window, o->crop_window, sizeof settings.crop_window);
  if (o->xresolution > 0) settings.x_resolution = o->xresolution;
  if (o->yresolution > 0) settings.y_resolution = o->yresolution;
  clr_sampler_desc sdesc;
  clr_filter_desc fdesc;
  CLR_CHECK(sampler_from_desc(d, o, warn, wu, &sdesc));
  CLR_CHECK(filter_from_desc(d, o, warn, wu, &fdesc));
  CLR_CHECK(check_scene_values(d, o, &settings, &sdesc, &fdesc));

  clr_result r = CLR_SUCCESS;
  if (write_files && clr_dist_rank(clr_dist_world()) == 0) { /* only rank 0 writes */
    r = output_paths(o->outfile ? o->outfile : settings.filename, st);
    if (r == CLR_SUCCESS && st->exr_path[0]) r = film_check_output_path(st->exr_path);
    if (r == CLR_SUCCESS && st->pfm_path[0]) r = film_check_output_path(st->pfm_path);
    if (r == CLR_SUCCESS) r = film_check_output_path(st->png_path);
    if (r == CLR_SUCCESS && o->error_map) r = film_check_output_path(o->error_map);
    if (r != CLR_SUCCESS && !o->outfile) /* the path came from the scene: say where */
      return clr_set_last_error(r, "%s:%d: Film \"filename\": %s", param_file(&d->film.params),
                                param_line(&d->film.params, "filename"), clr_last_error_message());
    if (r != CLR_SUCCESS) return r;
  }

  /* The scene is built on a helper thread while this one sets up the OpenCL side
   * (device_setup.c). */
  clr_context_desc cdesc;
  clr_context_desc_init(&cdesc);
  cdesc.device = o->device;
  clr_film_desc fd;
  clr_film_desc_init(&fd);
  fd.x_resolution = settings.x_resolution;
  fd.y_resolution = settings.y_resolution;
  memcpy(fd.crop_window, settings.crop_window, sizeof fd.crop_window);
  fd.scale = settings.scale;
  fd.max_sample_luminance = settings.max_sample_luminance;
  fd.filter = fdesc;
  sdesc.film.x_resolution = settings.x_resolution;
  sdesc.film.y_resolution = settings.y_resolution;
  memcpy(sdesc.film.crop_window, settings.crop_window, sizeof sdesc.film.crop_window);
  sdesc.film.filter_radius[0] = fdesc.radius[0];
  sdesc.film.filter_radius[1] = fdesc.radius[1];
  clr_camera_layout camera;
  clr_camera_layout_init(&camera, &sdesc, &fdesc);
  if (camera.filter_sampled) { /* pbrt-v4: each sample to its own pixel, the pixel bounds sampled */
    clr_filter_desc_init(&fd.filter, CLR_FILTER_BOX);
    sdesc.film.filter_radius[0] = sdesc.film.filter_radius[1] = fd.filter.radius[0];
  }
  scene_build_job build;
  memset(&build, 0, sizeof build);
  build.d = d;
  build.warn = warn;
  build.wu = wu;
  build.sampler_type = sdesc.type;
  build.pbrt_v4 = camera.pbrt_v4;
  clr_device_setup device;
  double t0 = now_seconds();
  r = clr_device_setup_run(&device, &cdesc, o->kernels, &fd, &sdesc, build_scene, &build);
  if (r != CLR_SUCCESS) {
    if (build.scene) { /* the scene was built; the device failed */
      clr_integrator_free(&build.integ);
      clr_render_scene_free(build.scene);
    }
    return r;
  }
  clr_render_scene *scene = build.scene;
  clr_integrator integ = build.integ;
  if (!o->quiet) clr_scene_desc_report_unused(d, warn, wu);
  st->seconds_build = build.seconds;
  st->seconds_device_wait = now_seconds() - t0 - build.seconds;
  clr_context ctx = device.ctx;
  clr_sampler sampler = device.sampler;
  clr_film film = device.film;
  if (r == CLR_SUCCESS) warn_spp_rounding(d, o, &sdesc, clr_sampler_spp(sampler), warn, wu);
  if (r == CLR_SUCCESS)
    r = clr_render_scene_set_film(scene, settings.x_resolution, settings.y_resolution);
  if (r == CLR_SUCCESS) clr_render_scene_set_samples_per_pixel(scene, clr_sampler_spp(sampler));
  int nthreads = o->nthreads > 0 ? o->nthreads : default_threads();
  output_info oi;
  memset(&oi, 0, sizeof oi);
  if (r == CLR_SUCCESS) {
    render_job job;
    memset(&job, 0, sizeof job);
    job.scene = scene;
    job.integrator = &integ;
    job.film = film;
    job.spp = clr_sampler_spp(sampler);
    job.seed = o->seed;
    job.host_samples = o->reference_samples != 0 || !ctx; /* --device host */
    job.camera = camera;
    clr_camera_layout_skip(&job.camera, integ.camera_offset, integ.time_offset, integ.lens_offset);
    job.region = render_region(sampler, &sdesc);
    job.dist = clr_dist_world();
    job.sampler = sampler;
    job.lazy = lazy_allowed(&job, o);
    st->spp = st->spp_target = job.spp;
    st->passes = 1;
    st->threads = nthreads;
    snprintf(st->sampler, sizeof st->sampler, "%s", clr_sampler_type_name(sdesc.type));
    snprintf(st->integrator, sizeof st->integrator, "%s",
             integ.type == CLR_INTEGRATOR_AO       ? "ambientocclusion"
             : integ.type == CLR_INTEGRATOR_DIRECT ? "directlighting"
                                                   : "path");
    oi.o = o;
    oi.st = st;
    oi.id.sampler = st->sampler;
    oi.id.integrator = st->integrator;
    oi.id.scene = o->scene_id ? o->scene_id : "";
    snprintf(oi.id.seed, sizeof oi.id.seed, "%u", (unsigned)o->seed);
    oi.id.seeding = o->seeding == CLR_SEEDING_PBRT_V3   ? "pbrt-v3"
                    : o->seeding == CLR_SEEDING_PBRT_V4 ? "pbrt-v4"
                                                        : "pixel";
    oi.id.randomization = clr_randomization_name(sdesc.randomization);
    oi.id.spp_target = job.spp;
    /* every request's values: skipping unread ones leaves the others' values as they were */
    snprintf(oi.id.layout, sizeof oi.id.layout, "camera %d, values %d", (int)integ.camera_offset,
             (int)integ.layout_values);
    oi.id.global_sampler = sdesc.type == CLR_SAMPLER_HALTON || sdesc.type == CLR_SAMPLER_SOBOL ||
                           sdesc.type == CLR_SAMPLER_INDEPENDENT; /* spp-independent samples */
    double tr = now_seconds();
    if (!pass_mode(o)) {
      r = render_tiles(&job, sampler, o, nthreads, st);
      oi.whole_passes = !st->partial;
    } else {
      int32_t spp_done = 0;
      oi.whole_passes = o->noise_threshold <= 0.0f; /* adaptive: pixels differ in spp */
      st->passes = 0;
      if (o->seeding == CLR_SEEDING_PBRT_V3)
        r = clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                               "--seeding pbrt-v3 renders whole tiles in one pass: --resume, "
                               "--time-limit, --checkpoint and --pass-spp need --seeding pixel");
      if (r == CLR_SUCCESS && o->resume && o->noise_threshold > 0.0f)
        r = clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                               "--resume with --noise-threshold: the A/B half films are not "
                               "saved in the image; resume without adaptive sampling");
      if (r == CLR_SUCCESS && o->resume) r = load_resumed(film, o->resume, &oi.id, &spp_done);
      if (r == CLR_SUCCESS)
        r = render_passes(&job, sampler, ctx, film, spp_done, o, nthreads, st,
                          write_files ? &oi : NULL);
    }
    st->seconds_render = now_seconds() - tr;
    st->seconds_tracing = job.trace_s;
    st->seconds_shading = job.shade_s;
    st->seconds_sample_generation += job.fetch_value_s; /* the workers' fetches, over threads */
    st->seconds_reconstruction = job.recon_s;
    st->rays = job.rays;
  }
  clr_render_image im;
  memset(&im, 0, sizeof im);
  int root = clr_dist_rank(clr_dist_world()) == 0; /* the other ranks sent rank 0 their tiles */
  if (r == CLR_SUCCESS && root) {
    im.full_width = settings.x_resolution;
    im.full_height = settings.y_resolution;
    im.pixel_bounds = film_pixel_bounds(film);
    im.width = im.pixel_bounds.x1 - im.pixel_bounds.x0;
    im.height = im.pixel_bounds.y1 - im.pixel_bounds.y0;
    if (image || (write_files && st->pfm_path[0])) { /* the EXR and PNG read the film */
      im.rgb = malloc((size_t)im.width * (size_t)im.height * 3 * sizeof(float));
      r = im.rgb ? film_get_rgb(film, im.rgb, 1.0f)
                 : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "image");
    }
    st->samples = film_sample_count(film);
    st->dropped_samples = film_dropped_samples(film);
  }
  if (r == CLR_SUCCESS && write_files && root) {
    double tw = now_seconds();
    r = write_image(film, &oi, im.rgb, im.width, im.height);
    st->seconds_output = now_seconds() - tw;
  }
  if (r == CLR_SUCCESS && image && root)
    *image = im;
  else
    free(im.rgb);
  if (sampler) clr_sampler_release(sampler);
  if (film) film_release(film);
  if (ctx) clr_context_release(ctx);
  clr_integrator_free(&integ);
  clr_render_scene_free(scene);
  st->seconds_total = now_seconds() - t_begin;
  if (stats) {
    double parse = stats->seconds_parse;
    *stats = local;
    stats->seconds_parse = parse;
  }
  return r;
}

clr_result clr_render_file(const char *path, const clr_render_options *opts,
                           clr_render_stats *stats) {
  if (!path)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_render_file: scene_path is NULL");
  warn_sink sink = {opts ? opts->quiet : 0};
  clr_parse_options po;
  clr_parse_options_init(&po);
  po.warn = warn_print;
  po.warn_user = &sink;
  double t0 = now_seconds();
  clr_scene_desc *desc = NULL;
  CLR_CHECK(clr_scene_parse_file(path, &po, &desc));
  double parse = now_seconds() - t0;
  if (stats) {
    clr_render_stats_init(stats);
    stats->seconds_parse = parse;
  }
  clr_render_options with_id;
  clr_render_options_init(&with_id);
  if (opts && opts->struct_size == sizeof with_id) with_id = *opts;
  char hash[17];
  clr_result r = CLR_SUCCESS;
  if (!with_id.scene_id) {
    r = clr_scene_file_hash(path, hash);
    with_id.scene_id = hash;
  }
  const clr_render_options *use = opts && opts->struct_size != sizeof with_id ? opts : &with_id;
  if (r == CLR_SUCCESS) r = clr_render_desc(desc, use, stats, 1, NULL);
  if (stats) stats->seconds_total += parse;
  clr_scene_desc_free(desc);
  return r;
}

int clr_render_stats_json(const clr_render_stats *s, char *buf, size_t size) {
  return snprintf(buf, size,
                  "{\"seconds\":{\"total\":%.6f,\"parse\":%.6f,\"build\":%.6f,\"render\":%.6f,"
                  "\"sample_generation\":%.6f,\"tracing\":%.6f,\"shading\":%.6f,"
                  "\"reconstruction\":%.6f,\"merge\":%.6f,\"output\":%.6f,\"device_wait\":%.6f},"
                  "\"rays\":%llu,\"samples\":%llu,\"dropped_samples\":%llu,\"tiles\":%d,"
                  "\"tiles_total\":%d,\"threads\":%d,\"spp\":%d,\"sampler\":\"%s\","
                  "\"integrator\":\"%s\",\"partial\":%d,\"spp_target\":%d,\"passes\":%d}",
                  s->seconds_total, s->seconds_parse, s->seconds_build, s->seconds_render,
                  s->seconds_sample_generation, s->seconds_tracing, s->seconds_shading,
                  s->seconds_reconstruction, s->seconds_merge, s->seconds_output,
                  s->seconds_device_wait, (unsigned long long)s->rays,
                  (unsigned long long)s->samples, (unsigned long long)s->dropped_samples,
                  s->tiles_done, s->tiles_total, s->threads, s->spp, s->sampler, s->integrator,
                  s->partial, s->spp_target, s->passes);
}
