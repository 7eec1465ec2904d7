/* Host ray tracing with Embree 3: triangle meshes, exact spheres (user geometry), instances. */
#include "tracer.h"

#include <math.h>
#include <pthread.h>
#include <stdalign.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <embree3/rtcore.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "render_error.h"

#define PI_D 3.14159265358979323846

/* Always inlined: each packet width gets its own constant-width loops, and the sphere's lane
 * pairs their registers. */
#define PACKET_INLINE static inline __attribute__((always_inline))

/* An affine map as the top 3 rows of a row-major 4x4 matrix, with its inverse. */
typedef struct affine {
  double m[12], inv[12];
} affine;

typedef struct tracer_mesh { /* the tracer's own copy; p has one padding float for Embree */
  int32_t vertex_count, triangle_count;
  float *p, *n, *uv;
  uint32_t *indices;
} tracer_mesh;

typedef struct sphere_shape { /* Embree's user data for one sphere: a stable heap address */
  affine object_to_group;
  double radius;
  int partial; /* pbrt-v3 zmin/zmax/phimax clip the sphere */
  int uv;      /* hits carry (u, v) (else 0, 0: no atan2 and acos for them) */
  double zmin, zmax, phimax, theta_zmin, theta_zmax;
} sphere_shape;

typedef struct
    disk_shape { /* pbrt-v3 Disk: z = height, innerradius <= r <= radius, phi <= phimax */
  affine object_to_group;
  double height, radius, inner, phimax;
} disk_shape;

typedef struct quadric_shape { /* pbrt-v3 cylinder, cone, paraboloid, hyperboloid */
  affine object_to_group;
  clr_quadric q;
} quadric_shape;

typedef enum geom_kind { GEOM_MESH, GEOM_SPHERE, GEOM_INSTANCE, GEOM_DISK, GEOM_QUADRIC } geom_kind;

typedef struct geom_record { /* indexed by Embree geometry id within its group */
  geom_kind kind;
  uint32_t user_id;
  tracer_mesh mesh;         /* GEOM_MESH */
  sphere_shape *sphere;     /* GEOM_SPHERE */
  disk_shape *disk;         /* GEOM_DISK */
  quadric_shape *quadric;   /* GEOM_QUADRIC */
  int32_t instanced_group;  /* GEOM_INSTANCE */
  affine instance_to_world; /* at time 0 when moving */
  int moving;               /* GEOM_INSTANCE with two time steps */
} geom_record;

typedef struct group {
  RTCScene scene;
  geom_record *records;
  uint32_t count, capacity;
} group;

struct clr_tracer_t {
  RTCDevice device;
  group *groups;
  int32_t group_count, group_capacity;
  int committed;
  int sphere_uv;     /* spheres added now get hits with (u, v) (clr_tracer_set_sphere_uv) */
  int packet_width;  /* rays per Embree packet: 8 or 16 (native_packet_width) */
  int user_geometry; /* a quadric was added (its callbacks run per ray in Embree's streams) */
  pthread_mutex_t error_lock; /* guards the message recorded by the error callback */
  char error_message[256];
};

/* ---- errors ---- */

static const char *embree_error_name(enum RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN:
      return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION:
      return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED:
      return "RTC_ERROR_CANCELLED";
  }
  return "unknown Embree error";
}

static void record_embree_error(void *user, enum RTCError code, const char *message) {
  struct clr_tracer_t *t = user;
  pthread_mutex_lock(&t->error_lock);
  snprintf(t->error_message, sizeof t->error_message, "%s", message ? message : "");
  pthread_mutex_unlock(&t->error_lock);
  (void)code;
}

/* Reports a pending Embree error of this thread as CLR_ERROR_EMBREE naming `call`. */
static clr_result embree_check(struct clr_tracer_t *t, const char *call) {
  enum RTCError code = rtcGetDeviceError(t->device);
  if (code == RTC_ERROR_NONE) return CLR_SUCCESS;
  char message[sizeof t->error_message];
  pthread_mutex_lock(&t->error_lock);
  memcpy(message, t->error_message, sizeof message);
  pthread_mutex_unlock(&t->error_lock);
  return clr_set_last_error(CLR_ERROR_EMBREE, "%s failed: %s (%d): %s", call,
                            embree_error_name(code), (int)code, message);
}

#define EMBREE_CHECK(t, call_name)                  \
  do {                                              \
    clr_result e_ = embree_check((t), (call_name)); \
    if (e_ != CLR_SUCCESS) return e_;               \
  } while (0)

/* ---- affine maps ---- */

/* Fills `a` from a row-major 4x4 matrix; 0 when it is not finite, not affine or singular. */
static int affine_from_matrix(const float m[16], affine *a) {
  for (int i = 0; i < 16; ++i)
    if (!isfinite(m[i])) return 0;
  if (m[12] != 0.0f || m[13] != 0.0f || m[14] != 0.0f || m[15] != 1.0f) return 0;
  for (int i = 0; i < 12; ++i) a->m[i] = m[i];
  const double *x = a->m;
  double c[9] = {x[5] * x[10] - x[6] * x[9], x[2] * x[9] - x[1] * x[10], x[1] * x[6] - x[2] * x[5],
                 x[6] * x[8] - x[4] * x[10], x[0] * x[10] - x[2] * x[8], x[2] * x[4] - x[0] * x[6],
                 x[4] * x[9] - x[5] * x[8],  x[1] * x[8] - x[0] * x[9],  x[0] * x[5] - x[1] * x[4]};
  double det = x[0] * c[0] + x[1] * c[3] + x[2] * c[6];
  if (det == 0.0 || !isfinite(det)) return 0;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) a->inv[4 * r + k] = c[3 * r + k] / det;
    a->inv[4 * r + 3] =
        -(a->inv[4 * r] * x[3] + a->inv[4 * r + 1] * x[7] + a->inv[4 * r + 2] * x[11]);
  }
  for (int i = 0; i < 12; ++i)
    if (!isfinite(a->inv[i])) return 0;
  return 1;
}

static inline void map_point(const double m[12], const double p[3], double out[3]) {
  for (int r = 0; r < 3; ++r)
    out[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
}

static inline void map_vector(const double m[12], const double v[3], double out[3]) {
  for (int r = 0; r < 3; ++r) out[r] = m[4 * r] * v[0] + m[4 * r + 1] * v[1] + m[4 * r + 2] * v[2];
}

/* Normals go through the transposed inverse. */
static void map_normal(const affine *a, const double n[3], double out[3]) {
  for (int r = 0; r < 3; ++r)
    out[r] = a->inv[r] * n[0] + a->inv[4 + r] * n[1] + a->inv[8 + r] * n[2];
}

/* ---- spheres: exact intersection in object space ---- */

typedef struct sphere_hit {
  float t, u, v;
  double ng[3]; /* group space */
} sphere_hit;

/* The hit's (u, v) at object-space point p on the surface, of azimuth phi (0, 0 without uv). */
static void sphere_uv(const sphere_shape *s, const double p[3], double phi, sphere_hit *hit) {
  if (!s->uv) {
    hit->u = hit->v = 0.0f;
    return;
  }
  double cos_theta = fmin(fmax(p[2] / s->radius, -1.0), 1.0);
  if (s->partial) {
    hit->u = (float)(phi / s->phimax);
    hit->v = (float)((acos(cos_theta) - s->theta_zmin) / (s->theta_zmax - s->theta_zmin));
  } else {
    hit->u = (float)(phi / (2.0 * PI_D));
    hit->v = (float)((acos(cos_theta) - PI_D) / (0.0 - PI_D)); /* thetaMin = pi, thetaMax = 0 */
  }
}

/* Azimuth of an object-space point in [0, 2 pi). */
static double sphere_phi(const double p[3]) {
  double phi = atan2(p[1], p[0]);
  return phi < 0.0 ? phi + 2.0 * PI_D : phi;
}

/* Smallest root of |o + t d|^2 = r^2 within [tnear, tfar]; 0 if none. hit NULL (occlusion): only
 * whether there is one, so a whole sphere answers at its first root in range (the refinement and
 * phi only clip partial spheres) and no hit's (u, v) and normal are made: the same answer. */
static int sphere_hit_test(const sphere_shape *s, const float org[3], const float dir[3],
                           float tnear, float tfar, sphere_hit *hit) {
  double og[3] = {org[0], org[1], org[2]}, dg[3] = {dir[0], dir[1], dir[2]}, o[3], d[3];
  map_point(s->object_to_group.inv, og, o);
  map_vector(s->object_to_group.inv, dg, d);
  double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  double half_b = d[0] * o[0] + d[1] * o[1] + d[2] * o[2];
  double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - s->radius * s->radius;
  double disc = half_b * half_b - a * c;
  if (!(disc >= 0.0) || a == 0.0) return 0;
  double q = -(half_b + copysign(sqrt(disc), half_b)); /* avoids cancellation */
  double t0 = q / a, t1 = q != 0.0 ? c / q : t0;
  if (t0 > t1) {
    double tmp = t0;
    t0 = t1;
    t1 = tmp;
  }
  double p[3] = {0.0, 0.0, 0.0}, phi = 0.0, t = 0.0; /* set by the root that is found */
  int found = 0;
  for (int root = 0; root < 2 && !found; ++root) {
    t = root ? t1 : t0;
    if (!((float)t >= tnear && (float)t <= tfar)) continue;
    if (!hit && !s->partial) return 1;
    for (int k = 0; k < 3; ++k) p[k] = o[k] + t * d[k];
    double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; ++k) p[k] *= s->radius / len; /* pbrt's refinement onto the surface */
    if (p[0] == 0.0 && p[1] == 0.0) p[0] = 1e-5 * s->radius;
    if (s->partial || s->uv) phi = sphere_phi(p); /* phi only clips and makes u */
    /* pbrt-v3 Sphere::Intersect: a clipped first root tries the second */
    if (s->partial && ((s->zmin > -s->radius && p[2] < s->zmin) ||
                       (s->zmax < s->radius && p[2] > s->zmax) || phi > s->phimax))
      continue;
    found = 1;
  }
  if (!found || !hit) return found;
  hit->t = (float)t;
  sphere_uv(s, p, phi, hit);
  map_normal(&s->object_to_group, p, hit->ng);
  return 1;
}

