/* clrender command line: subcommand dispatch. */
#include <stdio.h>
#include <string.h>
#include "cli.h"

static void usage(FILE *f) {
  fprintf(f,
          "usage: clrender COMMAND [options]\n"
          "commands:\n"
          "  devices              list every OpenCL platform and device\n"
          "  render SCENE.pbrt    render a pbrt-v3 scene to EXR + PNG (clrender render --help)\n"
          "  samples              print or plot sample vectors (clrender samples --help)\n"
          "  merge                merge films written with their sums (clrender merge --help)\n"
          "  help                 this text\n");
}

int main(int argc, char **argv) {
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  const char *cmd = argv[1];
  if (strcmp(cmd, "devices") == 0) return cli_devices(argc - 1, argv + 1);
  if (strcmp(cmd, "render") == 0) return cli_render(argc - 1, argv + 1);
  if (strcmp(cmd, "samples") == 0) return cli_samples(argc - 1, argv + 1);
  if (strcmp(cmd, "merge") == 0) return cli_merge(argc - 1, argv + 1);
  if (strcmp(cmd, "help") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
    usage(stdout);
    return 0;
  }
  fprintf(stderr, "clrender: unknown command \"%s\"\n", cmd);
  usage(stderr);
  return 2;
}
