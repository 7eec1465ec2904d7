/* TEMPORARY (renderer branch): minimal Embree 3 tracer behind tracer.h until the real one lands. */
#include <embree3/rtcore.h>
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "tracer.h"

#define STUB_MAX_GROUPS 4096
#define STUB_MAX_TOP 1048576

struct clr_tracer_t {
  RTCDevice device;
  RTCScene groups[STUB_MAX_GROUPS];
  int group_count;
  /* per geometry id of the world scene: user id, and whether it instances a group (1) */
  uint32_t *top_user;
  uint16_t *top_group; /* group instanced by a top geometry, 0 if none */
  uint32_t top_capacity;
  uint32_t *group_user[STUB_MAX_GROUPS];
  uint32_t group_user_cap[STUB_MAX_GROUPS];
};

static clr_result record(uint32_t **users, uint32_t *cap, uint32_t id, uint32_t user) {
  if (id >= *cap) {
    uint32_t n = *cap ? *cap * 2 : 64;
    while (n <= id) n *= 2;
    uint32_t *u = realloc(*users, n * sizeof *u);
    if (!u) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "tracer stub");
    *users = u;
    *cap = n;
  }
  (*users)[id] = user;
  return CLR_SUCCESS;
}

clr_result clr_tracer_create(clr_tracer *out) {
  clr_tracer t = calloc(1, sizeof *t);
  if (!t) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "tracer stub");
  t->device = rtcNewDevice(NULL);
  if (!t->device) { free(t); return clr_fail(NULL, CLR_ERROR_EMBREE, "rtcNewDevice failed"); }
  t->groups[0] = rtcNewScene(t->device);
  t->group_count = 1;
  t->top_group = calloc(STUB_MAX_TOP, sizeof *t->top_group);
  *out = t;
  return CLR_SUCCESS;
}

void clr_tracer_release(clr_tracer t) {
  if (!t) return;
  for (int i = 0; i < t->group_count; ++i) {
    rtcReleaseScene(t->groups[i]);
    free(t->group_user[i]);
  }
  free(t->top_user);
  free(t->top_group);
  rtcReleaseDevice(t->device);
  free(t);
}

clr_result clr_tracer_new_group(clr_tracer t, uint32_t *group) {
  if (t->group_count >= STUB_MAX_GROUPS) return clr_fail(NULL, CLR_ERROR_SCENE, "too many groups");
  t->groups[t->group_count] = rtcNewScene(t->device);
  *group = (uint32_t)t->group_count++;
  return CLR_SUCCESS;
}

static clr_result attach(clr_tracer t, uint32_t group, RTCGeometry g, uint32_t user,
                         uint32_t is_group, uint32_t *geom_id) {
  rtcCommitGeometry(g);
  uint32_t id = rtcAttachGeometry(t->groups[group], g);
  rtcReleaseGeometry(g);
  if (geom_id) *geom_id = id;
  if (group == 0) {
    if (id >= STUB_MAX_TOP) return clr_fail(NULL, CLR_ERROR_SCENE, "too many geometries");
    t->top_group[id] = (uint16_t)is_group;
    return record(&t->top_user, &t->top_capacity, id, user);
  }
  return record(&t->group_user[group], &t->group_user_cap[group], id, user);
}

clr_result clr_tracer_add_mesh(clr_tracer t, uint32_t group, const clr_mesh *mesh, uint32_t user_id,
                               uint32_t *geom_id) {
  RTCGeometry g = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                     3 * sizeof(float), (size_t)mesh->vertex_count);
  uint32_t *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                         3 * sizeof(uint32_t), (size_t)mesh->triangle_count);
  if (!v || !ix) { rtcReleaseGeometry(g); return clr_fail(NULL, CLR_ERROR_EMBREE, "buffers"); }
  memcpy(v, mesh->p, 3 * sizeof(float) * (size_t)mesh->vertex_count);
  memcpy(ix, mesh->indices, 3 * sizeof(uint32_t) * (size_t)mesh->triangle_count);
  return attach(t, group, g, user_id, 0, geom_id);
}

static void to_embree_xfm(const float m[16], float out[12]) {
  /* RTC_FORMAT_FLOAT3X4_ROW_MAJOR */
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out[r * 4 + c] = m[r * 4 + c];
}

clr_result clr_tracer_add_sphere(clr_tracer t, uint32_t group, const float object_to_group[16],
                                 float radius, uint32_t user_id, uint32_t *geom_id) {
  if (group != 0) return clr_fail(NULL, CLR_ERROR_SCENE, "tracer stub: sphere inside an object");
  RTCScene child = rtcNewScene(t->device);
  RTCGeometry s = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  float *pt = rtcSetNewGeometryBuffer(s, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                      4 * sizeof(float), 1);
  pt[0] = pt[1] = pt[2] = 0.0f;
  pt[3] = radius;
  rtcCommitGeometry(s);
  rtcAttachGeometry(child, s);
  rtcReleaseGeometry(s);
  rtcCommitScene(child);
  RTCGeometry inst = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(inst, child);
  rtcReleaseScene(child);
  float x[12];
  to_embree_xfm(object_to_group, x);
  rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, x);
  return attach(t, group, inst, user_id, 0, geom_id);
}

