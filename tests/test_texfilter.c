/* Texture filtering as pbrt-v3 (issue #11): the MIP map's pyramid (box-filtered levels of known
 * images, Lanczos resampling of sides that are not powers of two), its trilinear and EWA lookups
 * (bilinear at zero width, the image mean at full width, anisotropy), camera ray differentials
 * and ComputeDifferentials on a plane against the pinhole geometry, the 2D mappings'
 * derivatives, and renders: a fine checker far away filtered to its mean, bump maps in a mix. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "camera.h"
#include "clrender.h"
#include "clrender/image.h"
#include "mipmap.h"
#include "procedural_textures.h"
#include "renderer.h"
#include "scene_parser.h"
#include "scene_test_util.h"
#include "surface_differentials.h"
#include "textures.h"

/* A w x h image of one channel value per texel (all three channels equal). */
static float *grey_image(int w, int h, float (*f)(int s, int t)) {
  float *rgb = malloc((size_t)w * (size_t)h * 3 * sizeof *rgb);
  assert_non_null(rgb);
  for (int t = 0; t < h; ++t)
    for (int s = 0; s < w; ++s)
      for (int k = 0; k < 3; ++k) rgb[3 * (t * w + s) + k] = f(s, t);
  return rgb;
}

static float texel0(const rs_mipmap *m, int level, int s, int t) {
  return m->levels[level].rgb[3 * (t * m->levels[level].width + s)];
}

static float checker1(int s, int t) { return (float)((s + t) & 1); }
static float checker2(int s, int t) { return (float)(((s >> 1) + (t >> 1)) & 1); }
static float constant07(int s, int t) {
  (void)s;
  (void)t;
  return 0.7f;
}
static float stripes(int s, int t) {
  (void)t;
  return (float)(s & 1);
}
static uint32_t lcg_state = 1u;
static float random01(int s, int t) {
  (void)s;
  (void)t;
  lcg_state = lcg_state * 1664525u + 1013904223u;
  return (float)(lcg_state >> 8) / 16777216.0f;
}

/* An 8x8 checker of 2x2 blocks: level 1 (4x4) is the 1-texel checker of the blocks, levels 2
 * and 3 are its mean 0.5 everywhere (box filter of 2x2 texels). */
static void test_mipmap_checker_levels(void **state) {
  (void)state;
  float *img = grey_image(8, 8, checker2);
  rs_mipmap m;
  assert_int_equal(rs_mipmap_build(&m, 8, 8, img, RS_WRAP_REPEAT, 0, 8.0f), CLR_SUCCESS);
  assert_int_equal(m.count, 4);
  int sizes[4] = {8, 4, 2, 1};
  for (int l = 0; l < 4; ++l) {
    assert_int_equal(m.levels[l].width, sizes[l]);
    assert_int_equal(m.levels[l].height, sizes[l]);
  }
  for (int t = 0; t < 8; ++t)
    for (int s = 0; s < 8; ++s) assert_true(texel0(&m, 0, s, t) == checker2(s, t));
  for (int t = 0; t < 4; ++t)
    for (int s = 0; s < 4; ++s) assert_true(texel0(&m, 1, s, t) == checker1(s, t));
  for (int l = 2; l < 4; ++l)
    for (int t = 0; t < sizes[l]; ++t)
      for (int s = 0; s < sizes[l]; ++s) assert_true(texel0(&m, l, s, t) == 0.5f);
  rs_mipmap_free(&m);
  free(img);
}

/* A constant 5x3 image is resampled to 8x4 (then 4x2, 2x1, 1x1) and stays constant at every
 * level with repeat and clamp (the Lanczos weights are normalised); with black the edges lose
 * the taps that fall outside, as in pbrt-v3. */
static void test_mipmap_constant_resampled(void **state) {
  (void)state;
  float *img = grey_image(5, 3, constant07);
  rs_wrap wraps[2] = {RS_WRAP_REPEAT, RS_WRAP_CLAMP};
  int w[4] = {8, 4, 2, 1}, h[4] = {4, 2, 1, 1};
  for (int k = 0; k < 2; ++k) {
    rs_mipmap m;
    assert_int_equal(rs_mipmap_build(&m, 5, 3, img, wraps[k], 0, 8.0f), CLR_SUCCESS);
    assert_int_equal(m.count, 4);
    for (int l = 0; l < 4; ++l) {
      assert_int_equal(m.levels[l].width, w[l]);
      assert_int_equal(m.levels[l].height, h[l]);
      for (int i = 0; i < w[l] * h[l] * 3; ++i)
        assert_true(fabsf(m.levels[l].rgb[i] - 0.7f) < 1e-5f);
    }
    rs_mipmap_free(&m);
  }
  rs_mipmap m;
  assert_int_equal(rs_mipmap_build(&m, 5, 3, img, RS_WRAP_BLACK, 0, 8.0f), CLR_SUCCESS);
  assert_true(texel0(&m, 0, 0, 0) < 0.7f - 1e-3f);
  rs_mipmap_free(&m);
  free(img);
}

