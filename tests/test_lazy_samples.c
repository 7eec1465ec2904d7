/* Sample values on demand: clr_sampler_generate_at gives the floats of the whole vector at any
 * value range (halton and sobol, against the device's whole-layout batch), a prefix of a layout
 * without arrays generates the first values of the whole layout, bad arguments are refused, and
 * a path render that fetches its deeper bounces' values is bit-identical to one generating every
 * vector whole. */
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "renderer.h"
#include "scene_parser.h"
#include "scene_test_util.h"

#include "context_fixture.h"

/* The path tracer's layout at maxdepth 6: the camera (2, 1, 2), bounces 0-3 (1, 2, 2, 2) and
 * bounces 4-5 with Russian roulette's 1D: 5 + 4 * 7 + 2 * 8 = 49 values. */
static const clr_sample_request path6[] = {
    {2, 0}, {1, 0}, {2, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 0}, {1, 0}, {2, 0}, {2, 0},
    {2, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 0}, {1, 0},
    {2, 0}, {2, 0}, {2, 0}, {1, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 0}, {1, 0}};
#define PATH6_REQUESTS ((int)(sizeof path6 / sizeof path6[0]))
#define PATH6_VALUES 49
/* Arrays (directlighting's and AO's kind) between singles. */
static const clr_sample_request with_arrays[] = {{2, 0}, {1, 0}, {2, 0}, {1, 5}, {2, 0},
                                                 {2, 7}, {1, 0}, {2, 0}, {2, 3}, {1, 0}};
#define WITH_ARRAYS_REQUESTS ((int)(sizeof with_arrays / sizeof with_arrays[0]))

static clr_sampler make_sampler(clr_sampler_type type, clr_seeding seeding) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.seeding = seeding;
  d.pixel_samples = 16;
  d.film.x_resolution = 40;
  d.film.y_resolution = 24;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(ctx, &d, &s), CLR_SUCCESS);
  return s;
}

/* The device's values of pixels px, every sample, layout req (caller frees). */
static float *device_values(clr_sampler s, clr_bounds2i px, const clr_sample_request *req, int nreq,
                            int32_t *per_sample) {
  assert_int_equal(clr_sample_layout_values(req, nreq, per_sample), CLR_SUCCESS);
  size_t n = (size_t)(px.x1 - px.x0) * (size_t)(px.y1 - px.y0) * (size_t)clr_sampler_spp(s) *
             (size_t)*per_sample;
  float *v = malloc(n * sizeof *v);
  assert_non_null(v);
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = px;
  b.requests = req;
  b.request_count = nreq;
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = v;
  assert_int_equal(clr_sampler_generate(s, &b, &out), CLR_SUCCESS);
  return v;
}

/* got (npts points, items[i]'s the i-th, count values each) against values [first,
 * first + count) of the whole layout's items. */
static void expect_whole(const float *got, const float *whole, const int *items, int npts,
                         int32_t per_sample, int32_t first, int32_t count, const char *how) {
  for (int i = 0; i < npts; ++i) {
    int item = items[i];
    const float *want = whole + (size_t)item * (size_t)per_sample + first;
    if (memcmp(got + (size_t)i * (size_t)count, want, (size_t)count * sizeof(float)) != 0)
      fail_msg("%s: point %d values [%d, %d) differ from the whole layout's", how, i, first,
               first + count);
  }
}

/* Point orders over w x h pixels of spp samples: 0, i -> (i * 7) mod npts (every item once, out
 * of order); 1, pixel by pixel along rows, 2, down columns, each pixel's samples in reverse (runs
 * of one pixel, as the renderer's chunks ask; consecutive runs share y or x). */
static int point_item(int order, int i, int w, int h, int spp) {
  if (order == 0) return (int)(((int64_t)i * 7) % (w * h * spp));
  int run = i / spp, pixel = order == 1 ? run : run % h * w + run / h;
  return pixel * spp + (spp - 1 - i % spp);
}

/* Every value range [first, first + count) of a few bounces and single values, for the points of
 * px (in each point order), equals the device's whole-layout values bit for bit, through
 * clr_sampler_generate_at and through a prepared clr_sample_fetch. */