clr_result clr_tracer_add_instance(clr_tracer t, uint32_t group, const float instance_to_world[16],
                                   uint32_t user_id) {
  rtcCommitScene(t->groups[group]);
  RTCGeometry inst = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(inst, t->groups[group]);
  float x[12];
  to_embree_xfm(instance_to_world, x);
  rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, x);
  return attach(t, 0, inst, user_id, group, NULL);
}

clr_result clr_tracer_commit(clr_tracer t) {
  for (int i = 1; i < t->group_count; ++i) rtcCommitScene(t->groups[i]);
  rtcCommitScene(t->groups[0]);
  if (rtcGetDeviceError(t->device) != RTC_ERROR_NONE)
    return clr_fail(NULL, CLR_ERROR_EMBREE, "tracer stub: commit failed");
  return CLR_SUCCESS;
}

static void set_rayhit(struct RTCRayHit16 *rh, int k, const clr_ray *r) {
  rh->ray.org_x[k] = r->ox; rh->ray.org_y[k] = r->oy; rh->ray.org_z[k] = r->oz;
  rh->ray.dir_x[k] = r->dx; rh->ray.dir_y[k] = r->dy; rh->ray.dir_z[k] = r->dz;
  rh->ray.tnear[k] = r->tnear; rh->ray.tfar[k] = r->tfar;
  rh->ray.time[k] = 0; rh->ray.mask[k] = 0xffffffffu; rh->ray.id[k] = 0; rh->ray.flags[k] = 0;
  rh->hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
  rh->hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

void clr_tracer_intersect(clr_tracer t, const clr_ray *rays, clr_hit *hits, size_t count) {
  struct RTCIntersectContext ctx;
  for (size_t b = 0; b < count; b += 16) {
    int n = (int)(count - b < 16 ? count - b : 16);
    struct RTCRayHit16 rh __attribute__((aligned(64)));
    int valid[16] __attribute__((aligned(64)));
    for (int k = 0; k < 16; ++k) {
      valid[k] = k < n ? -1 : 0;
      set_rayhit(&rh, k, &rays[b + (k < n ? k : 0)]);
    }
    rtcInitIntersectContext(&ctx);
    rtcIntersect16(valid, t->groups[0], &ctx, &rh);
    for (int k = 0; k < n; ++k) {
      clr_hit *h = &hits[b + k];
      h->geom_id = rh.hit.geomID[k];
      h->inst_id = CLR_TRACER_INVALID_ID;
      h->user_id = CLR_TRACER_INVALID_ID;
      if (h->geom_id == RTC_INVALID_GEOMETRY_ID) continue;
      h->t = rh.ray.tfar[k];
      h->ng[0] = rh.hit.Ng_x[k]; h->ng[1] = rh.hit.Ng_y[k]; h->ng[2] = rh.hit.Ng_z[k];
      h->u = rh.hit.u[k]; h->v = rh.hit.v[k];
      h->prim_id = rh.hit.primID[k];
      uint32_t inst = rh.hit.instID[0][k];
      if (inst == RTC_INVALID_GEOMETRY_ID) {
        h->user_id = t->top_user[h->geom_id];
      } else if (t->top_group[inst]) {
        h->inst_id = t->top_user[inst];
        h->user_id = t->group_user[t->top_group[inst]][h->geom_id];
      } else {
        h->user_id = t->top_user[inst];
        h->geom_id = inst;
      }
    }
  }
}

void clr_tracer_occluded(clr_tracer t, const clr_ray *rays, uint8_t *occluded, size_t count) {
  struct RTCIntersectContext ctx;
  for (size_t b = 0; b < count; b += 16) {
    int n = (int)(count - b < 16 ? count - b : 16);
    struct RTCRay16 r __attribute__((aligned(64)));
    int valid[16] __attribute__((aligned(64)));
    for (int k = 0; k < 16; ++k) {
      const clr_ray *x = &rays[b + (k < n ? k : 0)];
      valid[k] = k < n ? -1 : 0;
      r.org_x[k] = x->ox; r.org_y[k] = x->oy; r.org_z[k] = x->oz;
      r.dir_x[k] = x->dx; r.dir_y[k] = x->dy; r.dir_z[k] = x->dz;
      r.tnear[k] = x->tnear; r.tfar[k] = x->tfar;
      r.time[k] = 0; r.mask[k] = 0xffffffffu; r.id[k] = 0; r.flags[k] = 0;
    }
    rtcInitIntersectContext(&ctx);
    rtcOccluded16(valid, t->groups[0], &ctx, &r);
    for (int k = 0; k < n; ++k) occluded[b + k] = r.tfar[k] < 0.0f;
  }
}