/* Offsets of the fields in Embree's SOA ray/hit packets of width N, in 4-byte words. */
enum {
  RAY_ORG = 0,
  RAY_TNEAR = 3,
  RAY_DIR = 4,
  RAY_TFAR = 8,
  HIT_NG = 12,
  HIT_U = 15,
  HIT_V = 16,
  HIT_PRIM = 17,
  HIT_GEOM = 18,
  HIT_INST = 19
};

/* World bounds of the object-space box [-r, r]^2 x [z0, z1] under `m`, padded by a relative
 * 1e-6 of its size plus `pad`. */
static void box_bounds(const double m[12], double r, double z0, double z1, double pad,
                       struct RTCBounds *b) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int corner = 0; corner < 8; ++corner) {
    double c[3] = {corner & 1 ? r : -r, corner & 2 ? r : -r, corner & 4 ? z1 : z0}, g[3];
    map_point(m, c, g);
    for (int k = 0; k < 3; ++k) {
      lo[k] = fmin(lo[k], g[k]);
      hi[k] = fmax(hi[k], g[k]);
    }
  }
  pad += 1e-6 * fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
  b->lower_x = (float)(lo[0] - pad), b->lower_y = (float)(lo[1] - pad),
  b->lower_z = (float)(lo[2] - pad);
  b->upper_x = (float)(hi[0] + pad), b->upper_y = (float)(hi[1] + pad),
  b->upper_z = (float)(hi[2] + pad);
}

/* A user geometry's ray test (spheres, disks): the closest hit within [tnear, tfar]. */
typedef int (*user_hit_test)(const void *shape, const float org[3], const float dir[3], float tnear,
                             float tfar, sphere_hit *hit);

/* Ray i's origin and direction in an Embree packet of n rays (structure of arrays). */
static inline void packet_ray(const float *f, unsigned n, unsigned i, float org[3], float dir[3]) {
  for (unsigned k = 0; k < 3; ++k) {
    org[k] = f[(RAY_ORG + k) * n + i];
    dir[k] = f[(RAY_DIR + k) * n + i];
  }
}

/* Writes a user geometry's hit into lane i of Embree's ray-hit packet. */
static inline void store_user_hit(const struct RTCIntersectFunctionNArguments *args, unsigned i,
                                  const sphere_hit *h) {
  const unsigned n = args->N;
  float *f = (float *)args->rayhit;
  unsigned *w = (unsigned *)args->rayhit;
  f[RAY_TFAR * n + i] = h->t;
  for (int k = 0; k < 3; ++k) f[(HIT_NG + k) * n + i] = (float)h->ng[k];
  f[HIT_U * n + i] = h->u;
  f[HIT_V * n + i] = h->v;
  w[HIT_PRIM * n + i] = args->primID;
  w[HIT_GEOM * n + i] = args->geomID;
  w[HIT_INST * n + i] = args->context->instID[0];
}

/* Embree's intersect callback over a packet, for any user geometry's ray test. */
static void user_intersect(const struct RTCIntersectFunctionNArguments *args, user_hit_test test) {
  const unsigned n = args->N;
  float *f = (float *)args->rayhit;
  for (unsigned i = 0; i < n; ++i) {
    if (!args->valid[i]) continue;
    float org[3], dir[3];
    packet_ray(f, n, i, org, dir);
    sphere_hit h;
    if (!test(args->geometryUserPtr, org, dir, f[RAY_TNEAR * n + i], f[RAY_TFAR * n + i], &h))
      continue;
    store_user_hit(args, i, &h);
  }
}

/* Embree's occlusion callback over a packet, for any user geometry's ray test. */
static void user_occluded(const struct RTCOccludedFunctionNArguments *args, user_hit_test test) {
  const unsigned n = args->N;
  float *f = (float *)args->ray;
  for (unsigned i = 0; i < n; ++i) {
    if (!args->valid[i]) continue;
    float org[3], dir[3];
    packet_ray(f, n, i, org, dir);
    sphere_hit h;
    if (test(args->geometryUserPtr, org, dir, f[RAY_TNEAR * n + i], f[RAY_TFAR * n + i], &h))
      f[RAY_TFAR * n + i] = -INFINITY;
  }
}

static int sphere_test(const void *shape, const float org[3], const float dir[3], float tnear,
                       float tfar, sphere_hit *hit) {
  return sphere_hit_test(shape, org, dir, tnear, tfar, hit);
}

static void sphere_bounds(const struct RTCBoundsFunctionArguments *args) {
  const sphere_shape *s = args->geometryUserPtr;
  box_bounds(s->object_to_group.m, s->radius, -s->radius, s->radius, 0.0, args->bounds_o);
}

/* sphere_test without the hit's surface figures (occlusion rays). */
static int sphere_occludes(const void *shape, const float org[3], const float dir[3], float tnear,
                           float tfar, sphere_hit *hit) {
  (void)hit;
  return sphere_hit_test(shape, org, dir, tnear, tfar, NULL);
}

#if defined(__SSE2__)
/* ---- whole spheres, two packet lanes at a time: sphere_hit_test's operations in SSE2 ---- */

static inline __m128d pd_blend(__m128d mask, __m128d yes, __m128d no) {
  return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no));
}

/* Lanes i and i + 1 of one float field of an Embree packet of n rays, as doubles. */
static inline __m128d packet_pair(const float *f, unsigned n, int field, unsigned i) {
  return _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(f + field * n + i))));
}

/* Row r of map_point (translate) or map_vector, in map_point's order of additions. */
static inline __m128d pd_map_row(const double m[12], int r, const __m128d x[3], int translate) {
  __m128d v = _mm_add_pd(_mm_mul_pd(_mm_set1_pd(m[4 * r]), x[0]),
                         _mm_mul_pd(_mm_set1_pd(m[4 * r + 1]), x[1]));
  v = _mm_add_pd(v, _mm_mul_pd(_mm_set1_pd(m[4 * r + 2]), x[2]));
  return translate ? _mm_add_pd(v, _mm_set1_pd(m[4 * r + 3])) : v;
}

static inline __m128d pd_dot(const __m128d a[3], const __m128d b[3]) {
  return _mm_add_pd(_mm_add_pd(_mm_mul_pd(a[0], b[0]), _mm_mul_pd(a[1], b[1])),
                    _mm_mul_pd(a[2], b[2]));
}

/* (float)t within [tnear, tfar], as sphere_hit_test compares. */
static inline __m128d pd_in_range(__m128d t, __m128d tnear, __m128d tfar) {
  __m128d tf = _mm_cvtps_pd(_mm_cvtpd_ps(t));
  return _mm_and_pd(_mm_cmpge_pd(tf, tnear), _mm_cmple_pd(tf, tfar));
}

/* A whole sphere's roots for lanes i, i + 1: the first root in range in `t`, and `found`. */
typedef struct sphere_pair {
  __m128d o[3], d[3], t, found;
} sphere_pair;

PACKET_INLINE void sphere_pair_roots(const sphere_shape *s, const float *f, unsigned n, unsigned i,
                                     sphere_pair *r) {
  __m128d og[3], dg[3];
  for (int k = 0; k < 3; ++k) {
    og[k] = packet_pair(f, n, RAY_ORG + k, i);
    dg[k] = packet_pair(f, n, RAY_DIR + k, i);
  }
  for (int k = 0; k < 3; ++k) {
    r->o[k] = pd_map_row(s->object_to_group.inv, k, og, 1);
    r->d[k] = pd_map_row(s->object_to_group.inv, k, dg, 0);
  }
  const __m128d zero = _mm_setzero_pd(), sign = _mm_set1_pd(-0.0);
  __m128d a = pd_dot(r->d, r->d), half_b = pd_dot(r->d, r->o);
  __m128d c = _mm_sub_pd(pd_dot(r->o, r->o), _mm_set1_pd(s->radius * s->radius));
  __m128d disc = _mm_sub_pd(_mm_mul_pd(half_b, half_b), _mm_mul_pd(a, c));
  __m128d ok = _mm_and_pd(_mm_cmpge_pd(disc, zero), _mm_cmpneq_pd(a, zero));
  /* A ray leaving from outside (c > 0, half_b > 0: AO's and shadow rays off the sphere) has two
   * negative roots, q / a <= -half_b / a and c / q <= -c / (2 half_b); both stay negative as
   * floats, below tnear >= 0 (check_rays), when half_b >= a 2^-100 and c >= half_b 2^-98 (which
   * imply half_b > 0 and c > 0, as a > 0 where ok). */
  __m128d away = _mm_and_pd(_mm_cmpge_pd(half_b, _mm_mul_pd(a, _mm_set1_pd(0x1p-100))),
                            _mm_cmpge_pd(c, _mm_mul_pd(half_b, _mm_set1_pd(0x1p-98))));
  ok = _mm_andnot_pd(away, ok);
  r->t = zero, r->found = ok;
  if (!_mm_movemask_pd(ok)) return; /* both rays miss: no root to find */
  __m128d root = _mm_or_pd(_mm_andnot_pd(sign, _mm_sqrt_pd(disc)), _mm_and_pd(sign, half_b));
  __m128d q = _mm_xor_pd(_mm_add_pd(half_b, root), sign);
  __m128d t0 = _mm_div_pd(q, a), t1 = pd_blend(_mm_cmpneq_pd(q, zero), _mm_div_pd(c, q), t0);
  __m128d swap = _mm_cmpgt_pd(t0, t1), lo = pd_blend(swap, t1, t0), hi = pd_blend(swap, t0, t1);
  __m128d tnear = packet_pair(f, n, RAY_TNEAR, i), tfar = packet_pair(f, n, RAY_TFAR, i);
  __m128d in_lo = _mm_and_pd(ok, pd_in_range(lo, tnear, tfar));
  __m128d in_hi = _mm_and_pd(ok, pd_in_range(hi, tnear, tfar));
  r->t = pd_blend(in_lo, lo, hi);
  r->found = _mm_or_pd(in_lo, in_hi);
}

