/* `clrender samples`: print the sample vectors of pixels as CSV, or plot a 2D projection. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "cli_args.h"
#include "clrender.h"
#include "sample_plot.h"

static void samples_usage(FILE *f) {
  fprintf(
      f,
      "usage: clrender samples --sampler NAME [options]\n"
      "Prints one CSV row per sample: px,py,sample,global_index,v0,v1,... (film offset first;\n"
      "global_index is empty for samplers without one).\n"
      "  --sampler NAME        random | stratified | halton | sobol | 02sequence (alias\n"
      "                        lowdiscrepancy) | maxmindist | independent | paddedsobol |\n"
      "                        zsobol | pmj02bn (required)\n"
      "  --spp N               samples per pixel (stratified: factored into xsamples*ysamples)\n"
      "  --xsamples N --ysamples N  stratified strata (default 4 x 4)\n"
      "  --dimensions N        stratified, 02sequence, maxmindist 1D/2D streams (default 4)\n"
      "  --jitter true|false   stratified jitter (default true)\n"
      "  --samplepixelcenter true|false  halton (default false)\n"
      "  --res WxH             film resolution (default 64x64)\n"
      "  --filter-radius R[,R] filter radius that grows the sample bounds (default 0.5)\n"
      "  --pixel x,y           one pixel (default 0,0)\n"
      "  --pixels x0,y0,x1,y1  pixels [x0,x1) x [y0,y1)\n"
      "  --requests LIST       request layout, e.g. 2,1,2,1,2,2 (default 2,1,2 = camera);\n"
      "                        D:N is an array of N D-dimensional values, e.g. 2,1,2,2:16\n"
      "  --seeding MODE        pixel (default; tiling-independent) | pbrt-v3 | pbrt-v4\n"
      "  --seed N              seed mixed into per-pixel streams, pbrt-v4's \"seed\" (default 0)\n"
      "  --randomization R     pbrt-v4 halton, sobol, paddedsobol, zsobol: none | permutedigits\n"
      "                        | fastowen | owen (default: pbrt-v4's for the sampler)\n"
      "  --device D            OpenCL device index or name substring\n"
      "  --kernels SHAPE       simd | portable | auto (default auto; same values either way)\n"
      "  --reference           compute on the host reference instead of the device\n"
      "  --plot FILE.png       draw the pixels' samples in projection --proj instead of CSV\n"
      "  --proj i,j            value indices to plot (default 0,1)\n");
}

typedef struct samples_options {
  clr_sampler_desc desc;
  clr_sample_request requests[CLR_MAX_REQUESTS];
  int32_t request_count;
  clr_bounds2i pixels;
  const char *device, *plot, *kernels;
  int32_t proj[2];
  int reference, spp_set;
  int32_t spp;
} samples_options;

static int parse_bool(const char *s, int32_t *out) {
  if (s && strcmp(s, "true") == 0) return *out = 1, 1;
  if (s && strcmp(s, "false") == 0) return *out = 0, 1;
  return 0;
}

static int parse_requests(const char *s, samples_options *o) {
  o->request_count = 0;
  const char *p = s;
  while (p && *p) {
    if (o->request_count == CLR_MAX_REQUESTS) return 0;
    char *end = NULL;
    long dims = strtol(p, &end, 10);
    if (end == p) return 0;
    long array = 0;
    if (*end == ':') {
      const char *a = end + 1;
      array = strtol(a, &end, 10);
      if (end == a || array < 1) return 0;
    }
    if (*end != ',' && *end != 0) return 0;
    if (dims < -1000000 || dims > 1000000 || array > 1000000) return 0;
    o->requests[o->request_count].dims = (int32_t)dims;
    o->requests[o->request_count].array_size = (int32_t)array;
    o->request_count++;
    p = *end ? end + 1 : end;
    if (*end == ',' && !*p) return 0;
  }
  return o->request_count > 0;
}

/* Splits n into x*y with x the largest divisor not above sqrt(n). */
static void factor_spp(int32_t n, int32_t *x, int32_t *y) {
  int32_t best = 1;
  for (int32_t d = 1; (int64_t)d * d <= n; ++d)
    if (n % d == 0) best = d;
  *x = n / best;
  *y = best;
}

static int bad_value(const char *flag, const char *value) {
  fprintf(stderr, "clrender samples: bad value for %s: \"%s\"\n", flag,
          value ? value : "(missing)");
  samples_usage(stderr);
  return 0;
}

