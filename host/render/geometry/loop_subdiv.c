/* Loop subdivision surfaces as pbrt-v3's "loopsubdiv" shape computes them. */
#include "loop_subdiv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"

#define NEXT(i) (((i) + 1) % 3)
#define PREV(i) (((i) + 2) % 3)
#define SD_PI 3.14159265358979323846f
#define SD_MAX_COUNT (INT32_MAX / 3)

/* f[i] is the face across edge (v[i], v[NEXT(i)]), -1 on a boundary. */
typedef struct sd_face {
  int32_t v[3], f[3];
} sd_face;

typedef struct sd_vertex {
  float p[3];
  int32_t start_face; /* any face containing the vertex (on a boundary, pbrt's choice) */
  int32_t boundary;
} sd_vertex;

typedef struct sd_mesh {
  int32_t nv, nf;
  sd_vertex *v;
  sd_face *f;
  float (*ring)[3]; /* scratch one-ring of ring_capacity points */
  int32_t ring_capacity;
} sd_mesh;

static void sd_free(sd_mesh *m) {
  free(m->v);
  free(m->f);
  free(m->ring);
  memset(m, 0, sizeof *m);
}

static clr_result sd_alloc(sd_mesh *m, int64_t nv, int64_t nf) {
  memset(m, 0, sizeof *m);
  if (nv > SD_MAX_COUNT || nf > SD_MAX_COUNT)
    return clr_set_last_error(CLR_ERROR_SCENE,
                              "clr_loop_subdivide: subdivided mesh too large (%lld "
                              "vertices, %lld triangles)",
                              (long long)nv, (long long)nf);
  m->nv = (int32_t)nv;
  m->nf = (int32_t)nf;
  m->v = calloc((size_t)(nv ? nv : 1), sizeof *m->v);
  m->f = calloc((size_t)(nf ? nf : 1), sizeof *m->f);
  if (!m->v || !m->f) {
    sd_free(m);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                              "clr_loop_subdivide: no memory for %lld vertices "
                              "and %lld triangles",
                              (long long)nv, (long long)nf);
  }
  return CLR_SUCCESS;
}

/* ---- topology queries (pbrt's SDFace / SDVertex methods) ---- */

static int vnum(const sd_face *f, int32_t vert) {
  for (int i = 0; i < 3; ++i)
    if (f->v[i] == vert) return i;
  return -1; /* unreachable for consistent topology */
}

static int32_t next_face(const sd_mesh *m, int32_t face, int32_t vert) {
  return m->f[face].f[vnum(&m->f[face], vert)];
}

static int32_t prev_face(const sd_mesh *m, int32_t face, int32_t vert) {
  return m->f[face].f[PREV(vnum(&m->f[face], vert))];
}

static int32_t valence(const sd_mesh *m, int32_t vert) {
  const sd_vertex *v = &m->v[vert];
  int32_t count = 1, face = v->start_face;
  if (!v->boundary) {
    while ((face = next_face(m, face, vert)) != v->start_face) ++count;
    return count;
  }
  while ((face = next_face(m, face, vert)) >= 0) ++count;
  face = v->start_face;
  while ((face = prev_face(m, face, vert)) >= 0) ++count;
  return count + 1;
}

/* Fills m->ring with the one-ring of `vert` in pbrt's order; returns its size (the valence). */
static int32_t one_ring(sd_mesh *m, int32_t vert, clr_result *result) {
  int32_t n = valence(m, vert);
  if (n > m->ring_capacity) {
    float(*grown)[3] = realloc(m->ring, (size_t)n * sizeof *grown);
    if (!grown) {
      *result = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                                   "clr_loop_subdivide: no memory for a one-ring");
      return 0;
    }
    m->ring = grown;
    m->ring_capacity = n;
  }
  const sd_vertex *v = &m->v[vert];
  int32_t face = v->start_face, k = 0;
  if (!v->boundary) {
    do {
      const sd_face *f = &m->f[face];
      memcpy(m->ring[k++], m->v[f->v[NEXT(vnum(f, vert))]].p, sizeof m->ring[0]);
      face = next_face(m, face, vert);
    } while (face != v->start_face);
  } else {
    int32_t f2;
    while ((f2 = next_face(m, face, vert)) >= 0) face = f2;
    memcpy(m->ring[k++], m->v[m->f[face].v[NEXT(vnum(&m->f[face], vert))]].p, sizeof m->ring[0]);
    do {
      memcpy(m->ring[k++], m->v[m->f[face].v[PREV(vnum(&m->f[face], vert))]].p, sizeof m->ring[0]);
      face = prev_face(m, face, vert);
    } while (face >= 0);
  }
  return n;
}