/* The hits of lanes i, i + 1 (those set in `lanes`) with the roots in r. */
PACKET_INLINE void sphere_pair_hits(const struct RTCIntersectFunctionNArguments *args,
                                    const sphere_shape *s, unsigned i, const sphere_pair *r,
                                    int lanes) {
  __m128d p[3];
  for (int k = 0; k < 3; ++k) p[k] = _mm_add_pd(r->o[k], _mm_mul_pd(r->t, r->d[k]));
  __m128d scale = _mm_div_pd(_mm_set1_pd(s->radius), _mm_sqrt_pd(pd_dot(p, p)));
  for (int k = 0; k < 3; ++k) p[k] = _mm_mul_pd(p[k], scale); /* pbrt's refinement */
  const __m128d zero = _mm_setzero_pd();
  __m128d on_axis = _mm_and_pd(_mm_cmpeq_pd(p[0], zero), _mm_cmpeq_pd(p[1], zero));
  p[0] = pd_blend(on_axis, _mm_set1_pd(1e-5 * s->radius), p[0]);
  const double *inv = s->object_to_group.inv;
  __m128d ng[3];
  for (int k = 0; k < 3; ++k) {
    ng[k] = _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_set1_pd(inv[k]), p[0]),
                                  _mm_mul_pd(_mm_set1_pd(inv[4 + k]), p[1])),
                       _mm_mul_pd(_mm_set1_pd(inv[8 + k]), p[2]));
  }
  alignas(16) double t[2], pl[3][2], nl[3][2];
  _mm_store_pd(t, r->t);
  for (int k = 0; k < 3; ++k) {
    _mm_store_pd(pl[k], p[k]);
    _mm_store_pd(nl[k], ng[k]);
  }
  for (int j = 0; j < 2; ++j) {
    if (!(lanes & (1 << j))) continue;
    double pj[3] = {pl[0][j], pl[1][j], pl[2][j]};
    sphere_hit h = {.t = (float)t[j], .ng = {nl[0][j], nl[1][j], nl[2][j]}};
    sphere_uv(s, pj, s->uv ? sphere_phi(pj) : 0.0, &h);
    store_user_hit(args, i + (unsigned)j, &h);
  }
}

/* Lanes i and i + 1 that Embree asked about, as bits 0 and 1. */
static inline int valid_pair(const int *valid, unsigned i) {
  return (valid[i] != 0) | (valid[i + 1] != 0) << 1;
}

static void sphere_intersect(const struct RTCIntersectFunctionNArguments *args) {
  const sphere_shape *s = args->geometryUserPtr;
  const unsigned n = args->N;
  if (s->partial || n % 2) {
    user_intersect(args, sphere_test);
    return;
  }
  const float *f = (const float *)args->rayhit;
  for (unsigned i = 0; i < n; i += 2) {
    int valid = valid_pair(args->valid, i);
    if (!valid) continue;
    sphere_pair r;
    sphere_pair_roots(s, f, n, i, &r);
    int lanes = valid & _mm_movemask_pd(r.found);
    if (lanes) sphere_pair_hits(args, s, i, &r, lanes);
  }
}

static void sphere_occluded(const struct RTCOccludedFunctionNArguments *args) {
  const sphere_shape *s = args->geometryUserPtr;
  const unsigned n = args->N;
  if (s->partial || n % 2) {
    user_occluded(args, sphere_occludes);
    return;
  }
  float *f = (float *)args->ray;
  for (unsigned i = 0; i < n; i += 2) {
    int valid = valid_pair(args->valid, i);
    if (!valid) continue;
    sphere_pair r;
    sphere_pair_roots(s, f, n, i, &r);
    int lanes = valid & _mm_movemask_pd(r.found);
    for (unsigned j = 0; j < 2; ++j)
      if (lanes & (1 << j)) f[RAY_TFAR * n + i + j] = -INFINITY;
  }
}
#else
static void sphere_intersect(const struct RTCIntersectFunctionNArguments *args) {
  user_intersect(args, sphere_test);
}

static void sphere_occluded(const struct RTCOccludedFunctionNArguments *args) {
  user_occluded(args, sphere_occludes);
}
#endif

/* ---- disks: pbrt-v3 Disk::Intersect in object space ---- */

static int disk_hit_test(const disk_shape *s, const float org[3], const float dir[3], float tnear,
                         float tfar, sphere_hit *hit) {
  double og[3] = {org[0], org[1], org[2]}, dg[3] = {dir[0], dir[1], dir[2]}, o[3], d[3];
  map_point(s->object_to_group.inv, og, o);
  map_vector(s->object_to_group.inv, dg, d);
  if (d[2] == 0.0) return 0;
  double t = (s->height - o[2]) / d[2];
  if (!((float)t >= tnear && (float)t <= tfar) || !(t > 0.0)) return 0;
  double x = o[0] + t * d[0], y = o[1] + t * d[1], r2 = x * x + y * y;
  if (r2 > s->radius * s->radius || r2 < s->inner * s->inner) return 0;
  double phi = atan2(y, x);
  if (phi < 0.0) phi += 2.0 * PI_D;
  if (phi > s->phimax) return 0;
  double r = sqrt(r2), z[3] = {0.0, 0.0, 1.0};
  hit->t = (float)t;
  hit->u = (float)(phi / s->phimax);
  hit->v = (float)((s->radius - r) / (s->radius - s->inner));
  map_normal(&s->object_to_group, z, hit->ng);
  return 1;
}

static int disk_test(const void *shape, const float org[3], const float dir[3], float tnear,
                     float tfar, sphere_hit *hit) {
  return disk_hit_test(shape, org, dir, tnear, tfar, hit);
}

static void disk_bounds(const struct RTCBoundsFunctionArguments *args) {
  const disk_shape *s = args->geometryUserPtr;
  box_bounds(s->object_to_group.m, s->radius, s->height, s->height, 1e-7, args->bounds_o);
}

static void disk_intersect(const struct RTCIntersectFunctionNArguments *args) {
  user_intersect(args, disk_test);
}

static void disk_occluded(const struct RTCOccludedFunctionNArguments *args) {
  user_occluded(args, disk_test);
}

/* ---- quadrics (quadrics.c): exact intersection in object space ---- */

static int quadric_test(const void *shape, const float org[3], const float dir[3], float tnear,
                        float tfar, sphere_hit *hit) {
  const quadric_shape *s = shape;
  double og[3] = {org[0], org[1], org[2]}, dg[3] = {dir[0], dir[1], dir[2]}, o[3], d[3], t;
  map_point(s->object_to_group.inv, og, o);
  map_vector(s->object_to_group.inv, dg, d);
  if (!clr_quadric_intersect(&s->q, o, d, tfar, &t) || !((float)t >= tnear && (float)t <= tfar))
    return 0;
  double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}, uv[2], du[3], dv[3], n[3];
  clr_quadric_param(&s->q, p, uv, du, dv);
  n[0] = du[1] * dv[2] - du[2] * dv[1];
  n[1] = du[2] * dv[0] - du[0] * dv[2];
  n[2] = du[0] * dv[1] - du[1] * dv[0];
  hit->t = (float)t;
  hit->u = (float)uv[0];
  hit->v = (float)uv[1];
  map_normal(&s->object_to_group, n, hit->ng);
  return 1;
}

static void quadric_bounds(const struct RTCBoundsFunctionArguments *args) {
  const quadric_shape *s = args->geometryUserPtr;
  double r, z0, z1;
  clr_quadric_bounds(&s->q, &r, &z0, &z1);
  box_bounds(s->object_to_group.m, r, z0, z1, 1e-7, args->bounds_o);
}

static void quadric_intersect(const struct RTCIntersectFunctionNArguments *args) {
  user_intersect(args, quadric_test);
}

static void quadric_occluded(const struct RTCOccludedFunctionNArguments *args) {
  user_occluded(args, quadric_test);
}

/* ---- building ---- */

static void free_record(geom_record *r) {
  free(r->mesh.p);
  free(r->mesh.n);
  free(r->mesh.uv);
  free(r->mesh.indices);
  free(r->sphere);
  free(r->disk);
  free(r->quadric);
  memset(r, 0, sizeof *r);
}

void clr_tracer_release(clr_tracer t) {
  if (!t) return;
  for (int32_t g = 0; g < t->group_count; ++g) {
    if (t->groups[g].scene) rtcReleaseScene(t->groups[g].scene);
    for (uint32_t i = 0; i < t->groups[g].count; ++i) free_record(&t->groups[g].records[i]);
    free(t->groups[g].records);
  }
  free(t->groups);
  if (t->device) rtcReleaseDevice(t->device);
  pthread_mutex_destroy(&t->error_lock);
  free(t);
}

/* Appends an empty group with a new Embree scene. */
static clr_result add_group(struct clr_tracer_t *t, const char *fn) {
  if (t->group_count == t->group_capacity) {
    if (t->group_capacity > INT32_MAX / 2)
      return clr_set_last_error(CLR_ERROR_SCENE, "%s: too many groups (%ld)", fn,
                                (long)t->group_count);
    int32_t capacity = t->group_capacity ? 2 * t->group_capacity : 4;
    group *groups = realloc(t->groups, (size_t)capacity * sizeof *groups);
    if (!groups)
      return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "%s: cannot grow the group table", fn);
    t->groups = groups;
    t->group_capacity = capacity;
  }
  RTCScene scene = rtcNewScene(t->device);
  EMBREE_CHECK(t, "rtcNewScene");
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  clr_result r = embree_check(t, "rtcSetSceneBuildQuality");
  if (r != CLR_SUCCESS) {
    rtcReleaseScene(scene);
    return r;
  }
  memset(&t->groups[t->group_count], 0, sizeof(group));
  t->groups[t->group_count++].scene = scene;
  return CLR_SUCCESS;
}