/* pbrt-v3's Lanczos (tau 2) in double, for the expected resampling weights. */
static double lanczos_d(double x) {
  x = fabs(x);
  if (x < 1e-5) return 1.0;
  if (x > 1.0) return 0.0;
  x *= 3.14159265358979323846;
  return sin(2.0 * x) / (2.0 * x) * (sin(x) / x);
}

/* A random 3x1 row resampled to 4x1 (repeat): each texel is the normalised four-tap Lanczos sum
 * of pbrt-v3's resampleWeights, evaluated here in double; a random 13x7 image keeps its mean
 * within 1 % (16x8) under repeat. */
static void test_mipmap_resampling(void **state) {
  (void)state;
  lcg_state = 7u;
  float *row = grey_image(3, 1, random01);
  rs_mipmap m;
  assert_int_equal(rs_mipmap_build(&m, 3, 1, row, RS_WRAP_REPEAT, 0, 8.0f), CLR_SUCCESS);
  assert_int_equal(m.levels[0].width, 4);
  assert_int_equal(m.levels[0].height, 1);
  for (int i = 0; i < 4; ++i) {
    double center = (i + 0.5) * 3.0 / 4.0, sum = 0, wsum = 0;
    int first = (int)floor(center - 2.0 + 0.5);
    for (int j = 0; j < 4; ++j) {
      double w = lanczos_d((first + j + 0.5 - center) / 2.0);
      sum += w * row[3 * (((first + j) % 3 + 3) % 3)];
      wsum += w;
    }
    assert_true(fabs(texel0(&m, 0, i, 0) - fmax(0.0, sum / wsum)) < 1e-5);
  }
  rs_mipmap_free(&m);
  free(row);
  float *img = grey_image(13, 7, random01);
  assert_int_equal(rs_mipmap_build(&m, 13, 7, img, RS_WRAP_REPEAT, 0, 8.0f), CLR_SUCCESS);
  assert_int_equal(m.levels[0].width, 16);
  assert_int_equal(m.levels[0].height, 8);
  double in = 0, out = 0;
  for (int i = 0; i < 13 * 7; ++i) in += img[3 * i];
  for (int i = 0; i < 16 * 8; ++i) out += m.levels[0].rgb[3 * i];
  in /= 13 * 7;
  out /= 16 * 8;
  fprintf(stderr, "resampled mean %.5f, image mean %.5f\n", out, in);
  assert_true(fabs(out - in) < 0.01 * in);
  /* the top level is the box mean of level 0 */
  assert_true(fabs(texel0(&m, m.count - 1, 0, 0) - out) < 1e-5);
  rs_mipmap_free(&m);
  free(img);
}

/* At zero filter width trilinear and EWA lookups are level 0's bilinear lookup, bit for bit;
 * bilinear at a texel centre is the texel. */
static void test_mipmap_zero_width_is_bilinear(void **state) {
  (void)state;
  lcg_state = 11u;
  float *img = grey_image(16, 8, random01);
  rs_mipmap ewa, tri;
  assert_int_equal(rs_mipmap_build(&ewa, 16, 8, img, RS_WRAP_REPEAT, 0, 8.0f), CLR_SUCCESS);
  assert_int_equal(rs_mipmap_build(&tri, 16, 8, img, RS_WRAP_REPEAT, 1, 8.0f), CLR_SUCCESS);
  const float zero[2] = {0, 0};
  for (int i = 0; i < 500; ++i) {
    float st[2] = {3.0f * random01(0, 0) - 1.0f, 3.0f * random01(0, 0) - 1.0f};
    float a[3], b[3], c[3];
    rs_mipmap_bilinear(&ewa, 0, st, a);
    rs_mipmap_lookup(&ewa, st, zero, zero, b);
    rs_mipmap_lookup(&tri, st, zero, zero, c);
    for (int k = 0; k < 3; ++k) assert_true(a[k] == b[k] && a[k] == c[k]);
  }
  float st[2] = {(5 + 0.5f) / 16, (3 + 0.5f) / 8}, v[3];
  rs_mipmap_bilinear(&ewa, 0, st, v);
  assert_true(fabsf(v[0] - img[3 * (3 * 16 + 5)]) < 1e-6f);
  rs_mipmap_free(&ewa);
  rs_mipmap_free(&tri);
  free(img);
}

