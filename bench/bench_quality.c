/* Sample quality (--only quality): RMSE against spp (powers of two) for every sampler of the
 * library on analytic integrands over the pixel's film offset (values 0, 1) and on a small render
 * of scenes/checkerboard.pbrt against a high-spp reference, with the least-squares convergence
 * slope; each sampler's point set and power spectrum; PNG figures in --out-dir. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "bench.h"
#include "quality_figures.h"
#include "quality_math.h"
#include "renderer.h"
#include "scene_parser.h"

#ifndef CLR_SOURCE_DIR
#define CLR_SOURCE_DIR "."
#endif
#ifndef CLR_BINARY_DIR
#define CLR_BINARY_DIR "build"
#endif

enum {
  FILM_SIDE = 64,    /* the host samplers' film: 64 x 64 pixels */
  FIRST_PIXEL = 8,   /* the pixels measured start at (8, 8), away from the film's edge */
  PIXEL_SIDE = 16,   /* 256 pixels, each an independent estimate */
  SPECTRUM_SIDE = 8, /* periodogram averaged over 64 pixels */
  SPECTRUM_POINTS = 256,
  SPECTRUM_K = 32,
  SCENE_W = 64, /* the checkerboard rendered at 64 x 48 */
  SCENE_H = 48,
  SCENE_REFERENCE_FACTOR = 16 /* reference spp = 16 x the largest spp measured */
};
/* The reference's sampler and seed: a scrambled sampler whose per-pixel streams differ from the
 * measured renders' (seed 0). */
static const char *const reference_sampler = "02sequence";
static const uint32_t reference_seed = 0x5eed;

typedef struct quality_run {
  int samplers;
  const char *names[QUALITY_MAX_SAMPLERS];
  int max_spp, scene_max_spp;
  /* curves[case * samplers + s]: the analytic integrands, then the scene */
  quality_curve curves[4 * QUALITY_MAX_SAMPLERS];
} quality_run;

/* x * y = spp with x the smallest power of two whose square reaches spp (stratified). */
static void strata(int spp, int32_t *x, int32_t *y) {
  int32_t a = 1;
  while (a * a < spp) a *= 2;
  *x = spp % a == 0 ? a : spp, *y = spp % a == 0 ? spp / a : 1;
}

/* The film offsets (values 0, 1) of side x side pixels x spp samples from the host reference,
 * malloc'ed, or NULL (with *why) when the sampler does not give exactly spp samples. */
static float *pixel_offsets(clr_sampler_type type, int spp, int side, char *why, size_t why_size) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.pixel_samples = spp;
  strata(spp, &d.x_samples, &d.y_samples);
  d.film.x_resolution = d.film.y_resolution = FILM_SIDE;
  clr_sampler s = NULL;
  if (clr_sampler_create(NULL, &d, &s) != CLR_SUCCESS) {
    snprintf(why, why_size, "%s", clr_last_error_message());
    return NULL;
  }
  if (clr_sampler_spp(s) != spp) {
    snprintf(why, why_size, "pixelsamples %d gives %d samples", spp, (int)clr_sampler_spp(s));
    clr_sampler_release(s);
    return NULL;
  }
  static const clr_sample_request film_offset = {2, 0};
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = (clr_bounds2i){FIRST_PIXEL, FIRST_PIXEL, FIRST_PIXEL + side, FIRST_PIXEL + side};
  b.requests = &film_offset;
  b.request_count = 1;
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = malloc((size_t)side * side * spp * 2 * sizeof(float));
  if (!out.host_values || clr_sampler_generate_reference(s, &b, &out) != CLR_SUCCESS) {
    snprintf(why, why_size, "%s", out.host_values ? clr_last_error_message() : "out of memory");
    free(out.host_values);
    out.host_values = NULL;
  }
  clr_sampler_release(s);
  return out.host_values;
}

