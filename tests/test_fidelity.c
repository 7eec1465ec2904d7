/* Renderer fidelity (issue #11): crops that merge exactly at their seams, spot light falloff,
 * sphere area lights, rays skipped by the light's own shape, output by extension. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>
#include "clrender.h"
#include "integrator.h"
#include "microfacet.h"
#include "renderer.h"
#include "scene_parser.h"
#include "cornell_test_scene.h"
#include "scene_test_util.h"

#define PI_D 3.14159265358979323846

static clr_render_image render_opts(const char *text, const clr_render_options *opts,
                                    clr_render_stats *stats) {
  return stu_render_image(text, "fidelity.pbrt", opts, stats);
}

static double image_mean(const clr_render_image *im) {
  double s = 0;
  size_t n = (size_t)im->width * im->height * 3;
  for (size_t i = 0; i < n; ++i) s += im->rgb[i];
  return s / (double)n;
}

/* ---- crops ---- */

/* A small Cornell-like box: area light, walls, a sphere; direct lighting keeps it fast. */
static const char *crop_box = CORNELL_CAMERA
    "Film \"image\" \"integer xresolution\" [24] \"integer yresolution\" [22]\n"
    "Integrator \"directlighting\"\nWorldBegin\n" CORNELL_LIGHT_FLOOR_AND_BACK_WALL
    "Material \"matte\" \"rgb Kd\" [0.1 0.6 0.2]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
    "\"point P\" [0 0 0  0 548 0  0 548 559  0 0 559]\n"
    "AttributeBegin\nTranslate 300 100 300\nShape \"sphere\" \"float radius\" [100]\nAttributeEnd\n"
    "WorldEnd\n";

/* Renders the crops given by the x cuts and y cuts, pastes each crop's pixels into one image and
 * checks it equals the full render within 1e-5 relative to max(|pixel|, image mean). Crops of
 * one frame cover disjoint pixels, so pasting is film_merge_sums' result for them. */
static void check_crops(const char *sampler, const char *filter, const float *xs, int nx,
                        const float *ys, int ny) {
  clr_render_options o;
  clr_render_options_init(&o);
  o.sampler = sampler;
  o.filter = filter;
  o.spp = 4;
  o.nthreads = 2;
  clr_render_image full = render_opts(crop_box, &o, NULL);
  double mean = image_mean(&full);
  assert_true(mean > 0.01);
  size_t n = (size_t)full.width * full.height * 3;
  float *merged = malloc(n * sizeof *merged);
  unsigned char *covered = calloc(n, 1);
  assert_non_null(merged);
  assert_non_null(covered);
  for (int i = 0; i + 1 < nx; ++i)
    for (int j = 0; j + 1 < ny; ++j) {
      o.crop_given = 1;
      o.crop_window[0] = xs[i], o.crop_window[1] = xs[i + 1];
      o.crop_window[2] = ys[j], o.crop_window[3] = ys[j + 1];
      clr_render_image c = render_opts(crop_box, &o, NULL);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
          for (int k = 0; k < 3; ++k) {
            size_t at =
                3 * ((size_t)(y + c.pixel_bounds.y0) * full.width + x + c.pixel_bounds.x0) + k;
            merged[at] = c.rgb[3 * ((size_t)y * c.width + x) + k];
            covered[at]++;
          }
      free(c.rgb);
    }
  int bad = 0;
  for (size_t i = 0; i < n; ++i) {
    assert_int_equal(covered[i], 1);
    double tol = 1e-5 * fmax(fabs((double)full.rgb[i]), mean);
    if (fabs((double)merged[i] - full.rgb[i]) > tol) {
      if (bad++ < 4)
        fprintf(stderr, "%s/%s: pixel (%zu,%zu)[%zu]: crops %g, full %g\n", sampler, filter,
                (i / 3) % (size_t)full.width, (i / 3) / (size_t)full.width, i % 3,
                (double)merged[i], (double)full.rgb[i]);
    }
  }
  assert_int_equal(bad, 0);
  free(merged);
  free(covered);
  free(full.rgb);
}

static const float halves[] = {0.0f, 0.5f, 1.0f};
static const float whole[] = {0.0f, 1.0f};
static const float odd[] = {0.0f, 0.37f, 1.0f};

static void test_crop_halves_every_sampler(void **state) {
  (void)state;
  const char *samplers[] = {"halton", "sobol", "random", "stratified"};
  for (int s = 0; s < 4; ++s) {
    check_crops(samplers[s], "box", whole, 2, halves, 3);      /* top and bottom halves */
    check_crops(samplers[s], "gaussian", halves, 3, whole, 2); /* left and right halves */
  }
}

static void test_crop_quarters_and_odd(void **state) {
  (void)state;
  check_crops("halton", "box", halves, 3, halves, 3);
  check_crops("sobol", "gaussian", halves, 3, halves, 3);
  check_crops("halton", "gaussian", odd, 3, odd, 3);
  check_crops("sobol", "box", odd, 3, odd, 3);
  check_crops("stratified", "box", odd, 3, whole, 2);
}

/* ---- spot light ---- */

/* pbrt-v3 SpotLight::Falloff: 1 inside coneangle - conedeltaangle, 0 outside coneangle, the 4th
 * power of the linear cosine ramp between. */
static double spot_falloff(double cos_t, double cone, double delta) {
  double ct = cos(cone * PI_D / 180.0), cf = cos((cone - delta) * PI_D / 180.0);
  if (cos_t < ct) return 0.0;
  if (cos_t >= cf) return 1.0;
  double d = (cos_t - ct) / (cf - ct);
  return d * d * d * d;
}

/* Lambertian plane under a spot light pointing down with a 10 degree "conedeltaangle": every
 * pixel centre is Kd/pi * I falloff(theta) cos(theta) / r^2. */
static void test_spot_conedeltaangle(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [32] \"integer yresolution\" [32]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
      "Integrator \"directlighting\"\n"
      "WorldBegin\nLightSource \"spot\" \"point from\" [0 0 1.5] \"point to\" [0 0 0] \"rgb I\" [5 "
      "5 5]\n"
      "\"float coneangle\" [30] \"float conedeltaangle\" [10]\n"
      "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n";
  clr_render_image im = render_opts(scene, NULL, NULL);
  int ramp = 0;
  for (int py = 0; py < 32; ++py)
    for (int px = 0; px < 32; ++px) {
      double wx = -(-1.0 + 2.0 * (px + 0.5) / 32.0), wy = 1.0 - 2.0 * (py + 0.5) / 32.0;
      double r2 = wx * wx + wy * wy + 1.5 * 1.5, cos_t = 1.5 / sqrt(r2);
      double f = spot_falloff(cos_t, 30.0, 10.0);
      if (f > 0.0 && f < 1.0) ++ramp;
      double expect = 0.5 / PI_D * 5.0 * f * cos_t / r2;
      double got = im.rgb[3 * (py * 32 + px)];
      assert_true(fabs(got - expect) <= 1e-4 * expect + 1e-7);
    }
  assert_true(ramp > 50); /* the falloff ring is well sampled */
  free(im.rgb);
}

/* ---- sphere area lights ---- */

/* Relative RMSE of `a` against reference `ref`: sqrt(mean((a - ref)^2)) / mean(ref). */
static double rel_rmse(const clr_render_image *a, const clr_render_image *ref) {
  size_t n = (size_t)ref->width * ref->height * 3;
  double e = 0;
  for (size_t i = 0; i < n; ++i)
    e += ((double)a->rgb[i] - ref->rgb[i]) * ((double)a->rgb[i] - ref->rgb[i]);
  return sqrt(e / (double)n) / image_mean(ref);
}

static const char *sphere_light_scene =
    "LookAt 0 3 -6  0 0.5 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n"
    "Film \"image\" \"integer xresolution\" [32] \"integer yresolution\" [24]\n"
    "Sampler \"halton\"\nIntegrator \"path\"\nWorldBegin\n"
    "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [4 4 4] \"bool twosided\" \"true\"\n"
    "Translate 0 2.2 0\nShape \"sphere\" \"float radius\" [0.5]\nAttributeEnd\n"
    "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" [8] \"float vscale\" [8]\n"
    "\"rgb tex1\" [0.8 0.8 0.8] \"rgb tex2\" [0.2 0.2 0.2]\n"
    "Material \"matte\" \"texture Kd\" \"checks\"\nShape \"sphere\" \"float radius\" [1]\n"
    "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5]\n"
    "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
    "\"point P\" [-10 -1 -10  10 -1 -10  10 -1 10  -10 -1 10]\nWorldEnd\n";

/* Lambertian plane z = 0 under a sphere light (radius r, radiance L, centre c): a sphere wholly
 * above a point's horizon gives irradiance E = pi L r^2 cos(phi) / d^2 (it acts as a point
 * source), so every pixel centre is Kd L r^2 cos(phi) / d^2. Cone sampling gives directions that
 * all reach the sphere; the MIS BSDF samples that hit it add the remaining noise: 64 samples at
 * the pixel centre are within 3 % (1.4 % measured), the image mean within 0.2 %. The light has
 * Material "none": camera rays pass through it to the plane. */