static void check_ranges(clr_sampler s, const clr_sample_request *req, int nreq,
                         const int32_t (*ranges)[2], int nranges) {
  clr_bounds2i px = clr_sampler_sample_bounds(s);
  px.x0 += 3;
  px.y0 += 2;
  px.x1 = px.x0 + 5;
  px.y1 = px.y0 + 3;
  int32_t per_sample = 0;
  float *whole = device_values(s, px, req, nreq, &per_sample);
  int spp = clr_sampler_spp(s), w = px.x1 - px.x0, npts = w * (px.y1 - px.y0) * spp;
  clr_sample_point *pts = malloc((size_t)npts * sizeof *pts);
  int *items = malloc((size_t)npts * sizeof *items);
  float *got = malloc((size_t)npts * (size_t)per_sample * sizeof *got);
  assert_non_null(pts);
  assert_non_null(items);
  assert_non_null(got);
  assert_int_not_equal(npts % 7, 0);
  clr_sample_fetch fetch = NULL;
  assert_int_equal(clr_sample_fetch_create(s, req, nreq, &fetch), CLR_SUCCESS);
  assert_non_null(fetch);
  for (int order = 0; order < 3; ++order) {
    for (int i = 0; i < npts; ++i) {
      int item = items[i] = point_item(order, i, w, px.y1 - px.y0, spp), pixel = item / spp;
      pts[i].x = px.x0 + pixel % w;
      pts[i].y = px.y0 + pixel / w;
      pts[i].sample = item % spp;
    }
    for (int r = 0; r < nranges; ++r) {
      int32_t first = ranges[r][0], count = ranges[r][1];
      assert_true(first + count <= per_sample);
      assert_int_equal(clr_sampler_generate_at(s, req, nreq, pts, npts, first, count, got),
                       CLR_SUCCESS);
      expect_whole(got, whole, items, npts, per_sample, first, count, "generate_at");
      memset(got, 0xff, (size_t)npts * (size_t)count * sizeof *got); /* NaNs: all written */
      assert_int_equal(clr_sample_fetch_values(fetch, pts, npts, first, count, got), CLR_SUCCESS);
      expect_whole(got, whole, items, npts, per_sample, first, count, "fetch");
      /* a few points at a time, as the path tracer's waves ask */
      for (int i = 0; i < npts; i += 12) {
        int n = npts - i < 12 ? npts - i : 12;
        assert_int_equal(clr_sample_fetch_values(fetch, pts + i, n, first, count,
                                                 got + (size_t)i * (size_t)count),
                         CLR_SUCCESS);
      }
      expect_whole(got, whole, items, npts, per_sample, first, count, "fetch by 12");
    }
  }
  clr_sample_fetch_release(fetch);
  free(pts);
  free(items);
  free(got);
  free(whole);
}

static void test_generate_at_equals_whole_layout(void **state) {
  (void)state;
  /* bounce 0 (5..12), bounce 1, bounce 3, bounce 4 with roulette (33..41), bounce 5 (41..49),
   * one value, a range across bounces, the whole vector */
  static const int32_t path_ranges[][2] = {{5, 7},  {12, 7}, {26, 7},  {33, 8},
                                           {41, 8}, {47, 1}, {10, 20}, {0, PATH6_VALUES}};
  /* inside the 1D array, across the 2D array, a single after the arrays, everything */
  static const int32_t array_ranges[][2] = {{5, 3}, {10, 15}, {25, 2}, {29, 7}, {0, 36}};
  clr_sampler_type types[] = {CLR_SAMPLER_HALTON, CLR_SAMPLER_SOBOL};
  clr_seeding seedings[] = {CLR_SEEDING_PIXEL, CLR_SEEDING_PBRT_V3};
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 2; ++k) {
      clr_sampler s = make_sampler(types[t], seedings[k]);
      int32_t n = 0;
      assert_int_equal(clr_sample_layout_values(path6, PATH6_REQUESTS, &n), CLR_SUCCESS);
      assert_int_equal(n, PATH6_VALUES);
      check_ranges(s, path6, PATH6_REQUESTS, path_ranges, 8);
      assert_int_equal(clr_sample_layout_values(with_arrays, WITH_ARRAYS_REQUESTS, &n),
                       CLR_SUCCESS);
      assert_int_equal(n, 36);
      check_ranges(s, with_arrays, WITH_ARRAYS_REQUESTS, array_ranges, 5);
      clr_sampler_release(s);
    }
}

/* The renderer generates a prefix of the path layout (no arrays): its values are the first
 * values of the whole layout's, for the global samplers and the pbrt-v4 ones (which walk the
 * layout in order). */