/* RMSE over the pixels of each pixel's mean of f against the exact integral. */
static double integrand_rmse(const qm_integrand *q, const float *xy, int pixels, int spp) {
  double sum2 = 0;
  for (int p = 0; p < pixels; ++p) {
    double sum = 0;
    const float *v = xy + (size_t)p * spp * 2;
    for (int i = 0; i < spp; ++i) sum += q->f(v[2 * i], v[2 * i + 1]);
    double e = sum / spp - q->exact;
    sum2 += e * e;
  }
  return sqrt(sum2 / pixels);
}

static void print_curve(const char *case_name, const char *sampler, const char *extra,
                        const quality_curve *c) {
  printf("{\"bench\":\"quality\",\"case\":\"%s\",\"sampler\":\"%s\"%s,\"spp\":[", case_name,
         sampler, extra);
  for (int i = 0; i < c->n; ++i) printf("%s%g", i ? "," : "", c->spp[i]);
  printf("],\"rmse\":[");
  for (int i = 0; i < c->n; ++i) printf("%s%.4g", i ? "," : "", c->rmse[i]);
  printf("],\"slope\":%.3f,\"slope_fit\":\"least squares of log rmse on log spp\"}\n", c->slope);
  fflush(stdout);
}

static void print_skip(const char *case_name, const char *sampler, int spp, const char *why) {
  printf("{\"bench\":\"quality\",\"case\":\"%s\",\"sampler\":\"%s\",\"spp\":%d,\"skipped\":",
         case_name, sampler, spp);
  bench_json_escape(stdout, why);
  printf("}\n");
}

/* Every sampler on every analytic integrand, spp 1, 2, 4, ... max_spp. */
static void measure_integrands(quality_run *q) {
  int nq = qm_integrand_count(), pixels = PIXEL_SIDE * PIXEL_SIDE;
  for (int s = 0; s < q->samplers; ++s) {
    for (int spp = 1; spp <= q->max_spp; spp *= 2) {
      char why[512];
      float *xy = pixel_offsets((clr_sampler_type)s, spp, PIXEL_SIDE, why, sizeof why);
      if (!xy) {
        print_skip("integrands", q->names[s], spp, why);
        continue;
      }
      for (int k = 0; k < nq; ++k) {
        quality_curve *c = &q->curves[k * q->samplers + s];
        c->spp[c->n] = spp;
        c->rmse[c->n++] = integrand_rmse(qm_integrand_get(k), xy, pixels, spp);
      }
      free(xy);
    }
    for (int k = 0; k < nq; ++k) {
      quality_curve *c = &q->curves[k * q->samplers + s];
      c->slope = qm_loglog_slope(c->spp, c->rmse, c->n);
      char extra[96];
      snprintf(extra, sizeof extra, ",\"pixels\":%d,\"exact\":%.9g", pixels,
               qm_integrand_get(k)->exact);
      print_curve(qm_integrand_get(k)->name, q->names[s], extra, c);
    }
  }
}

/* The checkerboard at SCENE_W x SCENE_H with `sampler` at spp, RGB malloc'ed, or NULL (*why). */
static float *render_scene(const clr_scene_desc *desc, const char *sampler, int spp, uint32_t seed,
                           const char *device, char *why, size_t why_size) {
  clr_render_options o;
  clr_render_options_init(&o);
  o.quiet = 1;
  o.sampler = sampler;
  o.spp = spp;
  o.seed = seed;
  o.xresolution = SCENE_W, o.yresolution = SCENE_H;
  o.device = device;
  clr_render_image img;
  memset(&img, 0, sizeof img);
  if (clr_render_desc(desc, &o, NULL, 0, &img) != CLR_SUCCESS) {
    snprintf(why, why_size, "%s", clr_last_error_message());
    return NULL;
  }
  if (img.width != SCENE_W || img.height != SCENE_H) {
    snprintf(why, why_size, "rendered %dx%d, expected %dx%d", (int)img.width, (int)img.height,
             SCENE_W, SCENE_H);
    free(img.rgb);
    return NULL;
  }
  return img.rgb;
}