static void test_sphere_light_irradiance(void **state) {
  (void)state;
  const double L = 3.0, r = 0.4, c[3] = {0.3, -0.2, 1.2}, kd = 0.5;
  char scene[2048];
  snprintf(scene, sizeof scene,
           "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
           "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
           "Sampler \"halton\" \"integer pixelsamples\" [64] \"bool samplepixelcenter\" \"true\"\n"
           "Integrator \"directlighting\"\nWorldBegin\n"
           "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [%g %g %g]\n"
           "Material \"none\"\nTranslate %g %g %g\nShape \"sphere\" \"float radius\" "
           "[%g]\nAttributeEnd\n"
           "Material \"matte\" \"rgb Kd\" [%g %g %g]\n"
           "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
           "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
           L, L, L, c[0], c[1], c[2], r, kd, kd, kd);
  clr_render_image im = render_opts(scene, NULL, NULL);
  double worst = 0, sum = 0, sum_expect = 0;
  for (int py = 0; py < 16; ++py)
    for (int px = 0; px < 16; ++px) {
      double wx = -(-1.0 + 2.0 * (px + 0.5) / 16.0), wy = 1.0 - 2.0 * (py + 0.5) / 16.0;
      double dx = c[0] - wx, dy = c[1] - wy, dz = c[2], d2 = dx * dx + dy * dy + dz * dz;
      double expect = kd * L * r * r * (dz / sqrt(d2)) / d2;
      double got = im.rgb[3 * (py * 16 + px)];
      if (fabs(got / expect - 1.0) > worst) worst = fabs(got / expect - 1.0);
      sum += got;
      sum_expect += expect;
    }
  fprintf(stderr, "sphere light irradiance: worst pixel error %.4f, mean ratio %.5f\n", worst,
          sum / sum_expect);
  assert_true(worst < 0.03);
  assert_true(fabs(sum / sum_expect - 1.0) < 0.002);
  free(im.rgb);
}

/* Two-sided sphere light over a checkerboard sphere, path tracer: the 16-spp image against a
 * 512-spp one of the same scene. */
static void test_sphere_light_noise(void **state) {
  (void)state;
  clr_render_options o;
  clr_render_options_init(&o);
  o.nthreads = 2;
  o.spp = 512;
  clr_render_image ref = render_opts(sphere_light_scene, &o, NULL);
  o.spp = 16;
  clr_render_image lo = render_opts(sphere_light_scene, &o, NULL);
  double e = rel_rmse(&lo, &ref), m = image_mean(&lo) / image_mean(&ref);
  double e2 = 0, ref_sum = 0;
  int n2 = 0;
  for (int i = 0; i < ref.width * ref.height * 3; ++i)
    if (ref.rgb[i] < 1.0f) {
      e2 += (lo.rgb[i] - ref.rgb[i]) * (double)(lo.rgb[i] - ref.rgb[i]);
      ref_sum += ref.rgb[i];
      ++n2;
    }
  fprintf(stderr,
          "sphere light: 16 spp relative RMSE %.4f (without the light's pixels %.4f), mean ratio "
          "%.4f\n",
          e, sqrt(e2 / n2) / (ref_sum / n2), m);
  /* regression bounds (measured 0.223 and 0.992 with cone sampling; against pbrt-v3, the 96x64
   * version tests/data/scenes/v3_spherelight.pbrt has pbrt-v3's error, see docs/rendering.md) */
  assert_true(e < 0.26);
  assert_true(fabs(m - 1.0) < 0.02);
  free(ref.rgb);
  free(lo.rgb);
}

/* ---- rays toward area lights ---- */

/* pbrt-v3 traces a BSDF-sampled ray toward an area light only when the light's own shape says
 * it can hit it (Light::Pdf_Li > 0); spheres always, triangles by a test against the triangle.
 * Direct lighting ("all", one sample per light) of a plane seen whole by an orthographic camera,
 * per camera sample: the camera ray; the point light's shadow ray (no BSDF ray: delta); the
 * sphere light's shadow ray and its BSDF ray (pbrt-v3's cone pdf needs no test); nothing for
 * a triangle light under the plane (its light sample has f = 0, every BSDF ray goes up and
 * misses it). 4 rays per sample, where tracing every BSDF ray gives 5. */
static void test_ray_count_pbrt_v3(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [6]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [4]\nIntegrator \"directlighting\"\nWorldBegin\n"
      "LightSource \"point\" \"point from\" [0 0 2] \"rgb I\" [1 1 1]\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
      "Translate 4 0 2\nShape \"sphere\" \"float radius\" [0.5]\nAttributeEnd\n"
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2]\n"
      "\"point P\" [-1 -1 -1  1 -1 -1  0 1 -1]\nAttributeEnd\n"
      "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n";
  clr_render_stats st;
  clr_render_stats_init(&st);
  clr_render_image im = render_opts(scene, NULL, &st);
  uint64_t samples = 8 * 6 * 4;
  assert_int_equal(st.rays, 4 * samples);
  free(im.rgb);
  /* A sphere light alone, seen by an orthographic camera: a camera ray that hits it shades its
   * (matte) surface, whose light samples lie behind it (f = 0: no shadow ray) and whose BSDF rays
   * leave the sphere (Shape::Pdf misses: no ray). One ray per sample, hit or miss. */
  const char *alone =
      "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [4]\nIntegrator \"directlighting\"\nWorldBegin\n"
      "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape \"sphere\" \"float radius\" "
      "[0.7]\nWorldEnd\n";
  clr_render_stats_init(&st);
  im = render_opts(alone, NULL, &st);
  assert_int_equal(st.rays, 8 * 8 * 4);
  assert_true(im.rgb[3 * (4 * 8 + 4)] >= 1.0f); /* the centre pixel sees the light */
  free(im.rgb);
}

/* The path tracer's ray at maxdepth after a non-specular bounce can change nothing (pbrt-v3 adds
 * only what a specular bounce sees there) and is not traced: a matte plane under a distant light,
 * seen from above, takes the camera ray and the shadow ray per sample at maxdepth 1 (pbrt-v3
 * traces a third), and the continuation ray too at maxdepth 2 (it escapes); the image is the
 * same, Kd/pi * L cos(theta) = 0.5/pi * 2 * 1, at both depths. */
static void test_path_last_bounce_rays(void **state) {
  (void)state;
  for (int depth = 1; depth <= 2; ++depth) {
    char scene[1024];
    snprintf(
        scene, sizeof scene,
        "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
        "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [6]\n"
        "Sampler \"halton\" \"integer pixelsamples\" [4]\n"
        "Integrator \"path\" \"integer maxdepth\" [%d]\nWorldBegin\n"
        "LightSource \"distant\" \"point from\" [0 0 1] \"point to\" [0 0 0] \"rgb L\" [2 2 2]\n"
        "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5]\n"
        "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
        "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
        depth);
    clr_render_stats st;
    clr_render_stats_init(&st);
    clr_render_image im = render_opts(scene, NULL, &st);
    uint64_t samples = 8 * 6 * 4;
    assert_int_equal(st.rays, (uint64_t)(depth + 1) * samples);
    const double e = 1.0 / PI_D;
    for (int i = 0; i < im.width * im.height * 3; ++i) assert_true(fabs(im.rgb[i] - e) <= 1e-5 * e);
    free(im.rgb);
  }
}

/* The light waves (a triangle light without shading normals: its light samples, the MIS BSDF
 * samples with their shape tests, and the path's next directions in the same frames) against the
 * scalar code the light takes when its mesh has shading normals equal to its face normal: pbrt-v3
 * gives both the same samples, so the images agree bit for bit, with direct lighting and with the
 * path tracer (Lambertian walls and boxes, interreflections, Russian roulette). */
static void test_light_waves_match_scalar(void **state) {
  (void)state;
  const char *integrators[] = {"\"path\" \"integer maxdepth\" [6]", "\"directlighting\""};
  for (int t = 0; t < 2; ++t) {
    clr_render_image im[2];
    for (int normals = 0; normals < 2; ++normals) {
      char scene[4096];
      snprintf(scene, sizeof scene,
               CORNELL_CAMERA
               "Film \"image\" \"integer xresolution\" [24] \"integer yresolution\" [24]\n"
               "Sampler \"sobol\" \"integer pixelsamples\" [8]\nIntegrator %s\nWorldBegin\n"
               "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [17 12 4]\n"
               "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
               "\"point P\" [343 548.7 227  343 548.7 332  213 548.7 332  213 548.7 227]%s\n"
               "AttributeEnd\nMaterial \"matte\" \"rgb Kd\" [0.7 0.6 0.5]\n"
               "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 6 4 6 7]\n\"point P\" "
               "[0 0 0  0 0 559  556 0 559  556 0 0  0 0 559  0 548 559  556 548 "
               "559  556 0 559] \n"
               "Material \"matte\" \"rgb Kd\" [0.6 0.1 0.1]\n"
               "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
               "\"point P\" [556 0 0  556 0 559  556 548 559  556 548 0]\n"
               "Material \"matte\" \"rgb Kd\" [0.2 0.5 0.2]\n"
               "Translate 180 0 200\nShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 "
               "6 4 6 7]\n\"point P\" [0 160 0  160 160 0  160 160 160  0 160 160  0 0 0  0 160 0  "
               "0 160 160  0 0 160]\nWorldEnd\n",
               integrators[t], normals ? " \"normal N\" [0 -1 0  0 -1 0  0 -1 0  0 -1 0]" : "");
      im[normals] = render_opts(scene, NULL, NULL);
    }
    assert_int_equal(im[0].width, im[1].width);
    assert_true(image_mean(&im[0]) > 0.01);
    size_t bytes = (size_t)im[0].width * im[0].height * 3 * sizeof(float);
    if (memcmp(im[0].rgb, im[1].rgb, bytes) != 0) {
      size_t n = bytes / sizeof(float), i = 0;
      while (i < n && im[0].rgb[i] == im[1].rgb[i]) ++i;
      fail_msg("%s: value %zu: %a with the light waves, %a without", integrators[t], i,
               im[0].rgb[i], im[1].rgb[i]);
    }
    free(im[0].rgb);
    free(im[1].rgb);
  }
}

