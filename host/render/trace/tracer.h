/* Host ray tracing with Embree 3: triangle meshes, exact spheres and one level of instancing. */
#ifndef CLR_TRACER_H
#define CLR_TRACER_H

#include <stdint.h>
#include "clrender/result.h"
#include "mesh.h"
#include "quadrics.h"

/* A scene being built (before clr_tracer_commit) or a static, queryable scene (after it).
 * Geometry goes into groups: group 0 is the world; every other group is an object definition
 * (pbrt ObjectBegin/ObjectEnd) that appears in the world only through instances.
 * Building calls are single-threaded; after commit, clr_tracer_intersect*, clr_tracer_occluded
 * and clr_tracer_mesh_interpolate may run concurrently from any number of threads. */
typedef struct clr_tracer_t *clr_tracer;

/* Value of geom_id/inst_id/prim_id/user_id meaning "none" (Embree's RTC_INVALID_GEOMETRY_ID). */
#define CLR_TRACER_INVALID_ID 0xffffffffu

/* A ray segment o + t d, t in [tnear, tfar]. Origins and directions must be finite, d non-zero,
 * tnear finite and >= 0, tfar not NaN (may be +INFINITY; tfar < tnear simply misses). */
typedef struct clr_ray {
  float ox, oy, oz, tnear, dx, dy, dz, tfar;
  float time; /* motion time in [0, 1] (0: start transform); only moving instances use it */
} clr_ray;

/* The closest hit of a ray. On a miss geom_id, prim_id, inst_id and user_id are
 * CLR_TRACER_INVALID_ID, t is +INFINITY and the other fields are 0. */
typedef struct clr_hit {
  float t;
  float ng[3]; /* world-space geometric normal, not normalised; triangles: (p1-p0) x (p2-p0),
                 * spheres: pointing outwards */
  float u, v;  /* triangles: Embree barycentrics (weights of vertices 1 and 2); spheres: pbrt-v3's
                 * (phi / 2pi, (theta - pi) / (0 - pi)) */
  uint32_t prim_id; /* triangle index in its mesh (0 for spheres) */
  uint32_t geom_id; /* id returned by clr_tracer_add_mesh/add_sphere, within its group */
  uint32_t inst_id; /* world id of the instance the hit lies in, CLR_TRACER_INVALID_ID if none */
  uint32_t user_id; /* user_id given when the hit mesh or sphere was added */
  float time;       /* the ray's time (a moving instance's hit is placed at it) */
} clr_hit;

/* Creates an empty tracer (an Embree device and the world group). Embree errors are recorded by
 * an error callback and reported as CLR_ERROR_EMBREE naming the failing call. */
clr_result clr_tracer_create(clr_tracer *out);
/* Releases the tracer and everything in it; NULL is fine. */
void clr_tracer_release(clr_tracer tracer);

/* Creates a new, empty object-definition group; its id (>= 1) goes to *group_id. */
clr_result clr_tracer_new_group(clr_tracer tracer, int32_t *group_id);

/* Adds a triangle mesh given in the group's space (world space for group 0). The tracer copies
 * the arrays it needs, so the mesh may be freed right after the call. The mesh must pass
 * clr_mesh_validate and have at least one triangle (CLR_ERROR_SCENE otherwise). *geom_id
 * (may be NULL) receives the mesh's id within the group. */
clr_result clr_tracer_add_mesh(clr_tracer tracer, int32_t group, const clr_mesh *mesh,
                               uint32_t user_id, uint32_t *geom_id);

/* Whether the spheres added from now on give their hits (u, v) (the default, 1). With 0 their
 * hits carry u = v = 0 and skip the atan2 and acos (the t, normal and the partial spheres' clipping
 * are unchanged): for callers that never read a sphere hit's (u, v) (clr_tracer_mesh_interpolate
 * does). */
clr_result clr_tracer_set_sphere_uv(clr_tracer tracer, int with_uv);

/* Adds pbrt-v3's full sphere of `radius` around the origin of object space, placed in the group
 * by the row-major affine 4x4 `object_to_group` (any invertible affine map: scaled, rotated,
 * sheared; bottom row must be 0 0 0 1). Intersected exactly (double-precision quadratic in
 * object space). *geom_id (may be NULL) receives the sphere's id within the group. */
clr_result clr_tracer_add_sphere(clr_tracer tracer, int32_t group, const float object_to_group[16],
                                 float radius, uint32_t user_id, uint32_t *geom_id);

/* A pbrt-v3 partial sphere: z clipped to [zmin, zmax] (object space, clamped to the radius),
 * phi to [0, phimax degrees]; a clipped nearer hit lets the farther one count. Hits of a partial
 * sphere have pbrt-v3's u = phi / phimax, v = (theta - theta(zmin)) / (theta(zmax) - theta(zmin)). */