static void test_prefix_layout_same_values(void **state) {
  (void)state;
  clr_sampler_type types[] = {CLR_SAMPLER_HALTON, CLR_SAMPLER_SOBOL, CLR_SAMPLER_ZSOBOL,
                              CLR_SAMPLER_PADDEDSOBOL};
  for (int t = 0; t < 4; ++t) {
    clr_sampler s = make_sampler(types[t], CLR_SEEDING_PIXEL);
    clr_bounds2i px = clr_sampler_sample_bounds(s);
    px.x1 = px.x0 + 9;
    px.y1 = px.y0 + 4;
    int32_t whole_n = 0, prefix_n = 0;
    float *whole = device_values(s, px, path6, PATH6_REQUESTS, &whole_n);
    for (int nreq = 3; nreq <= 11; nreq += 4) { /* camera; and bounce 0; and bounce 1 */
      float *prefix = device_values(s, px, path6, nreq, &prefix_n);
      size_t items = (size_t)9 * 4 * (size_t)clr_sampler_spp(s);
      for (size_t i = 0; i < items; ++i)
        if (memcmp(prefix + i * (size_t)prefix_n, whole + i * (size_t)whole_n,
                   (size_t)prefix_n * sizeof(float)) != 0)
          fail_msg("%s: item %zu, prefix of %d requests differs", clr_sampler_type_name(types[t]),
                   i, nreq);
      free(prefix);
    }
    free(whole);
    clr_sampler_release(s);
  }
}

static void test_generate_at_bad_arguments(void **state) {
  (void)state;
  clr_sampler s = make_sampler(CLR_SAMPLER_HALTON, CLR_SEEDING_PIXEL);
  clr_bounds2i sb = clr_sampler_sample_bounds(s);
  clr_sample_point ok = {sb.x0, sb.y0, 15}, pt;
  float v[PATH6_VALUES];
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, 1, 0, PATH6_VALUES, v),
                   CLR_SUCCESS);
  assert_int_equal(clr_sampler_generate_at(NULL, path6, PATH6_REQUESTS, &ok, 1, 0, 1, v),
                   CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, NULL, 1, 0, 1, v),
                   CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, 1, 0, 1, NULL),
                   CLR_ERROR_NULL_POINTER);
  assert_int_equal(clr_sampler_generate_at(s, NULL, 3, &ok, 1, 0, 1, v), CLR_ERROR_NULL_POINTER);
  /* nothing asked: no pointer needed */
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, NULL, 0, 0, 1, NULL),
                   CLR_SUCCESS);
  pt = ok;
  pt.x = sb.x1;
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &pt, 1, 0, 1, v),
                   CLR_ERROR_INVALID_PIXEL_RANGE);
  assert_non_null(strstr(clr_last_error_message(), "points[0]"));
  pt = ok;
  pt.y = sb.y0 - 1;
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &pt, 1, 0, 1, v),
                   CLR_ERROR_INVALID_PIXEL_RANGE);
  pt = ok;
  pt.sample = 16;
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &pt, 1, 0, 1, v),
                   CLR_ERROR_INVALID_SPP);
  assert_non_null(strstr(clr_last_error_message(), "sample 16"));
  pt.sample = -1;
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &pt, 1, 0, 1, v),
                   CLR_ERROR_INVALID_SPP);
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, 1, 48, 2, v),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "49 values"));
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, 1, -1, 1, v),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, -1, 0, 1, v),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, 1, 0, INT32_MAX, v),
                   CLR_ERROR_INVALID_ARGUMENT);
  static const clr_sample_request bad[] = {{1, 0}, {2, 0}};
  assert_int_equal(clr_sampler_generate_at(s, bad, 2, &ok, 1, 0, 1, v), CLR_ERROR_INVALID_REQUESTS);
  clr_sampler_release(s);
  /* samplers without a global index are refused, naming the sampler */
  clr_sampler_type others[] = {CLR_SAMPLER_ZSOBOL, CLR_SAMPLER_STRATIFIED, CLR_SAMPLER_RANDOM};
  for (int t = 0; t < 3; ++t) {
    s = make_sampler(others[t], CLR_SEEDING_PIXEL);
    assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, 1, 0, 1, v),
                     CLR_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(clr_last_error_message(), clr_sampler_type_name(others[t])));
    clr_sampler_release(s);
  }
  s = make_sampler(CLR_SAMPLER_HALTON, CLR_SEEDING_PBRT_V4); /* pbrt-v4's algorithm */
  assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, &ok, 1, 0, 1, v),
                   CLR_ERROR_INVALID_ARGUMENT);
  clr_sampler_release(s);
}