/* Filters as wide as the texture return the top level, the image mean (a power-of-two image:
 * the exact box mean); the 1-texel checker reads 0.5 from level 1 on, so an EWA footprint of a
 * quarter of the texture is exactly 0.5. */
static void test_mipmap_wide_filters(void **state) {
  (void)state;
  lcg_state = 3u;
  float *img = grey_image(16, 16, random01);
  double mean = 0;
  for (int i = 0; i < 256; ++i) mean += img[3 * i];
  mean /= 256;
  rs_mipmap ewa, tri;
  assert_int_equal(rs_mipmap_build(&ewa, 16, 16, img, RS_WRAP_REPEAT, 0, 8.0f), CLR_SUCCESS);
  assert_int_equal(rs_mipmap_build(&tri, 16, 16, img, RS_WRAP_REPEAT, 1, 8.0f), CLR_SUCCESS);
  float st[2] = {0.3f, 0.8f}, one[2] = {1, 0}, one_t[2] = {0, 1}, v[3];
  rs_mipmap_lookup(&ewa, st, one, one_t, v);
  assert_true(fabs(v[0] - mean) < 1e-5);
  rs_mipmap_lookup(&tri, st, one, one_t, v);
  assert_true(fabs(v[0] - mean) < 1e-5);
  rs_mipmap_trilinear(&tri, st, 4.0f, v);
  assert_true(fabs(v[0] - mean) < 1e-5);
  /* half a texture: between the two coarsest levels, within their spread of the mean */
  float half[2] = {0.5f, 0}, half_t[2] = {0, 0.5f};
  rs_mipmap_lookup(&ewa, st, half, half_t, v);
  assert_true(fabs(v[0] - mean) < 0.1);
  rs_mipmap_free(&ewa);
  rs_mipmap_free(&tri);
  free(img);
  float *ck = grey_image(8, 8, checker1);
  assert_int_equal(rs_mipmap_build(&ewa, 8, 8, ck, RS_WRAP_REPEAT, 0, 8.0f), CLR_SUCCESS);
  float q[2] = {0.25f, 0}, q_t[2] = {0, 0.25f};
  for (int i = 0; i < 50; ++i) {
    float p[2] = {random01(0, 0), random01(0, 0)};
    rs_mipmap_lookup(&ewa, p, q, q_t, v);
    assert_true(fabsf(v[0] - 0.5f) < 1e-6f);
  }
  rs_mipmap_free(&ewa);
  free(ck);
}

/* EWA is anisotropic: on 1-texel vertical stripes (0, 1, 0, ...) at a texel of value 1, a
 * footprint long across the stripes averages them (0.5 within 0.1), one as long along them keeps
 * the stripe (over 0.6: the narrow axis, clamped to major / maxanisotropy, stays under a texel);
 * trilinear, isotropic, averages both. */
static void test_mipmap_ewa_anisotropy(void **state) {
  (void)state;
  float *img = grey_image(8, 8, stripes);
  rs_mipmap ewa, tri;
  assert_int_equal(rs_mipmap_build(&ewa, 8, 8, img, RS_WRAP_REPEAT, 0, 8.0f), CLR_SUCCESS);
  assert_int_equal(rs_mipmap_build(&tri, 8, 8, img, RS_WRAP_REPEAT, 1, 8.0f), CLR_SUCCESS);
  float st[2] = {3.5f / 8, 0.5f}, across[2] = {0.5f, 0}, along[2] = {0, 0.5f},
        thin_t[2] = {0, 1e-4f}, thin_s[2] = {1e-4f, 0}, v[3];
  rs_mipmap_lookup(&ewa, st, across, thin_t, v);
  fprintf(stderr, "EWA across the stripes %.4f, ", v[0]);
  assert_true(fabsf(v[0] - 0.5f) < 0.1f);
  rs_mipmap_lookup(&ewa, st, along, thin_s, v);
  fprintf(stderr, "along them %.4f\n", v[0]);
  assert_true(v[0] > 0.6f);
  rs_mipmap_lookup(&tri, st, along, thin_s, v);
  assert_true(fabsf(v[0] - 0.5f) < 1e-6f);
  /* non-finite derivatives fall back to the bilinear lookup, huge ones to the top texel */
  float inf2[2] = {INFINITY, 0}, huge[2] = {1e30f, 0}, huge_t[2] = {0, 1e30f}, b[3];
  rs_mipmap_lookup(&ewa, st, inf2, along, v);
  rs_mipmap_bilinear(&ewa, 0, st, b);
  assert_true(v[0] == b[0]);
  rs_mipmap_lookup(&ewa, st, huge, huge_t, v);
  assert_true(fabsf(v[0] - 0.5f) < 1e-6f);
  rs_mipmap_free(&ewa);
  rs_mipmap_free(&tri);
  free(img);
}