/* ---- matte "sigma": Oren-Nayar ---- */

/* pbrt-v3 OrenNayar::f * pi / R for polar angles ti, to (radians) and azimuth difference dphi. */
static double oren_nayar(double sigma_deg, double ti, double to, double dphi) {
  double s = sigma_deg * PI_D / 180.0, s2 = s * s;
  double A = 1.0 - s2 / (2.0 * (s2 + 0.33)), B = 0.45 * s2 / (s2 + 0.09);
  double max_cos = (sin(ti) > 1e-4 && sin(to) > 1e-4) ? fmax(0.0, cos(dphi)) : 0.0;
  double sin_alpha = cos(ti) > cos(to) ? sin(to) : sin(ti);
  double tan_beta = cos(ti) > cos(to) ? tan(ti) : tan(to);
  return A + B * max_cos * sin_alpha * tan_beta;
}

/* A matte plane with "sigma" seen by an orthographic camera from polar angle `to` (azimuth 0)
 * under a distant light from polar angle ti, azimuth phi: every pixel is
 * Kd/pi * factor * L cos(ti). */
static double render_oren_nayar(double sigma, double ti, double phi, double to) {
  char scene[2048];
  snprintf(
      scene, sizeof scene,
      "LookAt %g 0 %g  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-0.5 0.5 -0.5 "
      "0.5]\n"
      "Film \"image\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
      "Integrator \"directlighting\"\nWorldBegin\n"
      "LightSource \"distant\" \"point from\" [%g %g %g] \"point to\" [0 0 0] \"rgb L\" [2 2 2]\n"
      "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5] \"float sigma\" [%g]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
      10 * sin(to), 10 * cos(to), sin(ti) * cos(phi), sin(ti) * sin(phi), cos(ti), sigma);
  clr_render_image im = render_opts(scene, NULL, NULL);
  double v = im.rgb[0];
  for (int i = 0; i < im.width * im.height * 3; ++i) assert_true(fabs(im.rgb[i] - v) <= 1e-5 * v);
  free(im.rgb);
  return v;
}

static void test_matte_sigma_oren_nayar(void **state) {
  (void)state;
  const double deg = PI_D / 180.0;
  const double cases[][4] = {/* sigma, theta_i, phi_i, theta_o (degrees) */
                             {20, 30, 0, 0},   {20, 40, 180, 50}, {35, 60, 30, 20},
                             {35, 20, 30, 60}, {0, 45, 0, 30},    {90, 70, 10, 45}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    double sg = cases[c][0], ti = cases[c][1] * deg, phi = cases[c][2] * deg,
           to = cases[c][3] * deg;
    double got = render_oren_nayar(sg, ti, phi, to);
    double expect = 0.5 / PI_D * oren_nayar(sg, ti, to, phi) * 2.0 * cos(ti);
    if (fabs(got - expect) > 2e-4 * expect)
      fprintf(stderr, "sigma %g ti %g phi %g to %g: got %g expect %g\n", sg, cases[c][1],
              cases[c][2], cases[c][3], got, expect);
    assert_true(fabs(got - expect) <= 2e-4 * expect);
  }
  /* reciprocity: f(wo, wi) = f(wi, wo), i.e. L / cos(theta_light) with camera and light swapped */
  double a = render_oren_nayar(35, 60 * deg, 30 * deg, 20 * deg) / cos(60 * deg);
  double b = render_oren_nayar(35, 20 * deg, 30 * deg, 60 * deg) / cos(20 * deg);
  assert_true(fabs(a - b) <= 2e-4 * a);
  /* sigma 0 is Lambertian: Kd/pi L cos */
  assert_true(fabs(render_oren_nayar(0, 50 * deg, 0, 10 * deg) - 0.5 / PI_D * 2.0 * cos(50 * deg)) <
              1e-6);
}

/* ---- Material "mirror" ---- */

/* A mirror plane (Kr) seen from above under a constant infinite light L: every pixel is Kr L,
 * with the path tracer and with direct lighting (pbrt-v3 SpecularReflect); with maxdepth 1 the
 * direct lighting integrator stops at the mirror (0), as pbrt-v3's depth + 1 < maxDepth, while
 * the path tracer still traces the specular bounce's ray at maxdepth and adds what it sees. */
static void test_mirror_sky(void **state) {
  (void)state;
  const char *integrators[] = {"\"path\" \"integer maxdepth\" [5]", "\"directlighting\"",
                               "\"directlighting\" \"integer maxdepth\" [1]",
                               "\"path\" \"integer maxdepth\" [1]"};
  const double expect_scale[] = {1.0, 1.0, 0.0, 1.0};
  for (int t = 0; t < 4; ++t) {
    char scene[2048];
    snprintf(scene, sizeof scene,
             "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
             "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
             "Sampler \"halton\" \"integer pixelsamples\" [4]\nIntegrator %s\nWorldBegin\n"
             "LightSource \"infinite\" \"rgb L\" [2 1 0.5]\n"
             "Material \"mirror\" \"rgb Kr\" [0.8 0.6 0.4]\n"
             "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
             "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
             integrators[t]);
    clr_render_image im = render_opts(scene, NULL, NULL);
    const double e[3] = {1.6, 0.6, 0.2};
    for (int i = 0; i < im.width * im.height; ++i)
      for (int c = 0; c < 3; ++c)
        assert_true(fabs(im.rgb[3 * i + c] - expect_scale[t] * e[c]) <= 1e-5 * e[c]);
    free(im.rgb);
  }
}

/* Path tracer: a mirror shows an emitter (Material "none", facing it) that the camera cannot see
 * directly: after a specular bounce the emitter's Le counts (pbrt-v3 specularBounce), the ray
 * passes through it and escapes: Kr L exactly. */
static void test_mirror_path_sees_emitter(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 1  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [4]\nIntegrator \"path\"\nWorldBegin\n"
      "AttributeBegin\nMaterial \"none\"\nAreaLightSource \"diffuse\" \"rgb L\" [3 2 1]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 2 1 0 3 2]\n"
      "\"point P\" [-10 -10 2  10 -10 2  10 10 2  -10 10 2]\nAttributeEnd\n"
      "Material \"mirror\" \"rgb Kr\" [0.5 0.5 0.5]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n";
  clr_render_image im = render_opts(scene, NULL, NULL);
  const double e[3] = {1.5, 1.0, 0.5};
  for (int i = 0; i < im.width * im.height; ++i)
    for (int c = 0; c < 3; ++c) assert_true(fabs(im.rgb[3 * i + c] - e[c]) <= 1e-5 * e[c]);
  free(im.rgb);
}

/* The camera looks down at a mirror at z = 0 that shows a matte plane at z = 2 facing it, lit by a
 * point light at z = 1: direct lighting gives Kr * Kd/pi * I cos(theta) / r^2 at the reflected
 * point (pixel centres, no interreflection in direct lighting). */
static void test_mirror_reflects_lit_plane(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 1.5  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
      "Integrator \"directlighting\"\nWorldBegin\n"
      "LightSource \"point\" \"point from\" [0.3 -0.2 1] \"rgb I\" [5 5 5]\n"
      "AttributeBegin\nMaterial \"mirror\" \"rgb Kr\" [0.7 0.7 0.7]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nAttributeEnd\n"
      "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 2 1 0 3 2]\n"
      "\"point P\" [-10 -10 2  10 -10 2  10 10 2  -10 10 2]\nWorldEnd\n";
  clr_render_image im = render_opts(scene, NULL, NULL);
  for (int py = 0; py < 16; ++py)
    for (int px = 0; px < 16; ++px) {
      double wx = -(-1.0 + 2.0 * (px + 0.5) / 16.0), wy = 1.0 - 2.0 * (py + 0.5) / 16.0;
      double dx = 0.3 - wx, dy = -0.2 - wy, r2 = dx * dx + dy * dy + 1.0;
      double expect = 0.7 * 0.5 / PI_D * 5.0 * (1.0 / sqrt(r2)) / r2;
      assert_true(fabs(im.rgb[3 * (py * 16 + px)] - expect) <= 1e-4 * expect);
    }
  free(im.rgb);
}