/* A closed box with a matte sphere, a glass sphere and an interface (material "none"): paths
 * reach every bounce of the layout (maxdepth 6) and past it is none; interfaces and specular
 * bounces consume no or fewer values, so a wave's vertices are at different bounces. */
static const char *box_scene =
    "LookAt 0 1 -3.2  0 1 0  0 1 0\nCamera \"perspective\" \"float fov\" [50]\n"
    "Film \"image\" \"integer xresolution\" [20] \"integer yresolution\" [16]\n"
    "Sampler \"%s\" \"integer pixelsamples\" [8]\n"
    "Integrator \"path\" \"integer maxdepth\" [6]\n"
    "WorldBegin\n"
    "LightSource \"point\" \"rgb I\" [4 4 4] \"point from\" [0 1.8 0]\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [3 3 3]\n"
    "Translate 0 1.99 0\nShape \"disk\" \"float radius\" [0.3]\nAttributeEnd\n"
    "Material \"matte\" \"rgb Kd\" [0.7 0.7 0.7]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 6 4 6 7  0 1 5 0 5 4"
    "  3 2 6 3 6 7  1 2 6 1 6 5]\n"
    "\"point P\" [-1 0 -4  1 0 -4  1 0 1  -1 0 1  -1 2 -4  1 2 -4  1 2 1  -1 2 1]\n"
    "AttributeBegin\nMaterial \"matte\" \"rgb Kd\" [0.8 0.3 0.2]\nTranslate -0.4 0.4 0\n"
    "Shape \"sphere\" \"float radius\" [0.4]\nAttributeEnd\n"
    "AttributeBegin\nMaterial \"glass\"\nTranslate 0.45 0.35 -0.5\n"
    "Shape \"sphere\" \"float radius\" [0.35]\nAttributeEnd\n"
    "AttributeBegin\nMaterial \"none\"\nTranslate 0.1 1.1 -1.6\n"
    "Shape \"sphere\" \"float radius\" [0.45]\nAttributeEnd\n"
    "WorldEnd\n";

static float *render(const char *sampler, int lazy, int threads, int tile, clr_seeding seeding,
                     int *n) {
  char text[4096];
  snprintf(text, sizeof text, box_scene, sampler);
  clr_render_options o;
  clr_render_options_init(&o);
  o.lazy_samples = lazy;
  o.nthreads = threads;
  o.tile_size = tile;
  o.seeding = seeding;
  clr_render_image im = stu_render_image(text, "box.pbrt", &o, NULL);
  *n = im.width * im.height * 3;
  return im.rgb;
}

/* Fetched and whole vectors give the same image bit for bit: fetching always (past bounce 0)
 * or as chosen per band, with 1 or 2 threads (the image never depends on the thread count) and
 * at another tile size (which changes the film sums' rounding alike in both). */
static void test_lazy_render_identical(void **state) {
  (void)state;
  const char *samplers[] = {"halton", "sobol"};
  enum {
    OFF = CLR_LAZY_SAMPLES_OFF,
    ALWAYS = CLR_LAZY_SAMPLES_ALWAYS,
    AUTO = CLR_LAZY_SAMPLES_AUTO
  };
  for (int t = 0; t < 2; ++t)
    for (int k = 0; k < 2; ++k) {
      clr_seeding seeding = k ? CLR_SEEDING_PBRT_V3 : CLR_SEEDING_PIXEL;
      int tile = k ? 16 : 5, n[6];
      float *img[6] = {render(samplers[t], OFF, 2, 16, seeding, &n[0]),
                       render(samplers[t], ALWAYS, 2, 16, seeding, &n[1]),
                       render(samplers[t], ALWAYS, 1, 16, seeding, &n[2]),
                       render(samplers[t], AUTO, 2, 16, seeding, &n[3]),
                       render(samplers[t], OFF, 2, tile, seeding, &n[4]),
                       render(samplers[t], ALWAYS, 1, tile, seeding, &n[5])};
      assert_int_equal(n[0], 20 * 16 * 3);
      double sum = 0.0;
      for (int i = 0; i < n[0]; ++i) sum += img[0][i];
      assert_true(sum > 0.0); /* the box is lit: the comparison is not of black images */
      for (int c = 1; c < 6; ++c) assert_int_equal(n[c], n[0]);
      for (int c = 1; c < 4; ++c) assert_memory_equal(img[c], img[0], (size_t)n[0] * sizeof(float));
      assert_memory_equal(img[5], img[4], (size_t)n[0] * sizeof(float));
      for (int c = 0; c < 6; ++c) free(img[c]);
    }
}

