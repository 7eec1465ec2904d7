/* The renderer's sample vectors with pbrt-v4 samplers: pbrt-v4's per-pixel call sequence (the
 * wavelength Get1D, GetCameraSample's GetPixel2D, Get1D time and Get2D lens, then the
 * integrator's values as sequential Get1D/Get2D), pbrt-v4's film position, and renders that do
 * not depend on threads or tiles. Pinned values were printed by pbrt-v4's own samplers.h (a
 * harness built outside the repository, 2026-11-30). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "camera_sample.h"
#include "integrator.h"
#include "render_scene.h"
#include "renderer.h"
#include "scene_parser.h"
#include "camera_layout_test_util.h"
#include "scene_test_util.h"

static const char *path_scene =
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [50]\n"
    "Film \"image\" \"integer xresolution\" [64] \"integer yresolution\" [64]\n"
    "Integrator \"path\" \"integer maxdepth\" [2]\n"
    "WorldBegin\nLightSource \"point\" \"point from\" [0 2 3] \"rgb I\" [5 5 5]\n"
    "Material \"matte\" \"rgb Kd\" [0.6 0.5 0.4]\nShape \"sphere\" \"float radius\" [1]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
    "\"point P\" [-5 -1 -5  5 -1 -5  5 -1 5  -5 -1 5]\nWorldEnd\n";

/* The same scene seen by a moving thin-lens camera: its rays read the camera's time and lens. */
static const char *moving_lens_scene =
    "ActiveTransform EndTime\nTranslate 0.1 0 0\nActiveTransform All\n"
    "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [50] "
    "\"float lensradius\" [0.05] \"float focaldistance\" [5]\n"
    "Film \"image\" \"integer xresolution\" [64] \"integer yresolution\" [64]\n"
    "Integrator \"path\" \"integer maxdepth\" [2]\n"
    "WorldBegin\nLightSource \"point\" \"point from\" [0 2 3] \"rgb I\" [5 5 5]\n"
    "Material \"matte\" \"rgb Kd\" [0.6 0.5 0.4]\nShape \"sphere\" \"float radius\" [1]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
    "\"point P\" [-5 -1 -5  5 -1 -5  5 -1 5  -5 -1 5]\nWorldEnd\n";

typedef struct parsed {
  clr_scene_desc *desc;
  clr_render_scene *scene;
} parsed;

static parsed parse(const char *text) {
  parsed p = {NULL, NULL};
  p.scene = stu_build(text, "test.pbrt", &p.desc);
  return p;
}

static void parsed_free(parsed *p) {
  clr_render_scene_free(p->scene);
  clr_scene_desc_free(p->desc);
}

/* pbrt-v4's layout: 1D wavelength, 2D film offset, 1D time, 2D lens, then the path integrator's
 * per-bounce requests; pbrt-v3's keeps the camera's 5 values first. A pinhole camera that does
 * not move skips time and lens (CLR_SAMPLE_REQUEST_SKIPPED): its vector holds the film offset's
 * 2 values, then the integrator's. */
