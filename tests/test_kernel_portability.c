/* Kernel portability check: every .cl file of kernels/, with each set of build defines the host uses
 * (host/lib/sampling/sampler_device.c: every sampler family in both kernel shapes, the index-width
 * and Sobol specialisations; the film and self-test kernels), compiled by clang as OpenCL C 1.2
 * with warnings as errors for
 *   spir64                  (LLVM IR, without cl_khr_fp64; also checked for what Oclgrind and
 *                            SPIR consumers cannot run: double, calls to undefined clr_*
 *                            functions, LLVM intrinsics outside a short list of ones every
 *                            implementation handles),
 *   nvptx64-nvidia-nvcl     (PTX),
 *   amdgcn-amd-amdhsa       (gfx90a, -nogpulib; its per-kernel registers, spills and scratch
 *                            bytes are printed and written to tests/kernel-resources.jsonl in
 *                            the build tree, which clrender_bench reports; with -nogpulib the
 *                            OpenCL builtins stay calls, so these are upper bounds: each caller
 *                            gets a default 16 KiB call stack, reported apart).
 * clang comes from scripts/install-deps.sh, so a missing clang fails the test. */
#define _DEFAULT_SOURCE
#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

#ifndef CLR_CLANG
#define CLR_CLANG ""
#endif

typedef struct define_set {
  const char *file;
  const char *defines;
} define_set;

/* The build defines of every program variant the host builds. */
static const define_set sets[] = {
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=0 -DCLR_KERNELS_PORTABLE"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=1 -DCLR_KERNELS_PORTABLE"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=2 -DCLR_KERNELS_PORTABLE"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=3 -DCLR_KERNELS_PORTABLE"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=4 -DCLR_KERNELS_PORTABLE"}, /* 02sequence */
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=5 -DCLR_KERNELS_PORTABLE"}, /* maxmindist */
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=-1 -DCLR_SAMPLER_V4 -DCLR_KERNELS_PORTABLE"},
    {"sampler_kernels.cl",
     "-DCLR_SAMPLER_TYPE=-1 -DCLR_SAMPLER_V4"}, /* pbrt-v4, SIMD sobol, zsobol, paddedsobol */
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=0"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=1"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=2"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=4"}, /* 02sequence, SIMD */
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=5"}, /* maxmindist, SIMD */
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=2 -DCLR_INDEX32 -DCLR_HALTON_INDEX32"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=3 -DCLR_INDEX32"},
    {"sampler_kernels.cl", "-DCLR_SAMPLER_TYPE=3"},
    {"film_kernels.cl", ""},
    {"selftest_kernels.cl", ""},
};

typedef struct target {
  const char *name, *flags, *output;
} target;

static const target targets[] = {
    /* Without cl_khr_fp64: the kernels must not need double (devices without it run them). */
    {"spir64", "-target spir64 -Xclang -cl-ext=-cl_khr_fp64 -emit-llvm -S", "ll"},
    {"nvptx64", "-target nvptx64-nvidia-nvcl -S", "ptx"},
    {"gfx90a", "-target amdgcn-amd-amdhsa -mcpu=gfx90a -S", "s"},
};

/* LLVM intrinsics an OpenCL implementation that consumes LLVM IR (Oclgrind, SPIR drivers) can be
 * expected to handle; anything else (llvm.bitreverse, llvm.fshr, llvm.usub.sat,
 * llvm.vector.reduce.*, ...) came from an idiom in the kernel source. */
static const char *const allowed_intrinsics[] = {
    "llvm.lifetime.",
    "llvm.memcpy.",
    "llvm.memset.",
    "llvm.memmove.",
    "llvm.smax.",
    "llvm.smin.",
    "llvm.umax.",
    "llvm.umin.",
    "llvm.fabs.",
    "llvm.fmuladd.",
    "llvm.bswap.",
    "llvm.assume",
    "llvm.experimental.noalias.scope.decl",
};

static char *read_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *text = malloc((size_t)n + 1);
  if (text && fread(text, 1, (size_t)n, f) != (size_t)n) n = 0;
  if (text) text[n] = 0;
  fclose(f);
  return text;
}

static char out_dir[4096];

/* Compiles one (set, target); returns the output path (static buffer) or NULL after printing the
 * compiler's messages. */
static const char *compile(const define_set *s, const target *t, int index) {
  static char out[4300];
  char err[4300], cmd[16384];
  snprintf(out, sizeof out, "%s/%d-%s.%s", out_dir, index, t->name, t->output);
  snprintf(err, sizeof err, "%s/%d-%s.log", out_dir, index, t->name);
  snprintf(cmd, sizeof cmd,
           "'%s' -x cl -cl-std=CL1.2 -Xclang -finclude-default-header -nogpulib -O2 -Wall "
           "-Wextra -Werror -cl-fp32-correctly-rounded-divide-sqrt -DCLR_OPENCL=1 %s -I'%s' %s "
           "-o '%s' '%s/%s' > '%s' 2>&1",
           CLR_CLANG, s->defines, CLR_KERNEL_DIR, t->flags, out, CLR_KERNEL_DIR, s->file, err);
  int status = system(cmd);
  if (status != 0) {
    char *log = read_file(err);
    printf("FAIL %s %s [%s]:\n%s\n", t->name, s->file, s->defines, log ? log : "(no log)");
    free(log);
    return NULL;
  }
  return out;
}

