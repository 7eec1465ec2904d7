/* TEMPORARY (renderer branch): the Embree tracer contract announced by the lead, until the
 * tracer module lands in main. Assumptions made here: group 0 is the world; hit.user_id is the
 * geometry's user_id, hit.inst_id the user_id of the instance it was reached through
 * (0xffffffff when none). */
#ifndef CLR_TRACER_H
#define CLR_TRACER_H

#include <stddef.h>
#include <stdint.h>
#include "clrender/result.h"
#include "mesh.h"

typedef struct clr_tracer_t *clr_tracer;

typedef struct clr_ray {
  float ox, oy, oz, tnear;
  float dx, dy, dz, tfar;
} clr_ray;

typedef struct clr_hit {
  float t;
  float ng[3];
  float u, v;
  uint32_t prim_id, geom_id, inst_id, user_id;
} clr_hit;

#define CLR_TRACER_INVALID_ID 0xffffffffu

clr_result clr_tracer_create(clr_tracer *out);
void clr_tracer_release(clr_tracer tracer);
clr_result clr_tracer_new_group(clr_tracer tracer, uint32_t *group);
clr_result clr_tracer_add_mesh(clr_tracer tracer, uint32_t group, const clr_mesh *mesh,
                               uint32_t user_id, uint32_t *geom_id);
clr_result clr_tracer_add_sphere(clr_tracer tracer, uint32_t group, const float object_to_group[16],
                                 float radius, uint32_t user_id, uint32_t *geom_id);
clr_result clr_tracer_add_instance(clr_tracer tracer, uint32_t group,
                                   const float instance_to_world[16], uint32_t user_id);
clr_result clr_tracer_commit(clr_tracer tracer);
void clr_tracer_intersect(clr_tracer tracer, const clr_ray *rays, clr_hit *hits, size_t count);
void clr_tracer_occluded(clr_tracer tracer, const clr_ray *rays, uint8_t *occluded, size_t count);

#endif