static void test_layout_requests(void **state) {
  (void)state;
  for (int moving = 0; moving < 2; ++moving) {
    parsed p = parse(moving ? moving_lens_scene : path_scene);
    clr_integrator v3, v4;
    assert_int_equal(
        clr_integrator_create_layout(p.desc, p.scene, CLR_SAMPLER_HALTON, 0, NULL, NULL, &v3),
        CLR_SUCCESS);
    assert_int_equal(
        clr_integrator_create_layout(p.desc, p.scene, CLR_SAMPLER_ZSOBOL, 1, NULL, NULL, &v4),
        CLR_SUCCESS);
    int camera = moving ? 5 : 2; /* the camera's stored values */
    assert_int_equal(v3.camera_offset, 0);
    assert_int_equal(v3.value_offset, camera);
    assert_int_equal(v4.camera_offset, 1);
    assert_int_equal(v4.value_offset, 1 + camera);
    assert_int_equal(v3.time_offset, moving ? 2 : -1);
    assert_int_equal(v3.lens_offset, moving ? 3 : -1);
    assert_int_equal(v4.lens_offset, moving ? 4 : -1);
    assert_int_equal(v4.request_count, v3.request_count + 1);
    assert_int_equal(v4.values_per_sample, v3.values_per_sample + 1);
    assert_int_equal(v3.layout_values, v3.values_per_sample + 5 - camera);
    static const int dims[] = {1, 2, 1, 2, 1, 2, 2, 2, 1};
    for (int i = 0; i < 9; ++i) {
      int skipped = !moving && (i == 2 || i == 3) ? CLR_SAMPLE_REQUEST_SKIPPED : 0;
      assert_int_equal(v4.requests[i].dims, dims[i] | skipped);
      assert_int_equal(v4.requests[i].array_size, 0);
      if (i) assert_int_equal(v3.requests[i - 1].dims, dims[i] | skipped);
    }
    clr_integrator_free(&v3);
    clr_integrator_free(&v4);
    parsed_free(&p);
  }
}

/* pbrt-v4's GetCameraSample with its default box filter (radius 0.5): pPixel + Lerp(u, -0.5,
 * 0.5) + 0.5 in float, which differs from pbrt-v3's pPixel + u for small offsets. */
static void test_film_position_box(void **state) {
  (void)state;
  static const struct {
    int px;
    float u, v4, v3;
  } cases[] = {{8, 0x1.ddc79p-18f, 0x1.00001p+3f, 0x1.00000ep+3f},
               {4, 0x1.3ca186p-13f, 0x1.000278p+2f, 0x1.00027ap+2f},
               {-2, 0x1.0f88fap-24f, -0x1p+1f, -0x1.fffffep+0f},
               {3, 0x1.645d9ap-9f, 0x1.805918p+1f, 0x1.805918p+1f}};
  clr_camera_layout v4 = layout_for(CLR_SAMPLER_ZSOBOL, CLR_SEEDING_PIXEL, CLR_FILTER_BOX, 0.0f);
  clr_camera_layout v3 = layout_for(CLR_SAMPLER_HALTON, CLR_SEEDING_PIXEL, CLR_FILTER_BOX, 0.0f);
  assert_true(v4.pbrt_v4 && v4.filter_sampled);
  assert_true(!v3.pbrt_v4 && !v3.filter_sampled);
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    float v[5] = {cases[i].u, 0.25f, 0.125f, 0.5f, 0.75f};
    clr_camera_sample a, b;
    clr_camera_sample_from_values(&v4, v, cases[i].px, 7, &a);
    clr_camera_sample_from_values(&v3, v, cases[i].px, 7, &b);
    assert_true(a.film_x == cases[i].v4);
    assert_true(b.film_x == cases[i].v3);
    assert_true(a.film_y == 7.25f && b.film_y == 7.25f);
    assert_true(a.pixel_x == (float)cases[i].px + 0.5f && a.pixel_y == 7.5f); /* own pixel */
    assert_true(b.pixel_x == b.film_x && b.pixel_y == b.film_y);              /* splatted */
    assert_true(a.time == 0.125f && a.lens_u == 0.5f && a.lens_v == 0.75f);
  }
}

/* pbrt-v4's TriangleFilter::Sample (SampleTent) and a box of radius 1.5; values printed by
 * pbrt-v4's own SampleTent. Filters pbrt-v4 has no exact Sample for keep the box of radius 0.5
 * and the film's filtering. */
