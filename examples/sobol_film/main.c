/* A standalone clrender program: Sobol sample positions from the sampler kernels, a constant
 * radiance at each, reconstructed by film_add_samples() with pbrt's Mitchell filter and written
 * as OpenEXR. Usage: sobol_film [OUTPUT.exr] */
#include <clrender.h>
#include <stdio.h>
#include <stdlib.h>

#define CHECK(call)                                                         \
  do {                                                                      \
    clr_result r_ = (call);                                                 \
    if (r_ != CLR_SUCCESS) {                                                \
      fprintf(stderr, "%s failed: %s (%s)\n", #call, clr_result_string(r_), \
              clr_last_error_message());                                    \
      exit(1);                                                              \
    }                                                                       \
  } while (0)

int main(int argc, char **argv) {
  const char *path = argc > 1 ? argv[1] : "sobol_film.exr";
  printf("clrender %s (headers %s)\n", clr_version(), CLR_VERSION_STRING);

  clr_context_desc context_desc;
  clr_context_desc_init(&context_desc);
  clr_context ctx;
  CHECK(clr_context_create(&context_desc, &ctx));
  printf("device: %s\n", clr_context_device_name(ctx));

  clr_film_desc film_desc;
  clr_film_desc_init(&film_desc);
  film_desc.x_resolution = 64;
  film_desc.y_resolution = 48;
  clr_filter_desc_init(&film_desc.filter, CLR_FILTER_MITCHELL);
  clr_film film;
  CHECK(film_create(ctx, &film_desc, &film));

  /* The sampler takes its resolution, crop and filter radius from the film. */
  clr_sampler_desc sampler_desc;
  clr_sampler_desc_init(&sampler_desc, CLR_SAMPLER_SOBOL);
  sampler_desc.pixel_samples = 16;
  CHECK(film_get_geometry(film, &sampler_desc.film));
  clr_sampler sampler;
  CHECK(clr_sampler_create(ctx, &sampler_desc, &sampler));

  /* One request: the 2D film offset of each sample, over the film's sample bounds. */
  const clr_sample_request film_offset = {2, 0};
  clr_bounds2i bounds = clr_sampler_sample_bounds(sampler);
  int32_t width = bounds.x1 - bounds.x0, height = bounds.y1 - bounds.y0;
  int32_t spp = clr_sampler_spp(sampler);
  size_t count = (size_t)width * (size_t)height * (size_t)spp;
  float *offsets = malloc(count * 2 * sizeof *offsets);
  clr_film_sample *samples = malloc(count * sizeof *samples);
  if (!offsets || !samples) return 1;
  clr_sample_batch batch;
  clr_sample_batch_init(&batch);
  batch.pixels = bounds;
  batch.requests = &film_offset;
  batch.request_count = 1;
  clr_sample_output output;
  clr_sample_output_init(&output);
  output.host_values = offsets;
  CHECK(clr_sampler_generate(sampler, &batch, &output));

  size_t i = 0;
  for (int32_t y = bounds.y0; y < bounds.y1; ++y)
    for (int32_t x = bounds.x0; x < bounds.x1; ++x)
      for (int32_t s = 0; s < spp; ++s, ++i)
        samples[i] = (clr_film_sample){
            (float)x + offsets[2 * i], (float)y + offsets[2 * i + 1], 0.5f, 0.25f, 0.125f, 1.0f};
  CHECK(film_add_samples(film, samples, count));

  /* A constant radiance reconstructs to itself: print the image's mean to show it. */
  size_t pixels = (size_t)film_desc.x_resolution * (size_t)film_desc.y_resolution;
  float *rgb = malloc(pixels * 3 * sizeof *rgb);
  if (!rgb) return 1;
  CHECK(film_get_rgb(film, rgb, 1.0f));
  double mean[3] = {0, 0, 0};
  for (size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) mean[c] += rgb[3 * p + c] / (double)pixels;
  printf("samples: %llu, mean RGB: %.6f %.6f %.6f\n", (unsigned long long)film_sample_count(film),
         mean[0], mean[1], mean[2]);

  clr_film_write_options options;
  clr_film_write_options_init(&options);
  options.sampler = "sobol";
  options.spp = spp;
  CHECK(film_write(film, path, &options));
  printf("wrote %s\n", path);

  free(rgb);
  free(samples);
  free(offsets);
  clr_sampler_release(sampler);
  film_release(film);
  clr_context_release(ctx);
  return 0;
}