/* ---- Material "plastic" ---- */

/* pbrt-v3's plastic glossy lobe in double: TrowbridgeReitz D and Smith G, FrDielectric(1.5, 1). */
static double ref_lambda(double tan2, double alpha) {
  return (-1.0 + sqrt(1.0 + alpha * alpha * tan2)) / 2.0;
}
static double ref_fr(double ci, double ei, double et) {
  if (ci < 0) {
    double t = ei;
    ei = et;
    et = t;
    ci = -ci;
  }
  double si = sqrt(fmax(0, 1 - ci * ci)), st = ei / et * si;
  if (st >= 1) return 1;
  double ct = sqrt(fmax(0, 1 - st * st));
  double a = (et * ci - ei * ct) / (et * ci + ei * ct),
         b = (ei * ci - et * ct) / (ei * ci + et * ct);
  return (a * a + b * b) / 2;
}
static double ref_microfacet_f(const double wo[3], const double wi[3], double alpha) {
  double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
  double l = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  for (int i = 0; i < 3; ++i) h[i] /= l * (h[2] < 0 ? -1 : 1); /* Faceforward(wh, (0, 0, 1)) */
  double c2 = h[2] * h[2], t2 = (1 - c2) / c2, e = t2 / (alpha * alpha);
  double D = 1 / (PI_D * alpha * alpha * c2 * c2 * (1 + e) * (1 + e));
  double to2 = (1 - wo[2] * wo[2]) / (wo[2] * wo[2]), ti2 = (1 - wi[2] * wi[2]) / (wi[2] * wi[2]);
  double G = 1 / (1 + ref_lambda(to2, alpha) + ref_lambda(ti2, alpha));
  double F = ref_fr(wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2], 1.5, 1.0);
  return D * G * F / (4 * fabs(wi[2]) * fabs(wo[2]));
}

static void dir_from(double theta, double phi, double w[3]) {
  w[0] = sin(theta) * cos(phi);
  w[1] = sin(theta) * sin(phi);
  w[2] = cos(theta);
}

/* The lobe's f against the double reference, reciprocity, the pdf integrated over the hemisphere
 * (at most 1, the rest reflects below the horizon) and samples distributed as the pdf says. */
static void test_plastic_lobe(void **state) {
  (void)state;
  assert_float_equal(clr_fr_dielectric(1.0f, 1.5f, 1.0f), 0.04f, 1e-6);
  const float alphas[] = {0.05f, clr_tr_roughness_to_alpha(0.1f), 0.5f};
  for (int a = 0; a < 3; ++a) {
    float alpha = alphas[a];
    for (int t = 0; t < 3; ++t) {
      double two[3], twi[3];
      dir_from((10.0 + 25.0 * t) * PI_D / 180.0, 0.3, two);
      dir_from((20.0 + 15.0 * t) * PI_D / 180.0, 2.5, twi);
      float wo[3] = {(float)two[0], (float)two[1], (float)two[2]};
      float wi[3] = {(float)twi[0], (float)twi[1], (float)twi[2]};
      double ref = ref_microfacet_f(two, twi, alpha);
      assert_true(fabs(clr_microfacet_f(wo, wi, alpha) - ref) <= 1e-4 * ref + 1e-7);
      assert_true(fabsf(clr_microfacet_f(wo, wi, alpha) - clr_microfacet_f(wi, wo, alpha)) <=
                  1e-5f * clr_microfacet_f(wo, wi, alpha));
    }
    /* pdf over the hemisphere by the midpoint rule in (cos theta, phi) */
    float wo[3];
    double dwo[3];
    dir_from(30.0 * PI_D / 180.0, 0.0, dwo);
    for (int i = 0; i < 3; ++i) wo[i] = (float)dwo[i];
    const int nt = 1200, np = 240;
    double integral = 0, mean_z = 0;
    for (int i = 0; i < nt; ++i)
      for (int j = 0; j < np; ++j) {
        double z = (i + 0.5) / nt, phi = 2 * PI_D * (j + 0.5) / np, r = sqrt(1 - z * z);
        float wi[3] = {(float)(r * cos(phi)), (float)(r * sin(phi)), (float)z};
        double p = clr_microfacet_pdf(wo, wi, alpha) * (1.0 / nt) * (2 * PI_D / np);
        integral += p;
        mean_z += p * z;
      }
    /* samples on a 256 x 256 grid of u: the fraction above the horizon equals the pdf's integral (so
     * the pdf integrates to one with what reflects below), and the mean of wi.z equals its mean */
    double sum_z = 0, valid = 0;
    for (int i = 0; i < 256; ++i)
      for (int j = 0; j < 256; ++j) {
        float u[2] = {(i + 0.5f) / 256.0f, (j + 0.5f) / 256.0f}, wi[3], pdf;
        if (clr_microfacet_sample(wo, u, alpha, wi, &pdf) > 0.0f && pdf > 0.0f) {
          sum_z += wi[2];
          valid += 1;
          assert_true(fabsf(pdf - clr_microfacet_pdf(wo, wi, alpha)) <= 1e-3f * pdf);
        }
      }
    fprintf(
        stderr,
        "plastic lobe alpha %.3f: pdf integral %.5f (sampled fraction %.5f), mean z %.5f vs %.5f\n",
        (double)alpha, integral, valid / 65536.0, mean_z / integral, sum_z / valid);
    assert_true(integral <= 1.0 + 2e-3 &&
                integral > 0.75); /* the rest reflects below the horizon */
    assert_true(fabs(valid / 65536.0 - integral) < 5e-3);
    assert_true(fabs(sum_z / valid - mean_z / integral) < 2e-3);
  }
}

/* pbrt-v3's anisotropic TrowbridgeReitz D and G in double. */
static double ref_aniso_lambda(const double w[3], double ax, double ay) {
  double s2 = 1 - w[2] * w[2], c2p = s2 > 0 ? w[0] * w[0] / s2 : 1,
         s2p = s2 > 0 ? w[1] * w[1] / s2 : 0;
  return ref_lambda(s2 / (w[2] * w[2]), sqrt(c2p * ax * ax + s2p * ay * ay));
}
static double ref_aniso_d(const double h[3], double ax, double ay) {
  double s2 = 1 - h[2] * h[2], c2 = h[2] * h[2];
  double e = s2 > 0 ? (h[0] * h[0] / s2 / (ax * ax) + h[1] * h[1] / s2 / (ay * ay)) * s2 / c2 : 0;
  return 1 / (PI_D * ax * ay * c2 * c2 * (1 + e) * (1 + e));
}

/* The one TrowbridgeReitz (microfacet.c) for the plastic/metal fast path and the lobe lists: D
 * and G against pbrt-v3's anisotropic formulas in double, isotropic (its shorter expression) and
 * anisotropic, and continuous across ax == ay. */
static void test_trowbridge_reitz(void **state) {
  (void)state;
  const float alphas[][2] = {{0.1f, 0.1f}, {0.3f, 0.3f}, {0.1f, 0.4f}, {0.5f, 0.2f}};
  for (int a = 0; a < 4; ++a)
    for (int t = 0; t < 6; ++t) {
      double dh[3], dwo[3], dwi[3];
      dir_from((5.0 + 12.0 * t) * PI_D / 180.0, 0.4 + t, dh);
      dir_from((15.0 + 10.0 * t) * PI_D / 180.0, 2.0 - t, dwo);
      dir_from((60.0 - 8.0 * t) * PI_D / 180.0, 1.0 + 2.0 * t, dwi);
      float h[3], wo[3], wi[3], ax = alphas[a][0], ay = alphas[a][1];
      for (int k = 0; k < 3; ++k) h[k] = (float)dh[k], wo[k] = (float)dwo[k], wi[k] = (float)dwi[k];
      double d = ref_aniso_d(dh, ax, ay);
      double g = 1 / (1 + ref_aniso_lambda(dwo, ax, ay) + ref_aniso_lambda(dwi, ax, ay));
      assert_true(fabs(clr_tr_d(h, ax, ay) - d) <= 1e-5 * d);
      assert_true(fabs(clr_tr_g(wo, wi, ax, ay) - g) <= 1e-5 * g);
      float ay1 = nextafterf(ax, 1.0f); /* the anisotropic expression next to the isotropic one */
      if (ax == ay) {
        assert_true(fabsf(clr_tr_d(h, ax, ay1) - clr_tr_d(h, ax, ax)) <= 1e-5f * (float)d);
        assert_true(fabsf(clr_tr_g(wo, wi, ax, ay1) - clr_tr_g(wo, wi, ax, ax)) <=
                    1e-5f * (float)g);
      }
    }
}