static void test_film_position_filters(void **state) {
  (void)state;
  static const struct {
    float u, r, tent;
  } tents[] = {{0x1.333334p-2f, 2.0f, -0x1.cda04p-2f},
               {0x1.666666p-1f, 2.0f, 0x1.cda04p-2f},
               {0.5f, 2.0f, 0.0f},
               {0.0f, 2.0f, -2.0f},
               {0x1.fffffep-1f, 2.0f, 0x1.ffd2cp+0f},
               {0.25f, 1.5f, -0x1.c1e25p-2f},
               {0x1.ddc79p-18f, 2.0f, -0x1.fe1168p+0f}};
  for (size_t i = 0; i < sizeof tents / sizeof tents[0]; ++i) {
    clr_camera_layout l =
        layout_for(CLR_SAMPLER_INDEPENDENT, CLR_SEEDING_PIXEL, CLR_FILTER_TRIANGLE, tents[i].r);
    assert_true(l.filter_sampled);
    float v[5] = {tents[i].u, tents[i].u, 0, 0, 0};
    clr_camera_sample cs;
    clr_camera_sample_from_values(&l, v, 10, -3, &cs);
    assert_true(cs.film_x == (10.0f + tents[i].tent) + 0.5f);
    assert_true(cs.film_y == (-3.0f + tents[i].tent) + 0.5f);
    assert_true(cs.pixel_x == 10.5f && cs.pixel_y == -2.5f);
  }
  clr_camera_layout box = layout_for(CLR_SAMPLER_PMJ02BN, CLR_SEEDING_PIXEL, CLR_FILTER_BOX, 1.5f);
  float v[5] = {0.25f, 1.0f, 0, 0, 0};
  clr_camera_sample cs;
  clr_camera_sample_from_values(&box, v, 2, 2, &cs);
  assert_true(cs.film_x == (2.0f + (0.75f * -1.5f + 0.25f * 1.5f)) + 0.5f);
  assert_true(cs.film_y == 4.0f && cs.pixel_y == 2.5f);
  clr_camera_layout gauss =
      layout_for(CLR_SAMPLER_ZSOBOL, CLR_SEEDING_PIXEL, CLR_FILTER_GAUSSIAN, 0.0f);
  assert_true(gauss.pbrt_v4 && !gauss.filter_sampled);
  clr_camera_sample_from_values(&gauss, v, 2, 2, &cs);
  assert_true(cs.film_x == 2.25f && cs.pixel_x == 2.25f && cs.film_y == 3.0f);
}

/* pbrt-v4's values for layout Get1D (wavelength), GetPixel2D, Get1D (time), Get2D (lens), Get1D
 * (light choice), Get2D (light): pixels (3, 5) sample 0 and (40, 21) sample 5, 64x64 film. */
typedef struct pinned_vector {
  clr_sampler_type type;
  clr_randomization randomization;
  uint32_t seed;
  int spp;
  float v[2][9];
} pinned_vector;