/* A lazy_samples value outside auto/off/always is refused, naming it; nothing is rendered. */
static void test_lazy_option_refused(void **state) {
  (void)state;
  char text[4096];
  snprintf(text, sizeof text, box_scene, "halton");
  clr_scene_desc *desc = NULL;
  clr_parse_options po;
  clr_parse_options_init(&po);
  assert_int_equal(clr_scene_parse_string(text, "box.pbrt", &po, &desc), CLR_SUCCESS);
  const int32_t bad[] = {-1, 3, 1000};
  for (int i = 0; i < 3; ++i) {
    clr_render_options o;
    clr_render_options_init(&o);
    o.quiet = 1;
    o.lazy_samples = bad[i];
    clr_render_image im;
    memset(&im, 0, sizeof im);
    assert_int_equal(clr_render_desc(desc, &o, NULL, 0, &im), CLR_ERROR_INVALID_ARGUMENT);
    assert_null(im.rgb);
    char want[64];
    snprintf(want, sizeof want, "lazy_samples %d", (int)bad[i]);
    assert_non_null(strstr(clr_last_error_message(), want));
  }
  clr_scene_desc_free(desc);
}

/* Two threads fetching through one handle at the same time get the values of
 * clr_sampler_generate_at (the handle is shared read only). */
typedef struct fetch_thread {
  clr_sample_fetch fetch;
  const clr_sample_point *pts;
  int npts;
  int32_t first, count;
  float *got;
  clr_result r;
} fetch_thread;

static void *fetch_thread_main(void *arg) {
  fetch_thread *t = arg;
  t->r = CLR_SUCCESS;
  for (int rep = 0; rep < 20 && t->r == CLR_SUCCESS; ++rep)
    for (int i = 0; i < t->npts && t->r == CLR_SUCCESS; i += 8)
      t->r = clr_sample_fetch_values(t->fetch, t->pts + i, t->npts - i < 8 ? t->npts - i : 8,
                                     t->first, t->count, t->got + (size_t)i * (size_t)t->count);
  return NULL;
}

static void test_fetch_shared_by_threads(void **state) {
  (void)state;
  clr_sampler_type types[] = {CLR_SAMPLER_HALTON, CLR_SAMPLER_SOBOL};
  for (int k = 0; k < 2; ++k) {
    clr_sampler s = make_sampler(types[k], CLR_SEEDING_PIXEL);
    clr_bounds2i sb = clr_sampler_sample_bounds(s);
    enum { NPTS = 100 };
    clr_sample_point pts[NPTS];
    for (int i = 0; i < NPTS; ++i) {
      pts[i].x = sb.x0 + (i * 13) % (sb.x1 - sb.x0);
      pts[i].y = sb.y0 + (i * 5) % (sb.y1 - sb.y0);
      pts[i].sample = (i * 3) % 16;
    }
    clr_sample_fetch fetch = NULL;
    assert_int_equal(clr_sample_fetch_create(s, path6, PATH6_REQUESTS, &fetch), CLR_SUCCESS);
    static float got[2][NPTS * 16], want[2][NPTS * 16];
    fetch_thread t[2] = {{fetch, pts, NPTS, 12, 7, got[0], CLR_SUCCESS},
                         {fetch, pts, NPTS, 33, 16, got[1], CLR_SUCCESS}};
    pthread_t th[2];
    for (int i = 0; i < 2; ++i)
      assert_int_equal(pthread_create(&th[i], NULL, fetch_thread_main, &t[i]), 0);
    for (int i = 0; i < 2; ++i) pthread_join(th[i], NULL);
    for (int i = 0; i < 2; ++i) {
      assert_int_equal(t[i].r, CLR_SUCCESS);
      assert_int_equal(clr_sampler_generate_at(s, path6, PATH6_REQUESTS, pts, NPTS, t[i].first,
                                               t[i].count, want[i]),
                       CLR_SUCCESS);
      assert_memory_equal(got[i], want[i], (size_t)NPTS * (size_t)t[i].count * sizeof(float));
    }
    clr_sample_fetch_release(fetch);
    clr_sampler_release(s); /* the handle held its own reference until now */
  }
}

