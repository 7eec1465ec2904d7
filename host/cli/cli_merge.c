/* `clrender merge A.exr B.exr ... -o OUT.exr`: sums films written with their sum channels. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "clrender.h"

static void merge_usage(FILE *f) {
  fprintf(f,
          "usage: clrender merge A.exr B.exr ... -o OUT.exr [--device D]\n"
          "Merges films rendered with their sums (crop windows of one frame, or independent\n"
          "sample passes of the same frame) into the image a single render would produce.\n"
          "Resolutions, filters and scales must match. Writes OUT.exr (with the sums, so it\n"
          "can be merged again) and its PNG preview OUT.png, and says so on stderr.\n");
}

int cli_merge(int argc, char **argv) {
  const char **inputs = calloc((size_t)argc + 1, sizeof *inputs);
  const char *out = NULL, *device = NULL;
  int n = 0;
  if (!inputs) return 1;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
      merge_usage(stdout);
      free(inputs);
      return 0;
    } else if ((strcmp(argv[i], "-o") == 0 || strcmp(argv[i], "--output") == 0) && i + 1 < argc) {
      out = argv[++i];
    } else if (strcmp(argv[i], "--device") == 0 && i + 1 < argc) {
      device = argv[++i];
    } else if (argv[i][0] == '-') {
      fprintf(stderr, "clrender merge: unknown or incomplete option \"%s\"\n", argv[i]);
      merge_usage(stderr);
      free(inputs);
      return 2;
    } else {
      inputs[n++] = argv[i];
    }
  }
  if (!out || n < 1) {
    fprintf(stderr, "clrender merge: %s\n", !out ? "-o OUT.exr is required" : "no input films");
    merge_usage(stderr);
    free(inputs);
    return 2;
  }
  clr_context_desc cd;
  clr_context_desc_init(&cd);
  cd.device = device;
  clr_context ctx = NULL;
  int status = 0;
  if (clr_context_create(&cd, &ctx) != CLR_SUCCESS ||
      film_merge_files(ctx, inputs, n, out) != CLR_SUCCESS) {
    fprintf(stderr, "clrender merge: %s\n", clr_last_error_message());
    status = 1;
  } else {
    /* the PNG preview beside it, as `clrender render` writes one */
    char png[4096];
    size_t len = strlen(out);
    int exr = len > 4 && (strcmp(out + len - 4, ".exr") == 0 || strcmp(out + len - 4, ".EXR") == 0);
    snprintf(png, sizeof png, "%.*s.png", (int)(exr ? len - 4 : len), out);
    clr_image im;
    if (clr_image_read(out, &im) != CLR_SUCCESS || clr_image_write_png(png, &im) != CLR_SUCCESS) {
      fprintf(stderr, "clrender merge: wrote %s; PNG preview: %s\n", out, clr_last_error_message());
      status = 1;
    } else {
      fprintf(stderr, "clrender merge: wrote %s and %s (%d films, %dx%d)\n", out, png, n,
              (int)im.width, (int)im.height);
    }
    clr_image_free(&im);
  }
  clr_context_release(ctx);
  free(inputs);
  return status;
}