static const pinned_vector pins[] = {
    {CLR_SAMPLER_ZSOBOL,
     CLR_RANDOMIZATION_FASTOWEN,
     0,
     16,
     {{0x1.6f16ap-2f, 0x1.645d9ap-9f, 0x1.09c074p-1f, 0x1.4b8d42p-1f, 0x1.5b8bf2p-1f,
       0x1.68df72p-1f, 0x1.690a6ep-3f, 0x1.927334p-1f, 0x1.f0a426p-3f},
      {0x1.41b6dp-1f, 0x1.ca7de4p-4f, 0x1.5150ap-3f, 0x1.08d07ap-1f, 0x1.cc7134p-1f, 0x1.734432p-1f,
       0x1.2def64p-1f, 0x1.0c7318p-2f, 0x1.6eb39ap-1f}}},
    {CLR_SAMPLER_HALTON,
     CLR_RANDOMIZATION_PERMUTEDIGITS,
     0,
     16,
     {{0x1.a578d8p-2f, 0x1.5p-2f, 0x1.e06528p-3f, 0x1.797c78p-3f, 0x1.9c841ap-1f, 0x1.9f5154p-3f,
       0x1.99308ep-1f, 0x1.33a84p-3f, 0x1.3e0c86p-3f},
      {0x1.e941fp-1f, 0x1.1bp-1f, 0x1.45e1d2p-4f, 0x1.1e0124p-1f, 0x1.79a902p-1f, 0x1.5dec86p-2f,
       0x1.1a3ea8p-2f, 0x1.144e8ap-1f, 0x1.b28108p-4f}}},
    {CLR_SAMPLER_SOBOL,
     CLR_RANDOMIZATION_FASTOWEN,
     0,
     16,
     {{0x1.2a25ap-2f, 0x1.8p-5f, 0x1.4p-4f, 0x1.dc8618p-2f, 0x1.d4ba66p-4f, 0x1.0e3ef8p-2f,
       0x1.99b38cp-5f, 0x1.32dc5ap-2f, 0x1.192f9p-1f},
      {0x1.ac76f6p-4f, 0x1.85p-1f, 0x1.91p-1f, 0x1.84259cp-3f, 0x1.7f3e0ap-2f, 0x1.fefac6p-2f,
       0x1.e1ddcap-1f, 0x1.4c5c28p-1f, 0x1.fc0b14p-1f}}},
    {CLR_SAMPLER_PADDEDSOBOL,
     CLR_RANDOMIZATION_OWEN,
     3,
     16,
     {{0x1.711538p-1f, 0x1.bb2394p-1f, 0x1.8176a6p-6f, 0x1.4dc524p-2f, 0x1.19bb8p-3f,
       0x1.14105ep-1f, 0x1.cf34ep-2f, 0x1.21e826p-3f, 0x1.c52ad4p-1f},
      {0x1.f2983ap-1f, 0x1.1e92e6p-1f, 0x1.3a84a4p-1f, 0x1.446b7cp-1f, 0x1.b82e2ep-2f,
       0x1.1032b4p-1f, 0x1.99848ap-1f, 0x1.d68ab2p-1f, 0x1.7bb88p-2f}}},
    {CLR_SAMPLER_RANDOM,
     CLR_RANDOMIZATION_DEFAULT,
     7,
     8, /* pbrt-v4's independent sampler: the values do not depend on spp */
     {{0x1.ab6926p-1f, 0x1.ef8fcep-2f, 0x1.4b3b08p-1f, 0x1.dbd52ep-1f, 0x1.b9c676p-3f,
       0x1.2bd58ap-1f, 0x1.56ab2ep-2f, 0x1.e45c9cp-2f, 0x1.7990fap-1f},
      {0x1.fbcdfep-2f, 0x1.5cef78p-5f, 0x1.d83082p-1f, 0x1.cdfce2p-2f, 0x1.b95c8cp-2f,
       0x1.e6883ap-2f, 0x1.913344p-1f, 0x1.e9d528p-1f, 0x1.542802p-1f}}},
};

/* The vector of sample `sample` of pixel (px, py) in the integrator's layout (host reference
 * generator and the device, which must agree). */
static void renderer_vector(const clr_sampler_desc *d, const clr_integrator *it, int px, int py,
                            int sample, int device, float *out) {
  clr_sampler s = NULL;
  clr_context ctx = NULL;
  if (device) {
    clr_context_desc cd;
    clr_context_desc_init(&cd);
    assert_int_equal(clr_context_create(&cd, &ctx), CLR_SUCCESS);
  }
  assert_int_equal(clr_sampler_create(ctx, d, &s), CLR_SUCCESS);
  float *v = malloc(sizeof(float) * (size_t)it->values_per_sample);
  assert_non_null(v);
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = (clr_bounds2i){px, py, px + 1, py + 1};
  b.requests = it->requests;
  b.request_count = it->request_count;
  b.first_sample = sample; /* pbrt-v4's StartPixelSample(pixel, sample) */
  b.sample_count = 1;
  clr_sample_output o;
  clr_sample_output_init(&o);
  o.host_values = v;
  assert_int_equal(
      device ? clr_sampler_generate(s, &b, &o) : clr_sampler_generate_reference(s, &b, &o),
      CLR_SUCCESS);
  memcpy(out, v, 9 * sizeof(float));
  free(v);
  clr_sampler_release(s);
  if (ctx) clr_context_release(ctx);
}

