/* clrender command line: subcommand dispatch. */
#include <stdio.h>
#include <string.h>
#include "cli.h"
#include "cli_equals.h"
#include "clrender.h"

static void usage(FILE *f) {
  fprintf(f,
          "usage: clrender COMMAND [options]\n"
          "commands:\n"
          "  devices              list every OpenCL platform and device\n"
          "  render SCENE.pbrt    render a pbrt-v3 scene to EXR + PNG (clrender render --help)\n"
          "  samples              print or plot sample vectors (clrender samples --help)\n"
          "  merge                merge films written with their sums (clrender merge --help)\n"
          "  help                 this text\n"
          "  --version            print the version\n"
          "Every option takes its value as \"--name value\" or \"--name=value\".\n");
}

int main(int argc, char **argv) {
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  const char *cmd = argv[1];
  if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
    printf("clrender %s\n", clr_version());
    return 0;
  }
  int (*sub)(int, char **) = strcmp(cmd, "devices") == 0   ? cli_devices
                             : strcmp(cmd, "render") == 0  ? cli_render
                             : strcmp(cmd, "samples") == 0 ? cli_samples
                             : strcmp(cmd, "merge") == 0   ? cli_merge
                                                           : NULL;
  if (sub) {
    cli_args a;
    if (!cli_split_equals(argc - 1, argv + 1, &a)) {
      fprintf(stderr, "clrender: out of memory\n");
      return 1;
    }
    int status = sub(a.argc, a.argv);
    cli_args_free(&a);
    return status;
  }
  if (strcmp(cmd, "help") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
    usage(stdout);
    return 0;
  }
  fprintf(stderr, "clrender: unknown command \"%s\"\n", cmd);
  usage(stderr);
  return 2;
}