/* 1: parsed, 0: bad arguments (reported), 2: --help printed. */
static int parse_samples_args(int argc, char **argv, samples_options *o, const char **sampler) {
  *sampler = NULL;
  clr_sampler_desc_init(&o->desc, CLR_SAMPLER_HALTON);
  o->desc.film.x_resolution = o->desc.film.y_resolution = 64;
  o->pixels = (clr_bounds2i){0, 0, 1, 1};
  o->proj[0] = 0;
  o->proj[1] = 1;
  parse_requests("2,1,2", o);
  int32_t v[4];
  float radius[2] = {0.5f, 0.5f};
  for (int i = 1; i < argc; ++i) {
    const char *f = argv[i];
    const char *val = i + 1 < argc ? argv[i + 1] : NULL;
    int takes_value = 1;
    if (strcmp(f, "--help") == 0 || strcmp(f, "-h") == 0) {
      samples_usage(stdout);
      return 2; /* help shown */
    } else if (strcmp(f, "--reference") == 0) {
      o->reference = 1;
      takes_value = 0;
    } else if (!val) {
      return bad_value(f, NULL);
    } else if (strcmp(f, "--sampler") == 0) {
      *sampler = val;
    } else if (strcmp(f, "--spp") == 0) {
      if (!cli_parse_int(val, 1, 1 << 20, &o->spp)) return bad_value(f, val);
      o->spp_set = 1;
    } else if (strcmp(f, "--xsamples") == 0) {
      if (!cli_parse_int(val, 1, 256, &o->desc.x_samples)) return bad_value(f, val);
    } else if (strcmp(f, "--ysamples") == 0) {
      if (!cli_parse_int(val, 1, 256, &o->desc.y_samples)) return bad_value(f, val);
    } else if (strcmp(f, "--dimensions") == 0) {
      if (!cli_parse_int(val, 1, 1024, &o->desc.dimensions)) return bad_value(f, val);
    } else if (strcmp(f, "--jitter") == 0) {
      if (!parse_bool(val, &o->desc.jitter)) return bad_value(f, val);
    } else if (strcmp(f, "--samplepixelcenter") == 0) {
      if (!parse_bool(val, &o->desc.sample_pixel_center)) return bad_value(f, val);
    } else if (strcmp(f, "--res") == 0) {
      if (!cli_parse_resolution(val, &o->desc.film.x_resolution, &o->desc.film.y_resolution))
        return bad_value(f, val);
    } else if (strcmp(f, "--filter-radius") == 0) {
      int32_t dummy[2];
      (void)dummy;
      char buf[64];
      snprintf(buf, sizeof buf, "%s", val);
      char *comma = strchr(buf, ',');
      if (comma) *comma = 0;
      if (!cli_parse_float(buf, &radius[0])) return bad_value(f, val);
      radius[1] = radius[0];
      if (comma && !cli_parse_float(comma + 1, &radius[1])) return bad_value(f, val);
    } else if (strcmp(f, "--pixel") == 0) {
      if (!cli_parse_ints(val, 2, v)) return bad_value(f, val);
      o->pixels = (clr_bounds2i){v[0], v[1], v[0] + 1, v[1] + 1};
    } else if (strcmp(f, "--pixels") == 0) {
      if (!cli_parse_ints(val, 4, v)) return bad_value(f, val);
      o->pixels = (clr_bounds2i){v[0], v[1], v[2], v[3]};
    } else if (strcmp(f, "--requests") == 0) {
      if (!parse_requests(val, o)) return bad_value(f, val);
    } else if (strcmp(f, "--seeding") == 0) {
      if (strcmp(val, "pbrt-v3") == 0)
        o->desc.seeding = CLR_SEEDING_PBRT_V3;
      else if (strcmp(val, "pixel") == 0)
        o->desc.seeding = CLR_SEEDING_PIXEL;
      else if (strcmp(val, "pbrt-v4") == 0)
        o->desc.seeding = CLR_SEEDING_PBRT_V4;
      else
        return bad_value(f, val);
    } else if (strcmp(f, "--seed") == 0) {
      int32_t seed;
      if (!cli_parse_int(val, 0, 2147483647L, &seed)) return bad_value(f, val);
      o->desc.seed = (uint32_t)seed;
    } else if (strcmp(f, "--randomization") == 0) {
      if (clr_randomization_from_name(val, &o->desc.randomization) != CLR_SUCCESS)
        return bad_value(f, val);
    } else if (strcmp(f, "--device") == 0) {
      o->device = val;
    } else if (strcmp(f, "--kernels") == 0) {
      clr_kernel_shape shape;
      if (clr_kernel_shape_from_name(val, &shape) != CLR_SUCCESS) return bad_value(f, val);
      o->kernels = val;
    } else if (strcmp(f, "--plot") == 0) {
      o->plot = val;
    } else if (strcmp(f, "--proj") == 0) {
      if (!cli_parse_ints(val, 2, o->proj) || o->proj[0] < 0 || o->proj[1] < 0)
        return bad_value(f, val);
    } else {
      fprintf(stderr, "clrender samples: unknown option \"%s\"\n", f);
      samples_usage(stderr);
      return 0;
    }
    i += takes_value;
  }
  if (!*sampler) {
    fprintf(stderr, "clrender samples: --sampler is required\n");
    samples_usage(stderr);
    return 0;
  }
  o->desc.film.filter_radius[0] = radius[0];
  o->desc.film.filter_radius[1] = radius[1];
  return 1;
}

