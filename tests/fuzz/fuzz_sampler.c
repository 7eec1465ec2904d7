/* Fuzz target, differential: clr_sampler_generate on the default OpenCL device (PoCL: the SIMD or
 * the portable kernels) must write the same values and global indices, bit for bit, as
 * clr_sampler_generate_reference (the kernels' C build) for any sampler, seeding, randomization,
 * film geometry, request layout (1D, 2D, arrays, skipped requests) and batch (a pixel rectangle
 * inside the sample bounds, a sample range); both succeed or fail alike. A difference aborts, so
 * libFuzzer reports it with the input. Layout of an input: 20 header bytes (read_sampler,
 * read_batch), then one byte per request (read_requests). */
#include <math.h>
#include "clrender.h"
#include "fuzz_common.h"

#define MAX_REQUESTS 12
#define MAX_VALUES (1u << 18) /* floats per batch, to keep an input fast */

static clr_context ctx;

static void fail(const char *what) {
  fprintf(stderr, "fuzz_sampler: the device and the host reference differ: %s\n", what);
  abort();
}

/* The sampler from 12 bytes; *portable gets the kernel shape. */
static void read_sampler(fuzz_reader *r, clr_sampler_desc *d, int *portable) {
  uint8_t type = fuzz_next(r), mode = fuzz_next(r);
  clr_sampler_desc_init(d, (clr_sampler_type)(type % CLR_SAMPLER_TYPE_COUNT));
  d->seeding = (clr_seeding)(mode % 3);
  d->randomization = (clr_randomization)(((mode >> 2) & 7) % 5);
  d->jitter = (mode >> 5) & 1;
  d->sample_pixel_center = (mode >> 6) & 1;
  *portable = mode >> 7;
  d->pixel_samples = 1 + fuzz_next(r) % 64;
  d->x_samples = 1 + fuzz_next(r) % 8;
  d->y_samples = 1 + fuzz_next(r) % 8;
  d->dimensions = 1 + fuzz_next(r) % 12;
  d->seed = (uint32_t)fuzz_next(r) * 0x9e3779b9u;
  d->film.x_resolution = 1 + fuzz_next(r) % 24;
  d->film.y_resolution = 1 + fuzz_next(r) % 24;
  uint8_t crop = fuzz_next(r);
  d->film.crop_window[0] = (float)(crop & 3) / 8.0f;
  d->film.crop_window[1] = 1.0f - (float)((crop >> 2) & 3) / 8.0f;
  d->film.crop_window[2] = (float)((crop >> 4) & 3) / 8.0f;
  d->film.crop_window[3] = 1.0f - (float)(crop >> 6) / 8.0f;
  d->film.filter_radius[0] = (float)(1 + fuzz_next(r) % 32) / 8.0f;
  d->film.filter_radius[1] = (float)(1 + fuzz_next(r) % 32) / 8.0f;
}

/* A pixel rectangle inside the sample bounds and a sample range, from 8 bytes. */
static void read_batch(fuzz_reader *r, clr_sampler sampler, clr_sample_batch *b) {
  clr_bounds2i s = clr_sampler_sample_bounds(sampler);
  int32_t w = s.x1 - s.x0, h = s.y1 - s.y0, spp = clr_sampler_spp(sampler);
  clr_sample_batch_init(b);
  b->pixels.x0 = s.x0 + fuzz_next(r) % w;
  b->pixels.y0 = s.y0 + fuzz_next(r) % h;
  b->pixels.x1 = b->pixels.x0 + 1 + fuzz_next(r) % (s.x1 - b->pixels.x0);
  b->pixels.y1 = b->pixels.y0 + 1 + fuzz_next(r) % (s.y1 - b->pixels.y0);
  b->first_sample = fuzz_next(r) % spp;
  b->sample_count = 1 + fuzz_next(r) % (spp - b->first_sample);
  if (fuzz_next(r) & 1) { /* often the whole pixel */
    b->first_sample = 0;
    b->sample_count = 0;
  }
  (void)fuzz_next(r);
}

/* The camera's film offset, then one request per byte: 1D or 2D, one value or an array of up to
 * 7, sometimes skipped. */
static int32_t read_requests(fuzz_reader *r, clr_sample_request *q) {
  int32_t n = 1;
  q[0] = (clr_sample_request){2, 0};
  while (r->n && n < MAX_REQUESTS) {
    uint8_t v = fuzz_next(r);
    q[n].dims = 1 + (v & 1);
    q[n].array_size = (v >> 1) & 7;
    if (((v >> 4) & 3) == 3 && !q[n].array_size) q[n].dims |= CLR_SAMPLE_REQUEST_SKIPPED;
    ++n;
  }
  return n;
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  ctx = fuzz_device_context("fuzz_sampler");
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_reader r = {data, size};
  clr_sampler_desc d;
  int portable = 0;
  read_sampler(&r, &d, &portable);
  uint8_t batch_bytes[8];
  for (int i = 0; i < 8; ++i) batch_bytes[i] = fuzz_next(&r);
  clr_sample_request q[MAX_REQUESTS];
  int32_t nq = read_requests(&r, q);
  clr_sampler sampler = NULL;
  clr_result made = clr_sampler_create(ctx, &d, &sampler);
  fuzz_report("clr_sampler_create", made);
  if (made != CLR_SUCCESS) return 0;
  if (clr_context_set_kernel_shape(ctx, portable ? CLR_KERNELS_PORTABLE : CLR_KERNELS_SIMD) !=
      CLR_SUCCESS)
    fail(clr_last_error_message());
  fuzz_reader br = {batch_bytes, sizeof batch_bytes};
  clr_sample_batch b;
  read_batch(&br, sampler, &b);
  b.requests = q;
  b.request_count = nq;
  int32_t per = 0;
  clr_result laid = clr_sample_layout_values(q, nq, &per);
  fuzz_report("clr_sample_layout_values", laid);
  size_t pixels = (size_t)(b.pixels.x1 - b.pixels.x0) * (size_t)(b.pixels.y1 - b.pixels.y0);
  size_t samples = pixels * (size_t)(b.sample_count ? b.sample_count : clr_sampler_spp(sampler));
  size_t values = samples * (size_t)(per > 0 ? per : 1);
  if (laid != CLR_SUCCESS || values > MAX_VALUES) {
    clr_sampler_release(sampler);
    return 0;
  }
  float *v = malloc(2 * values * sizeof *v);
  uint64_t *ix = malloc(2 * samples * sizeof *ix);
  if (!v || !ix) abort();
  memset(v, 0, 2 * values * sizeof *v);
  memset(ix, 0, 2 * samples * sizeof *ix);
  const int indices = clr_sampler_has_global_index(sampler);
  clr_sample_output dev, ref;
  clr_sample_output_init(&dev);
  clr_sample_output_init(&ref);
  dev.host_values = v;
  ref.host_values = v + values;
  dev.host_indices = indices ? ix : NULL;
  ref.host_indices = indices ? ix + samples : NULL;
  clr_result a = clr_sampler_generate(sampler, &b, &dev);
  fuzz_report("clr_sampler_generate", a);
  clr_result c = clr_sampler_generate_reference(sampler, &b, &ref);
  fuzz_report("clr_sampler_generate_reference", c);
  if (a != c) fail("one call failed");
  if (a == CLR_SUCCESS) {
    if (memcmp(v, v + values, values * sizeof *v) != 0) fail("values");
    if (indices && memcmp(ix, ix + samples, samples * sizeof *ix) != 0) fail("global indices");
  }
  free(v);
  free(ix);
  clr_sampler_release(sampler);
  return 0;
}
