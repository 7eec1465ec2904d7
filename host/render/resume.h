/* Resuming a render from the EXR it wrote: what identifies the render in the header, and the
 * checks that refuse an image of another render. */
#ifndef CLR_RESUME_H
#define CLR_RESUME_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/result.h"

/* The header attributes a render records to be resumed (film_write metadata, besides the film
 * geometry, clrender.sampler and clrender.spp that film_write records itself). */
typedef struct clr_resume_identity {
  const char *sampler;       /* sampler name */
  const char *integrator;    /* integrator name */
  const char *scene;         /* scene id (content hash) */
  char seed[16];             /* the seed as text */
  const char *seeding;       /* "pixel", "pbrt-v3" or "pbrt-v4" */
  const char *randomization; /* the sampler's randomization name ("default" unless given) */
  int32_t spp_target;        /* the sampler's total spp: pixel samplers' patterns depend on it */
  int32_t global_sampler;    /* 1: halton or sobol, whose samples do not depend on the total */
  char layout[48];           /* the sample vector's layout: camera offset, values per sample */
} clr_resume_identity;

#define CLR_RESUME_VALUE 128

/* The attribute names film_merge_file returns for clr_resume_check, in order. */
extern const char *const clr_resume_attributes[];
extern const int32_t clr_resume_attribute_count;

/* FNV-1a 64 of the scene file's bytes as 16 hex digits into out[17]. */
clr_result clr_scene_file_hash(const char *path, char out[17]);

/* Checks the values of clr_resume_attributes read from `path` against this render; *spp_done:
 * the samples per pixel the image holds. Refuses (naming the attribute, both values and why) an
 * image of another scene, sampler, integrator, seed, seeding or sample layout, a partial image that does not
 * hold whole passes, one with as many or more spp than asked, and a pixel sampler resumed to
 * another total spp than it was started with. */
clr_result clr_resume_check(const char *path, const char *values, const clr_resume_identity *now,
                            int32_t *spp_done);

#endif