static clr_scene_desc *parse(const char *text) {
  return stu_parse(text, CLR_BINARY_DIR "/texfilter.pbrt");
}

/* The pinhole model for the camera below (at the origin looking down +z, fov 90, 100 x 100):
 * the unit direction through raster (x, y), up to the sign of its x and y. */
static void pinhole_dir(double x, double y, double d[3]) {
  d[0] = 2.0 * x / 100.0 - 1.0;
  d[1] = 1.0 - 2.0 * y / 100.0;
  d[2] = 1.0;
  double l = sqrt(d[0] * d[0] + d[1] * d[1] + 1.0);
  for (int i = 0; i < 3; ++i) d[i] /= l;
}

/* Camera ray differentials and ComputeDifferentials on the plane z = 10 with (u, v) = (x, y) / 20
 * (dpdu = (20, 0, 0), dpdv = (0, 20, 0)), perspective and orthographic, at 4 spp (offsets scaled
 * by 1/2): dudx is the x distance between the hits of the main ray and of the offset ray lerped
 * halfway toward the ray through the next pixel, over 20, from the pinhole geometry in double;
 * dvdx = dudy = 0. Orthographic: every pixel is 2/100 wide, so dudx = 0.5 * 0.02 / 20. */
static void test_camera_differentials(void **state) {
  (void)state;
  const char *types[2] = {"perspective", "orthographic"}, *extra[2] = {"\"float fov\" [90]", ""};
  for (int c = 0; c < 2; ++c) {
    char text[512];
    snprintf(text, sizeof text,
             "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"%s\" %s\nFilm \"image\" \"integer xresolution\" "
             "[100] \"integer yresolution\" [100]\nWorldBegin\nWorldEnd\n",
             types[c], extra[c]);
    clr_scene_desc *d = parse(text);
    rs_camera cam;
    assert_int_equal(rs_camera_build(&cam, d, NULL, NULL), CLR_SUCCESS);
    assert_int_equal(rs_camera_set_film(&cam, 100, 100), CLR_SUCCESS);
    cam.differential_scale = 0.5f;
    const float pixels[3][2] = {{50.5f, 50.5f}, {80.25f, 30.75f}, {5.5f, 95.5f}};
    for (int k = 0; k < 3; ++k) {
      clr_ray ray;
      clr_ray_differential rd;
      rs_camera_ray(&cam, pixels[k][0], pixels[k][1], 0.5f, 0.5f, 0.5f, &ray, &rd);
      assert_int_equal(rd.has, 1);
      float t = (10.0f - ray.oz) / ray.dz;
      float p[3] = {ray.ox + t * ray.dx, ray.oy + t * ray.dy, 10.0f}, n[3] = {0, 0, -1},
            dpdu[3] = {20, 0, 0}, dpdv[3] = {0, 20, 0};
      float uv[2] = {p[0] / 20, p[1] / 20};
      rs_tex_ctx tc = rs_tex_ctx_at(uv, p);
      rs_compute_differentials(&rd, p, n, dpdu, dpdv, &tc);
      double expect_x, expect_y;
      if (c == 0) {
        double d0[3], dx[3], dy[3], hx, hy;
        pinhole_dir(pixels[k][0], pixels[k][1], d0);
        pinhole_dir(pixels[k][0] + 1, pixels[k][1], dx);
        pinhole_dir(pixels[k][0], pixels[k][1] + 1, dy);
        for (int i = 0; i < 3; ++i) {
          dx[i] = d0[i] + 0.5 * (dx[i] - d0[i]);
          dy[i] = d0[i] + 0.5 * (dy[i] - d0[i]);
        }
        hx = 10.0 * dx[0] / dx[2] - 10.0 * d0[0] / d0[2];
        hy = 10.0 * dy[1] / dy[2] - 10.0 * d0[1] / d0[2];
        expect_x = fabs(hx) / 20.0;
        expect_y = fabs(hy) / 20.0;
      } else {
        expect_x = expect_y = 0.5 * 0.02 / 20.0;
      }
      fprintf(stderr, "%s (%.2f, %.2f): dudx %.7g (expected %.7g), dvdy %.7g (%.7g)\n",
              c ? "orthographic" : "perspective", (double)pixels[k][0], (double)pixels[k][1],
              (double)tc.dudx, expect_x, (double)tc.dvdy, expect_y);
      assert_true(fabs(fabs(tc.dudx) - expect_x) < 1e-3 * expect_x);
      assert_true(fabs(fabs(tc.dvdy) - expect_y) < 1e-3 * expect_y);
      assert_true(fabsf(tc.dvdx) < 1e-3f * (float)expect_x &&
                  fabsf(tc.dudy) < 1e-3f * (float)expect_y);
      assert_true(fabs(fabs(tc.dpdx[0]) - 20.0 * expect_x) < 1e-3 * 20.0 * expect_x);
      assert_true(fabsf(tc.dpdx[2]) < 1e-5f);
    }
    clr_scene_desc_free(d);
  }
}

