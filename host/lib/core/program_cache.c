/* Program binary cache: one file per (device, implementation, version, program, options, source),
 * "CLRPBIN1", identity length and text, binary length and bytes, FNV-1a checksum of all before. */
#define _GNU_SOURCE /* openat, renameat, O_DIRECTORY */
#include "program_cache.h"
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "clrender/version.h"

#define CACHE_MAGIC "CLRPBIN1"
#define CACHE_MAX_BINARY ((uint64_t)256 << 20) /* larger files are not ours: ignored */

static uint64_t fnv1a(uint64_t h, const void *data, size_t n) {
  const unsigned char *p = data;
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

#define FNV_BASIS 0xcbf29ce484222325ull

/* A second, independent hash of the source (64-bit multiply-xorshift over 8-byte words). */
static uint64_t mix_hash(const char *s, size_t n) {
  uint64_t h = 0x9E3779B97F4A7C15ull ^ n;
  for (size_t i = 0; i < n; i += 8) {
    uint64_t w = 0;
    memcpy(&w, s + i, n - i < 8 ? n - i : 8);
    h = (h ^ w) * 0xff51afd7ed558ccdull;
    h ^= h >> 32;
  }
  return h;
}

static int cache_off(void) {
  const char *v = getenv("CLRENDER_PROGRAM_CACHE");
  return v && (!strcmp(v, "0") || !strcmp(v, "off") || !strcmp(v, "no"));
}

int clr_program_cache_dir(char *out, size_t size) {
  if (cache_off()) return 0;
  const char *dir = getenv("CLRENDER_CACHE_DIR"), *xdg = getenv("XDG_CACHE_HOME");
  const char *home = getenv("HOME");
  int n = -1;
  if (dir && dir[0] == '/')
    n = snprintf(out, size, "%s", dir);
  else if (xdg && xdg[0] == '/') /* the XDG spec ignores relative paths */
    n = snprintf(out, size, "%s/clrender", xdg);
  else if (home && home[0] == '/')
    n = snprintf(out, size, "%s/.cache/clrender", home);
  return n > 0 && (size_t)n < size;
}

static void device_string(cl_device_id d, cl_device_info what, char *out, size_t size) {
  if (clGetDeviceInfo(d, what, size - 1, out, NULL) != CL_SUCCESS) out[0] = 0;
  out[size - 1] = 0;
}

void clr_program_key_make(clr_program_key *key, cl_platform_id platform, cl_device_id device,
                          const char *program_name, const char *source, size_t length,
                          const char *options) {
  char pname[256] = "", pver[256] = "", dname[256] = "", dver[256] = "", drv[256] = "";
  if (clGetPlatformInfo(platform, CL_PLATFORM_NAME, sizeof pname - 1, pname, NULL) != CL_SUCCESS)
    pname[0] = 0;
  if (clGetPlatformInfo(platform, CL_PLATFORM_VERSION, sizeof pver - 1, pver, NULL) != CL_SUCCESS)
    pver[0] = 0;
  device_string(device, CL_DEVICE_NAME, dname, sizeof dname);
  device_string(device, CL_DEVICE_VERSION, dver, sizeof dver);
  device_string(device, CL_DRIVER_VERSION, drv, sizeof drv);
  snprintf(key->identity, sizeof key->identity,
           "clrender %s\nplatform %s\nplatform version %s\ndevice %s\ndevice version %s\n"
           "driver %s\nprogram %s\noptions %s\nsource %zu %016llx %016llx\n",
           CLR_VERSION_STRING, pname, pver, dname, dver, drv, program_name, options, length,
           (unsigned long long)fnv1a(FNV_BASIS, source, length),
           (unsigned long long)mix_hash(source, length));
  uint64_t h = fnv1a(FNV_BASIS, key->identity, strlen(key->identity));
  snprintf(key->file_name, sizeof key->file_name, "p-%016llx.bin", (unsigned long long)h);
}

/* The folder, if it is a directory of this user that nobody else may write. */
static int open_dir(int create) {
  char dir[4096];
  if (!clr_program_cache_dir(dir, sizeof dir)) return -1;
  if (create && mkdir(dir, 0700) != 0 && errno == ENOENT) { /* ~/.cache missing: one level up */
    char *slash = strrchr(dir, '/');
    if (slash && slash != dir) {
      *slash = 0;
      mkdir(dir, 0700);
      *slash = '/';
      mkdir(dir, 0700);
    }
  }
  int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  struct stat st;
  if (fd >= 0 && (fstat(fd, &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != geteuid() ||
                  (st.st_mode & (S_IWGRP | S_IWOTH)))) {
    close(fd);
    fd = -1;
  }
  return fd;
}

static int read_all(int fd, void *buf, size_t n) {
  char *p = buf;
  while (n) {
    ssize_t got = read(fd, p, n);
    if (got <= 0) return 0;
    p += got;
    n -= (size_t)got;
  }
  return 1;
}

static int write_all(int fd, const void *buf, size_t n) {
  const char *p = buf;
  while (n) {
    ssize_t put = write(fd, p, n);
    if (put <= 0) return 0;
    p += put;
    n -= (size_t)put;
  }
  return 1;
}

/* The cached binary of `key` (malloc'd), checked against the identity and checksum, or NULL. */
static unsigned char *read_binary(const clr_program_key *key, size_t *size) {
  int dir = open_dir(0);
  if (dir < 0) return NULL;
  int fd = openat(dir, key->file_name, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  close(dir);
  if (fd < 0) return NULL;
  unsigned char *data = NULL;
  struct stat st;
  size_t id_len = strlen(key->identity);
  size_t head = 8 + 8 + id_len + 8;
  if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == geteuid() &&
      (uint64_t)st.st_size > head + 8 && (uint64_t)st.st_size <= head + 8 + CACHE_MAX_BINARY) {
    size_t total = (size_t)st.st_size;
    data = malloc(total);
    uint64_t stored_id = 0, bin = 0, sum = 0;
    if (data && read_all(fd, data, total)) {
      memcpy(&stored_id, data + 8, 8);
      memcpy(&bin, data + head - 8, 8);
      memcpy(&sum, data + total - 8, 8);
    }
    if (!data || memcmp(data, CACHE_MAGIC, 8) != 0 || stored_id != id_len ||
        memcmp(data + 16, key->identity, id_len) != 0 || bin != total - head - 8 ||
        sum != fnv1a(FNV_BASIS, data, total - 8)) {
      free(data);
      data = NULL;
    } else {
      memmove(data, data + head, (size_t)bin);
      *size = (size_t)bin;
    }
  }
  close(fd);
  return data;
}

cl_program clr_program_cache_load(const clr_program_key *key, cl_context cl, cl_device_id device,
                                  const char *options) {
  size_t size = 0;
  unsigned char *binary = read_binary(key, &size);
  if (!binary) return NULL;
  const unsigned char *bins[1] = {binary};
  cl_int status = CL_SUCCESS, err = CL_SUCCESS;
  cl_program p = clCreateProgramWithBinary(cl, 1, &device, &size, bins, &status, &err);
  free(binary);
  if (err != CL_SUCCESS || status != CL_SUCCESS || !p) {
    if (p) clReleaseProgram(p);
    return NULL;
  }
  if (clBuildProgram(p, 1, &device, options, NULL, NULL) != CL_SUCCESS) {
    clReleaseProgram(p);
    return NULL;
  }
  return p;
}

/* The program's binary for its one device (malloc'd), or NULL. */
static unsigned char *program_binary(cl_program program, size_t *size) {
  cl_uint ndev = 0;
  if (clGetProgramInfo(program, CL_PROGRAM_NUM_DEVICES, sizeof ndev, &ndev, NULL) != CL_SUCCESS ||
      ndev != 1)
    return NULL;
  if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof *size, size, NULL) != CL_SUCCESS ||
      *size == 0 || *size > CACHE_MAX_BINARY)
    return NULL;
  unsigned char *bin = malloc(*size);
  unsigned char *bins[1] = {bin};
  if (bin && clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof bins, bins, NULL) == CL_SUCCESS)
    return bin;
  free(bin);
  return NULL;
}

