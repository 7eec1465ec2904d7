/* Fuzz target, differential: film_add_samples on the default OpenCL device (PoCL: the SIMD or the
 * portable kernels, any binning thread count, work-group size and accumulation tile size) must
 * give the host film (no context: the kernels' C build) the same counts and the same double sums,
 * bit for bit, for any film, filter and samples (NaN, Inf, negative, outside, on pixel and
 * radius boundaries, raw float bits), in one call or two, from host memory or a device buffer. A difference aborts, so libFuzzer
 * reports it with the input. Layout of an input: 16 header bytes (read_film), then samples of 8
 * bytes (read_sample) or, with FLAG_RAW, of 24 raw float bytes. */
#include <math.h>
#include "clrender.h"
#include "film_internal.h"
#include "fuzz_common.h"

#define FLAG_TABLE 1u    /* pbrt-v3's filter table */
#define FLAG_PORTABLE 2u /* the portable kernels, else SIMD */
#define FLAG_CLAMP 4u    /* a maximum sample luminance */
#define FLAG_RAW 8u      /* samples as raw floats */
#define FLAG_SPLIT 16u   /* two calls */
#define FLAG_BUFFER 32u  /* the device film takes its samples from a device buffer */
#define MAX_SAMPLES 4096

static clr_context ctx;

static float unit(fuzz_reader *r) { return (float)fuzz_next(r) / 255.0f; }

/* The film and its filter from 16 bytes; *flags, *threads, *group and *split get the rest. */
static void read_film(fuzz_reader *r, clr_film_desc *d, unsigned *flags, int *threads,
                      size_t *group, float *split) {
  static const size_t groups[] = {0, 1, 2, 4, 8, 16, 64};
  clr_film_desc_init(d);
  clr_filter_desc_init(&d->filter, (clr_filter_type)(fuzz_next(r) % 7));
  *flags = fuzz_next(r);
  d->filter.use_table = (*flags & FLAG_TABLE) != 0;
  d->filter.radius[0] = (float)(1 + fuzz_next(r) % 64) / 8.0f; /* 0.125 .. 8: reaches up to 17 */
  d->filter.radius[1] = (float)(1 + fuzz_next(r) % 64) / 8.0f;
  d->filter.b = ((float)fuzz_next(r) - 128.0f) / 32.0f;
  d->filter.c = ((float)fuzz_next(r) - 128.0f) / 32.0f;
  d->x_resolution = 1 + fuzz_next(r) % 40;
  d->y_resolution = 1 + fuzz_next(r) % 40;
  float cx0 = unit(r), cx1 = unit(r), cy0 = unit(r), cy1 = unit(r);
  d->crop_window[0] = fminf(cx0, cx1);
  d->crop_window[1] = fmaxf(cx0, cx1);
  d->crop_window[2] = fminf(cy0, cy1);
  d->crop_window[3] = fmaxf(cy0, cy1);
  d->accumulation_tile_size = 4 + fuzz_next(r) % 61;
  uint8_t clamp = fuzz_next(r);
  if (*flags & FLAG_CLAMP) d->max_sample_luminance = 0.25f + (float)clamp / 16.0f;
  uint8_t t = fuzz_next(r);
  *threads = 1 + t % 3;
  *group = groups[(t >> 2) % 7];
  *split = unit(r);
}

/* A coordinate over the sample bounds and a little beyond, or, for the top 16th of the range,
 * on a quarter-pixel grid (pixel centres, edges and radius boundaries exactly). */
static float read_coordinate(fuzz_reader *r, int32_t resolution, float radius) {
  unsigned v = (unsigned)fuzz_next(r) | (unsigned)fuzz_next(r) << 8;
  if ((v & 0xf000u) == 0xf000u) return (float)(v & 0xffu) / 4.0f - 8.0f;
  return -radius - 1.0f + (float)v / 65535.0f * ((float)resolution + 2.0f * radius + 2.0f);
}

static void read_sample(fuzz_reader *r, const clr_film_desc *d, clr_film_sample *s) {
  s->x = read_coordinate(r, d->x_resolution, d->filter.radius[0]);
  s->y = read_coordinate(r, d->y_resolution, d->filter.radius[1]);
  s->r = ((float)fuzz_next(r) - 32.0f) / 16.0f; /* some negative: luminance below the threshold */
  s->g = ((float)fuzz_next(r) - 32.0f) / 16.0f;
  s->b = ((float)fuzz_next(r) - 32.0f) / 16.0f;
  uint8_t w = fuzz_next(r);
  s->weight = w == 255 ? NAN : w == 254 ? INFINITY : (float)w / 64.0f;
}