/* ComputeDifferentials' failures: no differentials, an offset ray parallel to the plane (all
 * zero), degenerate partials (dpdx kept, (u, v) derivatives zero). */
static void test_differentials_degenerate(void **state) {
  (void)state;
  float p[3] = {0, 0, 10}, n[3] = {0, 0, -1}, dpdu[3] = {1, 0, 0}, dpdv[3] = {0, 1, 0},
        uv[2] = {0, 0};
  clr_ray_differential rd = {{0.01f, 0, 0}, {0, 0, 1}, {0, 0.01f, 0}, {0, 0, 1}, 1};
  rs_tex_ctx tc = rs_tex_ctx_at(uv, p);
  rs_compute_differentials(&rd, p, n, dpdu, dpdv, &tc);
  assert_true(fabsf(tc.dudx - 0.01f) < 1e-7f && fabsf(tc.dvdy - 0.01f) < 1e-7f);
  rs_compute_differentials(NULL, p, n, dpdu, dpdv, &tc);
  assert_true(tc.dudx == 0.0f && tc.dpdx[0] == 0.0f);
  clr_ray_differential parallel = rd;
  parallel.ry_d[0] = 1.0f;
  parallel.ry_d[2] = 0.0f;
  rs_compute_differentials(&parallel, p, n, dpdu, dpdv, &tc);
  assert_true(tc.dudx == 0.0f && tc.dvdy == 0.0f && tc.dpdx[0] == 0.0f);
  float flat[3] = {0, 0, 0};
  rs_compute_differentials(&rd, p, n, dpdu, flat, &tc);
  assert_true(fabsf(tc.dpdx[0] - 0.01f) < 1e-7f && tc.dudx == 0.0f && tc.dvdx == 0.0f);
}

/* pbrt-v3's mappings' derivatives: uv scales (u, v)'s by (uscale, vscale), planar projects
 * dpdx on v1 and v2, spherical and cylindrical match a central difference of their st along
 * dpdx within 2 % (their finite steps are 0.1 and 0.01 of dpdx). */
static void test_mapping_derivatives(void **state) {
  (void)state;
  clr_scene_desc *d = parse(
      "WorldBegin\nTexture \"u\" \"float\" \"checkerboard\" \"float uscale\" [4] "
      "\"float vscale\" [-2]\nTexture \"p\" \"float\" \"checkerboard\" \"string mapping\" "
      "\"planar\" \"vector v1\" [1 2 0] \"vector v2\" [0 0 3]\nTexture \"s\" \"float\" "
      "\"checkerboard\" \"string mapping\" \"spherical\"\nTexture \"c\" \"float\" "
      "\"checkerboard\" \"string mapping\" \"cylindrical\"\nWorldEnd\n");
  rs_texture_set set;
  assert_int_equal(rs_textures_build(&set, d, NULL, NULL), CLR_SUCCESS);
  float uv[2] = {0.3f, 0.6f}, p[3] = {0.6f, 0.8f, 0.5f}, st[2], dx[2], dy[2];
  rs_tex_ctx tc = rs_tex_ctx_at(uv, p);
  tc.dudx = 0.01f;
  tc.dvdx = 0.02f;
  tc.dudy = -0.03f;
  tc.dvdy = 0.04f;
  float dpdx[3] = {0.001f, -0.002f, 0.0015f}, dpdy[3] = {-0.002f, 0.001f, 0.001f};
  memcpy(tc.dpdx, dpdx, sizeof dpdx);
  memcpy(tc.dpdy, dpdy, sizeof dpdy);
  rs_texture_map_2d(&set.items[0], &tc, st, dx, dy);
  assert_true(fabsf(dx[0] - 0.04f) < 1e-7f && fabsf(dx[1] + 0.04f) < 1e-7f);
  assert_true(fabsf(dy[0] + 0.12f) < 1e-7f && fabsf(dy[1] + 0.08f) < 1e-7f);
  rs_texture_map_2d(&set.items[1], &tc, st, dx, dy);
  assert_true(fabsf(dx[0] - (0.001f - 0.004f)) < 1e-7f && fabsf(dx[1] - 0.0045f) < 1e-7f);
  assert_true(fabsf(dy[0] - 0.0f) < 1e-7f && fabsf(dy[1] - 0.003f) < 1e-7f);
  for (int m = 2; m < 4; ++m) {
    rs_texture_map_2d(&set.items[m], &tc, st, dx, dy);
    float a[2], b[2], h = 0.05f;
    rs_tex_ctx e = tc;
    for (int i = 0; i < 3; ++i) e.p[i] = p[i] + h * dpdx[i];
    rs_texture_map_2d(&set.items[m], &e, a, NULL, NULL);
    for (int i = 0; i < 3; ++i) e.p[i] = p[i] - h * dpdx[i];
    rs_texture_map_2d(&set.items[m], &e, b, NULL, NULL);
    for (int k = 0; k < 2; ++k) {
      float central = (a[k] - b[k]) / (2 * h);
      assert_true(fabsf(dx[k] - central) < 0.02f * fmaxf(fabsf(central), 1e-3f));
    }
  }
  rs_textures_free(&set);
  clr_scene_desc_free(d);
}

