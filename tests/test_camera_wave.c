/* A wave's camera samples and rays (clr_camera_samples_from_values, rs_camera_rays) equal the
 * sample-by-sample ones (clr_camera_sample_from_values, rs_camera_ray) bit for bit: pinhole,
 * lens, moving and orthographic cameras, screen windows, random and edge samples, waves longer
 * than RS_CAMERA_WAVE, runs starting inside a pixel. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include "camera.h"
#include "camera_sample.h"
#include "scene_parser.h"
#include "scene_test_util.h"
#include "camera_layout_test_util.h"

#define N 203 /* three waves and a part */
#define XRES 48
#define YRES 32

typedef struct samples_store {
  float a[7][N];
  clr_camera_samples s;
} samples_store;

static void store_init(samples_store *st) {
  memset(st->a, 0, sizeof st->a);
  st->s =
      (clr_camera_samples){st->a[0], st->a[1], st->a[2], st->a[3], st->a[4], st->a[5], st->a[6]};
}

static uint32_t next_u32(uint64_t *state) { /* splitmix64's high half */
  uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return (uint32_t)((z ^ (z >> 31)) >> 32);
}

static float next_unit(uint64_t *state) { return (float)(next_u32(state) >> 8) * 0x1p-24f; }

/* Film positions over and past the raster (crop windows reach outside it), edge values first:
 * pixel corners, the last float below 1, the raster's far edges. */
static void fill_samples(samples_store *st, uint64_t seed) {
  static const float edge[] = {0.0f, 0x1.fffffep-1f, 0.5f, 0x1p-24f};
  uint64_t state = seed;
  store_init(st);
  for (int k = 0; k < N; ++k) {
    float fx, fy;
    if (k < 16) {
      fx = (k & 1 ? (float)XRES : 0.0f) + edge[k % 4];
      fy = (k & 2 ? (float)YRES : 0.0f) + edge[(k / 4) % 4];
    } else {
      fx = -8.0f + 64.0f * next_unit(&state);
      fy = -8.0f + 48.0f * next_unit(&state);
    }
    st->s.film_x[k] = fx;
    st->s.film_y[k] = fy;
    st->s.time[k] = k < 16 ? edge[k % 4] : next_unit(&state);
    st->s.lens_u[k] = k < 16 ? edge[(k + 1) % 4] : next_unit(&state);
    st->s.lens_v[k] = k < 16 ? edge[(k + 2) % 4] : next_unit(&state);
  }
}

static void build_camera(const char *text, rs_camera *cam) {
  clr_scene_desc *d = stu_parse(text, CLR_BINARY_DIR "/camera_wave.pbrt");
  assert_int_equal(rs_camera_build(cam, d, NULL, NULL), CLR_SUCCESS);
  assert_int_equal(rs_camera_set_film(cam, XRES, YRES), CLR_SUCCESS);
  cam->differential_scale = 0.25f;
  clr_scene_desc_free(d);
}

/* The wave's rays (with and without differentials) against rs_camera_ray's, field by field. */
static void assert_wave_matches(const rs_camera *cam) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    samples_store st;
    fill_samples(&st, seed);
    for (int with_rd = 0; with_rd < 2; ++with_rd) {
      clr_ray rays[N], ray;
      clr_ray_differential rd[N], one;
      float weights[N];
      memset(rays, 0xa5, sizeof rays);
      memset(rd, 0, sizeof rd);
      rs_camera_rays(cam, &st.s, N, rays, with_rd ? rd : NULL, weights);
      for (int k = 0; k < N; ++k) {
        memset(&ray, 0xa5, sizeof ray);
        memset(&one, 0, sizeof one);
        float w = rs_camera_ray(cam, st.s.film_x[k], st.s.film_y[k], st.s.time[k], st.s.lens_u[k],
                                st.s.lens_v[k], &ray, with_rd ? &one : NULL);
        assert_memory_equal(&rays[k], &ray, sizeof ray);
        assert_memory_equal(&weights[k], &w, sizeof w);
        if (with_rd) assert_memory_equal(&rd[k], &one, sizeof one);
      }
    }
  }
}

static void test_pinhole(void **state) {
  (void)state;
  rs_camera cam;
  build_camera(
      "LookAt 0.25 1.5 -3  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" [45]\n"
      "WorldBegin\nWorldEnd\n",
      &cam);
  assert_int_equal(cam.fixed_origin, 1);
  assert_wave_matches(&cam);
  build_camera(
      "Scale -1 1 1\nLookAt 3 2 1  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" "
      "[70] \"float screenwindow\" [-0.5 1 -0.25 0.75]\nWorldBegin\nWorldEnd\n",
      &cam);
  assert_int_equal(cam.fixed_origin, 1);
  assert_wave_matches(&cam);
  build_camera(
      "Camera \"perspective\" \"float fov\" [30] \"float frameaspectratio\" [0.5]\n"
      "WorldBegin\nWorldEnd\n",
      &cam);
  assert_wave_matches(&cam);
}

