/* Fuzz target: EXR files through clr_exr_read and its accessors, then `clrender merge` of the
 * file (film_merge_files: clrender film metadata, sum channels, crop windows) on the default
 * OpenCL device, writing the merged film to a scratch file that is removed. */
#include <string.h>
#include "clrender.h"
#include "exr_io.h"
#include "fuzz_common.h"

static fuzz_file input;
static clr_context context;
static char merged[1024];

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  clr_context_desc cd;
  clr_context_desc_init(&cd);
  if (clr_context_create(&cd, &context) != CLR_SUCCESS) {
    fprintf(stderr, "fuzz_exr: no OpenCL device for the merge: %s\n", clr_last_error_message());
    abort();
  }
  snprintf(merged, sizeof merged, "%s/clr-fuzz-merged-%d.exr", CLR_FUZZ_WORK_DIR, (int)getpid());
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = fuzz_file_write(&input, data, size);
  clr_exr_image *image = NULL;
  clr_result r = clr_exr_read(path, &image);
  fuzz_report("clr_exr_read", r);
  if (r != CLR_SUCCESS) return 0;
  volatile float sink = 0.0f;
  size_t pixels = (size_t)image->width * (size_t)image->height;
  for (int32_t c = 0; c < image->channel_count; ++c) {
    const float *plane = clr_exr_image_channel(image, image->channel_names[c]);
    if (plane && pixels) sink += plane[0] + plane[pixels - 1];
  }
  for (int32_t a = 0; a < image->attr_count; ++a) {
    float f;
    int32_t i;
    const char *s = clr_exr_image_string_attr(image, image->attrs[a].name);
    if (s) sink += (float)strlen(s);
    if (clr_exr_image_float_attr(image, image->attrs[a].name, &f)) sink += f;
    if (clr_exr_image_int_attr(image, image->attrs[a].name, &i)) sink += (float)i;
  }
  (void)sink;
  /* Only files with clrender's film metadata get past the merge's first checks. */
  int film = clr_exr_image_string_attr(image, "clrender.filter") != NULL;
  clr_exr_image_free(image);
  if (film) {
    const char *paths[1] = {path};
    fuzz_report("film_merge_files", film_merge_files(context, paths, 1, merged));
    unlink(merged);
  }
  return 0;
}
