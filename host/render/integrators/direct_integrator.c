/* pbrt-v3's DirectLightingIntegrator over a batch of camera samples: every light sampled at each
 * hit, specular reflection and transmission followed to maxdepth. */
#include "integrator_internal.h"
#include "microfacet.h"
#include "specular_differentials.h"
#include "surface_bsdf.h"
#include "float_minmax.h"

/* pbrt-v3 SpecularReflect and SpecularTransmit for a lobe BSDF: each followed when it has such
 * a component, with f |cos| / pdf as the factor (sample values hashed); rd (or NULL): the
 * incoming ray's differentials, propagated into nextd (transmission with BSDF::eta as pbrt-v3's
 * SpecularTransmit). */
static void general_specular(const clr_surface *sf, const float wo[3], uint64_t key, int depth,
                             const clr_ray_differential *rd, clr_ray next[2],
                             clr_ray_differential *nextd, float factor[6], int cont[2]) {
  for (int q = 0; q < 2; ++q) {
    int mask = q ? CLR_BXDF_SPECULAR_TRANSMISSION : CLR_BXDF_SPECULAR_REFLECTION, flags;
    if (!clr_bsdf_count(&sf->bsdf, mask)) continue;
    float u[2] = {fallback(key, 9000 + 16 * depth + 2 * q),
                  fallback(key, 9001 + 16 * depth + 2 * q)};
    float wi[3], pdf, f[3];
    if (!clr_bsdf_sample(&sf->bsdf, wo, u, mask, wi, &pdf, f, &flags)) continue;
    if (rs_dot(wi, sf->ns) == 0.0f) continue;
    for (int a = 0; a < 3; ++a) factor[3 * q + a] = f[a] / pdf;
    clr_render_scene_spawn_ray(sf, wi, &next[q]);
    if (nextd) {
      nextd[q].has = 0;
      float eta = rs_dot(wo, sf->n_geom) > 0.0f ? 1.0f / sf->bsdf.eta : sf->bsdf.eta;
      if (!q) rs_reflect_differential(sf, rd, wo, wi, &nextd[q]);
      if (q) rs_transmit_differential(sf, rd, wo, wi, eta, &nextd[q]);
    }
    cont[q] = 1;
  }
}

/* Direct lighting of the surfaces s->surfaces[0..n) hit by s->rays2[0..n) (n samples mapped to
 * the caller's samples by map) into Lk; mirror surfaces continue into next[] (pbrt-v3
 * SpecularReflect while depth + 1 < maxdepth) with their differentials in nextd when diffs (the
 * rays2' differentials) is not NULL. Light sample values: the layout's depth-0 arrays,
 * hashed values deeper. */