/* ---- Loop's weights ---- */

static float loop_beta(int32_t n) { return n == 3 ? 3.f / 16.f : 3.f / (8.f * (float)n); }

static float loop_gamma(int32_t n) { return 1.f / ((float)n + 3.f / (8.f * loop_beta(n))); }

/* (1 - n beta) p + beta * sum(ring), the interior even-vertex and limit rules. */
static clr_result weight_one_ring(sd_mesh *m, int32_t vert, int use_gamma, float out[3]) {
  clr_result r = CLR_SUCCESS;
  int32_t n = one_ring(m, vert, &r);
  if (r != CLR_SUCCESS) return r;
  float beta = use_gamma ? loop_gamma(n) : loop_beta(n), w = 1.f - (float)n * beta;
  for (int c = 0; c < 3; ++c) out[c] = w * m->v[vert].p[c];
  for (int32_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) out[c] += beta * m->ring[i][c];
  return CLR_SUCCESS;
}

/* (1 - 2 beta) p + beta (first + last of the ring): the boundary even-vertex and limit rules. */
static clr_result weight_boundary(sd_mesh *m, int32_t vert, float beta, float out[3]) {
  clr_result r = CLR_SUCCESS;
  int32_t n = one_ring(m, vert, &r);
  if (r != CLR_SUCCESS) return r;
  for (int c = 0; c < 3; ++c) {
    out[c] = (1.f - 2.f * beta) * m->v[vert].p[c];
    out[c] += beta * m->ring[0][c];
    out[c] += beta * m->ring[n - 1][c];
  }
  return CLR_SUCCESS;
}

static int32_t other_vertex(const sd_face *f, int32_t a, int32_t b) {
  for (int i = 0; i < 3; ++i)
    if (f->v[i] != a && f->v[i] != b) return f->v[i];
  return f->v[0];
}

/* ---- one subdivision level ---- */

/* Index of the new vertex on each face edge (3 per face), created by the first face (in face
 * order) that has the edge, as pbrt's edge map does; returns the edge count. */
static int64_t number_edge_vertices(const sd_mesh *m, int32_t *edge_vertex) {
  int64_t next = m->nv;
  for (int32_t i = 0; i < m->nf; ++i) {
    const sd_face *f = &m->f[i];
    for (int k = 0; k < 3; ++k) {
      int32_t nb = f->f[k];
      if (nb < 0 || nb > i) {
        edge_vertex[3 * i + k] = (int32_t)(next < SD_MAX_COUNT ? next : SD_MAX_COUNT);
        ++next;
        continue;
      }
      const sd_face *g = &m->f[nb]; /* the neighbour has the edge reversed */
      int j = vnum(g, f->v[NEXT(k)]);
      edge_vertex[3 * i + k] = edge_vertex[3 * nb + j];
    }
  }
  return next - m->nv;
}

static void odd_vertex_position(const sd_mesh *m, int32_t face, int k, float out[3]) {
  const sd_face *f = &m->f[face];
  int32_t a = f->v[k], b = f->v[NEXT(k)];
  const float *p0 = m->v[a < b ? a : b].p, *p1 = m->v[a < b ? b : a].p;
  if (f->f[k] < 0) {
    for (int c = 0; c < 3; ++c) out[c] = 0.5f * p0[c], out[c] += 0.5f * p1[c];
    return;
  }
  const float *q0 = m->v[other_vertex(f, a, b)].p, *q1 = m->v[other_vertex(&m->f[f->f[k]], a, b)].p;
  for (int c = 0; c < 3; ++c) {
    out[c] = 3.f / 8.f * p0[c];
    out[c] += 3.f / 8.f * p1[c];
    out[c] += 1.f / 8.f * q0[c];
    out[c] += 1.f / 8.f * q1[c];
  }
}

/* Child faces: corner child j keeps vertex j, child 3 is the middle triangle (pbrt's layout). */
static void build_children(const sd_mesh *m, const int32_t *edge_vertex, sd_mesh *c) {
  for (int32_t i = 0; i < m->nf; ++i) {
    const sd_face *f = &m->f[i];
    sd_face *ch = &c->f[4 * (int64_t)i];
    for (int j = 0; j < 3; ++j) {
      ch[j].v[j] = f->v[j];
      ch[j].v[NEXT(j)] = edge_vertex[3 * i + j];
      ch[j].v[PREV(j)] = edge_vertex[3 * i + PREV(j)];
      ch[3].v[j] = edge_vertex[3 * i + j];
      ch[3].f[j] = 4 * i + NEXT(j);
      ch[j].f[NEXT(j)] = 4 * i + 3;
      int32_t f2 = f->f[j];
      ch[j].f[j] = f2 >= 0 ? 4 * f2 + vnum(&m->f[f2], f->v[j]) : -1;
      f2 = f->f[PREV(j)];
      ch[j].f[PREV(j)] = f2 >= 0 ? 4 * f2 + vnum(&m->f[f2], f->v[j]) : -1;
    }
  }
}