static void print_csv(const samples_options *o, const clr_sample_batch *b, int32_t values,
                      int32_t count, const float *v, const uint64_t *idx, int has_index) {
  printf("px,py,sample,global_index");
  for (int32_t k = 0; k < values; ++k) printf(",v%d", (int)k);
  printf("\n");
  int32_t w = o->pixels.x1 - o->pixels.x0;
  for (int32_t y = o->pixels.y0; y < o->pixels.y1; ++y)
    for (int32_t x = o->pixels.x0; x < o->pixels.x1; ++x)
      for (int32_t s = 0; s < count; ++s) {
        size_t item = ((size_t)(y - o->pixels.y0) * w + (size_t)(x - o->pixels.x0)) * count + s;
        printf("%d,%d,%d,", (int)x, (int)y, (int)(b->first_sample + s));
        if (has_index) printf("%llu", (unsigned long long)idx[item]);
        for (int32_t k = 0; k < values; ++k) printf(",%.9g", (double)v[item * values + k]);
        printf("\n");
      }
}

/* pbrt-v4 samplers take 1D requests before the film offset (the wavelengths in pbrt-v4): how
 * many lead the layout. */
static int32_t leading_1d(const samples_options *o) {
  int v4 = o->desc.seeding == CLR_SEEDING_PBRT_V4 || o->desc.type >= CLR_SAMPLER_INDEPENDENT;
  int32_t n = 0;
  while (v4 && n + 1 < o->request_count && o->requests[n].dims == 1) ++n;
  return n;
}

static int fail(const char *what) {
  fprintf(stderr, "clrender samples: %s: %s\n", what, clr_last_error_message());
  return 1;
}