/* The path tracer takes pbrt-v3's PathIntegrator dimensions: after the camera's 5, a light
 * choice, light 2D, scattering 2D and BSDF 2D at every bounce below maxdepth and Russian
 * roulette's 1D only past bounce 3, so that a Halton render follows pbrt-v3's paths sample for sample (v3_shapes at 1 spp:
 * 10 of 6144 pixels differ, against 2548 with a roulette value at every bounce). */
static void test_path_sample_layout(void **state) {
  (void)state;
  const int depths[] = {0, 3, 4, 5, 8};
  for (int k = 0; k < 5; ++k) {
    char scene[512];
    snprintf(scene, sizeof scene,
             "Camera \"perspective\"\nIntegrator \"path\" \"integer maxdepth\" [%d]\n"
             "WorldBegin\nLightSource \"point\"\nShape \"sphere\"\nWorldEnd\n",
             depths[k]);
    clr_scene_desc *desc = NULL;
    clr_render_scene *rs = stu_build(scene, "layout.pbrt", &desc);
    clr_integrator it;
    assert_int_equal(clr_integrator_create(desc, rs, NULL, NULL, &it), CLR_SUCCESS);
    /* bounces 0..maxdepth-1 (pbrt-v3 stops at maxdepth first); the pinhole's time and lens are
     * skipped requests (dimensions 2..4, no values) */
    int d = depths[k], expect = 2;
    for (int b = 0; b < d; ++b) expect += b > 3 ? 8 : 7;
    assert_int_equal(it.value_offset, 2);
    assert_int_equal(it.values_per_sample, expect);
    assert_int_equal(it.layout_values, expect + 3);
    assert_int_equal(it.path_bounces_in_layout, d);
    clr_integrator_free(&it);
    clr_render_scene_free(rs);
    clr_scene_desc_free(desc);
  }
}

/* A plastic plane (Kd, Ks, roughness 0.1 remapped) under a distant light seen by an orthographic
 * camera: every pixel is (Kd/pi + Ks f_microfacet(wo, wi)) L cos(theta_i), in pbrt-v3's frame
 * whose z is the shape's normal: a plane whose normal faces away from the camera (wound the other
 * way) sees wo and wi below its z, so FresnelDielectric(1.5, 1) swaps its etas (no total internal
 * reflection past 41.8 degrees); the faces of a box wound inwards differed by up to 17 % before.
 * Both the plastic fast path and the lobe list (a textured roughness). */
static void test_plastic_plane(void **state) {
  (void)state;
  const double deg = PI_D / 180.0;
  const double cases[][3] = {{30, 0, 30}, {40, 20, 35}, {60, 180, 20}, {10, 90, 50}, {70, 180, 60}};
  for (int c = 0; c < 20; ++c) {
    int flipped = (c / 5) & 1, lobes = c / 10;
    double ti = cases[c % 5][0] * deg, phi = cases[c % 5][1] * deg, to = cases[c % 5][2] * deg;
    char scene[2048];
    snprintf(
        scene, sizeof scene,
        "LookAt %g 0 %g  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-0.5 0.5 "
        "-0.5 0.5]\n"
        "Film \"image\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
        "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
        "Integrator \"directlighting\"\nWorldBegin\n"
        "LightSource \"distant\" \"point from\" [%g %g %g] \"point to\" [0 0 0] \"rgb L\" [2 2 2]\n"
        "Texture \"r\" \"float\" \"constant\" \"float value\" [0.1]\n"
        "Material \"plastic\" \"rgb Kd\" [0.3 0.3 0.3] \"rgb Ks\" [0.6 0.6 0.6] %s\n"
        "Shape \"trianglemesh\" \"integer indices\" [%s]\n"
        "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
        10 * sin(to), 10 * cos(to), sin(ti) * cos(phi), sin(ti) * sin(phi), cos(ti),
        lobes ? "\"texture roughness\" \"r\"" : "\"float roughness\" [0.1]",
        flipped ? "0 2 1 0 3 2" : "0 1 2 0 2 3");
    clr_render_image im = render_opts(scene, NULL, NULL);
    double wo[3], wi[3];
    dir_from(to, 0.0, wo);
    dir_from(ti, phi, wi);
    if (flipped) wo[2] = -wo[2], wi[2] = -wi[2];
    double alpha = clr_tr_roughness_to_alpha(0.1f);
    double expect = (0.3 / PI_D + 0.6 * ref_microfacet_f(wo, wi, alpha)) * 2.0 * cos(ti);
    for (int i = 0; i < im.width * im.height * 3; ++i) {
      if (fabs(im.rgb[i] - expect) > 2e-4 * expect)
        fprintf(stderr, "case %d (flipped %d, lobes %d): got %g expect %g\n", c % 5, flipped, lobes,
                (double)im.rgb[i], expect);
      assert_true(fabs(im.rgb[i] - expect) <= 2e-4 * expect);
    }
    free(im.rgb);
  }
}

/* A plastic plane under a constant sky (L = 1) seen straight down: radiance is the albedo
 * Kd + Ks * integral of f cos over the hemisphere (midpoint quadrature of the double reference).
 * Direct lighting and the path tracer combine light and BSDF samples by MIS (the mixture's
 * sampling and pdf): the 64-spp image mean is within 1 %. */
static void test_plastic_sky_albedo(void **state) {
  (void)state;
  const char *scene_fmt =
      "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [64]\nIntegrator \"%s\"\nWorldBegin\n"
      "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
      "Material \"plastic\" \"rgb Kd\" [0.3 0.3 0.3] \"rgb Ks\" [0.6 0.6 0.6] \"float roughness\" "
      "[0.3]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n";
  double alpha = clr_tr_roughness_to_alpha(0.3f), wo[3] = {0, 0, 1}, glossy = 0;
  const int nt = 2000, np = 64;
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      double z = (i + 0.5) / nt, phi = 2 * PI_D * (j + 0.5) / np, r = sqrt(1 - z * z);
      double wi[3] = {r * cos(phi), r * sin(phi), z};
      glossy += ref_microfacet_f(wo, wi, alpha) * z * (1.0 / nt) * (2 * PI_D / np);
    }
  double expect = 0.3 + 0.6 * glossy;
  const char *integrators[] = {"directlighting", "path"};
  for (int t = 0; t < 2; ++t) {
    char scene[2048];
    snprintf(scene, sizeof scene, scene_fmt, integrators[t]);
    clr_render_image im = render_opts(scene, NULL, NULL);
    double m = image_mean(&im);
    fprintf(stderr, "plastic under a sky (%s): mean %.5f, albedo %.5f\n", integrators[t], m,
            expect);
    assert_true(fabs(m - expect) <= 0.01 * expect);
    free(im.rgb);
  }
}

/* ---- Shape "disk" ---- */

/* An emitting partial disk (radius 0.9, innerradius 0.3, phimax 270) facing an orthographic
 * camera: exactly the pixel centres inside it show L. */
static void test_disk_shape(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [48] \"integer yresolution\" [48]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
      "Integrator \"directlighting\"\nWorldBegin\n"
      "AreaLightSource \"diffuse\" \"rgb L\" [2 2 2]\n"
      "Shape \"disk\" \"float radius\" [0.9] \"float innerradius\" [0.3] \"float phimax\" [270]\n"
      "\"float height\" [0.25]\nWorldEnd\n";
  clr_render_image im = render_opts(scene, NULL, NULL);
  int inside = 0, agree = 0;
  for (int py = 0; py < 48; ++py)
    for (int px = 0; px < 48; ++px) {
      double wx = -(-1.0 + 2.0 * (px + 0.5) / 48.0), wy = 1.0 - 2.0 * (py + 0.5) / 48.0;
      double r = sqrt(wx * wx + wy * wy), phi = atan2(wy, wx);
      if (phi < 0) phi += 2 * PI_D;
      int in = r <= 0.9 && r >= 0.3 && phi <= 1.5 * PI_D;
      float v = im.rgb[3 * (py * 48 + px)];
      inside += in;
      agree += in ? fabsf(v - 2.0f) < 1e-5f : v == 0.0f;
    }
  assert_true(inside > 48 * 48 / 4);
  assert_int_equal(agree, 48 * 48);
  free(im.rgb);
}

/* A disk light (radius R, radiance L) facing a parallel matte plane at distance h: irradiance at
 * lateral distance d is (pi L / 2) (1 - (h^2 + d^2 - R^2) / sqrt((h^2 + d^2 + R^2)^2 - 4 R^2 d^2)),
 * each pixel centre Kd/pi times that. The light has Material "none" (the camera sees through
 * it) and faces down (ReverseOrientation). 64 samples: worst pixel within 8 %, mean within 0.5 %. */