/* pbrt-v3's FBm and Turbulence drop octaves as the footprint grows: n = -1 - log2(|dpdx|), so
 * |dpdx| = 1/8 keeps 2 whole octaves; 2^-3.5 adds half (SmoothStep(0.3, 0.7, 0.5)) of the
 * third; |dpdx| >= 1/2 keeps none. Turbulence counts 0.2 for the partial octave's stead and for
 * each dropped one (the first two with the same weight). Zero differentials: every octave. */
static void test_noise_octaves(void **state) {
  (void)state;
  const float w = 0.6f, zero[3] = {0, 0, 0};
  float p[3] = {0.37f, -1.21f, 2.45f}, p1[3], p2[3];
  for (int k = 0; k < 3; ++k) {
    p1[k] = 1.99f * p[k];
    p2[k] = 1.99f * 1.99f * p[k];
  }
  float n0 = rs_noise(p[0], p[1], p[2]), n1 = rs_noise(p1[0], p1[1], p1[2]),
        n2 = rs_noise(p2[0], p2[1], p2[2]);
  float eighth[3] = {0.125f, 0, 0}, small[3] = {0, 0.015625f, 0}, half_oct[3] = {0, 0, 0};
  half_oct[2] = powf(2.0f, -3.5f);
  assert_true(fabsf(rs_fbm_d(p, eighth, small, w, 6) - (n0 + w * n1)) < 1e-6f);
  assert_true(fabsf(rs_fbm_d(p, small, eighth, w, 6) - (n0 + w * n1)) < 1e-6f);
  assert_true(fabsf(rs_fbm_d(p, half_oct, zero, w, 6) - (n0 + w * n1 + w * w * 0.5f * n2)) < 1e-5f);
  float big[3] = {0.5f, 0, 0};
  assert_true(rs_fbm_d(p, big, big, w, 6) == 0.0f);
  assert_true(rs_fbm_d(p, zero, zero, w, 6) == rs_fbm(p, w, 6));
  float turb = fabsf(n0) + w * fabsf(n1) + w * w * 0.2f + w * w * 0.2f + w * w * w * 0.2f;
  assert_true(fabsf(rs_turbulence_d(p, eighth, zero, w, 4) - turb) < 1e-6f);
  assert_true(rs_turbulence_d(p, zero, zero, w, 4) == rs_turbulence(p, w, 4));
}

static float checker_at(const rs_texture_set *set, int tex, float s, float t, float ds, float dt) {
  float uv[2] = {s, t}, p[3] = {0, 0, 0}, out[3];
  rs_tex_ctx tc = rs_tex_ctx_at(uv, p);
  tc.dudx = ds;
  tc.dvdy = -dt;
  rs_colour c = {tex, {0, 0, 0}};
  rs_colour_eval(set, &c, &tc, out);
  return out[0];
}

/* pbrt-v3's closed-form box filter of the 2D checkerboard (tex1 0, tex2 1: the value is tex2's
 * share of the footprint [s - ds, s + ds] x [t - dt, t + dt]): inside one check a point sample,
 * 0.25 of an odd s check on an even t check, 0.75 on an odd one, 0.5 for a whole period and
 * past a check's width; "aamode" "none" point-samples. */
