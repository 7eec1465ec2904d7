#define _POSIX_C_SOURCE 200809L
/* pbrt users write `--spp=4` as often as `--spp 4`: every "--flag=value" argument is split
 * into "--flag" "value" before a subcommand parses its arguments. */
#include <stdlib.h>
#include <string.h>
#include "cli_equals.h"

int cli_split_equals(int argc, char **argv, cli_args *out) {
  memset(out, 0, sizeof *out);
  out->argv = calloc((size_t)argc * 2 + 1, sizeof *out->argv);
  out->owned = calloc((size_t)argc + 1, sizeof *out->owned);
  if (!out->argv || !out->owned) {
    cli_args_free(out);
    return 0;
  }
  int n = 0;
  for (int i = 0; i < argc; ++i) {
    const char *a = argv[i], *eq = strchr(a, '=');
    if (i > 0 && a[0] == '-' && a[1] == '-' && eq && eq > a + 2) {
      char *copy = strdup(a); /* "--flag\0value" */
      if (!copy) {
        cli_args_free(out);
        return 0;
      }
      out->owned[out->owned_count++] = copy;
      copy[eq - a] = 0;
      out->argv[n++] = copy;
      out->argv[n++] = copy + (eq - a) + 1;
    } else {
      out->argv[n++] = argv[i];
    }
  }
  out->argc = n;
  return 1;
}

void cli_args_free(cli_args *a) {
  for (int i = 0; a->owned && i < a->owned_count; ++i) free(a->owned[i]);
  free(a->owned);
  free(a->argv);
  memset(a, 0, sizeof *a);
}
