/* pbrt-v3's AOIntegrator over a batch of camera samples. */
#include "hemisphere_wave.h"
#include "integrator_internal.h"
#include "float_minmax.h"

static void uniform_hemisphere(const float u[2], float w[3]) {
  float z = u[0], r = sqrtf(rs_fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * RS_PI * u[1];
  w[0] = r * cosf(phi);
  w[1] = r * sinf(phi);
  w[2] = z;
}

/* v where the ray is not occluded (0), else +0, by masking its bits: no branch to mispredict. */
static inline float unless_occluded(uint8_t occluded, float v) {
  uint32_t bits;
  memcpy(&bits, &v, sizeof bits);
  bits &= (uint32_t)occluded - 1u;
  memcpy(&v, &bits, sizeof v);
  return v;
}

clr_result clr_li_ao(const clr_integrator *it, const clr_render_scene *sc,
                     clr_integrator_scratch *s, const float *values, int count, float *L,
                     clr_integrator_counters *c) {
  clr_integrator_intersect_visible(sc, s, count, NULL, 1, c);
  int n = it->ao_samples;
  CLR_CHECK(reserve_rays(s, (size_t)count * (size_t)n));
  /* directions first, with each one's Dot(wi,n)/(pdf n) term, then one occlusion query; the
   * cosine-hemisphere directions of the whole wave in one vector loop */
  size_t total = (size_t)count * (size_t)n;
  if (total > s->ao_cap) {
    float *block = realloc(s->ao_terms, total * 6 * sizeof *block);
    if (!block) return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "integrator scratch");
    s->ao_terms = block;
    s->ao_cap = total;
  }
  float *term = s->ao_terms, *u0 = term + s->ao_cap, *u1 = u0 + s->ao_cap, *dx = u1 + s->ao_cap,
        *dy = dx + s->ao_cap, *dz = dy + s->ao_cap;
  if (it->ao_cos_sample) {
    int32_t m = 0;
    for (int i = 0; i < count; ++i) {
      if (s->surfaces[i].has_material < 0) continue;
      const float *u = values + (size_t)i * (size_t)it->values_per_sample + it->value_offset;
      for (int k = 0; k < n; ++k, ++m) {
        u0[m] = u[2 * k];
        u1[m] = u[2 * k + 1];
      }
    }
    clr_wave_cosine_hemisphere(m, u0, u1, dx, dy, dz);
  }
  size_t q = 0;
  for (int i = 0; i < count; ++i) {
    const clr_surface *sf = &s->surfaces[i];
    if (sf->has_material < 0) continue;
    const float *u = values + (size_t)i * (size_t)it->values_per_sample + it->value_offset;
    float ss[3] = {sf->dpdu[0], sf->dpdu[1], sf->dpdu[2]}, ts[3], up[3], down[3];
    rs_normalize(ss);
    rs_cross(sf->n_geom, ss, ts);
    /* clr_render_scene_spawn_ray's two possible origins, computed once per point */
    float e =
        1e-4f * (1.0f + rs_fmaxf(fabsf(sf->p[0]), rs_fmaxf(fabsf(sf->p[1]), fabsf(sf->p[2]))));
    for (int a = 0; a < 3; ++a) {
      up[a] = sf->p[a] + sf->ng[a] * e;
      down[a] = sf->p[a] + sf->ng[a] * -e;
    }
    if (it->ao_cos_sample) { /* the point's directions and terms in one vector loop */
      const float frame[9] = {ss[0], ss[1],     ss[2],     ts[0],    ts[1],
                              ts[2], sf->ng[0], sf->ng[1], sf->ng[2]};
      clr_wave_ao_directions(n, frame, (float)n, dx + q, dy + q, dz + q, u0 + q, term + q);
    }
    for (int k = 0; k < n; ++k, ++q) {
      float wi[3], cos_n;
      if (it->ao_cos_sample) { /* u0 holds Dot(wi, n) now */
        wi[0] = dx[q];
        wi[1] = dy[q];
        wi[2] = dz[q];
        cos_n = u0[q];
      } else {
        float w[3];
        uniform_hemisphere(u + 2 * k, w);
        for (int a = 0; a < 3; ++a) wi[a] = ss[a] * w[0] + ts[a] * w[1] + sf->ng[a] * w[2];
        cos_n = rs_dot(wi, sf->ng);
        term[q] = cos_n / ((1.0f / (2.0f * RS_PI)) * (float)n); /* the uniform pdf */
      }
      const float *o = cos_n < 0.0f ? down : up;
      clr_ray *r = &s->rays[q];
      r->ox = o[0];
      r->oy = o[1];
      r->oz = o[2];
      r->tnear = 0.0f;
      r->dx = wi[0];
      r->dy = wi[1];
      r->dz = wi[2];
      r->tfar = INFINITY;
      r->time = sf->time;
    }
  }
  occlude(sc, s->rays, s->occluded, q, c);
  q = 0;
  for (int i = 0; i < count; ++i) {
    const clr_surface *sf = &s->surfaces[i];
    L[3 * i] = L[3 * i + 1] = L[3 * i + 2] = 0.0f;
    if (sf->has_material < 0) continue;
    float sum = 0.0f;
    for (int k = 0; k < n; ++k, ++q) /* sum + 0 is sum: it starts at +0, so it is never -0 */
      sum += unless_occluded(s->occluded[q], term[q]);
    L[3 * i] = L[3 * i + 1] = L[3 * i + 2] = sum;
  }
  return CLR_SUCCESS;
}