static double image_rmse(const float *a, const float *b) {
  double sum2 = 0;
  size_t n = (size_t)SCENE_W * SCENE_H * 3;
  for (size_t i = 0; i < n; ++i) sum2 += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
  return sqrt(sum2 / (double)n);
}

/* Every sampler on the checkerboard's pixels, spp 1 ... scene_max_spp, against the reference. */
static void measure_scene(quality_run *q, const char *device) {
  char path[1024], why[512];
  snprintf(path, sizeof path, "%s/scenes/checkerboard.pbrt", CLR_SOURCE_DIR);
  clr_parse_options po;
  clr_parse_options_init(&po);
  po.warn = NULL;
  clr_scene_desc *desc = NULL;
  if (clr_scene_parse_file(path, &po, &desc) != CLR_SUCCESS) {
    print_skip("checkerboard", reference_sampler, 0, clr_last_error_message());
    return;
  }
  int ref_spp = SCENE_REFERENCE_FACTOR * q->scene_max_spp;
  double t0 = bench_now();
  float *ref =
      render_scene(desc, reference_sampler, ref_spp, reference_seed, device, why, sizeof why);
  if (!ref) {
    print_skip("checkerboard", reference_sampler, ref_spp, why);
    clr_scene_desc_free(desc);
    return;
  }
  printf(
      "{\"bench\":\"quality\",\"case\":\"checkerboard reference\",\"sampler\":\"%s\",\"spp\":%d,"
      "\"seed\":%u,\"resolution\":\"%dx%d\",\"seconds\":%.2f}\n",
      reference_sampler, ref_spp, (unsigned)reference_seed, SCENE_W, SCENE_H, bench_now() - t0);
  for (int s = 0; s < q->samplers; ++s) {
    quality_curve *c = &q->curves[qm_integrand_count() * q->samplers + s];
    for (int spp = 1; spp <= q->scene_max_spp; spp *= 2) {
      float *img = render_scene(desc, q->names[s], spp, 0, device, why, sizeof why);
      if (!img) {
        print_skip("checkerboard", q->names[s], spp, why);
        continue;
      }
      c->spp[c->n] = spp;
      c->rmse[c->n++] = image_rmse(img, ref);
      free(img);
    }
    c->slope = qm_loglog_slope(c->spp, c->rmse, c->n);
    char extra[128];
    snprintf(extra, sizeof extra, ",\"pixels\":%d,\"reference\":\"%s %d spp\"", SCENE_W * SCENE_H,
             reference_sampler, ref_spp);
    print_curve("checkerboard", q->names[s], extra, c);
  }
  free(ref);
  clr_scene_desc_free(desc);
}

/* Mean periodogram power over 1 <= |k| <= 8: low for blue noise, 1 for white noise. */
static double low_frequency_power(const double *radial) {
  double sum = 0;
  for (int r = 1; r <= 8; ++r) sum += radial[r];
  return sum / 8;
}

/* One sampler's 256 points of one pixel and the periodogram averaged over 64 pixels. */
static int measure_spectrum(clr_sampler_type type, const char *name, quality_spectrum *out) {
  char why[512];
  int side = 2 * SPECTRUM_K + 1, pixels = SPECTRUM_SIDE * SPECTRUM_SIDE;
  float *xy = pixel_offsets(type, SPECTRUM_POINTS, SPECTRUM_SIDE, why, sizeof why);
  double *power = calloc((size_t)side * side, sizeof(double));
  double *radial = calloc(SPECTRUM_K + 1, sizeof(double));
  int ok = xy && power && radial;
  for (int p = 0; ok && p < pixels; ++p)
    ok = qm_periodogram_add(xy + (size_t)p * SPECTRUM_POINTS * 2, SPECTRUM_POINTS, SPECTRUM_K,
                            power);
  if (!ok) {
    print_skip("spectrum", name, SPECTRUM_POINTS, xy ? "out of memory" : why);
    free(xy), free(power), free(radial);
    return 0;
  }
  for (int i = 0; i < side * side; ++i) power[i] /= pixels;
  qm_radial_average(power, SPECTRUM_K, radial);
  printf(
      "{\"bench\":\"quality\",\"case\":\"spectrum\",\"sampler\":\"%s\",\"points\":%d,"
      "\"pixels\":%d,\"low_frequency_power\":%.4f,\"radial_power\":[",
      name, SPECTRUM_POINTS, pixels, low_frequency_power(radial));
  for (int r = 1; r <= SPECTRUM_K; ++r) printf("%s%.3f", r > 1 ? "," : "", radial[r]);
  printf("]}\n");
  *out = (quality_spectrum){name, xy, SPECTRUM_POINTS, power, radial, SPECTRUM_K};
  return 1;
}