static clr_result direct_wave(const clr_integrator *it, const clr_render_scene *sc,
                              clr_integrator_scratch *s, const float *values, const uint64_t *keys,
                              int n, const int *map, int depth, float *Lk, int *cont, clr_ray *next,
                              const clr_ray_differential *diffs, clr_ray_differential *nextd,
                              float *factor, clr_integrator_counters *c) {
  float *wo = s->beta;
  int nj = 0;
  for (int k = 0; k < n; ++k) {
    const clr_surface *sf = &s->surfaces[k];
    int i = map[k];
    const float *v = values + (size_t)i * (size_t)it->values_per_sample;
    const float one[3] = {1, 1, 1};
    const clr_ray_differential *rd = diffs ? &diffs[k] : NULL;
    Lk[3 * k] = Lk[3 * k + 1] = Lk[3 * k + 2] = 0.0f;
    cont[2 * k] = cont[2 * k + 1] = 0;
    if (sf->has_material < 0) {
      add_escaped(sc, &s->rays2[k], one, Lk + 3 * k);
      continue;
    }
    wo[3 * k] = -s->rays2[k].dx;
    wo[3 * k + 1] = -s->rays2[k].dy;
    wo[3 * k + 2] = -s->rays2[k].dz;
    for (int a = 0; a < 3; ++a) Lk[3 * k + a] += sf->le[a];
    if (sf->glass) { /* pbrt-v3 without multiple lobes: SpecularReflection + SpecularTransmission,
                      * SpecularReflect and SpecularTransmit both followed */
      if (depth + 1 >= it->max_depth) continue;
      const float *w = wo + 3 * k;
      float wi[3], cos_o = rs_dot(w, sf->ns);
      int entering = rs_dot(w, sf->n_geom) > 0.0f;
      float F = clr_fr_dielectric(entering ? cos_o : -cos_o, 1.0f, sf->eta);
      mirror_direction(sf, w, wi);
      for (int a = 0; a < 3; ++a) factor[6 * k + a] = sf->kr[a] * F;
      if (!is_black(factor + 6 * k) && rs_dot(wi, sf->ns) != 0.0f) {
        clr_render_scene_spawn_ray(sf, wi, &next[2 * k]);
        if (nextd) rs_reflect_differential(sf, rd, w, wi, &nextd[2 * k]);
        cont[2 * k] = 1;
      }
      float eta = entering ? 1.0f / sf->eta : sf->eta;
      float sin2_t = eta * eta * rs_fmaxf(0.0f, 1.0f - cos_o * cos_o);
      if (sin2_t < 1.0f) {
        float cos_t = sqrtf(1.0f - sin2_t);
        for (int a = 0; a < 3; ++a) wi[a] = -eta * w[a] + (eta * cos_o - cos_t) * sf->ns[a];
        for (int a = 0; a < 3; ++a) factor[6 * k + 3 + a] = sf->kt[a] * (1.0f - F) * eta * eta;
        if (!is_black(factor + 6 * k + 3)) {
          clr_render_scene_spawn_ray(sf, wi, &next[2 * k + 1]);
          if (nextd) rs_transmit_differential(sf, rd, w, wi, eta, &nextd[2 * k + 1]);
          cont[2 * k + 1] = 1;
        }
      }
      continue;
    }
    if (sf->mirror) { /* no non-specular component: no light sampling */
      if (depth + 1 < it->max_depth && !is_black(sf->kr)) {
        float wi[3];
        mirror_direction(sf, wo + 3 * k, wi);
        if (rs_dot(wi, sf->ns) != 0.0f) {
          clr_render_scene_spawn_ray(sf, wi, &next[2 * k]);
          if (nextd) rs_reflect_differential(sf, rd, wo + 3 * k, wi, &nextd[2 * k]);
          for (int a = 0; a < 3; ++a) factor[6 * k + a] = sf->kr[a]; /* f |cos| / pdf */
          cont[2 * k] = 1;
        }
      }
      continue;
    }
    if (sf->general && depth + 1 < it->max_depth)
      general_specular(sf, wo + 3 * k, keys[i], depth, rd, next + 2 * k,
                       nextd ? nextd + 2 * k : NULL, factor + 6 * k, cont + 2 * k);
    if (!it->light_count) continue;
    if (it->direct_all) {
      int dim = 0;
      for (int j = 0; j < it->light_count; ++j) {
        int ns = it->light_samples[j], off = depth == 0 ? it->light_offsets[j] : -1;
        for (int q = 0; q < ns; ++q) {
          direct_job *jb = &s->jobs[nj++];
          jb->sample = k;
          jb->light = j;
          jb->continues = 0;
          int base = depth == 0 ? 100 : 5000 + 1000 * depth;
          for (int a = 0; a < 2; ++a) {
            jb->u_light[a] = off >= 0 ? v[off + 2 * q + a] : fallback(keys[i], base + dim++);
            jb->u_scatter[a] =
                off >= 0 ? v[off + 2 * ns + 2 * q + a] : fallback(keys[i], base + dim++);
          }
          jb->scale[0] = jb->scale[1] = jb->scale[2] = 1.0f / (float)ns;
        }
      }
    } else {
      float u[5];
      for (int a = 0; a < 5; ++a)
        u[a] = depth == 0 ? v[it->value_offset + a] : fallback(keys[i], 5000 + 1000 * depth + a);
      direct_job *jb = &s->jobs[nj++];
      jb->continues = 0;
      int nl = it->light_count;
      jb->light = (int)rs_fminf(u[0] * (float)nl, (float)(nl - 1));
      jb->sample = k;
      memcpy(jb->u_light, u + 1, 2 * sizeof(float));
      memcpy(jb->u_scatter, u + 3, 2 * sizeof(float));
      jb->scale[0] = jb->scale[1] = jb->scale[2] = (float)nl;
    }
  }
  CLR_CHECK(clr_estimate_direct(it, sc, s, s->jobs, nj, wo, c));
  add_jobs(s->jobs, nj, Lk);
  return CLR_SUCCESS;
}