/* Embree runs the widest ISA the CPU has, and its ISAs differ in the last bits of some hits:
 * CLRENDER_EMBREE_ISA caps it (Embree's max_isa), so that machines of different widths agree. */
static const char *const embree_isas[] = {"sse2", "sse4.2", "avx", "avx2", "avx512"};

static clr_result embree_config(char *config, size_t size) {
  const char *isa = getenv("CLRENDER_EMBREE_ISA");
  config[0] = 0;
  if (!isa || !*isa) return CLR_SUCCESS;
  for (size_t i = 0; i < sizeof embree_isas / sizeof *embree_isas; ++i)
    if (strcmp(isa, embree_isas[i]) == 0) {
      snprintf(config, size, "max_isa=%s", isa);
      return CLR_SUCCESS;
    }
  return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                            "CLRENDER_EMBREE_ISA=%.64s: expected sse2, sse4.2, avx, avx2 or avx512",
                            isa);
}

/* The packet width this device traces natively: 16 with AVX-512, 8 with AVX and AVX2, where
 * Embree splits a 16-wide packet into two 8-wide ones through copies (16 when neither is native:
 * the split is Embree's then, as before). */
static int native_packet_width(RTCDevice device) {
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) return 16;
  return rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) ? 8 : 16;
}

clr_result clr_tracer_create(clr_tracer *out) {
  if (!out) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_tracer_create: out is NULL");
  *out = NULL;
  struct clr_tracer_t *t = calloc(1, sizeof *t);
  if (!t) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "clr_tracer_create: out of memory");
  t->sphere_uv = 1;
  if (pthread_mutex_init(&t->error_lock, NULL) != 0) {
    free(t);
    return clr_set_last_error(CLR_ERROR_INTERNAL, "clr_tracer_create: pthread_mutex_init failed");
  }
  char config[32];
  clr_result c = embree_config(config, sizeof config);
  if (c != CLR_SUCCESS) {
    clr_tracer_release(t);
    return c;
  }
  t->device = rtcNewDevice(config[0] ? config : NULL);
  if (!t->device) {
    enum RTCError code = rtcGetDeviceError(NULL);
    clr_tracer_release(t);
    return clr_set_last_error(CLR_ERROR_EMBREE, "rtcNewDevice failed: %s (%d)",
                              embree_error_name(code), (int)code);
  }
  rtcSetDeviceErrorFunction(t->device, record_embree_error, t);
  t->packet_width = native_packet_width(t->device);
  clr_result r = embree_check(t, "rtcSetDeviceErrorFunction");
  if (r == CLR_SUCCESS &&
      rtcGetDeviceProperty(t->device, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED))
    r = clr_set_last_error(CLR_ERROR_EMBREE,
                           "clr_tracer_create: this Embree build culls back faces; "
                           "pbrt needs two-sided triangles");
  if (r == CLR_SUCCESS) r = add_group(t, "clr_tracer_create");
  if (r != CLR_SUCCESS) {
    clr_tracer_release(t);
    return r;
  }
  *out = t;
  return CLR_SUCCESS;
}

clr_result clr_tracer_new_group(clr_tracer t, int32_t *group_id) {
  if (!t || !group_id)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_tracer_new_group: %s is NULL",
                              t ? "group_id" : "tracer");
  if (t->committed)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "clr_tracer_new_group: the tracer is already committed");
  CLR_CHECK(add_group(t, "clr_tracer_new_group"));
  *group_id = t->group_count - 1;
  return CLR_SUCCESS;
}

/* Common checks of the building calls. */
static clr_result check_building(clr_tracer t, int32_t g, const void *arg, const char *arg_name,
                                 const char *fn) {
  if (!t) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "%s: tracer is NULL", fn);
  if (!arg) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "%s: %s is NULL", fn, arg_name);
  if (t->committed)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "%s: the tracer is already committed",
                              fn);
  if (g < 0 || g >= t->group_count)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "%s: group %ld out of range [0, %ld)", fn,
                              (long)g, (long)t->group_count);
  if (t->groups[g].count == t->groups[g].capacity) {
    group *gr = &t->groups[g];
    if (gr->capacity > UINT32_MAX / 4)
      return clr_set_last_error(CLR_ERROR_SCENE, "%s: too many geometries in group %ld", fn,
                                (long)g);
    uint32_t capacity = gr->capacity ? 2 * gr->capacity : 8;
    geom_record *records = realloc(gr->records, (size_t)capacity * sizeof *records);
    if (!records)
      return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "%s: cannot grow group %ld", fn, (long)g);
    gr->records = records;
    gr->capacity = capacity;
  }
  return CLR_SUCCESS;
}

/* Commits a configured geometry and attaches it to group g as record `record` (whose owned
 * memory is freed on failure); the geometry handle is released either way. */
static clr_result attach(struct clr_tracer_t *t, int32_t g, RTCGeometry geom, geom_record *record,
                         uint32_t *geom_id) {
  group *gr = &t->groups[g];
  rtcCommitGeometry(geom);
  clr_result r = embree_check(t, "rtcCommitGeometry");
  unsigned id = RTC_INVALID_GEOMETRY_ID;
  if (r == CLR_SUCCESS) {
    id = rtcAttachGeometry(gr->scene, geom);
    r = embree_check(t, "rtcAttachGeometry");
  }
  if (r == CLR_SUCCESS && id != gr->count) {
    rtcDetachGeometry(gr->scene, id);
    r = clr_set_last_error(CLR_ERROR_INTERNAL, "rtcAttachGeometry gave id %u, expected %u", id,
                           gr->count);
  }
  rtcReleaseGeometry(geom);
  if (r != CLR_SUCCESS) {
    free_record(record);
    return r;
  }
  gr->records[gr->count++] = *record;
  if (geom_id) *geom_id = id;
  return CLR_SUCCESS;
}

/* Copies the mesh arrays the tracer needs (positions padded for Embree's 16-byte loads). */
static clr_result copy_mesh(const clr_mesh *m, tracer_mesh *out) {
  size_t nv = (size_t)m->vertex_count, nt = (size_t)m->triangle_count;
  memset(out, 0, sizeof *out);
  out->vertex_count = m->vertex_count;
  out->triangle_count = m->triangle_count;
  out->p = malloc((3 * nv + 1) * sizeof(float));
  out->indices = malloc(3 * nt * sizeof(uint32_t));
  out->n = m->n ? malloc(3 * nv * sizeof(float)) : NULL;
  out->uv = m->uv ? malloc(2 * nv * sizeof(float)) : NULL;
  if (!out->p || !out->indices || (m->n && !out->n) || (m->uv && !out->uv))
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                              "clr_tracer_add_mesh: cannot copy a mesh of %zu "
                              "vertices and %zu triangles",
                              nv, nt);
  memcpy(out->p, m->p, 3 * nv * sizeof(float));
  out->p[3 * nv] = 0.0f;
  memcpy(out->indices, m->indices, 3 * nt * sizeof(uint32_t));
  if (m->n) memcpy(out->n, m->n, 3 * nv * sizeof(float));
  if (m->uv) memcpy(out->uv, m->uv, 2 * nv * sizeof(float));
  return CLR_SUCCESS;
}

clr_result clr_tracer_add_mesh(clr_tracer t, int32_t g, const clr_mesh *mesh, uint32_t user_id,
                               uint32_t *geom_id) {
  static const char fn[] = "clr_tracer_add_mesh";
  CLR_CHECK(check_building(t, g, mesh, "mesh", fn));
  CLR_CHECK(clr_mesh_validate(mesh, fn));
  if (mesh->triangle_count == 0)
    return clr_set_last_error(CLR_ERROR_SCENE, "%s: the mesh has no triangles (%ld vertices)", fn,
                              (long)mesh->vertex_count);
  geom_record record = {.kind = GEOM_MESH, .user_id = user_id};
  clr_result r = copy_mesh(mesh, &record.mesh);
  if (r != CLR_SUCCESS) {
    free_record(&record);
    return r;
  }
  RTCGeometry geom = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  r = embree_check(t, "rtcNewGeometry(RTC_GEOMETRY_TYPE_TRIANGLE)");
  if (r != CLR_SUCCESS) {
    free_record(&record);
    return r;
  }
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, record.mesh.p, 0,
                             3 * sizeof(float), (size_t)mesh->vertex_count);
  r = embree_check(t, "rtcSetSharedGeometryBuffer(RTC_BUFFER_TYPE_VERTEX)");
  if (r == CLR_SUCCESS) {
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               record.mesh.indices, 0, 3 * sizeof(uint32_t),
                               (size_t)mesh->triangle_count);
    r = embree_check(t, "rtcSetSharedGeometryBuffer(RTC_BUFFER_TYPE_INDEX)");
  }
  if (r != CLR_SUCCESS) {
    rtcReleaseGeometry(geom);
    free_record(&record);
    return r;
  }
  return attach(t, g, geom, &record, geom_id);
}

/* The shape's object-to-group transform from m, or an error naming fn (the record then freed). */
static clr_result set_object_to_group(geom_record *record, const float m[16], affine *out,
                                      const char *fn) {
  if (affine_from_matrix(m, out)) return CLR_SUCCESS;
  free_record(record);
  return clr_set_last_error(CLR_ERROR_SCENE,
                            "%s: object_to_group is not a finite, invertible affine matrix", fn);
}

/* Commits a user geometry (one primitive: a sphere or a disk) with its callbacks and attaches
 * it to group g; frees the record on failure. */
