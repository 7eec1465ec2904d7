/* Embree tracing throughput (rays/s, one thread) on a 100352-triangle height field: packets of
 * the tracer's width (rtcIntersect8/16; clr_tracer_packet_width) and occlusion (one call of
 * every ray: Embree's ray stream, rtcOccluded1M, in this triangle-only scene) against one ray
 * at a time (rtcIntersect1), the baseline, for incoherent and coherent rays. Not per
 * device: the tracer runs on the host. */
#include <math.h>
#include <stdlib.h>
#include "bench.h"
#include "mesh.h"
#include "tracer.h"

enum { GRID = 224 }; /* 224 x 224 quads = 100352 triangles */

static uint64_t rng_state = 1;
static double rnd(void) { /* 53-bit uniform in [0,1) from a 64-bit LCG */
  rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static clr_ray ray(double ox, double oy, double oz, double dx, double dy, double dz) {
  return (clr_ray){(float)ox, (float)oy, (float)oz, 0.0f, (float)dx,
                   (float)dy, (float)dz, INFINITY,  0.0f};
}

static int build_grid(clr_tracer *t) {
  clr_mesh m;
  if (clr_mesh_alloc(&m, (GRID + 1) * (GRID + 1), 2 * GRID * GRID, 0, 0, "grid") != CLR_SUCCESS)
    return 0;
  for (int y = 0; y <= GRID; ++y)
    for (int x = 0; x <= GRID; ++x) {
      float *p = m.p + 3 * (y * (GRID + 1) + x);
      p[0] = (float)x / GRID, p[1] = (float)y / GRID, p[2] = (float)(0.05 * rnd());
    }
  uint32_t *idx = m.indices;
  for (int y = 0; y < GRID; ++y)
    for (int x = 0; x < GRID; ++x) {
      uint32_t a = (uint32_t)(y * (GRID + 1) + x), b = a + 1, c = a + GRID + 1, d = c + 1;
      *idx++ = a, *idx++ = b, *idx++ = d, *idx++ = a, *idx++ = d, *idx++ = c;
    }
  int ok = clr_tracer_create(t) == CLR_SUCCESS &&
           clr_tracer_add_mesh(*t, 0, &m, 0, NULL) == CLR_SUCCESS &&
           clr_tracer_commit(*t) == CLR_SUCCESS;
  clr_mesh_free(&m);
  return ok;
}

typedef struct trace_run {
  clr_tracer tracer;
  const clr_ray *rays;
  clr_hit *hits;
  uint8_t *occluded;
  int count, mode; /* 0 packets, 1 single rays, 2 occlusion packets */
} trace_run;

static int trace_once(void *user) {
  trace_run *r = user;
  clr_result res = r->mode == 0 ? clr_tracer_intersect(r->tracer, r->rays, r->hits, r->count)
                   : r->mode == 1
                       ? clr_tracer_intersect_single(r->tracer, r->rays, r->hits, r->count)
                       : clr_tracer_occluded(r->tracer, r->rays, r->occluded, r->count);
  return res == CLR_SUCCESS;
}

static void report(const char *rays_kind, trace_run *r, int reps) {
  double rate[3];
  for (int mode = 0; mode < 3; ++mode) {
    r->mode = mode;
    double t = bench_median(reps, trace_once, r);
    rate[mode] = t > 0 ? r->count / t : -1;
  }
  printf(
      "{\"bench\":\"tracer\",\"rays\":\"%s\",\"triangles\":%d,\"threads\":1,"
      "\"packet_width\":%d,\"intersect_rays_per_s\":%.4g,\"occluded_rays_per_s\":%.4g,"
      "\"baseline\":\"intersect1\",\"baseline_rays_per_s\":%.4g,\"ratio\":%.3f}\n",
      rays_kind, 2 * GRID * GRID, clr_tracer_packet_width(r->tracer), rate[0], rate[2], rate[1],
      rate[0] / rate[1]);
}

void bench_tracer(const bench_options *o) {
  int count = o->quick ? 200000 : 1000000, reps = bench_reps(o, 1, 3);
  trace_run r = {NULL, NULL, NULL, NULL, count, 0};
  clr_ray *rays = malloc((size_t)count * sizeof *rays);
  r.hits = malloc((size_t)count * sizeof *r.hits);
  r.occluded = malloc((size_t)count);
  if (!rays || !r.hits || !r.occluded || !build_grid(&r.tracer)) {
    printf("{\"bench\":\"tracer\",\"error\":\"setup failed\"}\n");
    goto done;
  }
  r.rays = rays;
  for (int i = 0; i < count; ++i) { /* incoherent: random origins above, random targets on it */
    double ox = 2 * rnd() - 0.5, oy = 2 * rnd() - 0.5, oz = 0.5 + rnd(), qx = rnd(), qy = rnd();
    rays[i] = ray(ox, oy, oz, qx - ox, qy - oy, 0.025 - oz);
  }
  report("incoherent", &r, reps);
  for (int i = 0; i < count; ++i) { /* coherent: a pinhole camera's pixels in 4x4 blocks */
    int block = i / 16, x = 4 * (block % 250) + i % 4, y = 4 * (block / 250) + (i / 4) % 4;
    rays[i] = ray(0.5, 0.5, 2.0, (x + 0.5) / 1000 - 0.5, (y % 1000 + 0.5) / 1000 - 0.5, -2.0);
  }
  report("coherent", &r, reps);
done:
  if (r.tracer) clr_tracer_release(r.tracer);
  free(rays);
  free(r.hits);
  free(r.occluded);
}
