/* Shared helpers of the hardening tests (test_bad_input.c, test_faults.c, test_hardening.c):
 * work directories inside the build tree, running the CLI with its stderr captured, directory
 * snapshots (to prove nothing was written and nothing existing changed), and forged files. */
#ifndef CLR_TEST_HARDENING_UTIL_H
#define CLR_TEST_HARDENING_UTIL_H

/* Paths here are short (inside the build tree); truncation would only fail a test. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wformat-truncation"
#endif

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

/* Runs `cmd` through the shell (for setup only: rm -rf of our own work directories). */
/* In a forked child before exec: load tests/fault_preload.c so the CLI stops itself (SIGSTOP)
 * when its temporary output is complete, before the rename. */
static inline void hu_stop_before_commit(void) {
  setenv("LD_PRELOAD", CLR_FAULT_PRELOAD, 1);
  setenv("CLR_FAULT_STOP_BEFORE_COMMIT", "1", 1);
  /* Under AddressSanitizer the shim precedes the ASan runtime in the library list. */
  const char *asan = getenv("ASAN_OPTIONS");
  char options[1024];
  snprintf(options, sizeof options, "%s%sverify_asan_link_order=0", asan ? asan : "",
           asan && *asan ? ":" : "");
  setenv("ASAN_OPTIONS", options, 1);
}

static inline void hu_sh(const char *fmt, const char *arg) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, fmt, arg);
  if (system(cmd) != 0) fprintf(stderr, "warning: '%s' failed\n", cmd);
}

/* A fresh empty directory CLR_BINARY_DIR/hardening/<name>; returns its path (static buffer
 * per slot, so two may be held at once). */
static inline const char *hu_workdir(const char *name, int slot) {
  static char paths[4][512];
  char *p = paths[slot & 3];
  snprintf(p, 512, "%s/hardening/%s", CLR_BINARY_DIR, name);
  hu_sh("rm -rf '%s'", p);
  char parent[512];
  snprintf(parent, sizeof parent, "%s/hardening", CLR_BINARY_DIR);
  mkdir(parent, 0777);
  if (mkdir(p, 0777) != 0) fprintf(stderr, "mkdir %s: %s\n", p, strerror(errno));
  return p;
}

static inline int hu_write_file(const char *path, const void *data, size_t size) {
  FILE *f = fopen(path, "wb");
  if (!f) return 0;
  size_t n = fwrite(data, 1, size, f);
  return fclose(f) == 0 && n == size;
}

/* Whole file (NUL-terminated, *size without the NUL), or NULL. */
static inline char *hu_read_file(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t cap = 4096, n = 0;
  char *buf = malloc(cap + 1);
  for (size_t got; buf && (got = fread(buf + n, 1, cap - n, f)) > 0;) {
    n += got;
    if (n == cap) {
      char *grown = realloc(buf, 2 * cap + 1);
      if (!grown) {
        free(buf);
        buf = NULL;
        break;
      }
      buf = grown;
      cap *= 2;
    }
  }
  fclose(f);
  if (!buf) return NULL;
  buf[n] = 0;
  if (size) *size = n;
  return buf;
}

/* Names, types, sizes, modes, mtimes and content hashes (files up to 16 MiB) of a directory's
 * entries (sorted), as
 * one string (free() it): equal snapshots mean nothing was added, removed or changed. */
static inline int hu_cmp_names(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}
static inline char *hu_snapshot(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return strdup("(no directory)");
  char *names[256];
  int n = 0;
  for (struct dirent *e; (e = readdir(d)) != NULL && n < 256;)
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) names[n++] = strdup(e->d_name);
  closedir(d);
  qsort(names, (size_t)n, sizeof names[0], hu_cmp_names);
  size_t cap = 256 + (size_t)n * 600;
  char *out = malloc(cap);
  size_t len = 0;
  out[0] = 0;
  for (int i = 0; i < n; ++i) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    struct stat st;
    uint64_t hash = 1469598103934665603ull;
    if (lstat(path, &st) != 0) memset(&st, 0, sizeof st);
    if (S_ISREG(st.st_mode) && st.st_size <= (16 << 20)) { /* big (sparse) fixtures: size only */
      size_t size = 0;
      char *data = hu_read_file(path, &size);
      for (size_t k = 0; data && k < size; ++k)
        hash = (hash ^ (unsigned char)data[k]) * 1099511628211ull;
      free(data);
    }
    len += (size_t)snprintf(
        out + len, cap - len, "%s mode=%o size=%lld mtime=%lld.%09ld hash=%016llx\n", names[i],
        (unsigned)st.st_mode, (long long)st.st_size, (long long)st.st_mtim.tv_sec,
        (long)st.st_mtim.tv_nsec, (unsigned long long)hash);
    free(names[i]);
  }
  return out;
}

