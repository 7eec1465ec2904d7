/* Fuzz target: PNG textures through clr_png_read (libpng, converted to linear RGB). */
#include "fuzz_common.h"
#include "png_io.h"

static fuzz_file input;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  int32_t width = 0, height = 0;
  float *rgb = NULL;
  clr_result r = clr_png_read(fuzz_file_write(&input, data, size), &width, &height, &rgb);
  fuzz_report("clr_png_read", r);
  if (r == CLR_SUCCESS) {
    volatile float sink = rgb[0] + rgb[(size_t)width * (size_t)height * 3 - 1];
    (void)sink;
  }
  free(rgb);
  return 0;
}
