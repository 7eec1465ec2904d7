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
#include "clrender/film.h"
#include "clrender/kernels.h"
#include "integrator.h"
#include "pfm_output.h"
#include "pcg32.h"
#include "render_scene.h"
#include "renderer.h"
#include "scene_parser.h"

#define CHUNK_SAMPLES 256

void clr_render_options_init(clr_render_options *o) {
  if (!o) return;
  memset(o, 0, sizeof *o);
  o->struct_size = sizeof *o;
  o->tile_size = 16;
  o->seeding = CLR_SEEDING_PIXEL;
}

void clr_render_stats_init(clr_render_stats *s) {
  if (!s) return;
  memset(s, 0, sizeof *s);
  s->struct_size = sizeof *s;
}

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

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
  sd->seed = o->seed;
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
#define BATCH_VALUES_BUDGET ((size_t)8 << 20) /* floats per batch, at least one tile */

enum { TILE_PENDING, TILE_READY, TILE_BUSY, TILE_DONE, TILE_MERGED };

typedef struct sample_band {
  float *values;
  size_t values_cap;
  clr_bounds2i pixels; /* the band's pixel rectangle */
  int unfinished;      /* tiles of the band not yet shaded; the band is free at 0 */
  int in_use;
} sample_band;

typedef struct tile_info {
  int state;
  int band;
  clr_bounds2i pixels;
  clr_film_tile film_tile;
  clr_result result;
} tile_info;

typedef struct render_job {
  const clr_render_scene *scene;
  const clr_integrator *integrator;
  clr_film film;
  int spp;
  int host_samples; /* options->reference_samples: host reference generator (comparison) */
  int cancelled;    /* the progress callback asked to stop */
  uint32_t seed;
  clr_bounds2i region; /* the sample pixels rendered (render_region) */
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
} render_job;

/* A worker's buffers, reused from tile to tile. */
typedef struct worker_buffers {
  clr_film_sample *fs;
  size_t fs_cap;
  clr_ray rays[CHUNK_SAMPLES];
  uint64_t keys[CHUNK_SAMPLES];
  float L[3 * CHUNK_SAMPLES], weights[CHUNK_SAMPLES];
} worker_buffers;

static uint64_t sample_key(uint32_t seed, int px, int py, int s) {
  return clr_mix64(((uint64_t)seed << 32) ^
                   clr_mix64(((uint64_t)(uint32_t)px << 32) | (uint32_t)py)) +
         (uint64_t)s * 0x9E3779B97F4A7C15ull;
}

/* Traces and shades `n` consecutive samples of pixel row py starting at column px0, sample s0;
 * values: their sample vectors; fs: their film samples. */
static clr_result shade_run(render_job *job, worker_buffers *b, clr_integrator_scratch *scratch,
                            clr_integrator_counters *counters, int px0, int py, int s0, int n,
                            const float *values, clr_film_sample *fs) {
  const clr_integrator *it = job->integrator;
  int spp = job->spp;
  for (int k = 0, px = px0, s = s0; k < n; ++k) {
    const float *v = values + (size_t)k * (size_t)it->values_per_sample;
    fs[k].x = (float)px + v[0];
    fs[k].y = (float)py + v[1];
    b->weights[k] =
        clr_render_scene_camera_ray(job->scene, fs[k].x, fs[k].y, v[2], v[3], v[4], &b->rays[k]);
    b->keys[k] = sample_key(job->seed, px, py, s);
    if (++s == spp) {
      s = 0;
      ++px;
    }
  }
  CLR_CHECK(
      clr_integrator_li(it, job->scene, scratch, b->rays, values, b->keys, n, b->L, counters));
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
  size_t vps = (size_t)job->integrator->values_per_sample, spp = (size_t)job->spp;
  int w = tile->pixels.x1 - tile->pixels.x0, h = tile->pixels.y1 - tile->pixels.y0;
  int band_w = band->pixels.x1 - band->pixels.x0;
  size_t row = (size_t)w * spp, total = row * (size_t)h;
  if (total > b->fs_cap) {
    clr_film_sample *fs = realloc(b->fs, total * sizeof *fs);
    if (!fs) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "render tile");
    b->fs = fs;
    b->fs_cap = total;
  }
  for (int ly = 0; ly < h; ++ly) {
    int py = tile->pixels.y0 + ly;
    size_t first = ((size_t)(py - band->pixels.y0) * (size_t)band_w +
                    (size_t)(tile->pixels.x0 - band->pixels.x0)) *
                   spp;
    for (size_t base = 0; base < row; base += CHUNK_SAMPLES) {
      int n = (int)(row - base < CHUNK_SAMPLES ? row - base : CHUNK_SAMPLES);
      CLR_CHECK(shade_run(job, b, scratch, counters, tile->pixels.x0 + (int)(base / spp), py,
                          (int)(base % spp), n, band->values + (first + base) * vps,
                          b->fs + (size_t)ly * row + base));
    }
  }
  double t0 = now_seconds();
  clr_result r = film_get_tile(job->film, tile->pixels, &tile->film_tile);
  if (r == CLR_SUCCESS) r = film_tile_add_samples(tile->film_tile, b->fs, total);
  *recon_s += now_seconds() - t0;
  return r;
}