static clr_result attach_user(struct clr_tracer_t *t, int32_t g, geom_record *record, void *shape,
                              RTCBoundsFunction bounds, RTCIntersectFunctionN intersect,
                              RTCOccludedFunctionN occluded, uint32_t *geom_id) {
  t->user_geometry = 1;
  RTCGeometry geom = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_USER);
  clr_result r = embree_check(t, "rtcNewGeometry(RTC_GEOMETRY_TYPE_USER)");
  if (r != CLR_SUCCESS) {
    free_record(record);
    return r;
  }
  rtcSetGeometryUserPrimitiveCount(geom, 1);
  r = embree_check(t, "rtcSetGeometryUserPrimitiveCount");
  if (r == CLR_SUCCESS) {
    rtcSetGeometryUserData(geom, shape);
    rtcSetGeometryBoundsFunction(geom, bounds, NULL);
    rtcSetGeometryIntersectFunction(geom, intersect);
    rtcSetGeometryOccludedFunction(geom, occluded);
    r = embree_check(t,
                     "rtcSetGeometry{UserData,BoundsFunction,IntersectFunction,OccludedFunction}");
  }
  if (r != CLR_SUCCESS) {
    rtcReleaseGeometry(geom);
    free_record(record);
    return r;
  }
  return attach(t, g, geom, record, geom_id);
}

clr_result clr_tracer_set_sphere_uv(clr_tracer t, int with_uv) {
  if (!t)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_tracer_set_sphere_uv: tracer is NULL");
  t->sphere_uv = with_uv != 0;
  return CLR_SUCCESS;
}

clr_result clr_tracer_add_sphere(clr_tracer t, int32_t g, const float object_to_group[16],
                                 float radius, uint32_t user_id, uint32_t *geom_id) {
  return clr_tracer_add_partial_sphere(t, g, object_to_group, radius, -radius, radius, 360.0f,
                                       user_id, geom_id);
}

clr_result clr_tracer_add_partial_sphere(clr_tracer t, int32_t g, const float object_to_group[16],
                                         float radius, float zmin, float zmax, float phimax_deg,
                                         uint32_t user_id, uint32_t *geom_id) {
  static const char fn[] = "clr_tracer_add_sphere";
  CLR_CHECK(check_building(t, g, object_to_group, "object_to_group", fn));
  if (!(radius > 0.0f) || !isfinite(radius))
    return clr_set_last_error(CLR_ERROR_SCENE, "%s: radius %g must be positive and finite", fn,
                              (double)radius);
  geom_record record = {.kind = GEOM_SPHERE, .user_id = user_id};
  record.sphere = malloc(sizeof *record.sphere);
  if (!record.sphere) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
  record.sphere->radius = radius;
  { /* pbrt-v3 Sphere: z clamped to [-radius, radius] and sorted, phimax clamped to [0, 360] */
    double r = radius, z0 = fmin(zmin, zmax), z1 = fmax(zmin, zmax);
    z0 = fmin(fmax(z0, -r), r);
    z1 = fmin(fmax(z1, -r), r);
    double pm = fmin(fmax((double)phimax_deg, 0.0), 360.0) * PI_D / 180.0;
    sphere_shape *sp = record.sphere;
    sp->partial = !(z0 <= -r && z1 >= r && pm >= 2.0 * PI_D);
    sp->uv = t->sphere_uv;
    sp->zmin = z0;
    sp->zmax = z1;
    sp->phimax = pm;
    sp->theta_zmin = acos(fmin(fmax(z0 / r, -1.0), 1.0));
    sp->theta_zmax = acos(fmin(fmax(z1 / r, -1.0), 1.0));
  }
  CLR_CHECK(set_object_to_group(&record, object_to_group, &record.sphere->object_to_group, fn));
  return attach_user(t, g, &record, record.sphere, sphere_bounds, sphere_intersect, sphere_occluded,
                     geom_id);
}

clr_result clr_tracer_add_disk(clr_tracer t, int32_t g, const float object_to_group[16],
                               float height, float radius, float inner_radius, float phimax_deg,
                               uint32_t user_id, uint32_t *geom_id) {
  static const char fn[] = "clr_tracer_add_disk";
  CLR_CHECK(check_building(t, g, object_to_group, "object_to_group", fn));
  if (!(radius > 0.0f) || !isfinite(radius) || !(inner_radius >= 0.0f) ||
      !(inner_radius < radius) || !isfinite(height) || !(phimax_deg > 0.0f) ||
      !(phimax_deg <= 360.0f))
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s: radius %g, innerradius %g, height %g, phimax %g "
                              "(need 0 <= innerradius < radius, 0 < phimax <= 360)",
                              fn, (double)radius, (double)inner_radius, (double)height,
                              (double)phimax_deg);
  geom_record record = {.kind = GEOM_DISK, .user_id = user_id};
  record.disk = malloc(sizeof *record.disk);
  if (!record.disk) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
  record.disk->height = height;
  record.disk->radius = radius;
  record.disk->inner = inner_radius;
  record.disk->phimax = phimax_deg * PI_D / 180.0;
  CLR_CHECK(set_object_to_group(&record, object_to_group, &record.disk->object_to_group, fn));
  return attach_user(t, g, &record, record.disk, disk_bounds, disk_intersect, disk_occluded,
                     geom_id);
}

clr_result clr_tracer_add_quadric(clr_tracer t, int32_t g, const float object_to_group[16],
                                  const clr_quadric *quadric, uint32_t user_id, uint32_t *geom_id) {
  static const char fn[] = "clr_tracer_add_quadric";
  CLR_CHECK(check_building(t, g, object_to_group, "object_to_group", fn));
  geom_record record = {.kind = GEOM_QUADRIC, .user_id = user_id};
  record.quadric = malloc(sizeof *record.quadric);
  if (!record.quadric) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
  record.quadric->q = *quadric;
  const char *why;
  if (!clr_quadric_init(&record.quadric->q, &why)) {
    free_record(&record);
    return clr_set_last_error(CLR_ERROR_SCENE, "%s: %s", fn, why);
  }
  CLR_CHECK(set_object_to_group(&record, object_to_group, &record.quadric->object_to_group, fn));
  return attach_user(t, g, &record, record.quadric, quadric_bounds, quadric_intersect,
                     quadric_occluded, geom_id);
}

clr_result clr_tracer_add_instance(clr_tracer t, int32_t g, const float instance_to_world[16],
                                   uint32_t user_id) {
  static const char fn[] = "clr_tracer_add_instance";
  CLR_CHECK(check_building(t, 0, instance_to_world, "instance_to_world", fn));
  if (g < 1 || g >= t->group_count)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "%s: group %ld out of range [1, %ld): only "
                              "object-definition groups can be instanced",
                              fn, (long)g, (long)t->group_count);
  geom_record record = {.kind = GEOM_INSTANCE, .user_id = user_id, .instanced_group = g};
  if (!affine_from_matrix(instance_to_world, &record.instance_to_world))
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "%s: instance_to_world is not a finite, invertible "
                              "affine matrix",
                              fn);
  RTCGeometry geom = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_INSTANCE);
  EMBREE_CHECK(t, "rtcNewGeometry(RTC_GEOMETRY_TYPE_INSTANCE)");
  rtcSetGeometryInstancedScene(geom, t->groups[g].scene);
  clr_result r = embree_check(t, "rtcSetGeometryInstancedScene");
  if (r == CLR_SUCCESS) {
    rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, instance_to_world);
    r = embree_check(t, "rtcSetGeometryTransform");
  }
  if (r != CLR_SUCCESS) {
    rtcReleaseGeometry(geom);
    return r;
  }
  return attach(t, 0, geom, &record, NULL);
}

clr_result clr_tracer_add_motion_instance(clr_tracer t, int32_t g, const float translation[2][3],
                                          const float rotation[2][4], const float scale[2][3],
                                          uint32_t user_id) {
  static const char fn[] = "clr_tracer_add_motion_instance";
  CLR_CHECK(check_building(t, 0, translation, "translation", fn));
  if (!rotation || !scale)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "%s: %s is NULL", fn,
                              rotation ? "scale" : "rotation");
  if (g < 1 || g >= t->group_count)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "%s: group %ld out of range [1, %ld): only "
                              "object-definition groups can be instanced",
                              fn, (long)g, (long)t->group_count);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 4; ++i)
      if (!isfinite(rotation[k][i]) || (i < 3 && (!isfinite(translation[k][i]) ||
                                                  !isfinite(scale[k][i]) || scale[k][i] == 0.0f)))
        return clr_set_last_error(CLR_ERROR_SCENE,
                                  "%s: time step %d has a non-finite value or a zero scale", fn, k);
  struct RTCQuaternionDecomposition qd[2];
  for (int k = 0; k < 2; ++k) {
    rtcInitQuaternionDecomposition(&qd[k]);
    rtcQuaternionDecompositionSetScale(&qd[k], scale[k][0], scale[k][1], scale[k][2]);
    rtcQuaternionDecompositionSetQuaternion(&qd[k], rotation[k][3], rotation[k][0], rotation[k][1],
                                            rotation[k][2]);
    qd[k].translation_x = translation[k][0];
    qd[k].translation_y = translation[k][1];
    qd[k].translation_z = translation[k][2];
  }
  RTCGeometry geom = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_INSTANCE);
  EMBREE_CHECK(t, "rtcNewGeometry(RTC_GEOMETRY_TYPE_INSTANCE)");
  rtcSetGeometryInstancedScene(geom, t->groups[g].scene);
  rtcSetGeometryTimeStepCount(geom, 2);
  rtcSetGeometryTransformQuaternion(geom, 0, &qd[0]);
  rtcSetGeometryTransformQuaternion(geom, 1, &qd[1]);
  clr_result r = embree_check(t, "rtcSetGeometryTransformQuaternion");
  float m[16] = {0};
  m[15] = 1.0f;
  if (r == CLR_SUCCESS) rtcGetGeometryTransform(geom, 0.0f, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, m);
  geom_record record = {
      .kind = GEOM_INSTANCE, .user_id = user_id, .instanced_group = g, .moving = 1};
  if (r == CLR_SUCCESS && !affine_from_matrix(m, &record.instance_to_world))
    r = clr_set_last_error(CLR_ERROR_SCENE, "%s: the start transform is not invertible", fn);
  if (r != CLR_SUCCESS) {
    rtcReleaseGeometry(geom);
    return r;
  }
  return attach(t, 0, geom, &record, NULL);
}