/* The pinned vectors in the full layout (a moving thin-lens camera), and without the skipped time
 * and lens values (a pinhole): the other values keep pbrt-v4's bits. */
static void test_vectors_match_pbrt_v4(void **state) {
  (void)state;
  for (int moving = 0; moving < 2; ++moving) {
    parsed p = parse(moving ? moving_lens_scene : path_scene);
    static const int at[2][3] = {{3, 5, 0}, {40, 21, 5}};
    /* pinned value of the vector's value j: pinhole vectors lack pins 3..5 (time, lens) */
    static const int full[9] = {0, 1, 2, 3, 4, 5, 6, 7, 8}, pinhole[9] = {0, 1, 2, 6, 7, 8, -1};
    const int *pinned = moving ? full : pinhole;
    for (size_t i = 0; i < sizeof pins / sizeof pins[0]; ++i) {
      const pinned_vector *pin = &pins[i];
      clr_sampler_desc d;
      clr_sampler_desc_init(&d, pin->type);
      d.seeding = CLR_SEEDING_PBRT_V4;
      if (pin->randomization != CLR_RANDOMIZATION_DEFAULT) d.randomization = pin->randomization;
      d.seed = pin->seed;
      d.pixel_samples = pin->spp;
      d.film.x_resolution = d.film.y_resolution = 64;
      assert_true(clr_camera_sample_is_pbrt_v4(&d));
      clr_integrator it;
      assert_int_equal(clr_integrator_create_layout(p.desc, p.scene, pin->type, 1, NULL, NULL, &it),
                       CLR_SUCCESS);
      for (int k = 0; k < 2; ++k)
        for (int device = 0; device < 2; ++device) {
          float v[9];
          renderer_vector(&d, &it, at[k][0], at[k][1], at[k][2], device, v);
          for (int j = 0; j < 9 && pinned[j] >= 0; ++j) {
            float want = pin->v[k][pinned[j]];
            if (v[j] != want)
              fprintf(stderr, "sampler %s pixel (%d, %d) value %d: %a, pbrt-v4 %a\n",
                      clr_sampler_type_name(pin->type), at[k][0], at[k][1], j, (double)v[j],
                      (double)want);
            assert_true(v[j] == want);
          }
          clr_camera_sample cs;
          clr_camera_layout l = layout_for(pin->type, CLR_SEEDING_PBRT_V4, CLR_FILTER_BOX, 0.0f);
          clr_camera_layout_skip(&l, it.camera_offset, it.time_offset, it.lens_offset);
          clr_camera_sample_from_values(&l, v + it.camera_offset, at[k][0], at[k][1], &cs);
          float lx = (1.0f - v[1]) * -0.5f + v[1] * 0.5f, ly = (1.0f - v[2]) * -0.5f + v[2] * 0.5f;
          assert_true(cs.film_x == ((float)at[k][0] + lx) + 0.5f);
          assert_true(cs.film_y == ((float)at[k][1] + ly) + 0.5f);
          if (moving)
            assert_true(cs.time == v[3] && cs.lens_u == v[4] && cs.lens_v == v[5]);
          else /* never read by a pinhole's rays */
            assert_true(cs.time == 0.0f && cs.lens_u == 0.5f && cs.lens_v == 0.5f);
          assert_true(v[it.value_offset] == pin->v[k][6]); /* the integrator's first Get1D */
        }
      clr_integrator_free(&it);
    }
    parsed_free(&p);
  }
  /* pbrt-v3 names with the default seeding keep pbrt-v3's layout */
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, CLR_SAMPLER_HALTON);
  assert_false(clr_camera_sample_is_pbrt_v4(&d));
  clr_sampler_desc_init(&d, CLR_SAMPLER_PMJ02BN);
  assert_true(clr_camera_sample_is_pbrt_v4(&d));
}