static clr_result subdivide_once(sd_mesh *m, sd_mesh *c) {
  int32_t *edge_vertex = malloc(3 * (size_t)(m->nf ? m->nf : 1) * sizeof *edge_vertex);
  if (!edge_vertex)
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "clr_loop_subdivide: no memory for edges");
  int64_t edges = number_edge_vertices(m, edge_vertex);
  clr_result r = sd_alloc(c, (int64_t)m->nv + edges, 4 * (int64_t)m->nf);
  for (int32_t i = 0; r == CLR_SUCCESS && i < m->nv; ++i) { /* even vertices */
    const sd_vertex *v = &m->v[i];
    sd_vertex *child = &c->v[i];
    child->boundary = v->boundary;
    child->start_face = 4 * v->start_face + vnum(&m->f[v->start_face], i);
    r = v->boundary ? weight_boundary(m, i, 1.f / 8.f, child->p)
                    : weight_one_ring(m, i, 0, child->p);
  }
  for (int32_t i = 0; r == CLR_SUCCESS && i < m->nf; ++i) { /* odd vertices */
    for (int k = 0; k < 3; ++k) {
      int32_t nb = m->f[i].f[k];
      if (nb >= 0 && nb < i) continue;
      sd_vertex *odd = &c->v[edge_vertex[3 * i + k]];
      odd->boundary = nb < 0;
      odd->start_face = 4 * i + 3;
      odd_vertex_position(m, i, k, odd->p);
    }
  }
  if (r == CLR_SUCCESS) build_children(m, edge_vertex, c);
  free(edge_vertex);
  if (r != CLR_SUCCESS) sd_free(c);
  return r;
}

/* ---- limit surface ---- */

static void cross(const float a[3], const float b[3], float out[3]) {
  out[0] = (float)((double)a[1] * b[2] - (double)a[2] * b[1]);
  out[1] = (float)((double)a[2] * b[0] - (double)a[0] * b[2]);
  out[2] = (float)((double)a[0] * b[1] - (double)a[1] * b[0]);
}

/* pbrt's tangents S, T of the limit surface at `vert` (positions already at the limit). */
static clr_result limit_normal(sd_mesh *m, int32_t vert, float normal[3]) {
  clr_result r = CLR_SUCCESS;
  int32_t n = one_ring(m, vert, &r);
  if (r != CLR_SUCCESS) return r;
  float(*ring)[3] = m->ring, s[3] = {0, 0, 0}, t[3] = {0, 0, 0};
  const float *p = m->v[vert].p;
  if (!m->v[vert].boundary) {
    for (int32_t j = 0; j < n; ++j) {
      float angle = 2.f * SD_PI * (float)j / (float)n, cj = cosf(angle), sj = sinf(angle);
      for (int c = 0; c < 3; ++c) s[c] += cj * ring[j][c], t[c] += sj * ring[j][c];
    }
  } else {
    for (int c = 0; c < 3; ++c) s[c] = ring[n - 1][c] - ring[0][c];
    if (n == 2) {
      for (int c = 0; c < 3; ++c) t[c] = ring[0][c] + ring[1][c] - 2.f * p[c];
    } else if (n == 3) {
      for (int c = 0; c < 3; ++c) t[c] = ring[1][c] - p[c];
    } else if (n == 4) {
      for (int c = 0; c < 3; ++c)
        t[c] = -1.f * ring[0][c] + 2.f * ring[1][c] + 2.f * ring[2][c] + -1.f * ring[3][c] +
               -2.f * p[c];
    } else {
      float theta = SD_PI / (float)(n - 1);
      for (int c = 0; c < 3; ++c) t[c] = sinf(theta) * (ring[0][c] + ring[n - 1][c]);
      for (int32_t k = 1; k < n - 1; ++k) {
        float w = (2.f * cosf(theta) - 2.f) * sinf((float)k * theta);
        for (int c = 0; c < 3; ++c) t[c] += w * ring[k][c];
      }
      for (int c = 0; c < 3; ++c) t[c] = -t[c];
    }
  }
  cross(s, t, normal);
  return CLR_SUCCESS;
}