/* Instance-to-world of world record `inst` at `time` (interpolated by Embree when moving). */
static void instance_affine(const struct clr_tracer_t *t, uint32_t inst, float time, affine *out) {
  const geom_record *rec = &t->groups[0].records[inst];
  *out = rec->instance_to_world;
  if (!rec->moving) return;
  float m[16] = {0};
  m[15] = 1.0f;
  rtcGetGeometryTransform(rtcGetGeometry(t->groups[0].scene, inst), time,
                          RTC_FORMAT_FLOAT3X4_ROW_MAJOR, m);
  affine a;
  if (affine_from_matrix(m, &a)) *out = a;
}

clr_result clr_tracer_instance_transform(clr_tracer t, uint32_t inst_id, float time,
                                         float out[16]) {
  static const char fn[] = "clr_tracer_instance_transform";
  if (!t || !out)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "%s: %s is NULL", fn, t ? "out" : "tracer");
  if (!t->committed || inst_id >= t->groups[0].count ||
      t->groups[0].records[inst_id].kind != GEOM_INSTANCE)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "%s: %lu is not an instance id", fn,
                              (unsigned long)inst_id);
  affine a;
  instance_affine(t, inst_id, time, &a);
  for (int i = 0; i < 12; ++i) out[i] = (float)a.m[i];
  out[12] = out[13] = out[14] = 0.0f;
  out[15] = 1.0f;
  return CLR_SUCCESS;
}

clr_result clr_tracer_instance_info(clr_tracer t, uint32_t inst_id, int32_t *group,
                                    uint32_t *user_id) {
  if (!t)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_tracer_instance_info: tracer is NULL");
  if (inst_id >= t->groups[0].count || t->groups[0].records[inst_id].kind != GEOM_INSTANCE)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "clr_tracer_instance_info: %lu is not an "
                              "instance id",
                              (unsigned long)inst_id);
  if (group) *group = t->groups[0].records[inst_id].instanced_group;
  if (user_id) *user_id = t->groups[0].records[inst_id].user_id;
  return CLR_SUCCESS;
}

clr_result clr_tracer_commit(clr_tracer t) {
  if (!t) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_tracer_commit: tracer is NULL");
  if (t->committed)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "clr_tracer_commit: already committed");
  for (int32_t g = t->group_count - 1; g >= 0; --g) { /* instanced scenes before the world */
    rtcCommitScene(t->groups[g].scene);
    EMBREE_CHECK(t, "rtcCommitScene");
  }
  t->committed = 1;
  return CLR_SUCCESS;
}

/* ---- queries ---- */

static int ray_is_valid(const clr_ray *r) {
  return isfinite(r->ox) && isfinite(r->oy) && isfinite(r->oz) && isfinite(r->dx) &&
         isfinite(r->dy) && isfinite(r->dz) && (r->dx != 0.0f || r->dy != 0.0f || r->dz != 0.0f) &&
         isfinite(r->tnear) && r->tnear >= 0.0f && !isnan(r->tfar);
}

/* Checks the handles and count; the rays themselves are checked as they are loaded. */
static clr_result check_query(clr_tracer t, const clr_ray *rays, const void *out, int32_t count,
                              const char *fn) {
  if (!t || !rays || !out)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "%s: %s is NULL", fn,
                              !t      ? "tracer"
                              : !rays ? "rays"
                                      : "the output array");
  if (count < 0)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "%s: count %ld < 0", fn, (long)count);
  if (!t->committed)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "%s: the tracer is not committed", fn);
  return CLR_SUCCESS;
}

static clr_result invalid_ray(const clr_ray *r, int32_t i, const char *fn) {
  return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                            "%s: ray %ld is invalid (o = (%g, %g, %g), "
                            "d = (%g, %g, %g), tnear = %g, tfar = %g)",
                            fn, (long)i, (double)r->ox, (double)r->oy, (double)r->oz, (double)r->dx,
                            (double)r->dy, (double)r->dz, (double)r->tnear, (double)r->tfar);
}

#if defined(__SSE2__)
_Static_assert(offsetof(clr_ray, tnear) == 3 * sizeof(float) &&
                   offsetof(clr_ray, tfar) == offsetof(clr_ray, dx) + 3 * sizeof(float),
               "clr_ray: origin, tnear, then direction, tfar");

/* Four rays' first eight floats, one vector of four lanes per field. */
typedef struct four_rays {
  __m128 ox, oy, oz, tnear, dx, dy, dz, tfar;
} four_rays;

/* Two 4x4 transposes of rays r[0..3]. */
static inline __attribute__((always_inline)) four_rays transpose_four(const clr_ray *r) {
  four_rays q = {_mm_loadu_ps(&r[0].ox), _mm_loadu_ps(&r[1].ox), _mm_loadu_ps(&r[2].ox),
                 _mm_loadu_ps(&r[3].ox), _mm_loadu_ps(&r[0].dx), _mm_loadu_ps(&r[1].dx),
                 _mm_loadu_ps(&r[2].dx), _mm_loadu_ps(&r[3].dx)};
  _MM_TRANSPOSE4_PS(q.ox, q.oy, q.oz, q.tnear);
  _MM_TRANSPOSE4_PS(q.dx, q.dy, q.dz, q.tfar);
  return q;
}

/* Non-zero when one of the four rays fails ray_is_valid (check_rays' test, lane-wise). */
static inline __attribute__((always_inline)) int four_invalid(const four_rays *q) {
  __m128 f = _mm_add_ps(_mm_sub_ps(q->ox, q->ox), _mm_sub_ps(q->oy, q->oy));
  f = _mm_add_ps(f, _mm_sub_ps(q->oz, q->oz));
  f = _mm_add_ps(f, _mm_sub_ps(q->dx, q->dx));
  f = _mm_add_ps(f, _mm_sub_ps(q->dy, q->dy));
  f = _mm_add_ps(f, _mm_sub_ps(q->dz, q->dz));
  f = _mm_add_ps(f, _mm_sub_ps(q->tnear, q->tnear));
  const __m128 zero = _mm_setzero_ps();
  __m128 bad = _mm_or_ps(_mm_cmpneq_ps(f, zero), _mm_cmpnge_ps(q->tnear, zero));
  bad = _mm_or_ps(bad, _mm_cmpunord_ps(q->tfar, q->tfar));
  __m128 no_dir = _mm_and_ps(_mm_cmpeq_ps(q->dx, zero), _mm_cmpeq_ps(q->dy, zero));
  bad = _mm_or_ps(bad, _mm_and_ps(no_dir, _mm_cmpeq_ps(q->dz, zero)));
  return _mm_movemask_ps(bad);
}
#endif

/* Non-zero when r fails ray_is_valid, without branches (x - x is 0 exactly for finite x). */
static inline int ray_invalid(const clr_ray *r) {
  float f = (r->ox - r->ox) + (r->oy - r->oy) + (r->oz - r->oz) + (r->dx - r->dx) +
            (r->dy - r->dy) + (r->dz - r->dz) + (r->tnear - r->tnear);
  return !(f == 0.0f) | !(r->tnear >= 0.0f) | (r->tfar != r->tfar) |
         ((r->dx == 0.0f) & (r->dy == 0.0f) & (r->dz == 0.0f));
}

/* Checks every ray before any is traced (the outputs stay untouched on failure): a branch-free
 * pass, four rays at a time where SSE2 is there, then the slow search only when one is bad. */
static clr_result check_rays(const clr_ray *rays, int32_t count, const char *fn) {
  int bad = 0;
  int32_t i = 0;
#if defined(__SSE2__)
  for (; i + 4 <= count; i += 4) {
    four_rays q = transpose_four(rays + i);
    bad |= four_invalid(&q);
  }
#endif
  for (; i < count; ++i) bad |= ray_invalid(&rays[i]);
  if (bad)
    for (int32_t i = 0; i < count; ++i)
      if (!ray_is_valid(&rays[i])) return invalid_ray(&rays[i], i, fn);
  return CLR_SUCCESS;
}

/* Turns an Embree hit into a clr_hit with a world-space normal and the user id. */
static void finish_hit(const struct clr_tracer_t *t, float tfar, const float ng[3], float u,
                       float v, uint32_t prim, uint32_t geom, uint32_t inst, float time,
                       clr_hit *out) {
  if (geom == RTC_INVALID_GEOMETRY_ID) {
    *out = (clr_hit){.t = INFINITY,
                     .prim_id = CLR_TRACER_INVALID_ID,
                     .geom_id = CLR_TRACER_INVALID_ID,
                     .inst_id = CLR_TRACER_INVALID_ID,
                     .user_id = CLR_TRACER_INVALID_ID,
                     .time = time};
    return;
  }
  const group *gr = &t->groups[0];
  out->ng[0] = ng[0], out->ng[1] = ng[1], out->ng[2] = ng[2];
  if (inst != RTC_INVALID_GEOMETRY_ID) {
    const geom_record *instance = &gr->records[inst];
    double n[3] = {ng[0], ng[1], ng[2]}, w[3];
    affine a;
    instance_affine(t, inst, time, &a);
    map_normal(&a, n, w);
    out->ng[0] = (float)w[0], out->ng[1] = (float)w[1], out->ng[2] = (float)w[2];
    gr = &t->groups[instance->instanced_group];
  }
  out->t = tfar;
  out->u = u;
  out->v = v;
  out->prim_id = prim;
  out->geom_id = geom;
  out->inst_id = inst;
  out->user_id = gr->records[geom].user_id;
  out->time = time;
}

