/* Fuzz target: clrender's command line. The input is split at NUL bytes (or newlines when it
 * has no NUL) into arguments after "clrender", and goes through main's dispatch and the render,
 * samples and merge flag parsers (cli_args.c helpers included). The link wraps the calls that
 * would start work (-Wl,--wrap, see CMakeLists.txt): opening an OpenCL context and rendering
 * fail with a message, and a sampler is validated, then released, so only parsing is fuzzed. */
#include <signal.h>
#include <string.h>
#include "clrender.h"
#include "fuzz_common.h"
#include "render.h"

int clr_cli_main(int argc, char **argv); /* host/cli/main.c, built with -Dmain=clr_cli_main */

clr_result __real_clr_sampler_create(clr_context ctx, const clr_sampler_desc *desc,
                                     clr_sampler *out);
clr_result __wrap_clr_sampler_create(clr_context ctx, const clr_sampler_desc *desc,
                                     clr_sampler *out);
clr_result __wrap_clr_context_create(const clr_context_desc *desc, clr_context *out);
clr_result __wrap_clr_render_file(const char *scene_path, const clr_render_options *options,
                                  clr_render_stats *stats);

clr_result __wrap_clr_context_create(const clr_context_desc *desc, clr_context *out) {
  (void)desc;
  if (out) *out = NULL;
  return clr_set_last_error(CLR_ERROR_NO_DEVICE, "fuzz_cli: no device");
}

clr_result __wrap_clr_sampler_create(clr_context ctx, const clr_sampler_desc *desc,
                                     clr_sampler *out) {
  clr_result r = __real_clr_sampler_create(ctx, desc, out);
  if (r != CLR_SUCCESS) return r;
  clr_sampler_release(*out);
  *out = NULL;
  return clr_set_last_error(CLR_ERROR_INTERNAL, "fuzz_cli: sampler not run");
}

clr_result __wrap_clr_render_file(const char *scene_path, const clr_render_options *options,
                                  clr_render_stats *stats) {
  (void)options;
  (void)stats;
  return clr_set_last_error(CLR_ERROR_IO, "fuzz_cli: not rendering '%s'", scene_path);
}

#define MAX_ARGS 64

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = malloc(size + 1);
  if (!text) return 0;
  memcpy(text, data, size);
  text[size] = 0;
  char separator = memchr(data, 0, size) ? '\0' : '\n';
  char *argv[MAX_ARGS + 2];
  int argc = 0;
  argv[argc++] = "clrender";
  for (size_t start = 0; start < size && argc <= MAX_ARGS;) {
    char *end = memchr(text + start, separator, size - start);
    size_t n = end ? (size_t)(end - (text + start)) : size - start;
    text[start + n] = 0;
    argv[argc++] = text + start;
    start += n + 1;
  }
  argv[argc] = NULL;
  int skip = 0;
  /* `devices` only lists the machine's devices; `samples --help` exits the process. */
  if (argc > 1 && strcmp(argv[1], "devices") == 0) skip = 1;
  for (int i = 2; i < argc; ++i)
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) skip = 1;
  if (!skip) {
    /* `render` installs SIGINT/SIGTERM handlers before it starts: keep the fuzzer's own. */
    struct sigaction old_int, old_term;
    sigaction(SIGINT, NULL, &old_int);
    sigaction(SIGTERM, NULL, &old_term);
    clr_cli_main(argc, argv);
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
  }
  free(text);
  return 0;
}