static void test_disk_light_irradiance(void **state) {
  (void)state;
  const double R = 0.5, h = 1.0, L = 2.0, kd = 0.5;
  const char *scene =
      "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
      "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [64] \"bool samplepixelcenter\" \"true\"\n"
      "Integrator \"directlighting\"\nWorldBegin\n"
      "AttributeBegin\nMaterial \"none\"\nAreaLightSource \"diffuse\" \"rgb L\" [2 2 2]\n"
      "Translate 0 0 1\nReverseOrientation\nShape \"disk\" \"float radius\" [0.5]\nAttributeEnd\n"
      "Material \"matte\" \"rgb Kd\" [0.5 0.5 0.5]\n"
      "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
      "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n";
  clr_render_stats st;
  clr_render_stats_init(&st);
  clr_render_image im = render_opts(scene, NULL, &st);
  double worst = 0, sum = 0, sum_expect = 0;
  for (int py = 0; py < 16; ++py)
    for (int px = 0; px < 16; ++px) {
      double wx = -(-1.0 + 2.0 * (px + 0.5) / 16.0), wy = 1.0 - 2.0 * (py + 0.5) / 16.0;
      double d2 = wx * wx + wy * wy, a = h * h + d2 + R * R;
      double E = PI_D * L / 2.0 * (1.0 - (h * h + d2 - R * R) / sqrt(a * a - 4.0 * R * R * d2));
      double expect = kd / PI_D * E, got = im.rgb[3 * (py * 16 + px)];
      worst = fmax(worst, fabs(got / expect - 1.0));
      sum += got;
      sum_expect += expect;
    }
  fprintf(stderr, "disk light irradiance: worst pixel %.4f, mean ratio %.5f\n", worst,
          sum / sum_expect);
  assert_true(worst < 0.08); /* measured 0.050: MIS noise where the light is small */
  assert_true(fabs(sum / sum_expect - 1.0) < 0.005);
  free(im.rgb);
}

/* ---- Material "glass" (smooth) ---- */

/* White furnace: a glass sphere (Kr = Kt = 1) under a constant sky L = 1 seen by an orthographic
 * camera: every path leaves the sphere again, its radiance scalings (eta_i/eta_t)^2 cancel, so
 * every pixel is 1, with the path tracer (FresnelSpecular, one branch) and direct lighting
 * (SpecularReflect and SpecularTransmit, both branches, maxdepth 12). */
static void test_glass_furnace(void **state) {
  (void)state;
  const char *integrators[] = {"\"path\" \"integer maxdepth\" [64]",
                               "\"directlighting\" \"integer maxdepth\" [12]"};
  for (int t = 0; t < 2; ++t) {
    char scene[2048];
    snprintf(scene, sizeof scene,
             "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-0.7 0.7 "
             "-0.7 0.7]\n"
             "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
             "Sampler \"halton\" \"integer pixelsamples\" [16]\nIntegrator %s\nWorldBegin\n"
             "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
             "Material \"glass\"\nShape \"sphere\" \"float radius\" [1]\nWorldEnd\n",
             integrators[t]);
    clr_render_image im = render_opts(scene, NULL, NULL);
    double worst = 0;
    for (int i = 0; i < im.width * im.height * 3; ++i) worst = fmax(worst, fabs(im.rgb[i] - 1.0));
    fprintf(stderr, "glass furnace (%s): worst pixel error %.2e\n", integrators[t], worst);
    assert_true(worst < (t == 0 ? 1e-4 : 2e-3)); /* direct lighting stops after 12 bounces */
    free(im.rgb);
  }
}

/* A glass half-space (one interface, z < 0 inside) under a constant sky, seen from angle theta:
 * the reflected fraction F(theta) sees the sky, the rest enters and is scaled by 1/eta^2: the
 * radiance is F + (1 - F) / 2.25 (pbrt-v3 radiance transport), with F the dielectric Fresnel
 * reflectance for eta 1.5. */
static void test_glass_fresnel(void **state) {
  (void)state;
  const double deg = PI_D / 180.0, angles[] = {0.0, 45.0, 70.0};
  for (int a = 0; a < 3; ++a) {
    double th = angles[a] * deg;
    for (int t = 0; t < 2; ++t) {
      char scene[2048];
      snprintf(scene, sizeof scene,
               "LookAt %g 0 %g  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-0.5 "
               "0.5 -0.5 0.5]\n"
               "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
               "Sampler \"halton\" \"integer pixelsamples\" [64]\nIntegrator \"%s\"\nWorldBegin\n"
               "LightSource \"infinite\" \"rgb L\" [1 1 1]\n"
               "Material \"glass\" \"float index\" [1.5]\n"
               "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
               "\"point P\" [-100 -100 0  100 -100 0  100 100 0  -100 100 0]\nWorldEnd\n",
               5 * sin(th), 5 * cos(th), t ? "directlighting" : "path");
      clr_render_image im = render_opts(scene, NULL, NULL);
      double c = cos(th), st = sin(th) / 1.5, ct = sqrt(1 - st * st);
      double rs = (c - 1.5 * ct) / (c + 1.5 * ct), rp = (1.5 * c - ct) / (1.5 * c + ct);
      double F = (rs * rs + rp * rp) / 2, expect = F + (1 - F) / 2.25, m = image_mean(&im);
      fprintf(stderr, "glass at %g deg (%s): mean %.5f, expected %.5f (F %.4f)\n", angles[a],
              t ? "directlighting" : "path", m, expect, F);
      /* direct lighting follows both branches: exact; the path tracer picks one by F */
      assert_true(fabs(m - expect) <= (t ? 1e-5 : 0.005) * expect);
      free(im.rgb);
    }
  }
}

/* ---- Material "metal" ---- */

static double ref_fr_conductor(double c, double eta, double k) {
  c = fabs(c);
  double c2 = c * c, s2 = 1 - c2, eta2 = eta * eta, k2 = k * k, t0 = eta2 - k2 - s2;
  double a2b2 = sqrt(t0 * t0 + 4 * eta2 * k2), t1 = a2b2 + c2, a = sqrt(0.5 * (a2b2 + t0)),
         t2 = 2 * c * a;
  double rs = (t1 - t2) / (t1 + t2), t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
  return 0.5 * (rs * (t3 - t4) / (t3 + t4) + rs);
}

/* The lobe of ref_microfacet_f with a conductor's Fresnel instead of plastic's dielectric one. */
static double ref_metal_f(const double wo[3], const double wi[3], double alpha, double eta,
                          double k) {
  double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
  double l = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  for (int i = 0; i < 3; ++i) h[i] /= l;
  double cos_h = wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2];
  return ref_microfacet_f(wo, wi, alpha) / ref_fr(cos_h, 1.5, 1.0) *
         ref_fr_conductor(cos_h, eta, k);
}

/* A metal plane (rgb eta and k, roughness 0.2) under a distant light, orthographic camera: every
 * pixel is f L cos(theta_i), f pbrt-v3's TrowbridgeReitz lobe with FrConductor. */
static void test_metal_plane(void **state) {
  (void)state;
  const double eta[3] = {0.2, 0.92, 1.1}, k[3] = {3.9, 2.45, 2.14};
  assert_float_equal(
      clr_fr_conductor(1.0f, 0.92f, 2.45f),
      ((0.92 - 1) * (0.92 - 1) + 2.45 * 2.45) / ((0.92 + 1) * (0.92 + 1) + 2.45 * 2.45), 1e-6);
  const double deg = PI_D / 180.0;
  const double cases[][3] = {{30, 180, 20}, {40, 160, 35}, {60, 90, 20}};
  for (int c = 0; c < 3; ++c) {
    double ti = cases[c][0] * deg, phi = cases[c][1] * deg, to = cases[c][2] * deg;
    char scene[2048];
    snprintf(
        scene, sizeof scene,
        "LookAt %g 0 %g  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-0.5 0.5 "
        "-0.5 0.5]\n"
        "Film \"image\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
        "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
        "Integrator \"directlighting\"\nWorldBegin\n"
        "LightSource \"distant\" \"point from\" [%g %g %g] \"point to\" [0 0 0] \"rgb L\" [2 2 2]\n"
        "Material \"metal\" \"rgb eta\" [0.2 0.92 1.1] \"rgb k\" [3.9 2.45 2.14] \"float "
        "roughness\" [0.2]\n"
        "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
        "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
        10 * sin(to), 10 * cos(to), sin(ti) * cos(phi), sin(ti) * sin(phi), cos(ti));
    clr_render_image im = render_opts(scene, NULL, NULL);
    double wo[3], wi[3];
    dir_from(to, 0.0, wo);
    dir_from(ti, phi, wi);
    double alpha = clr_tr_roughness_to_alpha(0.2f);
    for (int ch = 0; ch < 3; ++ch) {
      double expect = ref_metal_f(wo, wi, alpha, eta[ch], k[ch]) * 2.0 * cos(ti);
      assert_true(expect > 1e-3);
      for (int i = 0; i < im.width * im.height; ++i) {
        double got = im.rgb[3 * i + ch];
        if (fabs(got - expect) > 2e-4 * expect)
          fprintf(stderr, "case %d ch %d: got %g expect %g\n", c, ch, got, expect);
        assert_true(fabs(got - expect) <= 2e-4 * expect);
      }
    }
    free(im.rgb);
  }
}

/* Default metal (copper, roughness 0.01 remapped) under a constant sky seen straight down: the
 * radiance is the lobe's albedo (quadrature of the double reference), with direct lighting and
 * the path tracer (MIS of sky and lobe samples), within 1 %. */
