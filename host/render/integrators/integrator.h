/* pbrt-v3 integrators (ambientocclusion, directlighting, path) for matte scenes, evaluated
 * wavefront-style over a chunk of camera samples with batched Embree queries. */
#ifndef CLR_INTEGRATOR_H
#define CLR_INTEGRATOR_H

#include <stdint.h>
#include "clrender/sampler.h"
#include "render_scene.h"

typedef enum { CLR_INTEGRATOR_AO, CLR_INTEGRATOR_DIRECT, CLR_INTEGRATOR_PATH } clr_integrator_type;

/* Values per path bounce in the layout: 1D light choice, 2D light, 2D scattering, 2D BSDF, 1D
 * Russian roulette (pbrt-v3 PathIntegrator::Li order); bounces 0 to 3 have no roulette value,
 * as pbrt-v3 draws it only past bounce 3 (7 values each). */
#define CLR_PATH_VALUES_PER_BOUNCE 8

typedef struct clr_integrator {
  clr_integrator_type type;
  int ao_samples, ao_cos_sample;
  int direct_all; /* directlighting strategy "all" (1) or "one" (0) */
  int max_depth;
  float rr_threshold;
  int light_count;
  float *light_cdf; /* light_count + 1 entries: light selection for path (uniform or power) */
  struct clr_light_distribution *light_spatial; /* "spatial" (pbrt-v3's default), or NULL */
  /* direct and path: how light_wave.h samples each light (clr_wave_light_kind), and its
   * triangle or point; all NULL when it samples none */
  uint8_t *light_wave_kind;
  clr_light_triangle *light_triangles;
  clr_light_point *light_points;
  int *light_samples; /* directlighting "all": pbrt nsamples per light */
  int *light_offsets; /* directlighting "all": value offset of light j's two arrays or -1 */
  int camera_offset;  /* the camera's film offset: 0, or 1 after pbrt-v4's wavelength Get1D */
  /* the camera's time and lens values, or -1 where the scene's rays never read them (their
   * requests are skipped: clr_render_scene_camera_reads) */
  int time_offset, lens_offset;
  int value_offset; /* first integrator value (after the camera's values) */
  int path_bounces_in_layout;
  clr_sample_request requests[CLR_MAX_REQUESTS];
  int32_t request_count;
  int32_t values_per_sample; /* values stored per sample (skipped requests have none) */
  int32_t layout_values;     /* values of every request, skipped or not */
} clr_integrator;

/* Reads desc->integrator; unknown types warn and render as "path". */
clr_result clr_integrator_create(const clr_scene_desc *desc, const clr_render_scene *scene,
                                 clr_warn_fn warn, void *warn_user, clr_integrator *out);
/* The same for a given sampler: array sizes (ambientocclusion nsamples, directlighting light
 * nsamples) rounded with its RoundCount as pbrt-v3's integrators do (02sequence, maxmindist:
 * up to a power of two, with AOIntegrator's warning). clr_integrator_create: no rounding. */
clr_result clr_integrator_create_for(const clr_scene_desc *desc, const clr_render_scene *scene,
                                     clr_sampler_type sampler, clr_warn_fn warn, void *warn_user,
                                     clr_integrator *out);
/* The same with pbrt-v4's camera layout when pbrt_v4_camera: a 1D value (pbrt-v4's wavelength
 * sample, unused by these RGB integrators) before the film offset, time and lens. */
clr_result clr_integrator_create_layout(const clr_scene_desc *desc, const clr_render_scene *scene,
                                        clr_sampler_type sampler, int pbrt_v4_camera,
                                        clr_warn_fn warn, void *warn_user, clr_integrator *out);
void clr_integrator_free(clr_integrator *integrator);

/* Path bounces whose vertices clr_integrator_counters counts one by one (the last entry counts
 * every deeper bounce). */
#define CLR_COUNTED_BOUNCES 16

typedef struct clr_integrator_counters {
  uint64_t rays;        /* every ray given to the tracer (camera, shadow, bounce) */
  double trace_seconds; /* time inside tracer calls */
  clr_result error;     /* first failing tracer call, CLR_SUCCESS when none */
  /* path: camera samples, and the vertices per bounce that draw the bounce's sample values */
  uint64_t samples, bounce_vertices[CLR_COUNTED_BOUNCES];
} clr_integrator_counters;

typedef struct clr_integrator_scratch clr_integrator_scratch;
clr_integrator_scratch *clr_integrator_scratch_create(void);
void clr_integrator_scratch_free(clr_integrator_scratch *scratch);

/* Fills out[j * value_count + k] with value first_value + k of the layout of sample samples[j]
 * (an index into the clr_integrator_li call's samples). */
typedef clr_result (*clr_fetch_values_fn)(void *user, const int32_t *samples, int32_t n,
                                          int32_t first_value, int32_t value_count, float *out);

/* The sample values clr_integrator_li reads: `count` vectors of `stride` floats, each the
 * layout's first `stride` values. The whole layout (stride == values_per_sample), or for path
 * the camera's and the first path_bounces bounces' values, `fetch` giving a deeper bounce's
 * values for the paths that reach it (clr_integrator_path_prefix). */
typedef struct clr_integrator_values {
  const float *values;
  int32_t stride;
  int32_t path_bounces; /* bounces held in the vectors (path_bounces_in_layout when whole) */
  clr_fetch_values_fn fetch;
  void *fetch_user;
} clr_integrator_values;

/* The whole layout's vectors. */
clr_integrator_values clr_integrator_values_whole(const clr_integrator *it, const float *values);

/* Path only: the requests and values of the layout's prefix holding the camera's values and
 * those of the first `bounces` bounces (at most path_bounces_in_layout); 0 for the other
 * integrators. */
int32_t clr_integrator_path_prefix(const clr_integrator *it, int32_t bounces, int32_t *values);

/* Radiance of `count` camera rays. diffs: their differentials (may be NULL), used at their
 * first hits as pbrt-v3 does; values: their sample vectors; keys: per-sample hash keys for
 * dimensions past the layout; L: 3 floats per sample. */
clr_result clr_integrator_li(const clr_integrator *it, const clr_render_scene *scene,
                             clr_integrator_scratch *scratch, const clr_ray *rays,
                             const clr_ray_differential *diffs, const clr_integrator_values *values,
                             const uint64_t *keys, int count, float *L,
                             clr_integrator_counters *counters);

#endif