int cli_samples(int argc, char **argv) {
  samples_options o;
  memset(&o, 0, sizeof o);
  const char *name = NULL;
  int parsed = parse_samples_args(argc, argv, &o, &name);
  if (parsed != 1) return parsed == 2 ? 0 : 2;
  clr_sampler_type type;
  if (clr_sampler_type_from_name(name, &type) != CLR_SUCCESS) {
    fprintf(stderr, "clrender samples: %s\n", clr_last_error_message());
    samples_usage(stderr);
    return 2;
  }
  clr_sampler_desc desc = o.desc;
  clr_sampler_desc_init(&o.desc, type);
  o.desc.x_samples = desc.x_samples;
  o.desc.y_samples = desc.y_samples;
  o.desc.dimensions = desc.dimensions;
  o.desc.jitter = desc.jitter;
  o.desc.sample_pixel_center = desc.sample_pixel_center;
  o.desc.seeding = desc.seeding;
  o.desc.seed = desc.seed;
  o.desc.randomization = desc.randomization;
  o.desc.film = desc.film;
  if (o.spp_set) {
    o.desc.pixel_samples = o.spp;
    if (type == CLR_SAMPLER_STRATIFIED) factor_spp(o.spp, &o.desc.x_samples, &o.desc.y_samples);
  }
  if (type == CLR_SAMPLER_ZEROTWO && o.desc.pixel_samples > 0 &&
      (o.desc.pixel_samples & (o.desc.pixel_samples - 1)) != 0) {
    int32_t up = 1;
    while (up < o.desc.pixel_samples && up < (1 << 30)) up <<= 1;
    fprintf(stderr,
            "clrender samples: warning: Pixel samples being rounded up to power of 2 "
            "(from %d to %d).\n",
            (int)o.desc.pixel_samples, (int)up);
  }
  if (type == CLR_SAMPLER_MAXMINDIST && o.desc.pixel_samples > 0 &&
      o.desc.pixel_samples < (1 << 17) &&
      (o.desc.pixel_samples & (o.desc.pixel_samples - 1)) != 0) {
    int32_t up = 1;
    while (up < o.desc.pixel_samples) up <<= 1;
    fprintf(stderr,
            "clrender samples: warning: Non power-of-two sample count rounded up to %d "
            "for MaxMinDistSampler.\n",
            (int)up);
  }
  if (o.plot && (o.proj[0] >= CLR_MAX_VALUES_PER_SAMPLE || o.proj[1] >= CLR_MAX_VALUES_PER_SAMPLE))
    return bad_value("--proj", "index too large"), 2;

  clr_context ctx = NULL;
  if (!o.reference) {
    clr_context_desc cd;
    clr_context_desc_init(&cd);
    cd.device = o.device;
    if (clr_context_create(&cd, &ctx) != CLR_SUCCESS) return fail("cannot open the OpenCL device");
    clr_kernel_shape shape = CLR_KERNELS_AUTO;
    if (o.kernels && (clr_kernel_shape_from_name(o.kernels, &shape) != CLR_SUCCESS ||
                      clr_context_set_kernel_shape(ctx, shape) != CLR_SUCCESS)) {
      clr_context_release(ctx);
      return fail("cannot choose the kernel shape");
    }
  }
  clr_sampler sampler = NULL;
  if (clr_sampler_create(ctx, &o.desc, &sampler) != CLR_SUCCESS) {
    fprintf(stderr, "clrender samples: %s\n", clr_last_error_message());
    samples_usage(stderr);
    clr_context_release(ctx);
    return 2;
  }
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = o.pixels;
  b.requests = o.requests;
  b.request_count = o.request_count;
  int32_t values = 0;
  int status = 0;
  float *v = NULL;
  uint64_t *idx = NULL;
  if (clr_sample_layout_values(o.requests + leading_1d(&o), o.request_count - leading_1d(&o),
                               &values) != CLR_SUCCESS) {
    fprintf(stderr, "clrender samples: --requests: %s\n", clr_last_error_message());
    samples_usage(stderr);
    status = 2;
    goto done;
  }
  for (int32_t i = 0; i < leading_1d(&o); ++i)
    values += o.requests[i].array_size ? o.requests[i].array_size : 1;
  int32_t count = clr_sampler_spp(sampler);
  size_t pixels = (size_t)(o.pixels.x1 > o.pixels.x0 ? o.pixels.x1 - o.pixels.x0 : 0) *
                  (size_t)(o.pixels.y1 > o.pixels.y0 ? o.pixels.y1 - o.pixels.y0 : 0);
  v = malloc(pixels * (size_t)count * (size_t)values * sizeof(float) + 4);
  idx = malloc(pixels * (size_t)count * sizeof(uint64_t) + 8);
  if (!v || !idx) {
    fprintf(stderr, "clrender samples: out of memory for %zu pixels\n", pixels);
    status = 1;
    goto done;
  }
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = v;
  out.host_indices = idx;
  clr_result r = o.reference ? clr_sampler_generate_reference(sampler, &b, &out)
                             : clr_sampler_generate(sampler, &b, &out);
  if (r == CLR_ERROR_INVALID_PIXEL_RANGE) {
    fprintf(stderr, "clrender samples: --pixel/--pixels: %s\n", clr_last_error_message());
    status = 2;
    goto done;
  }
  if (r != CLR_SUCCESS) {
    status = fail("sample generation failed");
    goto done;
  }
  if (o.plot) {
    if (o.proj[0] >= values || o.proj[1] >= values) {
      fprintf(stderr, "clrender samples: --proj %d,%d outside the %d values per sample\n",
              (int)o.proj[0], (int)o.proj[1], (int)values);
      status = 2;
      goto done;
    }
    if (clr_plot_samples(o.plot, o.pixels, count, values, v, o.proj) != CLR_SUCCESS)
      status = fail("cannot write the plot");
  } else {
    print_csv(&o, &b, values, count, v, idx, clr_sampler_has_global_index(sampler));
    if (fflush(stdout) != 0 || ferror(stdout)) {
      fprintf(stderr, "clrender samples: cannot write to standard output\n");
      status = 1;
    }
  }
done:
  free(v);
  free(idx);
  clr_sampler_release(sampler);
  clr_context_release(ctx);
  return status;
}