/* ---- ray packets ---- */

/* Embree's packets (RTCRayHit8, RTCRayHit16) hold one array of `width` lanes per field, in the
 * same field order at every width; a field's index is its offset in the 16-wide struct. */
#define FIELD(member) (offsetof(struct RTCRayHit16, member) / (16 * sizeof(float)))
enum {
  PACKET_FIELDS = sizeof(struct RTCRayHit16) / (16 * sizeof(float)),
  F_ORG_X = FIELD(ray.org_x),
  F_ORG_Y = FIELD(ray.org_y),
  F_ORG_Z = FIELD(ray.org_z),
  F_TNEAR = FIELD(ray.tnear),
  F_DIR_X = FIELD(ray.dir_x),
  F_DIR_Y = FIELD(ray.dir_y),
  F_DIR_Z = FIELD(ray.dir_z),
  F_TIME = FIELD(ray.time),
  F_TFAR = FIELD(ray.tfar),
  F_MASK = FIELD(ray.mask),
  F_ID = FIELD(ray.id),
  F_FLAGS = FIELD(ray.flags),
  F_NG_X = FIELD(hit.Ng_x),
  F_NG_Y = FIELD(hit.Ng_y),
  F_NG_Z = FIELD(hit.Ng_z),
  F_HIT_U = FIELD(hit.u),
  F_HIT_V = FIELD(hit.v),
  F_PRIM_ID = FIELD(hit.primID),
  F_GEOM_ID = FIELD(hit.geomID),
  F_INST_ID = FIELD(hit.instID)
};
#undef FIELD
_Static_assert(sizeof(struct RTCRayHit8) == PACKET_FIELDS * 8 * sizeof(float) &&
                   offsetof(struct RTCRayHit8, hit.instID) == F_INST_ID * 8 * sizeof(float),
               "RTCRayHit8 has RTCRayHit16's field order");

/* One lane of one field: float or unsigned. */
typedef union lane {
  float f;
  uint32_t u;
} lane;

#if defined(__SSE2__)
/* Lanes [i, i + 4) of four rays' fields (clr_ray's first eight floats are Embree's org_x, org_y,
 * org_z, tnear, dir_x, dir_y, dir_z and, past time, tfar); non-zero when one of them is invalid. */
PACKET_INLINE int load_four(const clr_ray *r, int width, lane *p, int i) {
  four_rays q = transpose_four(r);
  _mm_storeu_ps(&p[F_ORG_X * width + i].f, q.ox);
  _mm_storeu_ps(&p[F_ORG_Y * width + i].f, q.oy);
  _mm_storeu_ps(&p[F_ORG_Z * width + i].f, q.oz);
  _mm_storeu_ps(&p[F_TNEAR * width + i].f, q.tnear);
  _mm_storeu_ps(&p[F_DIR_X * width + i].f, q.dx);
  _mm_storeu_ps(&p[F_DIR_Y * width + i].f, q.dy);
  _mm_storeu_ps(&p[F_DIR_Z * width + i].f, q.dz);
  _mm_storeu_ps(&p[F_TFAR * width + i].f, q.tfar);
  _mm_storeu_ps(&p[F_TIME * width + i].f, _mm_setr_ps(r[0].time, r[1].time, r[2].time, r[3].time));
  return four_invalid(&q);
}
#endif

/* Loads rays [base, base + lanes) into a `width`-lane packet (unused lanes are masked off);
 * non-zero when one of those rays is invalid (check_rays' test). */
PACKET_INLINE int load_packet(const clr_ray *rays, int32_t lanes, int width, lane *p, int *valid) {
  for (int32_t i = 0; i < width; ++i) {
    valid[i] = i < lanes ? -1 : 0;
    p[F_MASK * width + i].u = 0xffffffffu;
    p[F_ID * width + i].u = (uint32_t)i;
    p[F_FLAGS * width + i].u = 0;
  }
  int32_t i = 0, bad = 0;
#if defined(__SSE2__)
  for (; i + 4 <= lanes; i += 4) bad |= load_four(rays + i, width, p, i);
#endif
  for (; i < width; ++i) {
    static const clr_ray unused = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f};
    const clr_ray *r = i < lanes ? &rays[i] : &unused; /* unused is valid */
    bad |= ray_invalid(r);
    p[F_ORG_X * width + i].f = r->ox, p[F_ORG_Y * width + i].f = r->oy;
    p[F_ORG_Z * width + i].f = r->oz, p[F_TNEAR * width + i].f = r->tnear;
    p[F_DIR_X * width + i].f = r->dx, p[F_DIR_Y * width + i].f = r->dy;
    p[F_DIR_Z * width + i].f = r->dz, p[F_TFAR * width + i].f = r->tfar;
    p[F_TIME * width + i].f = r->time;
  }
  return bad;
}

/* Traces one loaded packet of `lanes` rays: closest hits into `hits` (rtcIntersect8/16), or,
 * when hits is NULL, occlusion flags into `occluded` (rtcOccluded8/16). */
PACKET_INLINE void trace_packet(const struct clr_tracer_t *t, lane *p, int width, const int *valid,
                                const clr_ray *rays, int32_t lanes, clr_hit *hits,
                                uint8_t *occluded) {
  struct RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCScene scene = t->groups[0].scene;
  if (!hits) {
    if (width == 8)
      rtcOccluded8(valid, scene, &context, (struct RTCRay8 *)p);
    else
      rtcOccluded16(valid, scene, &context, (struct RTCRay16 *)p);
    for (int32_t i = 0; i < lanes; ++i) occluded[i] = p[F_TFAR * width + i].f == -INFINITY;
    return;
  }
  for (int i = 0; i < width; ++i) {
    p[F_GEOM_ID * width + i].u = RTC_INVALID_GEOMETRY_ID;
    p[F_INST_ID * width + i].u = RTC_INVALID_GEOMETRY_ID;
  }
  if (width == 8)
    rtcIntersect8(valid, scene, &context, (struct RTCRayHit8 *)p);
  else
    rtcIntersect16(valid, scene, &context, (struct RTCRayHit16 *)p);
  for (int32_t i = 0; i < lanes; ++i) {
    float ng[3] = {p[F_NG_X * width + i].f, p[F_NG_Y * width + i].f, p[F_NG_Z * width + i].f};
    finish_hit(t, p[F_TFAR * width + i].f, ng, p[F_HIT_U * width + i].f, p[F_HIT_V * width + i].f,
               p[F_PRIM_ID * width + i].u, p[F_GEOM_ID * width + i].u, p[F_INST_ID * width + i].u,
               rays[i].time, &hits[i]);
  }
}

/* Calls of up to this many rays load them all first and check the rays there, in vector
 * compares over each field, before tracing any; larger calls check ray by ray first. */
#define LOADED_RAYS 512

/* trace_packets at one packet width. */
PACKET_INLINE clr_result trace_packets_of(const struct clr_tracer_t *t, int width,
                                          const clr_ray *rays, int32_t count, clr_hit *hits,
                                          uint8_t *occluded, const char *fn) {
  const size_t floats = (size_t)PACKET_FIELDS * (size_t)width; /* per packet */
  if (count > LOADED_RAYS) {
    CLR_CHECK(check_rays(rays, count, fn));
    for (int32_t base = 0; base < count; base += width) {
      int32_t lanes = count - base < width ? count - base : width;
      alignas(64) int valid[16];
      alignas(64) lane p[PACKET_FIELDS * 16];
      (void)load_packet(rays + base, lanes, width, p, valid); /* checked above */
      trace_packet(t, p, width, valid, rays + base, lanes, hits ? hits + base : NULL,
                   hits ? NULL : occluded + base);
    }
    return CLR_SUCCESS;
  }
  int32_t npackets = count / width + (count % width != 0);
  alignas(64) lane packets[PACKET_FIELDS * LOADED_RAYS];
  alignas(64) int valid[LOADED_RAYS];
  int bad = 0;
  for (int32_t k = 0; k < npackets; ++k) {
    int32_t base = width * k, lanes = count - base < width ? count - base : width;
    bad |= load_packet(rays + base, lanes, width, packets + floats * (size_t)k, valid + base);
  }
  if (bad) CLR_CHECK(check_rays(rays, count, fn)); /* it names the first invalid ray */
  for (int32_t k = 0; k < npackets; ++k) {
    int32_t base = width * k, lanes = count - base < width ? count - base : width;
    trace_packet(t, packets + floats * (size_t)k, width, valid + base, rays + base, lanes,
                 hits ? hits + base : NULL, hits ? NULL : occluded + base);
  }
  return CLR_SUCCESS;
}

/* A ray as Embree's single-ray and stream calls take it. */
static struct RTCRay embree_ray(const clr_ray *r) {
  return (struct RTCRay){.org_x = r->ox,
                         .org_y = r->oy,
                         .org_z = r->oz,
                         .tnear = r->tnear,
                         .dir_x = r->dx,
                         .dir_y = r->dy,
                         .dir_z = r->dz,
                         .time = r->time,
                         .tfar = r->tfar,
                         .mask = 0xffffffffu};
}

/* embree_ray written field by field into *e: building the struct first made GCC store it in
 * pieces and reload it 16 bytes at a time, a store-forwarding stall per ray. */
static inline void store_embree_ray(const clr_ray *r, struct RTCRay *e) {
  e->org_x = r->ox, e->org_y = r->oy, e->org_z = r->oz, e->tnear = r->tnear;
  e->dir_x = r->dx, e->dir_y = r->dy, e->dir_z = r->dz, e->time = r->time;
  e->tfar = r->tfar, e->mask = 0xffffffffu, e->id = 0, e->flags = 0;
}

/* Occlusion of checked rays through Embree's ray stream (rtcOccluded1M), which sorts them by
 * direction octant and traverses each octant's rays together, in chunks of STREAM_RAYS. */
