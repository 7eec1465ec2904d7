/* TEMPORARY (renderer branch): host-only stand-in for the sampler module (hash-random values,
 * halton samplepixelcenter honoured) until host/lib/sampler.c lands in main. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "clr_internal.h"
#include "clrender/sampler.h"
#include "pcg32.h"

struct clr_sampler_t {
  clr_sampler_desc desc;
  int spp;
  int refs;
};

void clr_sampler_desc_init(clr_sampler_desc *d, clr_sampler_type type) {
  memset(d, 0, sizeof *d);
  d->struct_size = sizeof *d;
  d->type = type;
  d->pixel_samples = type == CLR_SAMPLER_RANDOM ? 4 : 16;
  d->x_samples = d->y_samples = 4;
  d->jitter = 1;
  d->dimensions = 4;
  d->seeding = CLR_SEEDING_PIXEL;
  d->film.x_resolution = 1280;
  d->film.y_resolution = 720;
  d->film.crop_window[1] = d->film.crop_window[3] = 1.0f;
  d->film.filter_radius[0] = d->film.filter_radius[1] = 0.5f;
}

static const char *names[] = {"random", "stratified", "halton", "sobol"};
clr_result clr_sampler_type_from_name(const char *name, clr_sampler_type *type) {
  for (int i = 0; i < 4; ++i)
    if (name && strcmp(name, names[i]) == 0) { *type = (clr_sampler_type)i; return CLR_SUCCESS; }
  return clr_fail(NULL, CLR_ERROR_INVALID_SAMPLER, "unknown sampler \"%s\"", name ? name : "");
}
const char *clr_sampler_type_name(clr_sampler_type t) { return (unsigned)t < 4 ? names[t] : "?"; }

clr_result clr_sampler_create(clr_context ctx, const clr_sampler_desc *desc, clr_sampler *out) {
  (void)ctx;
  clr_sampler s = calloc(1, sizeof *s);
  if (!s) return clr_fail(NULL, CLR_ERROR_OUT_OF_MEMORY, "sampler stub");
  s->desc = *desc;
  s->refs = 1;
  s->spp = desc->type == CLR_SAMPLER_STRATIFIED ? desc->x_samples * desc->y_samples
                                                : desc->pixel_samples;
  if (desc->type == CLR_SAMPLER_SOBOL) {
    int p = 1;
    while (p < s->spp) p *= 2;
    s->spp = p;
  }
  int spp = s->spp;
  if (spp < 1) { free(s); return clr_fail(NULL, CLR_ERROR_INVALID_SPP, "spp %d", spp); }
  *out = s;
  return CLR_SUCCESS;
}
void clr_sampler_retain(clr_sampler s) { if (s) s->refs++; }
void clr_sampler_release(clr_sampler s) { if (s && --s->refs == 0) free(s); }
int32_t clr_sampler_spp(clr_sampler s) { return s->spp; }
int clr_sampler_has_global_index(clr_sampler s) { return s->desc.type >= CLR_SAMPLER_HALTON; }

clr_bounds2i clr_sampler_pixel_bounds(clr_sampler s) {
  const clr_film_geometry *f = &s->desc.film;
  clr_bounds2i b;
  b.x0 = (int32_t)ceilf((float)f->x_resolution * f->crop_window[0]);
  b.x1 = (int32_t)ceilf((float)f->x_resolution * f->crop_window[1]);
  b.y0 = (int32_t)ceilf((float)f->y_resolution * f->crop_window[2]);
  b.y1 = (int32_t)ceilf((float)f->y_resolution * f->crop_window[3]);
  return b;
}
clr_bounds2i clr_sampler_sample_bounds(clr_sampler s) {
  clr_bounds2i p = clr_sampler_pixel_bounds(s), b;
  const float *r = s->desc.film.filter_radius;
  b.x0 = (int32_t)floorf((float)p.x0 + 0.5f - r[0]);
  b.y0 = (int32_t)floorf((float)p.y0 + 0.5f - r[1]);
  b.x1 = (int32_t)ceilf((float)p.x1 - 0.5f + r[0]);
  b.y1 = (int32_t)ceilf((float)p.y1 - 0.5f + r[1]);
  return b;
}

void clr_sample_batch_init(clr_sample_batch *b) { memset(b, 0, sizeof *b); b->struct_size = sizeof *b; }
void clr_sample_output_init(clr_sample_output *o) { memset(o, 0, sizeof *o); o->struct_size = sizeof *o; }

clr_result clr_sample_layout_values(const clr_sample_request *r, int32_t count, int32_t *values) {
  int32_t n = 0;
  for (int i = 0; i < count; ++i) n += r[i].dims * (r[i].array_size > 0 ? r[i].array_size : 1);
  *values = n;
  return CLR_SUCCESS;
}

clr_result clr_sampler_generate_reference(clr_sampler s, const clr_sample_batch *b,
                                          const clr_sample_output *o) {
  int32_t nv;
  clr_sample_layout_values(b->requests, b->request_count, &nv);
  int spp = b->sample_count ? b->sample_count : s->spp;
  int w = b->pixels.x1 - b->pixels.x0;
  for (int py = b->pixels.y0; py < b->pixels.y1; ++py)
    for (int px = b->pixels.x0; px < b->pixels.x1; ++px)
      for (int i = 0; i < spp; ++i) {
        size_t base = ((size_t)((py - b->pixels.y0) * w + (px - b->pixels.x0)) * (size_t)spp + (size_t)i);
        uint64_t key = ((uint64_t)(uint32_t)px << 40) ^ ((uint64_t)(uint32_t)py << 20) ^
                       (uint64_t)(b->first_sample + i) ^ ((uint64_t)s->desc.seed << 52);
        float *v = o->host_values + base * (size_t)nv;
        for (int k = 0; k < nv; ++k) v[k] = clr_hash_float(clr_mix64(key) + (uint64_t)k * 0x9E3779B97F4A7C15ull);
        if (s->desc.type == CLR_SAMPLER_HALTON && s->desc.sample_pixel_center) v[0] = v[1] = 0.5f;
        if (o->host_indices) o->host_indices[base] = base;
      }
  return CLR_SUCCESS;
}

clr_result clr_sampler_generate(clr_sampler s, const clr_sample_batch *b, const clr_sample_output *o) {
  return clr_sampler_generate_reference(s, b, o);
}