/* Undefined clr_* functions and unexpected intrinsics in spir64 IR; returns the problems. */
static int check_ir(const char *path, const define_set *s) {
  char *ir = read_file(path);
  if (!ir) return 1;
  int problems = 0;
  if (strstr(ir, " double")) {
    printf("FAIL spir64 %s [%s]: the IR uses double\n", s->file, s->defines);
    ++problems;
  }
  for (char *line = strtok(ir, "\n"); line; line = strtok(NULL, "\n")) {
    if (strncmp(line, "declare ", 8) != 0) continue;
    char *at = strchr(line, '@');
    if (!at) continue;
    if (strncmp(at + 1, "clr_", 4) == 0) {
      printf("FAIL spir64 %s [%s]: %s is called but never defined (not inlined and not static)\n",
             s->file, s->defines, at);
      ++problems;
    } else if (strncmp(at + 1, "llvm.", 5) == 0) {
      int ok = 0;
      for (size_t i = 0; i < sizeof allowed_intrinsics / sizeof *allowed_intrinsics; ++i)
        ok |= strncmp(at + 1, allowed_intrinsics[i], strlen(allowed_intrinsics[i])) == 0;
      if (!ok) {
        printf(
            "FAIL spir64 %s [%s]: intrinsic %s (a compiler idiom not every OpenCL "
            "implementation runs)\n",
            s->file, s->defines, at);
        ++problems;
      }
    }
  }
  free(ir);
  return problems;
}

/* A "    .field: N" line's value inside [record, end), or -1. */
static long field(const char *record, const char *end, const char *key) {
  char pattern[64];
  snprintf(pattern, sizeof pattern, "\n    %s:", key);
  const char *at = strstr(record, pattern);
  if (!at || at >= end) return -1;
  return strtol(at + strlen(pattern), NULL, 10);
}

/* Per-kernel resources from the gfx90a assembly's metadata, as JSON Lines. */
static void report_gfx90a(const char *path, const define_set *s, FILE *jsonl) {
  char *text = read_file(path);
  if (!text) return;
  const char *record = strstr(text, "amdhsa.kernels:");
  while (record && (record = strstr(record, "\n  - .args:")) != NULL) {
    const char *next = strstr(record + 1, "\n  - .args:");
    const char *end = next ? next : record + strlen(record);
    char name[128] = "?";
    const char *at = strstr(record, "\n    .name:");
    if (at && at < end) sscanf(at, " .name: %127s", name);
    /* Calls left in the kernel's code: with -nogpulib the OpenCL builtins stay external, and
     * each caller gets the backend's default 16 KiB call stack in its private bytes. */
    long calls = 0;
    char label[160];
    snprintf(label, sizeof label, "\n%s:", name);
    const char *body = strstr(text, label);
    const char *body_end = body ? strstr(body, ".Lfunc_end") : NULL;
    for (const char *c = body; c && body_end && (c = strstr(c, "s_swappc_b64")) && c < body_end;
         ++c)
      ++calls;
    long priv = field(record, end, ".private_segment_fixed_size");
    long own = calls && priv >= 16384 ? priv - 16384 : priv;
    char line[1024];
    snprintf(line, sizeof line,
             "{\"target\":\"gfx90a\",\"file\":\"%s\",\"defines\":\"%s\",\"kernel\":\"%s\","
             "\"vgprs\":%ld,\"sgprs\":%ld,\"private_bytes\":%ld,\"private_bytes_own\":%ld,"
             "\"vgpr_spills\":%ld,\"sgpr_spills\":%ld,\"builtin_calls\":%ld}",
             s->file, s->defines, name, field(record, end, ".vgpr_count"),
             field(record, end, ".sgpr_count"), priv, own, field(record, end, ".vgpr_spill_count"),
             field(record, end, ".sgpr_spill_count"), calls);
    printf("%s\n", line);
    if (jsonl) fprintf(jsonl, "%s\n", line);
    record = end;
  }
  free(text);
}

static void test_every_kernel_compiles_for_every_target(void **state) {
  (void)state;
  if (!*CLR_CLANG || access(CLR_CLANG, X_OK) != 0)
    fail_msg(
        "clang was not found at configure time (\"%s\"): install clang-14 or clang-15 "
        "(scripts/install-deps.sh) and re-run cmake",
        CLR_CLANG);
  snprintf(out_dir, sizeof out_dir, "%s/tests/kernel-portability", CLR_BINARY_DIR);
  mkdir(out_dir, 0755);

  /* Every .cl in kernels/ must have a define set. */
  DIR *dir = opendir(CLR_KERNEL_DIR);
  assert_non_null(dir);
  int missing = 0;
  for (struct dirent *e; (e = readdir(dir)) != NULL;) {
    size_t n = strlen(e->d_name);
    if (n < 3 || strcmp(e->d_name + n - 3, ".cl") != 0) continue;
    int found = 0;
    for (size_t i = 0; i < sizeof sets / sizeof *sets; ++i)
      found |= strcmp(sets[i].file, e->d_name) == 0;
    if (!found) {
      printf("FAIL %s has no define set in tests/test_kernel_portability.c\n", e->d_name);
      ++missing;
    }
  }
  closedir(dir);

  char jsonl_path[4200];
  snprintf(jsonl_path, sizeof jsonl_path, "%s/tests/kernel-resources.jsonl", CLR_BINARY_DIR);
  FILE *jsonl = fopen(jsonl_path, "w");
  int failures = missing;
  for (size_t i = 0; i < sizeof sets / sizeof *sets; ++i)
    for (size_t t = 0; t < sizeof targets / sizeof *targets; ++t) {
      const char *out = compile(&sets[i], &targets[t], (int)i);
      if (!out) {
        ++failures;
        continue;
      }
      if (t == 0) failures += check_ir(out, &sets[i]);
      if (t == 2) report_gfx90a(out, &sets[i], jsonl);
    }
  if (jsonl) fclose(jsonl);
  printf("%d failure(s), compiler %s\n", failures, CLR_CLANG);
  assert_int_equal(failures, 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_kernel_compiles_for_every_target),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