static clr_render_image render(const char *text, const char *sampler, clr_seeding seeding,
                               int nthreads, int tile_size, int host_samples, const char *filter,
                               uint64_t *samples) {
  clr_render_options o;
  clr_render_options_init(&o);
  o.sampler = sampler;
  o.seeding = seeding;
  o.spp = 8;
  o.nthreads = nthreads;
  o.tile_size = tile_size;
  o.reference_samples = host_samples;
  o.filter = filter;
  o.xresolution = 24;
  o.yresolution = 20;
  clr_render_stats st;
  clr_render_stats_init(&st);
  clr_render_image im = stu_render_image(text, "test.pbrt", &o, &st);
  if (samples) *samples = st.samples;
  return im;
}

/* A render with pbrt-v4 samplers is the same bits whatever the threads and with the host's
 * reference sample vectors; other tile sizes agree to 1e-5 (shading chunks differ, as with every
 * sampler: test_render's test_tile_sizes_agree). */
static void test_render_deterministic(void **state) {
  (void)state;
  static const struct {
    const char *sampler;
    clr_seeding seeding;
    const char *filter;
  } cases[] = {{"halton", CLR_SEEDING_PBRT_V4, "box"},
               {"zsobol", CLR_SEEDING_PIXEL, "triangle"},
               {"pmj02bn", CLR_SEEDING_PIXEL, "gaussian"}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    clr_render_image a =
        render(path_scene, cases[c].sampler, cases[c].seeding, 1, 16, 0, cases[c].filter, NULL);
    clr_render_image b =
        render(path_scene, cases[c].sampler, cases[c].seeding, 3, 16, 0, cases[c].filter, NULL);
    clr_render_image h =
        render(path_scene, cases[c].sampler, cases[c].seeding, 2, 16, 1, cases[c].filter, NULL);
    clr_render_image t =
        render(path_scene, cases[c].sampler, cases[c].seeding, 3, 5, 0, cases[c].filter, NULL);
    size_t n = (size_t)a.width * (size_t)a.height * 3;
    assert_int_equal(a.width, 24);
    assert_int_equal(b.width, 24);
    assert_int_equal(h.width, 24);
    assert_int_equal(t.width, 24);
    assert_memory_equal(a.rgb, b.rgb, n * sizeof(float));
    assert_memory_equal(a.rgb, h.rgb, n * sizeof(float));
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
      sum += a.rgb[i];
      assert_true(fabsf(a.rgb[i] - t.rgb[i]) <= 1e-5f * fmaxf(1.0f, fabsf(a.rgb[i])));
    }
    assert_true(sum > 0.0 && isfinite(sum));
    free(a.rgb);
    free(b.rgb);
    free(h.rgb);
    free(t.rgb);
  }
}

/* pbrt-v4 samples the pixel bounds only and gives each sample to its own pixel when it samples
 * the filter (box, triangle): 24 x 20 pixels x 8 samples reach the film. pbrt-v3's layout and
 * filters pbrt-v4 cannot sample exactly splat over the bounds grown by the radius (2: 28 x 24). */
static void test_filter_sampled_film(void **state) {
  (void)state;
  static const struct {
    const char *sampler;
    clr_seeding seeding;
    const char *filter;
    uint64_t samples;
  } cases[] = {{"zsobol", CLR_SEEDING_PIXEL, "triangle", 24 * 20 * 8},
               {"halton", CLR_SEEDING_PBRT_V4, "triangle", 24 * 20 * 8},
               {"halton", CLR_SEEDING_PIXEL, "triangle", 28 * 24 * 8},
               {"zsobol", CLR_SEEDING_PIXEL, "gaussian", 28 * 24 * 8}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    uint64_t samples = 0;
    clr_render_image im =
        render(path_scene, cases[c].sampler, cases[c].seeding, 2, 16, 0, cases[c].filter, &samples);
    assert_int_equal(samples, cases[c].samples);
    free(im.rgb);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_layout_requests),       cmocka_unit_test(test_film_position_box),
      cmocka_unit_test(test_film_position_filters), cmocka_unit_test(test_vectors_match_pbrt_v4),
      cmocka_unit_test(test_render_deterministic),  cmocka_unit_test(test_filter_sampled_film),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