void clr_program_cache_store(const clr_program_key *key, cl_program program) {
  size_t size = 0;
  unsigned char *bin = program_binary(program, &size);
  if (!bin) return;
  int dir = open_dir(1);
  char temp[64];
  snprintf(temp, sizeof temp, "%s.tmp-%ld", key->file_name, (long)getpid());
  int fd = dir < 0 ? -1 : openat(dir, temp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd >= 0) {
    uint64_t id_len = strlen(key->identity), bin_len = size;
    uint64_t sum = fnv1a(FNV_BASIS, CACHE_MAGIC, 8);
    sum = fnv1a(sum, &id_len, 8);
    sum = fnv1a(sum, key->identity, id_len);
    sum = fnv1a(sum, &bin_len, 8);
    sum = fnv1a(sum, bin, size);
    int ok = write_all(fd, CACHE_MAGIC, 8) && write_all(fd, &id_len, 8) &&
             write_all(fd, key->identity, id_len) && write_all(fd, &bin_len, 8) &&
             write_all(fd, bin, size) && write_all(fd, &sum, 8);
    ok = close(fd) == 0 && ok;
    if (!ok || renameat(dir, temp, dir, key->file_name) != 0) unlinkat(dir, temp, 0);
  }
  if (dir >= 0) close(dir);
  free(bin);
}
