/* Adaptive sampling from A/B half films (see adaptive.h). */
#include "adaptive.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "render_error.h"

clr_result clr_adaptive_init(clr_adaptive *ad, clr_context ctx, clr_film film, float threshold) {
  memset(ad, 0, sizeof *ad);
  ad->bounds = film_pixel_bounds(film);
  ad->width = ad->bounds.x1 - ad->bounds.x0;
  ad->height = ad->bounds.y1 - ad->bounds.y0;
  ad->threshold = threshold;
  size_t n = (size_t)ad->width * (size_t)ad->height;
  ad->active = malloc(n ? n : 1);
  ad->error = malloc((n ? n : 1) * sizeof *ad->error);
  if (!ad->active || !ad->error) {
    clr_adaptive_free(ad);
    return clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "adaptive sampling: %zu pixels", n);
  }
  memset(ad->active, 1, n);
  for (size_t i = 0; i < n; ++i) ad->error[i] = INFINITY;
  ad->active_count = (int64_t)n;
  for (int k = 0; k < 2; ++k) {
    clr_result r = film_create(ctx, film_get_desc(film), &ad->half[k]);
    if (r != CLR_SUCCESS) {
      clr_adaptive_free(ad);
      return r;
    }
  }
  return CLR_SUCCESS;
}

void clr_adaptive_free(clr_adaptive *ad) {
  for (int k = 0; k < 2; ++k) film_release(ad->half[k]);
  free(ad->active);
  free(ad->error);
  memset(ad, 0, sizeof *ad);
}

int clr_adaptive_pixel_active(const clr_adaptive *ad, int32_t x, int32_t y) {
  if (!ad) return 1;
  x = x < ad->bounds.x0 ? ad->bounds.x0 : x >= ad->bounds.x1 ? ad->bounds.x1 - 1 : x;
  y = y < ad->bounds.y0 ? ad->bounds.y0 : y >= ad->bounds.y1 ? ad->bounds.y1 - 1 : y;
  return ad->active[(size_t)(y - ad->bounds.y0) * (size_t)ad->width + (size_t)(x - ad->bounds.x0)];
}

int64_t clr_adaptive_count_active(const clr_adaptive *ad, clr_bounds2i pixels) {
  int64_t n = 0;
  for (int32_t y = pixels.y0; y < pixels.y1; ++y)
    for (int32_t x = pixels.x0; x < pixels.x1; ++x) n += clr_adaptive_pixel_active(ad, x, y);
  return n;
}

int clr_adaptive_next_run(const clr_adaptive *ad, int32_t y, int32_t x, int32_t x1, int32_t gap,
                          int32_t *start) {
  while (x < x1 && !clr_adaptive_pixel_active(ad, x, y)) ++x;
  *start = x;
  int32_t end = x;
  while (x < x1) {
    if (clr_adaptive_pixel_active(ad, x, y)) {
      end = ++x;
    } else if (x - end + 1 < gap) {
      ++x;
    } else {
      break;
    }
  }
  return end > *start ? end : x1;
}

clr_result clr_adaptive_add_pass(clr_adaptive *ad, clr_film pass, int32_t pass_index) {
  return film_merge_film(ad->half[pass_index & 1], pass);
}

clr_result clr_adaptive_update(clr_adaptive *ad) {
  size_t n = (size_t)ad->width * (size_t)ad->height;
  float *a = malloc(n * 3 * sizeof *a), *b = malloc(n * 3 * sizeof *b);
  clr_result r = a && b ? film_get_rgb(ad->half[0], a, 1.0f)
                        : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "adaptive sampling");
  if (r == CLR_SUCCESS) r = film_get_rgb(ad->half[1], b, 1.0f);
  for (size_t i = 0; r == CLR_SUCCESS && i < n; ++i) {
    if (!ad->active[i]) continue;
    double diff = 0.0, sum = 0.0;
    for (int c = 0; c < 3; ++c) {
      diff += fabs((double)a[3 * i + c] - (double)b[3 * i + c]);
      sum += 0.5 * ((double)a[3 * i + c] + (double)b[3 * i + c]);
    }
    ad->error[i] = (float)(diff / (1e-4 + sqrt(sum > 0.0 ? sum : 0.0)));
    if (ad->error[i] < ad->threshold) {
      ad->active[i] = 0;
      --ad->active_count;
    }
  }
  free(a);
  free(b);
  return r;
}

clr_result clr_adaptive_write_error_map(const clr_adaptive *ad, clr_context ctx, clr_film film,
                                        const char *path) {
  clr_film_desc desc = *film_get_desc(film);
  desc.scale = 1.0f;
  clr_film map = NULL;
  CLR_CHECK(film_create(ctx, &desc, &map));
  size_t n = (size_t)ad->width * (size_t)ad->height;
  double *rgb = malloc(n * 3 * sizeof *rgb), *weight = malloc(n * sizeof *weight);
  clr_result r =
      rgb && weight ? CLR_SUCCESS : clr_set_last_error(CLR_ERROR_OUT_OF_MEMORY, "error map");
  for (size_t i = 0; r == CLR_SUCCESS && i < n; ++i) {
    double e = isfinite(ad->error[i]) ? (double)ad->error[i] : 0.0;
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = e;
    weight[i] = 1.0;
  }
  if (r == CLR_SUCCESS && n) r = film_merge_sums(map, ad->bounds, rgb, weight, NULL);
  if (r == CLR_SUCCESS) {
    clr_film_write_options wo;
    clr_film_write_options_init(&wo);
    wo.include_sums = 0;
    const char *keys[1] = {"clrender.error_map"}, *vals[1] = {"A/B estimate per pixel"};
    wo.metadata_keys = keys;
    wo.metadata_values = vals;
    wo.metadata_count = 1;
    r = film_write(map, path, &wo);
  }
  free(rgb);
  free(weight);
  film_release(map);
  return r;
}
