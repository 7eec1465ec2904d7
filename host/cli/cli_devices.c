/* `clrender devices`: every OpenCL platform and device, with the index --device accepts. */
#include <stdio.h>
#include <string.h>
#include "cli.h"
#include "clrender.h"

static void devices_usage(FILE *f) {
  fprintf(f,
          "usage: clrender devices [--help]\n"
          "Lists every OpenCL platform and device with the index --device accepts; * marks\n"
          "the default device (the CLRENDER_DEVICE environment variable, else the first GPU,\n"
          "else the first device). Exit status: 0 ok, 1 no OpenCL platform, 2 usage error.\n");
}

int cli_devices(int argc, char **argv) {
  if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
    devices_usage(stdout);
    return 0;
  }
  if (argc > 1) {
    fprintf(stderr, "clrender devices: unknown option \"%s\"\n", argv[1]);
    devices_usage(stderr);
    return 2;
  }
  clr_device_info infos[64];
  int count = 0;
  clr_result r = clr_device_list(infos, 64, &count);
  if (r != CLR_SUCCESS) {
    fprintf(stderr, "clrender: %s\n", clr_last_error_message());
    return 1;
  }
  clr_context ctx = NULL;
  int chosen = -1;
  if (clr_context_create(NULL, &ctx) == CLR_SUCCESS) {
    for (int i = 0; i < count && i < 64; ++i) {
      char full[300];
      snprintf(full, sizeof full, "%s: %s", infos[i].platform_name, infos[i].device_name);
      if (strcmp(full, clr_context_device_name(ctx)) == 0) chosen = i;
    }
    clr_context_release(ctx);
  }
  for (int i = 0; i < count && i < 64; ++i) {
    /* The kernel shape a context on this device uses (or why it cannot be used). */
    char index[16], shape[160];
    snprintf(index, sizeof index, "%d", i);
    clr_context_desc cd;
    clr_context_desc_init(&cd);
    cd.device = index;
    clr_context dc = NULL;
    if (clr_context_create(&cd, &dc) == CLR_SUCCESS)
      snprintf(shape, sizeof shape, "kernels %s",
               clr_kernel_shape_name(clr_context_kernel_shape(dc)));
    else
      snprintf(shape, sizeof shape, "unusable: %s", clr_last_error_message());
    clr_context_release(dc);
    printf("%c %d  %s: %s  [%s, %u compute units, %.1f GiB, %s, driver %s, %s]\n",
           i == chosen ? '*' : ' ', infos[i].index, infos[i].platform_name, infos[i].device_name,
           infos[i].is_gpu ? "GPU" : "CPU", infos[i].compute_units,
           (double)infos[i].global_memory_bytes / (1024.0 * 1024.0 * 1024.0),
           infos[i].device_version, infos[i].driver_version, shape);
  }
  printf("(* = default; choose with --device INDEX|NAME or CLRENDER_DEVICE)\n");
  return 0;
}