clr_result clr_tracer_add_partial_sphere(clr_tracer tracer, int32_t group,
                                         const float object_to_group[16], float radius, float zmin,
                                         float zmax, float phimax_deg, uint32_t user_id,
                                         uint32_t *geom_id);

/* Adds pbrt-v3's disk (z = height in object space, innerradius <= r <= radius, phi <= phimax
 * degrees) as exact user geometry; hits: u = phi / phimax, v = (radius - r) / (radius -
 * innerradius), ng the object z axis mapped as a normal. */
clr_result clr_tracer_add_disk(clr_tracer tracer, int32_t group, const float object_to_group[16],
                               float height, float radius, float inner_radius, float phimax_deg,
                               uint32_t user_id, uint32_t *geom_id);

/* Adds one of pbrt-v3's quadrics (quadrics.h: cylinder, cone, paraboloid, hyperboloid) as exact
 * user geometry; hits: pbrt-v3's (u, v), ng = dpdu x dpdv mapped as a normal. Parameters that
 * describe no surface are an error naming the problem. */
clr_result clr_tracer_add_quadric(clr_tracer tracer, int32_t group, const float object_to_group[16],
                                  const clr_quadric *quadric, uint32_t user_id, uint32_t *geom_id);

/* Places group `group` (>= 1) into the world with the row-major affine 4x4 `instance_to_world`.
 * Instances and world geometry share the world's id sequence: the n-th mesh, sphere or instance
 * added to group 0 gets id n (from 0); hits inside this instance report that id as inst_id. */
clr_result clr_tracer_add_instance(clr_tracer tracer, int32_t group,
                                   const float instance_to_world[16], uint32_t user_id);

/* Places group `group` (>= 1) into the world moving over the ray time [0, 1]: at time k
 * (0 or 1) its instance-to-world is T(translation[k]) R(rotation[k], a unit quaternion x y z w)
 * S(scale[k], diagonal); in between Embree lerps T and S and slerps R (pbrt-v3's
 * AnimatedTransform for a diagonal S). Ids as clr_tracer_add_instance. */
clr_result clr_tracer_add_motion_instance(clr_tracer tracer, int32_t group,
                                          const float translation[2][3], const float rotation[2][4],
                                          const float scale[2][3], uint32_t user_id);

/* Instance-to-world (row-major 4x4) of the instance with world id inst_id at ray time `time`. */
clr_result clr_tracer_instance_transform(clr_tracer tracer, uint32_t inst_id, float time,
                                         float out[16]);

/* Group and user_id of the instance with world id inst_id (either output may be NULL). */
clr_result clr_tracer_instance_info(clr_tracer tracer, uint32_t inst_id, int32_t *group,
                                    uint32_t *user_id);

/* Builds the acceleration structures (high build quality, static). Afterwards nothing more can
 * be added and the scene can be queried. Committing twice is an error. */
clr_result clr_tracer_commit(clr_tracer tracer);

/* Closest hits of `count` rays, traced as packets of clr_tracer_packet_width rays
 * (rtcIntersect8 or rtcIntersect16). */
clr_result clr_tracer_intersect(clr_tracer tracer, const clr_ray *rays, clr_hit *hits,
                                int32_t count);
/* Rays per packet: 16 where Embree traces 16-wide packets natively (AVX-512), else 8 where it
 * traces 8-wide ones natively (AVX, AVX2), else 16. */
int clr_tracer_packet_width(clr_tracer tracer);
/* Same results traced one ray at a time (rtcIntersect1); for comparison and benchmarks. */
clr_result clr_tracer_intersect_single(clr_tracer tracer, const clr_ray *rays, clr_hit *hits,
                                       int32_t count);
/* occluded[i] = 1 when anything lies on ray i within [tnear, tfar], else 0 (rtcOccluded8 or
 * rtcOccluded16; calls of more than 512 rays in a scene without quadrics go through Embree's
 * ray stream, rtcOccluded1M). */
clr_result clr_tracer_occluded(clr_tracer tracer, const clr_ray *rays, uint8_t *occluded,
                               int32_t count);

/* Surface data at a hit from clr_tracer_intersect, all in world space (outputs may be NULL):
 * p the hit point; n_shading the unit shading normal (triangles: interpolated vertex normals
 * when the mesh has them, else the geometric normal; spheres: the outward normal); uv the
 * interpolated vertex uvs, or pbrt-v3's default (0,0),(1,0),(1,1) per-triangle
 * parameterisation when the mesh has none; for spheres the hit's (u, v). A miss or a hit that
 * does not belong to this tracer gives CLR_ERROR_INVALID_ARGUMENT. */
clr_result clr_tracer_mesh_interpolate(clr_tracer tracer, const clr_hit *hit, float p[3],
                                       float n_shading[3], float uv[2]);

#endif