static void test_checker_closed_form(void **state) {
  (void)state;
  clr_scene_desc *d = parse(
      "WorldBegin\nTexture \"ck\" \"float\" \"checkerboard\" \"float tex1\" [0] \"float "
      "tex2\" [1]\nTexture \"pt\" \"float\" \"checkerboard\" \"float tex1\" [0] \"float "
      "tex2\" [1] \"string aamode\" \"none\"\nWorldEnd\n");
  rs_texture_set set;
  assert_int_equal(rs_textures_build(&set, d, NULL, NULL), CLR_SUCCESS);
  assert_true(checker_at(&set, 0, 0.5f, 0.5f, 0.1f, 0.1f) == 0.0f);
  assert_true(checker_at(&set, 0, 1.5f, 0.5f, 0.1f, 0.1f) == 1.0f);
  assert_true(fabsf(checker_at(&set, 0, 0.9f, 0.25f, 0.2f, 0.1f) - 0.25f) < 1e-5f);
  assert_true(fabsf(checker_at(&set, 0, 0.9f, 1.25f, 0.2f, 0.1f) - 0.75f) < 1e-5f);
  assert_true(fabsf(checker_at(&set, 0, 0.5f, 0.25f, 1.0f, 0.1f) - 0.5f) < 1e-6f);
  assert_true(checker_at(&set, 0, 0.3f, 0.25f, 3.0f, 0.1f) == 0.5f);
  assert_true(fabsf(checker_at(&set, 0, 1.0f, 0.25f, 0.5f, 0.0f) - 0.5f) < 1e-6f);
  assert_true(checker_at(&set, 1, 0.9f, 0.25f, 0.2f, 0.1f) == 0.0f);
  rs_textures_free(&set);
  clr_scene_desc_free(d);
}

static float *render(const char *scene, int *w, int *h) {
  return stu_render(scene, CLR_BINARY_DIR "/texfilter.pbrt", w, h);
}

/* A 1-texel checker (16x16 PNG, 0 and 1, gamma off) tiled 3 x 3 times over a plane seen
 * head-on, a pixel covering 3x3 texels, 1 spp at pixel centres, a distant light along the normal
 * (L = pi, matte: radiance = Kd): with the MIP map every pixel is the checker's mean 0.5 (within
 * 1e-3); unfiltered ("bilinear") each pixel centre falls on a texel centre: 0 or 1. */