/* Runs the CLI with argv (NULL-terminated) in directory `cwd`, stderr to `err_path`; returns
 * the exit status, 128 + signal when killed, or -1. */
static inline int hu_run_cli(const char *cwd, char *const argv[], const char *err_path) {
  pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    if (cwd && chdir(cwd) != 0) _exit(126);
    int err = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int null = open("/dev/null", O_RDWR);
    if (err < 0 || null < 0) _exit(126);
    dup2(null, 0);
    dup2(null, 1);
    dup2(err, 2);
    execv(CLR_CLI_PATH, argv);
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

/* ---- forged files ---- */

static inline uint32_t hu_crc32(const unsigned char *p, size_t n) {
  uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

static inline void hu_be32(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16);
  p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}

/* A 64-byte PNG whose IHDR declares width x height (8-bit RGB) with a tiny IDAT and IEND. */
static inline size_t hu_forged_png(unsigned char out[64], uint32_t width, uint32_t height) {
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  size_t n = 0;
  memcpy(out, sig, 8);
  n = 8;
  unsigned char *ihdr = out + n;
  hu_be32(ihdr, 13);
  memcpy(ihdr + 4, "IHDR", 4);
  hu_be32(ihdr + 8, width);
  hu_be32(ihdr + 12, height);
  ihdr[16] = 8, ihdr[17] = 2, ihdr[18] = 0, ihdr[19] = 0, ihdr[20] = 0;
  hu_be32(ihdr + 21, hu_crc32(ihdr + 4, 17));
  n += 25;
  unsigned char *idat = out + n; /* a zlib stream holding one empty stored block */
  static const unsigned char z[7] = {0x78, 0x01, 0x01, 0x00, 0x00, 0xff, 0xff};
  hu_be32(idat, 7);
  memcpy(idat + 4, "IDAT", 4);
  memcpy(idat + 8, z, 7);
  hu_be32(idat + 15, hu_crc32(idat + 4, 11));
  n += 19;
  unsigned char *iend = out + n;
  hu_be32(iend, 0);
  memcpy(iend + 4, "IEND", 4);
  hu_be32(iend + 8, hu_crc32(iend + 4, 4));
  n += 12;
  return n;
}

#ifdef CLR_EXR_IO_H
/* A small valid EXR (4x4 R, G, B, no clrender metadata) at `path`; with `forge`, its data window
 * is then patched to 1000000 x 1000000 pixels (the file stays a few hundred bytes). */
static inline int hu_small_exr(const char *path, int forge) {
  float plane[16];
  for (int i = 0; i < 16; ++i) plane[i] = 0.25f * (float)i;
  clr_exr_channel ch[3] = {{"R", plane, 0}, {"G", plane, 0}, {"B", plane, 0}};
  if (clr_exr_write(path, 4, 4, (clr_bounds2i){0, 0, 4, 4}, ch, 3, NULL, 0) != CLR_SUCCESS)
    return 0;
  if (!forge) return 1;
  size_t size = 0;
  char *data = hu_read_file(path, &size);
  if (!data) return 0;
  static const char key[] = "dataWindow\0box2i";
  int ok = 0;
  for (size_t i = 0; i + sizeof key + 4 + 16 <= size; ++i)
    if (memcmp(data + i, key, sizeof key) == 0) {
      unsigned char *box = (unsigned char *)data + i + sizeof key + 4; /* after the size */
      int32_t v[4] = {0, 0, 999999, 999999};
      for (int k = 0; k < 4; ++k)
        for (int b = 0; b < 4; ++b) box[4 * k + b] = (unsigned char)((uint32_t)v[k] >> (8 * b));
      ok = 1;
      break;
    }
  ok = ok && hu_write_file(path, data, size);
  free(data);
  return ok;
}
#endif

#endif