static void fail(const char *what) {
  fprintf(stderr, "fuzz_film: the device film and the host film differ: %s\n", what);
  abort();
}

static void compare(clr_film dev, clr_film host) {
  if (film_sample_count(dev) != film_sample_count(host)) fail("accepted samples");
  if (film_dropped_samples(dev) != film_dropped_samples(host)) fail("dropped samples");
  if (film_outside_samples(dev) != film_outside_samples(host)) fail("outside samples");
  clr_bounds2i b = film_pixel_bounds(host);
  size_t pixels = (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0);
  double *sums = malloc(pixels * 8 * sizeof *sums);
  if (!sums) abort();
  if (film_get_sums(dev, sums, sums + 3 * pixels, NULL) != CLR_SUCCESS ||
      film_get_sums(host, sums + 4 * pixels, sums + 7 * pixels, NULL) != CLR_SUCCESS)
    fail(clr_last_error_message());
  if (memcmp(sums, sums + 4 * pixels, 4 * pixels * sizeof *sums) != 0) fail("sums");
  free(sums);
}

/* film_add_samples_buffer from a device copy of the samples (none for none). */
static clr_result add_from_buffer(clr_film film, const clr_film_sample *s, size_t n) {
  if (!n) return film_add_samples(film, s, n);
  cl_int err = CL_SUCCESS;
  cl_mem buf = clCreateBuffer(clr_context_cl_context(ctx), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              n * sizeof *s, (void *)s, &err);
  if (err != CL_SUCCESS) fail("clCreateBuffer");
  clr_result r = film_add_samples_buffer(film, buf, n);
  clReleaseMemObject(buf);
  return r;
}

/* Adds the same samples to both films; both calls succeed or fail alike. */
static void add_both(clr_film dev, clr_film host, const clr_film_sample *s, size_t n,
                     int from_buffer) {
  clr_result a = from_buffer ? add_from_buffer(dev, s, n) : film_add_samples(dev, s, n);
  fuzz_report("film_add_samples (device)", a);
  clr_result b = film_add_samples(host, s, n);
  fuzz_report("film_add_samples (host)", b);
  if (a != b) fail("one call failed");
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  ctx = fuzz_device_context("fuzz_film");
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_reader r = {data, size};
  clr_film_desc d;
  unsigned flags = 0;
  int threads = 1;
  size_t group = 0;
  float split = 0;
  read_film(&r, &d, &flags, &threads, &group, &split);
  clr_film dev = NULL, host = NULL;
  clr_result made = film_create(ctx, &d, &dev);
  fuzz_report("film_create", made);
  if (made != CLR_SUCCESS) return 0;
  if (film_create(NULL, &d, &host) != CLR_SUCCESS) fail("the host film refused the description");
  if (clr_context_set_kernel_shape(
          ctx, (flags & FLAG_PORTABLE) ? CLR_KERNELS_PORTABLE : CLR_KERNELS_SIMD) != CLR_SUCCESS ||
      film_set_bin_threads(dev, threads) != CLR_SUCCESS ||
      film_set_group_size(dev, group) != CLR_SUCCESS)
    fail(clr_last_error_message());
  size_t per = (flags & FLAG_RAW) ? sizeof(clr_film_sample) : 8, n = r.n / per;
  if (n > MAX_SAMPLES) n = MAX_SAMPLES;
  clr_film_sample *samples = malloc((n ? n : 1) * sizeof *samples);
  if (!samples) abort();
  for (size_t i = 0; i < n; ++i) {
    if (flags & FLAG_RAW) {
      memcpy(&samples[i], r.p, sizeof samples[i]);
      r.p += sizeof samples[i];
    } else {
      read_sample(&r, &d, &samples[i]);
    }
  }
  size_t first = (flags & FLAG_SPLIT) ? (size_t)(split * (float)n) : n;
  if (first > n) first = n;
  const int from_buffer = (flags & FLAG_BUFFER) != 0;
  add_both(dev, host, samples, first, from_buffer);
  if (first < n) add_both(dev, host, samples + first, n - first, from_buffer);
  compare(dev, host);
  free(samples);
  film_release(dev);
  film_release(host);
  return 0;
}