static void test_fetch_bad_arguments(void **state) {
  (void)state;
  clr_sampler s = make_sampler(CLR_SAMPLER_SOBOL, CLR_SEEDING_PIXEL);
  clr_bounds2i sb = clr_sampler_sample_bounds(s);
  clr_sample_point ok = {sb.x0, sb.y0, 15}, pt;
  float v[PATH6_VALUES];
  clr_sample_fetch f = (clr_sample_fetch)&ok; /* set to NULL on failure */
  assert_int_equal(clr_sample_fetch_create(NULL, path6, PATH6_REQUESTS, &f),
                   CLR_ERROR_NULL_POINTER);
  assert_null(f);
  assert_non_null(strstr(clr_last_error_message(), "sampler"));
  assert_int_equal(clr_sample_fetch_create(s, path6, PATH6_REQUESTS, NULL), CLR_ERROR_NULL_POINTER);
  assert_non_null(strstr(clr_last_error_message(), "out"));
  assert_int_equal(clr_sample_fetch_create(s, NULL, 3, &f), CLR_ERROR_NULL_POINTER);
  assert_null(f);
  clr_sampler z = make_sampler(CLR_SAMPLER_ZSOBOL, CLR_SEEDING_PIXEL);
  assert_int_equal(clr_sample_fetch_create(z, path6, PATH6_REQUESTS, &f),
                   CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "zsobol"));
  clr_sampler_release(z);
  assert_int_equal(clr_sample_fetch_create(s, path6, PATH6_REQUESTS, &f), CLR_SUCCESS);
  assert_int_equal(clr_sample_fetch_values(f, &ok, 1, 0, PATH6_VALUES, v), CLR_SUCCESS);
  assert_int_equal(clr_sample_fetch_values(NULL, &ok, 1, 0, 1, v), CLR_ERROR_NULL_POINTER);
  assert_non_null(strstr(clr_last_error_message(), "fetch"));
  assert_int_equal(clr_sample_fetch_values(f, NULL, 1, 0, 1, v), CLR_ERROR_NULL_POINTER);
  assert_non_null(strstr(clr_last_error_message(), "points"));
  assert_int_equal(clr_sample_fetch_values(f, &ok, 1, 0, 1, NULL), CLR_ERROR_NULL_POINTER);
  assert_non_null(strstr(clr_last_error_message(), "values"));
  assert_int_equal(clr_sample_fetch_values(f, NULL, 0, 0, 1, NULL), CLR_SUCCESS);
  pt = ok;
  pt.x = sb.x1;
  assert_int_equal(clr_sample_fetch_values(f, &pt, 1, 0, 1, v), CLR_ERROR_INVALID_PIXEL_RANGE);
  assert_non_null(strstr(clr_last_error_message(), "clr_sample_fetch_values: points[0]"));
  pt = ok;
  pt.sample = 16;
  assert_int_equal(clr_sample_fetch_values(f, &pt, 1, 0, 1, v), CLR_ERROR_INVALID_SPP);
  assert_non_null(strstr(clr_last_error_message(), "sample 16"));
  assert_int_equal(clr_sample_fetch_values(f, &ok, 1, 40, 10, v), CLR_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(clr_last_error_message(), "layout's 49 values"));
  assert_int_equal(clr_sample_fetch_values(f, &ok, 1, -1, 1, v), CLR_ERROR_INVALID_ARGUMENT);
  assert_int_equal(clr_sample_fetch_values(f, &ok, -1, 0, 1, v), CLR_ERROR_INVALID_ARGUMENT);
  clr_sample_fetch_release(f);
  clr_sample_fetch_release(NULL);
  clr_sampler_release(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_generate_at_equals_whole_layout),
      cmocka_unit_test(test_prefix_layout_same_values),
      cmocka_unit_test(test_generate_at_bad_arguments),
      cmocka_unit_test(test_fetch_shared_by_threads),
      cmocka_unit_test(test_fetch_bad_arguments),
      cmocka_unit_test(test_lazy_render_identical),
      cmocka_unit_test(test_lazy_option_refused),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