static void test_metal_sky_albedo(void **state) {
  (void)state;
  const double eta[3] = {0.2004376970, 0.9240334304, 1.1022119527};
  const double k[3] = {3.9129485033, 2.4528477015, 2.1421879552};
  double alpha = clr_tr_roughness_to_alpha(0.3f), wo[3] = {0, 0, 1}, expect[3] = {0, 0, 0};
  const int nt = 4000, np = 64;
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      double z = (i + 0.5) / nt, phi = 2 * PI_D * (j + 0.5) / np, r = sqrt(1 - z * z);
      double wi[3] = {r * cos(phi), r * sin(phi), z};
      for (int c = 0; c < 3; ++c)
        expect[c] += ref_metal_f(wo, wi, alpha, eta[c], k[c]) * z * (1.0 / nt) * (2 * PI_D / np);
    }
  const char *integrators[] = {"directlighting", "path"};
  for (int t = 0; t < 2; ++t) {
    char scene[2048];
    snprintf(
        scene, sizeof scene,
        "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
        "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
        "Sampler \"halton\" \"integer pixelsamples\" [64]\nIntegrator \"%s\"\nWorldBegin\n"
        "LightSource \"infinite\" \"rgb L\" [1 1 1]\nMaterial \"metal\" \"float roughness\" [0.3]\n"
        "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
        "\"point P\" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]\nWorldEnd\n",
        integrators[t]);
    clr_render_image im = render_opts(scene, NULL, NULL);
    for (int c = 0; c < 3; ++c) {
      double m = 0;
      for (int i = 0; i < im.width * im.height; ++i) m += im.rgb[3 * i + c];
      m /= im.width * im.height;
      fprintf(stderr, "metal under a sky (%s) channel %d: mean %.5f, albedo %.5f\n", integrators[t],
              c, m, expect[c]);
      assert_true(fabs(m - expect[c]) <= 0.01 * expect[c]);
    }
    free(im.rgb);
  }
}

/* A partial sphere (radius 1, zmin -0.5, zmax 0.8, phimax 270) seen from above: a ray at distance
 * rho from the axis meets the top at z = sqrt(1 - rho^2): kept when z <= 0.8; else it passes the
 * cut to the bottom, at z <= -0.8 < zmin: clipped too. So exactly the pixel centres with
 * 0.6 <= rho <= 1 and phi <= 270 degrees see the sphere (AO > 0), the others nothing. */
static void test_partial_sphere(void **state) {
  (void)state;
  const char *scene =
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\" \"float screenwindow\" [-1.1 1.1 -1.1 "
      "1.1]\n"
      "Film \"image\" \"integer xresolution\" [48] \"integer yresolution\" [48]\n"
      "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
      "Integrator \"ambientocclusion\" \"integer nsamples\" [4]\nWorldBegin\n"
      "Shape \"sphere\" \"float radius\" [1] \"float zmin\" [-0.5] \"float zmax\" [0.8] \"float "
      "phimax\" [270]\n"
      "WorldEnd\n";
  clr_render_image im = render_opts(scene, NULL, NULL);
  int hits = 0, checked = 0;
  for (int py = 0; py < 48; ++py)
    for (int px = 0; px < 48; ++px) {
      double wx = -1.1 * (-1.0 + 2.0 * (px + 0.5) / 48.0),
             wy = 1.1 * (1.0 - 2.0 * (py + 0.5) / 48.0);
      double rho = sqrt(wx * wx + wy * wy), phi = atan2(wy, wx);
      if (phi < 0) phi += 2 * PI_D;
      if (fabs(rho - 0.6) < 1e-3 || fabs(rho - 1.0) < 1e-3 || fabs(phi - 1.5 * PI_D) < 1e-3)
        continue;
      int in = rho >= 0.6 && rho <= 1.0 && phi <= 1.5 * PI_D;
      float v = im.rgb[3 * (py * 48 + px)];
      if (in != (v > 0.0f))
        fprintf(stderr, "pixel (%d,%d) rho %g phi %g: %g\n", px, py, rho, phi, (double)v);
      assert_int_equal(in, v > 0.0f);
      hits += in;
      ++checked;
    }
  assert_true(hits > 300 && checked > 48 * 48 - 20);
  free(im.rgb);
}

/* ---- textures: scale, mix, uv ---- */

/* A matte plane lit straight down by a distant light (L = pi, so each pixel is Kd), seen by an
 * orthographic camera, its Kd from pbrt-v3's scale (tex1 * tex2), mix ((1 - amount) tex1 +
 * amount tex2, tex1 itself a scale texture) and uv ((u - floor u, v - floor v, 0), uv = xy of
 * the plane's vertices scaled by 2) textures. */
static void test_textures_scale_mix_uv(void **state) {
  (void)state;
  const char *kinds[] = {"scaled", "mixed", "uvs"};
  for (int t = 0; t < 3; ++t) {
    char scene[4096];
    snprintf(scene, sizeof scene,
             "LookAt 0 0 10  0 0 0  0 1 0\nCamera \"orthographic\"\n"
             "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
             "Sampler \"halton\" \"integer pixelsamples\" [1] \"bool samplepixelcenter\" \"true\"\n"
             "Integrator \"directlighting\"\nWorldBegin\n"
             "LightSource \"distant\" \"point from\" [0 0 1] \"point to\" [0 0 0] \"rgb L\" [%.9g "
             "%.9g %.9g]\n"
             "Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [0.5 0.5 0.5]\n"
             "Texture \"scaled\" \"spectrum\" \"scale\" \"texture tex1\" \"a\" \"rgb tex2\" [0.4 "
             "0.8 1]\n"
             "Texture \"mixed\" \"spectrum\" \"mix\" \"texture tex1\" \"scaled\" \"rgb tex2\" [1 0 "
             "0] \"float amount\" [0.25]\n"
             "Texture \"uvs\" \"spectrum\" \"uv\" \"float uscale\" [2] \"float vscale\" [2]\n"
             "Material \"matte\" \"texture Kd\" \"%s\"\n"
             "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"
             "\"point P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] \"float uv\" [-1 -1  1 -1  1 1  -1 "
             "1]\nWorldEnd\n",
             PI_D, PI_D, PI_D, kinds[t]);
    clr_render_image im = render_opts(scene, NULL, NULL);
    for (int py = 0; py < 8; ++py)
      for (int px = 0; px < 8; ++px) {
        double wx = -(-1.0 + 2.0 * (px + 0.5) / 8.0), wy = 1.0 - 2.0 * (py + 0.5) / 8.0, e[3];
        if (t == 0)
          e[0] = 0.2, e[1] = 0.4, e[2] = 0.5;
        else if (t == 1)
          e[0] = 0.75 * 0.2 + 0.25, e[1] = 0.75 * 0.4, e[2] = 0.75 * 0.5;
        else
          e[0] = 2 * wx - floor(2 * wx), e[1] = 2 * wy - floor(2 * wy), e[2] = 0;
        for (int c = 0; c < 3; ++c)
          assert_true(fabs(im.rgb[3 * (py * 8 + px) + c] - e[c]) <= 1e-5 * fmax(1.0, e[c]));
      }
    free(im.rgb);
  }
}

/* ---- the command line ---- */

static char tmpdir[512];

static void write_text(const char *name, const char *text) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
  fclose(f);
}

/* Runs `clrender ARGS` (ARGS may use %s for tmpdir, several times) with stderr captured into out;
 * returns the exit status. */
static int run_cli(char *out, size_t size, const char *args) {
  char expanded[4096], cmd[5000];
  const char *a = args;
  size_t n = 0;
  while (*a && n + 600 < sizeof expanded) {
    if (a[0] == '%' && a[1] == 's') {
      n += (size_t)snprintf(expanded + n, sizeof expanded - n, "%s", tmpdir);
      a += 2;
    } else {
      expanded[n++] = *a++;
    }
  }
  expanded[n] = 0;
  snprintf(cmd, sizeof cmd, "%s %s 2>&1", CLR_CLI_PATH, expanded);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t got = fread(out, 1, size - 1, p);
  out[got] = 0;
  int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static int exists(const char *name) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  return access(path, F_OK) == 0;
}

static clr_image read_image(const char *name) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  clr_image im;
  assert_int_equal(clr_image_read(path, &im), CLR_SUCCESS);
  return im;
}

static const char *cli_scene = CORNELL_CAMERA
    "Film \"image\" \"integer xresolution\" [16] \"integer yresolution\" [12]\n"
    "Sampler \"halton\" \"integer pixelsamples\" [4]\nIntegrator "
    "\"directlighting\"\nWorldBegin\n" CORNELL_LIGHT_FLOOR_AND_BACK_WALL
    "AttributeBegin\nTranslate 300 100 300\nShape \"sphere\" \"float radius\" [100]\nAttributeEnd\n"
    "WorldEnd\n";

/* Crops rendered by the CLI, merged by `clrender merge`, equal the full render; merge says what
 * it wrote and writes the PNG preview. */