static void *worker_main(void *arg) {
  render_job *job = arg;
  clr_integrator_scratch *scratch = clr_integrator_scratch_create();
  worker_buffers *buffers = calloc(1, sizeof *buffers);
  clr_integrator_counters counters = {0, 0.0, CLR_SUCCESS};
  double busy = 0.0, recon = 0.0;
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
    pthread_cond_broadcast(&job->cond);
  }
  job->trace_s += counters.trace_seconds;
  job->recon_s += recon;
  job->shade_s += busy - counters.trace_seconds - recon;
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

/* Generates the band starting at tile `first` into band `bi`; returns its tile count in *count. */
static clr_result generate_band(render_job *job, clr_sampler sampler, clr_sample_batch *batch,
                                const tile_grid *g, int first, int bi, int *count) {
  sample_band *band = &job->bands[bi];
  int row_left = g->ntx - first % g->ntx;
  int n = row_left < g->band_tiles ? row_left : g->band_tiles;
  clr_bounds2i a = tile_pixels(g, first), z = tile_pixels(g, first + n - 1);
  clr_bounds2i px = {a.x0, a.y0, z.x1, a.y1};
  size_t need = (size_t)(px.x1 - px.x0) * (size_t)(px.y1 - px.y0) * (size_t)job->spp *
                (size_t)job->integrator->values_per_sample;
  if (need > band->values_cap) {
    free(band->values);
    band->values = malloc(need * sizeof *band->values);
    band->values_cap = band->values ? need : 0;
    if (!band->values)
      return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "sample values (%zu floats)", need);
  }
  batch->pixels = px;
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = band->values;
  CLR_CHECK(job->host_samples ? clr_sampler_generate_reference(sampler, batch, &out)
                              : clr_sampler_generate(sampler, batch, &out));
  band->pixels = px;
  for (int t = first; t < first + n; ++t) {
    job->tiles[t].band = bi;
    job->tiles[t].pixels = tile_pixels(g, t);
  }
  *count = n;
  return CLR_SUCCESS;
}

static int free_band(const render_job *job) {
  for (int i = 0; i < job->nbands; ++i)
    if (!job->bands[i].in_use) return i;
  return -1;
}