static void measure_spectra(const quality_run *q, const char *path) {
  quality_spectrum spectra[QUALITY_MAX_SAMPLERS];
  int n = 0;
  for (int s = 0; s < q->samplers; ++s)
    n += measure_spectrum((clr_sampler_type)s, q->names[s], &spectra[n]);
  if (n > 0 && quality_plot_spectra(path, spectra, n, SPECTRUM_SIDE * SPECTRUM_SIDE) != CLR_SUCCESS)
    print_skip("spectrum figure", "", 0, clr_last_error_message());
  else if (n > 0)
    printf("{\"bench\":\"quality\",\"figure\":\"%s\"}\n", path);
  for (int i = 0; i < n; ++i) {
    free((void *)spectra[i].points), free((void *)spectra[i].power);
    free((void *)spectra[i].radial);
  }
}

/* mkdir -p; 1 when the folder exists afterwards. */
static int make_dirs(const char *dir) {
  char p[1024];
  if (snprintf(p, sizeof p, "%s", dir) >= (int)sizeof p) return 0;
  for (char *c = p + 1; *c; ++c)
    if (*c == '/') {
      *c = 0;
      if (mkdir(p, 0777) != 0 && errno != EEXIST) return 0;
      *c = '/';
    }
  struct stat st;
  return (mkdir(p, 0777) == 0 || errno == EEXIST) && stat(p, &st) == 0 && S_ISDIR(st.st_mode);
}

int bench_quality(const bench_options *o) {
  static quality_run q;
  memset(&q, 0, sizeof q);
  q.samplers = bench_sampler_count();
  if (q.samplers > QUALITY_MAX_SAMPLERS) q.samplers = QUALITY_MAX_SAMPLERS;
  for (int s = 0; s < q.samplers; ++s) q.names[s] = clr_sampler_type_name((clr_sampler_type)s);
  q.max_spp = o->quick ? 1024 : 4096;
  q.scene_max_spp = o->quick ? 32 : 256;
  const char *dir = o->out_dir ? o->out_dir : CLR_BINARY_DIR "/bench-quality";
  if (!make_dirs(dir)) {
    fprintf(stderr, "clrender_bench: --out-dir %s: cannot create the folder: %s\n", dir,
            strerror(errno));
    return 0;
  }
  char path[1200];
  snprintf(path, sizeof path, "%s/spectra.png", dir);
  measure_spectra(&q, path);
  measure_integrands(&q);
  measure_scene(&q, o->only_device);
  const char *cases[4];
  for (int k = 0; k < qm_integrand_count(); ++k) cases[k] = qm_integrand_get(k)->name;
  cases[qm_integrand_count()] = "checkerboard (scene)";
  snprintf(path, sizeof path, "%s/convergence.png", dir);
  if (quality_plot_convergence(path, cases, qm_integrand_count() + 1, q.names, q.samplers,
                               q.curves) != CLR_SUCCESS)
    print_skip("convergence figure", "", 0, clr_last_error_message());
  else
    printf("{\"bench\":\"quality\",\"figure\":\"%s\"}\n", path);
  return 1;
}