static void test_cli_crops_merge(void **state) {
  (void)state;
  char out[8192];
  write_text("box.pbrt", cli_scene);
  assert_int_equal(run_cli(out, sizeof out, "render %s/box.pbrt --outfile=%s/full.exr --quiet"), 0);
  assert_int_equal(
      run_cli(out, sizeof out,
              "render %s/box.pbrt --outfile %s/top.exr --cropwindow 0 1 0 0.5 --quiet"),
      0);
  assert_int_equal(
      run_cli(out, sizeof out,
              "render %s/box.pbrt --outfile %s/bottom.exr --cropwindow 0 1 0.5 1 --quiet"),
      0);
  assert_int_equal(
      run_cli(out, sizeof out, "merge %s/top.exr %s/bottom.exr --output=%s/merged.exr"), 0);
  assert_non_null(strstr(out, "wrote"));
  assert_non_null(strstr(out, "merged.exr"));
  assert_non_null(strstr(out, "merged.png"));
  assert_true(exists("merged.png"));
  clr_image full = read_image("full.exr"), merged = read_image("merged.exr");
  assert_int_equal(full.width, merged.width);
  assert_int_equal(full.height, merged.height);
  size_t n = (size_t)full.width * full.height * 3;
  double mean = 0;
  for (size_t i = 0; i < n; ++i) mean += full.rgb[i];
  mean /= (double)n;
  assert_true(mean > 0.01);
  for (size_t i = 0; i < n; ++i)
    assert_true(fabs((double)merged.rgb[i] - full.rgb[i]) <=
                1e-5 * fmax(fabs((double)full.rgb[i]), mean));
  clr_image_free(&full);
  clr_image_free(&merged);
}

/* Output by extension: .pfm holds the EXR's pixels (bottom row first), an unknown extension is an
 * error naming it and writes nothing, --outfile overrides the Film's filename. */
static void test_cli_output_formats(void **state) {
  (void)state;
  char out[8192], path[1024];
  write_text("named.pbrt", cli_scene);
  assert_int_equal(run_cli(out, sizeof out, "render %s/named.pbrt --outfile %s/img.exr --quiet"),
                   0);
  assert_int_equal(run_cli(out, sizeof out, "render %s/named.pbrt --outfile %s/img.pfm --quiet"),
                   0);
  assert_true(exists("img.png"));
  clr_image exr = read_image("img.exr");
  snprintf(path, sizeof path, "%s/img.pfm", tmpdir);
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  char header[32] = {0};
  const char expect[] = "PF\n16 12\n-1\n";
  assert_int_equal(fread(header, 1, strlen(expect), f), strlen(expect));
  assert_string_equal(header, expect);
  float *pix = malloc(16 * 12 * 3 * sizeof *pix);
  assert_non_null(pix);
  assert_int_equal(fread(pix, sizeof *pix, 16 * 12 * 3, f), 16 * 12 * 3);
  assert_int_equal(fgetc(f), EOF);
  fclose(f);
  for (int y = 0; y < 12; ++y)
    assert_memory_equal(pix + 3 * 16 * (11 - y), exr.rgb + 3 * 16 * y, 3 * 16 * sizeof(float));
  free(pix);
  clr_image_free(&exr);
  assert_int_equal(run_cli(out, sizeof out, "render %s/named.pbrt --outfile %s/img.tga --quiet"),
                   1);
  assert_non_null(strstr(out, "\".tga\""));
  assert_false(exists("img.tga"));
  /* the scene names a .jpg: an error at its Film line unless --outfile overrides it */
  char scene[4096];
  snprintf(scene, sizeof scene, "Film \"image\" \"string filename\" \"%s/scene.jpg\"\n%s", tmpdir,
           strstr(cli_scene, "Sampler"));
  write_text("jpg.pbrt", scene);
  assert_int_equal(run_cli(out, sizeof out, "render %s/jpg.pbrt --quiet"), 1);
  assert_non_null(strstr(out, "jpg.pbrt:1"));
  assert_non_null(strstr(out, "\".jpg\""));
  assert_int_equal(
      run_cli(out, sizeof out, "render %s/jpg.pbrt --quiet --spp=1 --outfile=%s/over.png"), 0);
  assert_true(exists("over.png"));
  assert_false(exists("scene.jpg"));
}

/* --version, devices --help, --nthreads 0, --flag=value, and the warnings pbrt users see. */
static void test_cli_habits(void **state) {
  (void)state;
  char out[8192], expect[64];
  assert_int_equal(run_cli(out, sizeof out, "--version"), 0);
  snprintf(expect, sizeof expect, "clrender %s\n", clr_version());
  assert_string_equal(out, expect);
  assert_int_equal(run_cli(out, sizeof out, "devices --help"), 0);
  assert_non_null(strstr(out, "usage: clrender devices"));
  assert_non_null(strstr(out, "--device"));
  assert_int_equal(run_cli(out, sizeof out, "devices --bogus"), 2);
  char scene[4096];
  snprintf(scene, sizeof scene,
           "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
           "Sampler \"sobol\" \"integer pixelsamples\" [10]\n"
           "Accelerator \"bvh\" \"integer maxnodeprims\" [4]\nWorldBegin\n"
           "Shape \"nurbs\" \"float radius\" [1] \"rgb Kd\" [1 0 0]\n"
           "Shape \"sphere\" \"float radius\" [1] \"float bogus\" [2]\nWorldEnd\n");
  write_text("habits.pbrt", scene);
  assert_int_equal(
      run_cli(out, sizeof out, "render %s/habits.pbrt --nthreads=0 --outfile=%s/h.exr --stats"), 0);
  assert_true(exists("h.exr"));
  assert_null(strstr(out, "Accelerator"));
  assert_null(strstr(out, "'radius'"));
  assert_null(strstr(out, "'Kd'"));
  assert_non_null(strstr(out, "habits.pbrt:5: shape \"nurbs\" not supported"));
  assert_non_null(strstr(out, "habits.pbrt:6: unused parameter 'bogus' in Shape 'sphere'"));
  assert_non_null(strstr(out, "habits.pbrt:2: non power-of-two sample count rounded up to 16"));
  assert_non_null(strstr(out, "\"spp\":16"));
  assert_non_null(strstr(out, "\"threads\":"));
  /* one format: every warning is "clrender: warning: FILE:LINE: ..." or names its flag */
  int warnings = 0;
  for (const char *l = out; (l = strstr(l, "clrender: warning: ")) != NULL; ++l, ++warnings) {
    const char *m = l + strlen("clrender: warning: ");
    assert_true(strncmp(m, tmpdir, strlen(tmpdir)) == 0 || strncmp(m, "--", 2) == 0);
  }
  assert_int_equal(warnings, 3);
  assert_int_equal(run_cli(out, sizeof out, "render %s/habits.pbrt --spp=10 --outfile=%s/h.exr"),
                   0);
  assert_non_null(strstr(out, "--spp 10: non power-of-two sample count rounded up to 16"));
  assert_int_equal(run_cli(out, sizeof out, "render %s/habits.pbrt --spp=x --outfile=%s/h.exr"), 2);
}

static int cli_setup(void **state) {
  (void)state;
  snprintf(tmpdir, sizeof tmpdir, "%s/test_fidelity_tmp_XXXXXX", CLR_BINARY_DIR);
  return mkdtemp(tmpdir) ? 0 : -1;
}

static int cli_teardown(void **state) {
  (void)state;
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  return system(cmd) == 0 ? 0 : -1;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_crop_halves_every_sampler),
      cmocka_unit_test(test_crop_quarters_and_odd),
      cmocka_unit_test(test_spot_conedeltaangle),
      cmocka_unit_test(test_sphere_light_irradiance),
      cmocka_unit_test(test_sphere_light_noise),
      cmocka_unit_test(test_ray_count_pbrt_v3),
      cmocka_unit_test(test_path_last_bounce_rays),
      cmocka_unit_test(test_light_waves_match_scalar),
      cmocka_unit_test(test_matte_sigma_oren_nayar),
      cmocka_unit_test(test_mirror_sky),
      cmocka_unit_test(test_mirror_reflects_lit_plane),
      cmocka_unit_test(test_mirror_path_sees_emitter),
      cmocka_unit_test(test_plastic_lobe),
      cmocka_unit_test(test_trowbridge_reitz),
      cmocka_unit_test(test_path_sample_layout),
      cmocka_unit_test(test_plastic_plane),
      cmocka_unit_test(test_plastic_sky_albedo),
      cmocka_unit_test(test_disk_shape),
      cmocka_unit_test(test_disk_light_irradiance),
      cmocka_unit_test(test_glass_furnace),
      cmocka_unit_test(test_glass_fresnel),
      cmocka_unit_test(test_metal_plane),
      cmocka_unit_test(test_metal_sky_albedo),
      cmocka_unit_test(test_partial_sphere),
      cmocka_unit_test(test_textures_scale_mix_uv),
      cmocka_unit_test(test_cli_crops_merge),
      cmocka_unit_test(test_cli_output_formats),
      cmocka_unit_test(test_cli_habits),
  };
  return cmocka_run_group_tests(tests, cli_setup, cli_teardown);
}