/* Main thread: generates bands ahead of the workers and merges finished tiles in tile order. */
static clr_result run_pipeline(render_job *job, clr_sampler sampler, const tile_grid *g,
                               const clr_render_options *o, clr_render_stats *st) {
  clr_sample_batch batch;
  clr_sample_batch_init(&batch);
  batch.requests = job->integrator->requests;
  batch.request_count = job->integrator->request_count;
  int next_gen = 0, next_merge = 0;
  clr_result r = CLR_SUCCESS;
  double t_start = now_seconds(), t_first = 0.0;
  pthread_mutex_lock(&job->mutex);
  while (r == CLR_SUCCESS && next_merge < g->ntiles) {
    if (!job->cancelled && o->progress_callback)
      job->cancelled = o->progress_callback(o->progress_user, next_merge, g->ntiles) != 0;
    int cancelled = job->cancelled;
    int bi = free_band(job);
    if (!cancelled && next_gen < g->ntiles && bi >= 0) {
      job->bands[bi].in_use = 1;
      pthread_mutex_unlock(&job->mutex);
      int n = 0;
      double t0 = now_seconds();
      r = generate_band(job, sampler, &batch, g, next_gen, bi, &n);
      st->seconds_sample_generation += now_seconds() - t0;
      pthread_mutex_lock(&job->mutex);
      if (r != CLR_SUCCESS) {
        job->bands[bi].in_use = 0;
        break;
      }
      job->bands[bi].unfinished = n;
      for (int t = next_gen; t < next_gen + n; ++t) job->tiles[t].state = TILE_READY;
      next_gen += n;
      job->ready_end = next_gen;
      pthread_cond_broadcast(&job->cond);
      continue;
    }
    tile_info *m = &job->tiles[next_merge];
    if (m->state != TILE_DONE) {
      if (next_merge >= next_gen) break; /* cancelled with nothing in flight */
      pthread_cond_wait(&job->cond, &job->mutex);
      continue;
    }
    pthread_mutex_unlock(&job->mutex);
    r = m->result;
    if (r == CLR_SUCCESS) {
      double t0 = now_seconds();
      r = film_merge_tile(job->film, m->film_tile);
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

/* Runs the tile pipeline; *partial set when cancelled. */
static clr_result render_tiles(render_job *job, clr_sampler sampler, const clr_render_options *o,
                               int nthreads, clr_render_stats *st) {
  tile_grid g;
  (void)sampler;
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
  if (!job->tiles || !job->bands || !threads) {
    free(job->tiles);
    free(job->bands);
    free(threads);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "render tiles");
  }
  pthread_mutex_init(&job->mutex, NULL);
  pthread_cond_init(&job->cond, NULL);
  int started = 0;
  for (; started < nthreads; ++started)
    if (pthread_create(&threads[started], NULL, worker_main, job) != 0) break;
  clr_result r = started ? run_pipeline(job, sampler, &g, o, st)
                         : clr_set_last_error(CLR_ERROR_INTERNAL, "pthread_create failed");
  if (!started) job->stop = 1;
  for (int i = 0; i < started; ++i) pthread_join(threads[i], NULL);
  for (int i = 0; i < g.ntiles; ++i)
    if (job->tiles[i].film_tile) film_tile_release(job->tiles[i].film_tile);
  for (int i = 0; i < job->nbands; ++i) free(job->bands[i].values);
  if (o->progress && st->tiles_done < g.ntiles) fputc('\n', stderr);
  pthread_cond_destroy(&job->cond);
  pthread_mutex_destroy(&job->mutex);
  free(job->tiles);
  free(job->bands);
  free(threads);
  st->partial = st->tiles_done < g.ntiles;
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

clr_result clr_render_desc(const clr_scene_desc *d, const clr_render_options *opts,
                           clr_render_stats *stats, int write_files, clr_render_image *image) {
  clr_render_options defaults;
  clr_render_options_init(&defaults);
  const clr_render_options *o = opts ? opts : &defaults;
  if (o->struct_size != sizeof *o)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "clr_render_options.struct_size %zu, expected %zu", o->struct_size,
                              sizeof *o);
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
  if (write_files) {
    r = output_paths(o->outfile ? o->outfile : settings.filename, st);
    if (r == CLR_SUCCESS && st->exr_path[0]) r = film_check_output_path(st->exr_path);
    if (r == CLR_SUCCESS && st->pfm_path[0]) r = film_check_output_path(st->pfm_path);
    if (r == CLR_SUCCESS) r = film_check_output_path(st->png_path);
    if (r != CLR_SUCCESS && !o->outfile) /* the path came from the scene: say where */
      return clr_set_last_error(r, "%s:%d: Film \"filename\": %s", param_file(&d->film.params),
                                param_line(&d->film.params, "filename"), clr_last_error_message());
    if (r != CLR_SUCCESS) return r;
  }

  double t0 = now_seconds();
  clr_render_scene *scene = NULL;
  CLR_CHECK(clr_render_scene_build(d, warn, wu, &scene));
  clr_integrator integ;
  r = clr_integrator_create_for(d, scene, sdesc.type, warn, wu, &integ);
  if (r != CLR_SUCCESS) {
    clr_render_scene_free(scene);
    return r;
  }
  if (!o->quiet) clr_scene_desc_report_unused(d, warn, wu);
  st->seconds_build = now_seconds() - t0;

  clr_context ctx = NULL;
  clr_sampler sampler = NULL;
  clr_film film = NULL;
  clr_context_desc cdesc;
  clr_context_desc_init(&cdesc);
  cdesc.device = o->device;
  r = clr_context_create(&cdesc, &ctx);
  if (r == CLR_SUCCESS && o->kernels) {
    clr_kernel_shape shape;
    r = clr_kernel_shape_from_name(o->kernels, &shape);
    if (r == CLR_SUCCESS) r = clr_context_set_kernel_shape(ctx, shape);
  }
  if (r == CLR_SUCCESS) {
    clr_film_desc fd;
    clr_film_desc_init(&fd);
    fd.x_resolution = settings.x_resolution;
    fd.y_resolution = settings.y_resolution;
    memcpy(fd.crop_window, settings.crop_window, sizeof fd.crop_window);
    fd.scale = settings.scale;
    fd.max_sample_luminance = settings.max_sample_luminance;
    fd.filter = fdesc;
    r = film_create(ctx, &fd, &film);
  }
  if (r == CLR_SUCCESS) {
    sdesc.film.x_resolution = settings.x_resolution;
    sdesc.film.y_resolution = settings.y_resolution;
    memcpy(sdesc.film.crop_window, settings.crop_window, sizeof sdesc.film.crop_window);
    sdesc.film.filter_radius[0] = fdesc.radius[0];
    sdesc.film.filter_radius[1] = fdesc.radius[1];
    r = clr_sampler_create(ctx, &sdesc, &sampler);
  }
  if (r == CLR_SUCCESS) warn_spp_rounding(d, o, &sdesc, clr_sampler_spp(sampler), warn, wu);
  if (r == CLR_SUCCESS)
    r = clr_render_scene_set_film(scene, settings.x_resolution, settings.y_resolution);
  int nthreads = o->nthreads > 0 ? o->nthreads : default_threads();
  if (r == CLR_SUCCESS) {
    render_job job;
    memset(&job, 0, sizeof job);
    job.scene = scene;
    job.integrator = &integ;
    job.film = film;
    job.spp = clr_sampler_spp(sampler);
    job.seed = o->seed;
    job.host_samples = o->reference_samples != 0;
    job.region = render_region(sampler, &sdesc);
    st->spp = job.spp;
    st->threads = nthreads;
    snprintf(st->sampler, sizeof st->sampler, "%s", clr_sampler_type_name(sdesc.type));
    snprintf(st->integrator, sizeof st->integrator, "%s",
             integ.type == CLR_INTEGRATOR_AO       ? "ambientocclusion"
             : integ.type == CLR_INTEGRATOR_DIRECT ? "directlighting"
                                                   : "path");
    double tr = now_seconds();
    r = render_tiles(&job, sampler, o, nthreads, st);
    st->seconds_render = now_seconds() - tr;
    st->seconds_tracing = job.trace_s;
    st->seconds_shading = job.shade_s;
    st->seconds_reconstruction = job.recon_s;
    st->rays = job.rays;
  }
  clr_render_image im;
  memset(&im, 0, sizeof im);
  if (r == CLR_SUCCESS) {
    im.full_width = settings.x_resolution;
    im.full_height = settings.y_resolution;
    im.pixel_bounds = film_pixel_bounds(film);
    im.width = im.pixel_bounds.x1 - im.pixel_bounds.x0;
    im.height = im.pixel_bounds.y1 - im.pixel_bounds.y0;
    im.rgb = malloc((size_t)im.width * (size_t)im.height * 3 * sizeof(float));
    r = im.rgb ? film_get_rgb(film, im.rgb, 1.0f)
               : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "image");
    st->samples = film_sample_count(film);
    st->dropped_samples = film_dropped_samples(film);
  }
  if (r == CLR_SUCCESS && write_files) {
    double tw = now_seconds();
    clr_film_write_options wo;
    clr_film_write_options_init(&wo);
    wo.sampler = st->sampler;
    wo.spp = st->spp;
    wo.render_time_s = st->seconds_render;
    wo.partial = st->partial;
    const char *keys[1] = {"integrator"}, *vals[1] = {st->integrator};
    wo.metadata_keys = keys;
    wo.metadata_values = vals;
    wo.metadata_count = 1;
    if (st->exr_path[0]) r = film_write(film, st->exr_path, &wo);
    if (r == CLR_SUCCESS && st->pfm_path[0])
      r = clr_write_pfm(st->pfm_path, im.rgb, im.width, im.height);
    if (r == CLR_SUCCESS) r = film_write_png(film, st->png_path, 1.0f);
    st->seconds_output = now_seconds() - tw;
  }
  if (r == CLR_SUCCESS && image)
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
  clr_result r = clr_render_desc(desc, opts, stats, 1, NULL);
  if (stats) stats->seconds_total += parse;
  clr_scene_desc_free(desc);
  return r;
}

int clr_render_stats_json(const clr_render_stats *s, char *buf, size_t size) {
  return snprintf(buf, size,
                  "{\"seconds\":{\"total\":%.6f,\"parse\":%.6f,\"build\":%.6f,\"render\":%.6f,"
                  "\"sample_generation\":%.6f,\"tracing\":%.6f,\"shading\":%.6f,"
                  "\"reconstruction\":%.6f,\"merge\":%.6f,\"output\":%.6f},"
                  "\"rays\":%llu,\"samples\":%llu,\"dropped_samples\":%llu,\"tiles\":%d,"
                  "\"tiles_total\":%d,\"threads\":%d,\"spp\":%d,\"sampler\":\"%s\","
                  "\"integrator\":\"%s\",\"partial\":%d}",
                  s->seconds_total, s->seconds_parse, s->seconds_build, s->seconds_render,
                  s->seconds_sample_generation, s->seconds_tracing, s->seconds_shading,
                  s->seconds_reconstruction, s->seconds_merge, s->seconds_output,
                  (unsigned long long)s->rays, (unsigned long long)s->samples,
                  (unsigned long long)s->dropped_samples, s->tiles_done, s->tiles_total, s->threads,
                  s->spp, s->sampler, s->integrator, s->partial);
}