static clr_result write_limit_mesh(sd_mesh *m, clr_mesh *out) {
  CLR_CHECK(clr_mesh_alloc(out, m->nv, m->nf, 1, 0, "clr_loop_subdivide"));
  clr_result r = CLR_SUCCESS;
  for (int32_t i = 0; r == CLR_SUCCESS && i < m->nv; ++i)
    r = m->v[i].boundary ? weight_boundary(m, i, 1.f / 5.f, out->p + 3 * (size_t)i)
                         : weight_one_ring(m, i, 1, out->p + 3 * (size_t)i);
  for (int32_t i = 0; i < m->nv; ++i) memcpy(m->v[i].p, out->p + 3 * (size_t)i, sizeof m->v[i].p);
  for (int32_t i = 0; r == CLR_SUCCESS && i < m->nv; ++i)
    r = limit_normal(m, i, out->n + 3 * (size_t)i);
  for (int32_t i = 0; i < m->nf; ++i)
    for (int k = 0; k < 3; ++k) out->indices[3 * (size_t)i + k] = (uint32_t)m->f[i].v[k];
  if (r != CLR_SUCCESS) clr_mesh_free(out);
  return r;
}

/* ---- input topology ---- */

/* Open-addressing map from directed edges (a, b) to face * 3 + edge number. */
typedef struct edge_map {
  uint64_t *keys; /* UINT64_MAX marks an empty slot */
  int32_t *values;
  size_t mask;
} edge_map;

static size_t edge_slot(const edge_map *map, uint64_t key) {
  uint64_t h = key * 0x9E3779B97F4A7C15ull;
  size_t slot = (size_t)(h >> 17) & map->mask;
  while (map->keys[slot] != UINT64_MAX && map->keys[slot] != key) slot = (slot + 1) & map->mask;
  return slot;
}

static uint64_t edge_key(uint32_t a, uint32_t b) { return (uint64_t)a << 32 | b; }

/* Links each face to its neighbours; fails on edges that are not manifold and consistently
 * wound. `orig` maps vertex numbers back to the caller's for messages. */
static clr_result link_faces(sd_mesh *m, const uint32_t *orig) {
  edge_map map;
  size_t size = 4;
  while (size < 6 * (size_t)m->nf) size *= 2;
  map.mask = size - 1;
  map.keys = malloc(size * sizeof *map.keys);
  map.values = malloc(size * sizeof *map.values);
  if (!map.keys || !map.values) {
    free(map.keys);
    free(map.values);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                              "clr_loop_subdivide: no memory for the edge map");
  }
  memset(map.keys, 0xff, size * sizeof *map.keys);
  clr_result r = CLR_SUCCESS;
  for (int32_t i = 0; r == CLR_SUCCESS && i < m->nf; ++i) {
    for (int k = 0; k < 3 && r == CLR_SUCCESS; ++k) {
      uint32_t a = (uint32_t)m->f[i].v[k], b = (uint32_t)m->f[i].v[NEXT(k)];
      size_t slot = edge_slot(&map, edge_key(a, b));
      if (map.keys[slot] != UINT64_MAX)
        r = clr_set_last_error(
            CLR_ERROR_SCENE,
            "clr_loop_subdivide: non-manifold mesh: edge (%u, %u) of "
            "triangle %ld is in more than two triangles or in two of opposite winding (also "
            "triangle %ld)",
            orig[a], orig[b], (long)i, (long)(map.values[slot] / 3));
      map.keys[slot] = edge_key(a, b);
      map.values[slot] = 3 * i + k;
    }
  }
  for (int32_t i = 0; r == CLR_SUCCESS && i < m->nf; ++i) {
    for (int k = 0; k < 3; ++k) {
      size_t slot = edge_slot(&map, edge_key((uint32_t)m->f[i].v[NEXT(k)], (uint32_t)m->f[i].v[k]));
      m->f[i].f[k] = map.keys[slot] == UINT64_MAX ? -1 : map.values[slot] / 3;
    }
  }
  free(map.keys);
  free(map.values);
  return r;
}

/* Marks boundary vertices and checks that each vertex's triangles form one fan. */
static clr_result classify_vertices(sd_mesh *m, const int32_t *incident, const uint32_t *orig) {
  for (int32_t i = 0; i < m->nv; ++i) {
    sd_vertex *v = &m->v[i];
    int32_t face = v->start_face;
    do face = next_face(m, face, i);
    while (face >= 0 && face != v->start_face);
    v->boundary = face < 0;
    int32_t fan = valence(m, i) - v->boundary;
    if (fan != incident[i])
      return clr_set_last_error(CLR_ERROR_SCENE,
                                "clr_loop_subdivide: non-manifold mesh: vertex %u joins "
                                "%ld triangles that do not form a single fan",
                                orig[i], (long)incident[i]);
  }
  return CLR_SUCCESS;
}