static void test_lens_and_motion(void **state) {
  (void)state;
  rs_camera cam;
  build_camera(
      "LookAt 0 1 -3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [45] "
      "\"float lensradius\" [0.2] \"float focaldistance\" [3]\nWorldBegin\nWorldEnd\n",
      &cam);
  assert_int_equal(cam.fixed_origin, 0);
  assert_wave_matches(&cam);
  build_camera(
      "ActiveTransform StartTime\nLookAt 0 1 -3  0 0 0  0 1 0\n"
      "ActiveTransform EndTime\nLookAt 1 1 -3  1 0 0  0 1 0\nActiveTransform All\n"
      "TransformTimes 0.25 0.75\nCamera \"perspective\" \"float fov\" [45] "
      "\"float shutteropen\" [0.1] \"float shutterclose\" [0.9]\nWorldBegin\nWorldEnd\n",
      &cam);
  assert_int_equal(cam.fixed_origin, 0);
  assert_wave_matches(&cam);
}

/* Shutter times mapped onto TransformTimes (clamped to [0, 1]) for a pinhole. */
static void test_pinhole_shutter_times(void **state) {
  (void)state;
  rs_camera cam;
  build_camera(
      "TransformTimes 0.25 0.75\nCamera \"perspective\" \"float shutteropen\" [0.1] "
      "\"float shutterclose\" [0.9]\nWorldBegin\nWorldEnd\n",
      &cam);
  assert_int_equal(cam.fixed_origin, 1);
  assert_true(cam.motion.end_time - cam.motion.start_time > 0.0f);
  assert_wave_matches(&cam);
  /* a shutter at -0: every time is -0 before the clamp (fmaxf's own answer kept) */
  build_camera(
      "Camera \"perspective\" \"float shutteropen\" [-0] \"float shutterclose\" [-0]\n"
      "WorldBegin\nWorldEnd\n",
      &cam);
  assert_true(cam.shutter_open == 0.0f && signbit(cam.shutter_open));
  assert_wave_matches(&cam);
}

static void test_orthographic(void **state) {
  (void)state;
  rs_camera cam;
  build_camera(
      "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" "
      "[-2 2 -1.5 1.5]\nWorldBegin\nWorldEnd\n",
      &cam);
  assert_int_equal(cam.fixed_origin, 0);
  assert_wave_matches(&cam);
  build_camera(
      "Camera \"orthographic\" \"float lensradius\" [0.1] \"float focaldistance\" "
      "[2]\nWorldBegin\nWorldEnd\n",
      &cam);
  assert_wave_matches(&cam);
}

/* One layout's wave samples against clr_camera_sample_from_values for runs of n samples from
 * column px, sample s of spp (the chunk may start inside a pixel). */
static void assert_samples_match(const clr_camera_layout *l, int stride) {
  enum { MAX_STRIDE = 9 };
  static float values[N * MAX_STRIDE];
  uint64_t state = 7;
  for (int i = 0; i < N * stride; ++i)
    values[i] = i % 11 == 0 ? 0.0f : i % 13 == 0 ? 0x1.fffffep-1f : next_unit(&state);
  static const int runs[][4] = {{5, -3, 0, 16}, {-2, 7, 5, 16}, {0, 0, 0, 1}, {40, 31, 2, 3}};
  for (size_t r = 0; r < sizeof runs / sizeof runs[0]; ++r) {
    int px = runs[r][0], py = runs[r][1], s = runs[r][2], spp = runs[r][3];
    samples_store st;
    store_init(&st);
    clr_camera_samples_from_values(l, values, (size_t)stride, px, py, s, spp, N, &st.s);
    for (int k = 0; k < N; ++k) {
      clr_camera_sample cs;
      clr_camera_sample_from_values(l, values + (size_t)k * (size_t)stride, px, py, &cs);
      float got[7] = {st.s.film_x[k], st.s.film_y[k], st.s.pixel_x[k], st.s.pixel_y[k],
                      st.s.time[k],   st.s.lens_u[k], st.s.lens_v[k]};
      float want[7] = {cs.film_x, cs.film_y, cs.pixel_x, cs.pixel_y, cs.time, cs.lens_u, cs.lens_v};
      assert_memory_equal(got, want, sizeof got);
      if (++s == spp) {
        s = 0;
        ++px;
      }
    }
  }
}

static void test_camera_samples(void **state) {
  (void)state;
  clr_camera_layout v3 = layout_for(CLR_SAMPLER_HALTON, CLR_SEEDING_PIXEL, CLR_FILTER_BOX, 0.0f);
  assert_false(v3.pbrt_v4);
  assert_samples_match(&v3, 5);
  clr_camera_layout_skip(&v3, 0, -1, -1);
  assert_samples_match(&v3, 2);
  clr_camera_layout_skip(&v3, 2, 6, 3);
  assert_samples_match(&v3, 9);
  clr_camera_layout v4 =
      layout_for(CLR_SAMPLER_INDEPENDENT, CLR_SEEDING_PIXEL, CLR_FILTER_TRIANGLE, 2.0f);
  assert_true(v4.pbrt_v4 && v4.filter_sampled);
  assert_samples_match(&v4, 5);
  clr_camera_layout gauss =
      layout_for(CLR_SAMPLER_ZSOBOL, CLR_SEEDING_PIXEL, CLR_FILTER_GAUSSIAN, 0.0f);
  assert_samples_match(&gauss, 5);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pinhole),
      cmocka_unit_test(test_lens_and_motion),
      cmocka_unit_test(test_pinhole_shutter_times),
      cmocka_unit_test(test_orthographic),
      cmocka_unit_test(test_camera_samples),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