clr_result clr_li_direct(const clr_integrator *it, const clr_render_scene *sc,
                         clr_integrator_scratch *s, const float *values, const uint64_t *keys,
                         int count, float *L, clr_integrator_counters *c) {
  size_t per = 0;
  if (it->direct_all)
    for (int j = 0; j < it->light_count; ++j) per += (size_t)it->light_samples[j];
  else
    per = it->light_count ? 1 : 0;
  /* entries: a camera sample's path through mirrors and glass (glass splits one in two) */
  size_t cap = (size_t)(count > 0 ? count : 1);
  float *Lk = NULL, *weight = NULL, *factor = NULL;
  int *map = NULL, *cont = NULL;
  clr_ray *next = NULL;
  /* the entries' differentials and their continuations' (only when the camera rays have them) */
  clr_ray_differential *diffs = NULL, *nextd = NULL;
  const clr_ray_differential *cur = clr_render_scene_uses_differentials(sc) ? s->diffs : NULL;
  clr_result r = CLR_SUCCESS;
  int n = count;
  for (int depth = 0; r == CLR_SUCCESS && n > 0; ++depth) {
    if (depth == 0 || (size_t)n > cap || !Lk) {
      cap = (size_t)n > cap ? (size_t)n : cap;
      float *a = realloc(Lk, cap * 3 * sizeof *a),
            *b = a ? realloc(weight, cap * 3 * sizeof *b) : NULL;
      if (a) Lk = a;
      if (b) weight = b;
      float *f = b ? realloc(factor, cap * 6 * sizeof *f) : NULL;
      if (f) factor = f;
      int *m1 = f ? realloc(map, cap * sizeof *m1) : NULL;
      if (m1) map = m1;
      int *c1 = m1 ? realloc(cont, cap * 2 * sizeof *c1) : NULL;
      if (c1) cont = c1;
      clr_ray *nx = c1 ? realloc(next, cap * 2 * sizeof *nx) : NULL;
      if (nx) next = nx;
      clr_ray_differential *nd = nx && cur ? realloc(nextd, cap * 2 * sizeof *nd) : NULL;
      if (nd) nextd = nd;
      if (!nx || (cur && !nd)) {
        r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "direct lighting integrator");
        break;
      }
    }
    if (depth == 0)
      for (int i = 0; i < count; ++i) { /* s->rays2[0..count) holds the camera rays */
        map[i] = i;
        L[3 * i] = L[3 * i + 1] = L[3 * i + 2] = 0.0f;
        weight[3 * i] = weight[3 * i + 1] = weight[3 * i + 2] = 1.0f;
      }
    r = reserve_samples(s, (size_t)n);
    if (r == CLR_SUCCESS) r = reserve_rays(s, (size_t)n);
    if (r == CLR_SUCCESS) r = reserve_jobs(s, (size_t)n * per + 1);
    if (r != CLR_SUCCESS) break;
    clr_integrator_intersect_visible(sc, s, n, cur, 0, c);
    r = direct_wave(it, sc, s, values, keys, n, map, depth, Lk, cont, next, cur, cur ? nextd : NULL,
                    factor, c);
    if (r != CLR_SUCCESS) break;
    int m = 0;
    for (int k = 0; k < n; ++k)
      for (int a = 0; a < 3; ++a) L[3 * map[k] + a] += weight[3 * k + a] * Lk[3 * k + a];
    for (int k = 0; k < n; ++k) m += cont[2 * k] + cont[2 * k + 1];
    if (m == 0) break;
    r = reserve_samples(s, (size_t)m);
    float *nw = r == CLR_SUCCESS ? malloc((size_t)m * 3 * sizeof *nw) : NULL;
    int *nm = nw ? malloc((size_t)m * sizeof *nm) : NULL;
    clr_ray_differential *ndf = nm && cur ? malloc((size_t)m * sizeof *ndf) : NULL;
    if (!nm || (cur && !ndf)) {
      free(nw);
      free(nm);
      if (r == CLR_SUCCESS)
        r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "direct lighting integrator");
      break;
    }
    int at = 0;
    for (int k = 0; k < n; ++k)
      for (int q = 0; q < 2; ++q) {
        if (!cont[2 * k + q]) continue;
        const float *f = factor + 6 * k + 3 * q;
        s->rays2[at] = next[2 * k + q];
        if (ndf) ndf[at] = nextd[2 * k + q];
        for (int a = 0; a < 3; ++a) nw[3 * at + a] = weight[3 * k + a] * f[a];
        nm[at++] = map[k];
      }
    free(weight);
    free(map);
    weight = nw;
    map = nm;
    free(diffs);
    diffs = ndf;
    cur = ndf;
    if ((size_t)m > cap) { /* the other per-entry arrays are grown at the top of the loop */
      float *a = realloc(Lk, (size_t)m * 3 * sizeof *a);
      if (!a) {
        r = clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "direct lighting integrator");
        break;
      }
      Lk = a;
    }
    n = m;
  }
  free(Lk);
  free(weight);
  free(factor);
  free(map);
  free(cont);
  free(next);
  free(diffs);
  free(nextd);
  return r;
}