/* Copies the used vertices (in order) and the triangles of `in` into level 0. */
static clr_result build_base(const clr_mesh *in, sd_mesh *m, uint32_t **orig_out) {
  memset(m, 0, sizeof *m);
  int32_t *remap = malloc((size_t)(in->vertex_count ? in->vertex_count : 1) * sizeof *remap);
  int32_t *incident = calloc((size_t)(in->vertex_count ? in->vertex_count : 1), sizeof *incident);
  uint32_t *orig = malloc((size_t)(in->vertex_count ? in->vertex_count : 1) * sizeof *orig);
  clr_result r = remap && incident && orig
                     ? CLR_SUCCESS
                     : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY,
                                          "clr_loop_subdivide: no memory for %ld vertices",
                                          (long)in->vertex_count);
  for (int32_t t = 0; r == CLR_SUCCESS && t < in->triangle_count; ++t) {
    const uint32_t *tri = in->indices + 3 * (size_t)t;
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
      r = clr_set_last_error(CLR_ERROR_SCENE,
                             "clr_loop_subdivide: triangle %ld repeats a vertex (%u %u %u)",
                             (long)t, tri[0], tri[1], tri[2]);
    for (int k = 0; k < 3; ++k) ++incident[tri[k]];
  }
  int32_t used = 0;
  for (int32_t i = 0; r == CLR_SUCCESS && i < in->vertex_count; ++i) {
    remap[i] = incident[i] ? used : -1;
    if (incident[i]) incident[used] = incident[i], orig[used++] = (uint32_t)i;
  }
  if (r == CLR_SUCCESS) r = sd_alloc(m, used, in->triangle_count);
  for (int32_t i = 0; r == CLR_SUCCESS && i < used; ++i)
    memcpy(m->v[i].p, in->p + 3 * (size_t)orig[i], sizeof m->v[i].p);
  for (int32_t t = 0; r == CLR_SUCCESS && t < in->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      int32_t v = remap[in->indices[3 * (size_t)t + k]];
      m->f[t].v[k] = v;
      m->v[v].start_face = t; /* the last triangle using it, as in pbrt */
    }
  }
  if (r == CLR_SUCCESS) r = link_faces(m, orig);
  if (r == CLR_SUCCESS) r = classify_vertices(m, incident, orig);
  free(remap);
  free(incident);
  if (r != CLR_SUCCESS) {
    free(orig);
    sd_free(m);
    return r;
  }
  *orig_out = orig;
  return CLR_SUCCESS;
}

clr_result clr_loop_subdivide(const clr_mesh *in, int32_t nlevels, clr_mesh *out) {
  if (!out) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_loop_subdivide: out is NULL");
  memset(out, 0, sizeof *out);
  if (!in) return clr_set_last_error(CLR_ERROR_NULL_POINTER, "clr_loop_subdivide: in is NULL");
  if (nlevels < 0)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "clr_loop_subdivide: nlevels is %ld, must be >= 0", (long)nlevels);
  /* Each level makes four triangles of one: refuse up front what could never fit. */
  int64_t triangles = in->triangle_count;
  for (int32_t i = 0; i < nlevels; ++i) {
    if (triangles > CLR_LOOP_MAX_TRIANGLES / 4)
      return clr_set_last_error(CLR_ERROR_SCENE,
                                "clr_loop_subdivide: \"nlevels\" %ld would make "
                                "%ld triangles x 4^%ld, more than the limit of %ld triangles",
                                (long)nlevels, (long)in->triangle_count, (long)nlevels,
                                (long)CLR_LOOP_MAX_TRIANGLES);
    triangles *= 4;
  }
  CLR_CHECK(clr_mesh_validate(in, "clr_loop_subdivide: input mesh"));
  sd_mesh level = {0};
  uint32_t *orig = NULL;
  CLR_CHECK(build_base(in, &level, &orig));
  free(orig);
  clr_result r = CLR_SUCCESS;
  for (int32_t i = 0; r == CLR_SUCCESS && i < nlevels; ++i) {
    sd_mesh next = {0};
    r = subdivide_once(&level, &next);
    sd_free(&level);
    if (r == CLR_SUCCESS) level = next;
  }
  if (r == CLR_SUCCESS) r = write_limit_mesh(&level, out);
  sd_free(&level);
  return r;
}