static void test_filtered_render(void **state) {
  (void)state;
  float rgb[16 * 16 * 3];
  for (int i = 0; i < 256; ++i)
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = checker1(i % 16, i / 16);
  clr_image im = {16, 16, rgb};
  assert_int_equal(clr_image_write_png(CLR_BINARY_DIR "/texfilter_checker.png", &im), CLR_SUCCESS);
  const char *filters[2] = {"", "\"string filtertype\" \"bilinear\""};
  for (int f = 0; f < 2; ++f) {
    char scene[2048];
    snprintf(scene, sizeof scene,
             "LookAt 0.5 0.5 5  0.5 0.5 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" "
             "[-0.5 0.5 -0.5 0.5]\nFilm \"image\" \"integer xresolution\" [16] \"integer "
             "yresolution\" [16]\nSampler \"halton\" \"integer pixelsamples\" [1] \"bool "
             "samplepixelcenter\" \"true\"\nIntegrator \"directlighting\"\nWorldBegin\n"
             "LightSource \"distant\" \"point from\" [0 0 1] \"point to\" [0 0 0] \"rgb L\" "
             "[3.14159265 3.14159265 3.14159265]\n"
             "Texture \"ck\" \"spectrum\" \"imagemap\" \"string filename\" "
             "\"texfilter_checker.png\" \"bool gamma\" \"false\" \"float uscale\" [3] \"float "
             "vscale\" [3] %s\nMaterial \"matte\" \"texture Kd\" \"ck\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" [0 0 0  1 0 0  "
             "1 1 0  0 1 0] \"float uv\" [0 0 1 0 1 1 0 1]\nWorldEnd\n",
             filters[f]);
    int w, h;
    float *px = render(scene, &w, &h);
    double worst = 0;
    for (int i = 0; i < w * h; ++i) worst = fmax(worst, fabs(px[3 * i] - 0.5));
    fprintf(stderr, "%s: worst pixel off 0.5 by %.5f\n", f ? "unfiltered" : "MIP map", worst);
    if (f == 0)
      assert_true(worst < 1e-3);
    else
      assert_true(worst > 0.49);
    free(px);
  }
}

/* pbrt-v3's MixMaterial keeps its first material's bumped shading frame for both materials' lobes
 * and ignores the second's bump map: the bumped plane of test_bump_plane (radiance cos 45 under
 * a light along the normal) mixed half and half with a plain matte still gives cos 45; with the
 * bumped matte second, 1. */
static void test_bump_in_mix(void **state) {
  (void)state;
  float rgb[6] = {0, 0, 0, 1, 1, 1};
  clr_image im = {2, 1, rgb};
  assert_int_equal(clr_image_write_png(CLR_BINARY_DIR "/texfilter_ramp.png", &im), CLR_SUCCESS);
  for (int order = 0; order < 2; ++order) {
    char scene[2048];
    snprintf(scene, sizeof scene,
             "LookAt 0.5 0.5 5  0.5 0.5 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" "
             "[-0.2 0.2 -0.2 0.2]\nFilm \"image\" \"integer xresolution\" [8] \"integer "
             "yresolution\" [8]\nSampler \"halton\" \"integer pixelsamples\" [1] \"bool "
             "samplepixelcenter\" \"true\"\nIntegrator \"directlighting\"\nWorldBegin\n"
             "LightSource \"distant\" \"point from\" [0 0 1] \"point to\" [0 0 0] \"rgb L\" "
             "[3.14159265 3.14159265 3.14159265]\n"
             "Texture \"ramp\" \"float\" \"imagemap\" \"string filename\" \"texfilter_ramp.png\" "
             "\"bool gamma\" \"false\" \"float scale\" [0.5] \"string wrap\" \"clamp\" "
             "\"string filtertype\" \"bilinear\"\n"
             "MakeNamedMaterial \"bumped\" \"string type\" \"matte\" \"rgb Kd\" [1 1 1] "
             "\"texture bumpmap\" \"ramp\"\n"
             "MakeNamedMaterial \"plain\" \"string type\" \"matte\" \"rgb Kd\" [1 1 1]\n"
             "MakeNamedMaterial \"both\" \"string type\" \"mix\" \"string namedmaterial1\" "
             "\"%s\" \"string namedmaterial2\" \"%s\"\nNamedMaterial \"both\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" [0 0 0  1 0 0  "
             "1 1 0  0 1 0] \"float uv\" [0 0 1 0 1 1 0 1]\nWorldEnd\n",
             order ? "plain" : "bumped", order ? "bumped" : "plain");
    int w, h;
    float *px = render(scene, &w, &h);
    double mean = 0;
    for (int i = 0; i < w * h; ++i) mean += px[3 * i];
    mean /= w * h;
    fprintf(stderr, "mix with the bumped matte %s: %.6f\n", order ? "second" : "first", mean);
    assert_true(fabs(mean - (order ? 1.0 : 0.70710678)) < 1e-4);
    free(px);
  }
}

/* A bad "maxanisotropy" is an error naming the file, line and value. */
static void test_bad_maxanisotropy(void **state) {
  (void)state;
  float rgb[3] = {1, 1, 1};
  clr_image im = {1, 1, rgb};
  assert_int_equal(clr_image_write_png(CLR_BINARY_DIR "/texfilter_1x1.png", &im), CLR_SUCCESS);
  const char *values[3] = {"0", "-2", "1e9"};
  for (int i = 0; i < 3; ++i) {
    char text[512];
    snprintf(text, sizeof text,
             "WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\" \"string filename\" "
             "\"texfilter_1x1.png\" \"float maxanisotropy\" [%s]\nWorldEnd\n",
             values[i]);
    clr_scene_desc *d = parse(text);
    rs_texture_set set;
    assert_int_equal(rs_textures_build(&set, d, NULL, NULL), CLR_ERROR_SCENE);
    const char *msg = clr_last_error_message();
    assert_non_null(strstr(msg, "texfilter.pbrt:2"));
    assert_non_null(strstr(msg, "maxanisotropy"));
    rs_textures_free(&set);
    clr_scene_desc_free(d);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mipmap_checker_levels),
      cmocka_unit_test(test_mipmap_constant_resampled),
      cmocka_unit_test(test_mipmap_resampling),
      cmocka_unit_test(test_mipmap_zero_width_is_bilinear),
      cmocka_unit_test(test_mipmap_wide_filters),
      cmocka_unit_test(test_mipmap_ewa_anisotropy),
      cmocka_unit_test(test_camera_differentials),
      cmocka_unit_test(test_differentials_degenerate),
      cmocka_unit_test(test_mapping_derivatives),
      cmocka_unit_test(test_noise_octaves),
      cmocka_unit_test(test_checker_closed_form),
      cmocka_unit_test(test_filtered_render),
      cmocka_unit_test(test_bump_in_mix),
      cmocka_unit_test(test_bad_maxanisotropy),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