#define STREAM_RAYS 512
static void occluded_stream(const struct clr_tracer_t *t, const clr_ray *rays, int32_t count,
                            uint8_t *occluded) {
  struct RTCRay chunk[STREAM_RAYS];
  struct RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (int32_t base = 0; base < count; base += STREAM_RAYS) {
    int32_t n = count - base < STREAM_RAYS ? count - base : STREAM_RAYS;
    for (int32_t i = 0; i < n; ++i) store_embree_ray(&rays[base + i], &chunk[i]);
    rtcOccluded1M(t->groups[0].scene, &context, chunk, (unsigned)n, sizeof *chunk);
    for (int32_t i = 0; i < n; ++i) occluded[base + i] = chunk[i].tfar == -INFINITY;
  }
}

/* Whether an occlusion call of `count` rays takes Embree's ray stream: calls larger than one
 * loaded batch (AO's many directions per point) in scenes without quadrics. On S the stream cut
 * the Cornell ao64 render by 17 %; a quadric's callback, which a stream calls ray by ray, made
 * the sphere's slower. */
static int occlusion_streams(const struct clr_tracer_t *t, int32_t count) {
  return count > LOADED_RAYS && !t->user_geometry;
}

/* Checks every ray, then traces them in packets of the device's native width (see
 * trace_packet), or occlusion_streams' calls in a stream; nothing is traced and the outputs
 * stay untouched when a ray is invalid. */
static clr_result trace_packets(const struct clr_tracer_t *t, const clr_ray *rays, int32_t count,
                                clr_hit *hits, uint8_t *occluded, const char *fn) {
  if (!hits && occlusion_streams(t, count)) {
    CLR_CHECK(check_rays(rays, count, fn));
    occluded_stream(t, rays, count, occluded);
    return CLR_SUCCESS;
  }
  if (t->packet_width == 8) return trace_packets_of(t, 8, rays, count, hits, occluded, fn);
  return trace_packets_of(t, 16, rays, count, hits, occluded, fn);
}

int clr_tracer_packet_width(clr_tracer t) { return t ? t->packet_width : 0; }

clr_result clr_tracer_intersect(clr_tracer t, const clr_ray *rays, clr_hit *hits, int32_t count) {
  CLR_CHECK(check_query(t, rays, hits, count, "clr_tracer_intersect"));
  CLR_CHECK(trace_packets(t, rays, count, hits, NULL, "clr_tracer_intersect"));
  return embree_check(t, t->packet_width == 8 ? "rtcIntersect8" : "rtcIntersect16");
}

clr_result clr_tracer_intersect_single(clr_tracer t, const clr_ray *rays, clr_hit *hits,
                                       int32_t count) {
  CLR_CHECK(check_query(t, rays, hits, count, "clr_tracer_intersect_single"));
  CLR_CHECK(check_rays(rays, count, "clr_tracer_intersect_single"));
  for (int32_t i = 0; i < count; ++i) {
    const clr_ray *r = &rays[i];
    struct RTCRayHit rh = {
        .ray = embree_ray(r),
        .hit = {.geomID = RTC_INVALID_GEOMETRY_ID, .instID = {RTC_INVALID_GEOMETRY_ID}}};
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(t->groups[0].scene, &context, &rh);
    float ng[3] = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    finish_hit(t, rh.ray.tfar, ng, rh.hit.u, rh.hit.v, rh.hit.primID, rh.hit.geomID,
               rh.hit.instID[0], r->time, &hits[i]);
  }
  return embree_check(t, "rtcIntersect1");
}

clr_result clr_tracer_occluded(clr_tracer t, const clr_ray *rays, uint8_t *occluded,
                               int32_t count) {
  CLR_CHECK(check_query(t, rays, occluded, count, "clr_tracer_occluded"));
  CLR_CHECK(trace_packets(t, rays, count, NULL, occluded, "clr_tracer_occluded"));
  if (occlusion_streams(t, count)) return embree_check(t, "rtcOccluded1M");
  return embree_check(t, t->packet_width == 8 ? "rtcOccluded8" : "rtcOccluded16");
}

/* ---- surface data at hits ---- */

static void store_unit(const double v[3], float out[3]) {
  double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) out[k] = (float)(len > 0.0 ? v[k] / len : 0.0);
}

static void triangle_surface(const tracer_mesh *m, const clr_hit *hit, double p[3], double n[3],
                             float uv[2]) {
  const uint32_t *tri = m->indices + 3 * (size_t)hit->prim_id;
  double b[3] = {1.0 - (double)hit->u - (double)hit->v, hit->u, hit->v};
  const float *v[3] = {m->p + 3 * (size_t)tri[0], m->p + 3 * (size_t)tri[1],
                       m->p + 3 * (size_t)tri[2]};
  for (int k = 0; k < 3; ++k) p[k] = b[0] * v[0][k] + b[1] * v[1][k] + b[2] * v[2][k];
  double len2 = 0.0;
  if (m->n) {
    for (int k = 0; k < 3; ++k)
      n[k] =
          b[0] * m->n[3 * tri[0] + k] + b[1] * m->n[3 * tri[1] + k] + b[2] * m->n[3 * tri[2] + k];
    len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  }
  if (!(len2 > 0.0)) { /* no (usable) vertex normals: the geometric normal */
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k)
      e1[k] = (double)v[1][k] - v[0][k], e2[k] = (double)v[2][k] - v[0][k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  }
  if (m->uv) {
    for (int k = 0; k < 2; ++k)
      uv[k] = (float)(b[0] * m->uv[2 * tri[0] + k] + b[1] * m->uv[2 * tri[1] + k] +
                      b[2] * m->uv[2 * tri[2] + k]);
  } else { /* pbrt-v3's default uvs (0,0), (1,0), (1,1) */
    uv[0] = (float)(b[1] + b[2]);
    uv[1] = (float)b[2];
  }
}

static void sphere_surface(const sphere_shape *s, const clr_hit *hit, double p[3], double n[3],
                           float uv[2]) {
  double phi = 2.0 * PI_D * hit->u, theta = PI_D * (1.0 - hit->v);
  if (s->partial) {
    phi = s->phimax * hit->u;
    theta = s->theta_zmin + hit->v * (s->theta_zmax - s->theta_zmin);
  }
  double o[3] = {s->radius * sin(theta) * cos(phi), s->radius * sin(theta) * sin(phi),
                 s->radius * cos(theta)};
  map_point(s->object_to_group.m, o, p);
  map_normal(&s->object_to_group, o, n);
  uv[0] = hit->u;
  uv[1] = hit->v;
}

clr_result clr_tracer_mesh_interpolate(clr_tracer t, const clr_hit *hit, float p_out[3],
                                       float n_out[3], float uv_out[2]) {
  static const char fn[] = "clr_tracer_mesh_interpolate";
  if (!t || !hit)
    return clr_set_last_error(CLR_ERROR_NULL_POINTER, "%s: %s is NULL", fn, t ? "hit" : "tracer");
  const geom_record *instance = NULL;
  const group *gr = &t->groups[0];
  if (hit->inst_id != CLR_TRACER_INVALID_ID) {
    if (hit->inst_id >= gr->count || gr->records[hit->inst_id].kind != GEOM_INSTANCE)
      return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT, "%s: inst_id %lu is not an instance",
                                fn, (unsigned long)hit->inst_id);
    instance = &gr->records[hit->inst_id];
    gr = &t->groups[instance->instanced_group];
  }
  if (hit->geom_id >= gr->count || gr->records[hit->geom_id].kind == GEOM_INSTANCE)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "%s: geom_id %lu is not a hit mesh or sphere "
                              "(a miss?)",
                              fn, (unsigned long)hit->geom_id);
  const geom_record *rec = &gr->records[hit->geom_id];
  double p[3], n[3];
  float uv[2];
  if (rec->kind == GEOM_MESH) {
    if (hit->prim_id >= (uint32_t)rec->mesh.triangle_count)
      return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                                "%s: prim_id %lu out of range (%ld triangles)", fn,
                                (unsigned long)hit->prim_id, (long)rec->mesh.triangle_count);
    triangle_surface(&rec->mesh, hit, p, n, uv);
  } else if (rec->kind == GEOM_DISK) {
    const disk_shape *s = rec->disk;
    double phi = hit->u * s->phimax, r = s->radius - hit->v * (s->radius - s->inner);
    double o[3] = {r * cos(phi), r * sin(phi), s->height}, z[3] = {0.0, 0.0, 1.0};
    map_point(s->object_to_group.m, o, p);
    map_normal(&s->object_to_group, z, n);
    uv[0] = hit->u;
    uv[1] = hit->v;
  } else if (rec->kind == GEOM_QUADRIC) {
    const quadric_shape *s = rec->quadric;
    double o[3], puv[2], du[3], dv[3], no[3];
    clr_quadric_point(&s->q, hit->u, hit->v, o);
    clr_quadric_param(&s->q, o, puv, du, dv);
    no[0] = du[1] * dv[2] - du[2] * dv[1];
    no[1] = du[2] * dv[0] - du[0] * dv[2];
    no[2] = du[0] * dv[1] - du[1] * dv[0];
    map_point(s->object_to_group.m, o, p);
    map_normal(&s->object_to_group, no, n);
    uv[0] = hit->u;
    uv[1] = hit->v;
  } else {
    sphere_surface(rec->sphere, hit, p, n, uv);
  }
  if (instance) {
    double pw[3], nw[3];
    affine a;
    instance_affine(t, hit->inst_id, hit->time, &a);
    map_point(a.m, p, pw);
    map_normal(&a, n, nw);
    memcpy(p, pw, sizeof p);
    memcpy(n, nw, sizeof n);
  }
  if (p_out)
    for (int k = 0; k < 3; ++k) p_out[k] = (float)p[k];
  if (n_out) store_unit(n, n_out);
  if (uv_out) uv_out[0] = uv[0], uv_out[1] = uv[1];
  return CLR_SUCCESS;
}
