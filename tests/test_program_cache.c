/* The on-disk program binary cache: a program loaded from it gives the same samples as one built
 * from source; corrupt, truncated, foreign, symlinked or unsafe entries are ignored and rewritten;
 * CLRENDER_PROGRAM_CACHE=0 writes nothing. The folder lives in the build tree. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <cmocka.h>

#include "read_file_test_util.h"
#include "clrender.h"
#include "program_cache.h"

#define DIR_PATH CLR_BINARY_DIR "/test_program_cache_dir"
#define VALUES (16 * 16 * 4 * 5)

static void empty_dir(void) {
  DIR *d = opendir(DIR_PATH);
  if (!d) return;
  char path[4096];
  for (struct dirent *e; (e = readdir(d));) {
    if (e->d_name[0] == '.') continue;
    snprintf(path, sizeof path, "%s/%s", DIR_PATH, e->d_name);
    unlink(path);
  }
  closedir(d);
}

/* The one cache entry's path; fails the test unless exactly one file is there. */
static void entry_path(char *out, size_t size) {
  DIR *d = opendir(DIR_PATH);
  assert_non_null(d);
  int n = 0;
  for (struct dirent *e; (e = readdir(d));) {
    if (e->d_name[0] == '.') continue;
    ++n;
    assert_int_equal(strncmp(e->d_name, "p-", 2), 0);
    assert_null(strstr(e->d_name, ".tmp"));
    snprintf(out, size, "%s/%s", DIR_PATH, e->d_name);
  }
  closedir(d);
  assert_int_equal(n, 1);
}

static int file_count(void) {
  DIR *d = opendir(DIR_PATH);
  if (!d) return 0;
  int n = 0;
  for (struct dirent *e; (e = readdir(d));) n += e->d_name[0] != '.';
  closedir(d);
  return n;
}

/* Sobol samples of a 16x16 film, 4 spp, 5 dimensions, from a fresh context's device program. */
static void device_samples(float *values) {
  clr_context ctx = NULL;
  assert_int_equal(clr_context_create(NULL, &ctx), CLR_SUCCESS);
  clr_sampler_desc sd;
  clr_sampler_desc_init(&sd, CLR_SAMPLER_SOBOL);
  sd.pixel_samples = 4;
  sd.film.x_resolution = sd.film.y_resolution = 16;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(ctx, &sd, &s), CLR_SUCCESS);
  clr_sample_request req[3] = {{2, 0}, {2, 0}, {1, 0}};
  clr_sample_batch batch;
  clr_sample_batch_init(&batch);
  batch.pixels = (clr_bounds2i){0, 0, 16, 16};
  batch.sample_count = 4;
  batch.requests = req;
  batch.request_count = 3;
  clr_sample_output out;
  clr_sample_output_init(&out);
  out.host_values = values;
  assert_int_equal(clr_sampler_generate(s, &batch, &out), CLR_SUCCESS);
  clr_sampler_release(s);
  clr_context_release(ctx);
}

static float reference[VALUES];

static int setup(void **state) {
  (void)state;
  setenv("CLRENDER_CACHE_DIR", DIR_PATH, 1);
  unsetenv("CLRENDER_PROGRAM_CACHE");
  mkdir(DIR_PATH, 0700);
  chmod(DIR_PATH, 0700);
  empty_dir();
  device_samples(reference); /* built from source, then stored */
  return 0;
}

static ino_t inode_of(const char *path) {
  struct stat st;
  assert_int_equal(lstat(path, &st), 0);
  return st.st_ino;
}

/* Renders again: the samples must equal the reference. */
static void same_samples(void) {
  static float values[VALUES];
  memset(values, 0xff, sizeof values);
  device_samples(values);
  assert_memory_equal(values, reference, sizeof values);
}

static void test_stored_then_loaded(void **state) {
  (void)state;
  char path[4096];
  entry_path(path, sizeof path);
  ino_t before = inode_of(path);
  same_samples();
  /* A build from source stores its binary again (a new file renamed in place): the same inode
   * means the program came from the cache. */
  assert_true(inode_of(path) == before);
}

static void write_file(const char *path, const void *data, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(data, 1, n, f), n);
  assert_int_equal(fclose(f), 0);
}

static uint64_t fnv1a(const unsigned char *p, size_t n) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

/* Replaces the entry with edit(bytes), renders, and checks the samples and that a valid entry
 * (a new file) took its place. */
static void damaged_entry(void (*edit)(unsigned char *data, size_t *n)) {
  char path[4096];
  entry_path(path, sizeof path);
  size_t n = 0;
  unsigned char *data = read_file_bytes(path, &n);
  unsigned char *copy = malloc(n + 4096);
  assert_non_null(copy);
  memcpy(copy, data, n);
  edit(copy, &n);
  unlink(path);
  write_file(path, copy, n);
  ino_t damaged = inode_of(path);
  same_samples();
  assert_true(inode_of(path) != damaged); /* rebuilt from source and stored again, whole: */
  size_t m = 0;
  unsigned char *again = read_file_bytes(path, &m);
  uint64_t sum = 0;
  memcpy(&sum, again + m - 8, 8);
  assert_true(sum == fnv1a(again, m - 8));
  free(again);
  free(copy);
  free(data);
}

static void flip_binary_byte(unsigned char *d, size_t *n) { d[*n - 100] ^= 0x5a; }
static void truncate_half(unsigned char *d, size_t *n) {
  (void)d;
  *n /= 2;
}
static void garbage(unsigned char *d, size_t *n) {
  for (size_t i = 0; i < *n; ++i) d[i] = (unsigned char)(i * 131u + 7u);
}
/* Another device's identity (one character changed), checksum made valid again. */
static void foreign_identity(unsigned char *d, size_t *n) {
  d[16 + 9] ^= 1; /* inside "clrender <version>" */
  uint64_t sum = fnv1a(d, *n - 8);
  memcpy(d + *n - 8, &sum, 8);
}
/* Our identity and a valid checksum around a binary the implementation must refuse. */
static void foreign_binary(unsigned char *d, size_t *n) {
  uint64_t id_len = 0, bin = 0;
  memcpy(&id_len, d + 8, 8);
  size_t head = 16 + (size_t)id_len + 8;
  memcpy(&bin, d + head - 8, 8);
  for (size_t i = 0; i < bin; ++i) d[head + i] = (unsigned char)(i * 29u + 3u);
  uint64_t sum = fnv1a(d, *n - 8);
  memcpy(d + *n - 8, &sum, 8);
}

static void test_corrupt_entries_ignored(void **state) {
  (void)state;
  damaged_entry(flip_binary_byte);
  damaged_entry(truncate_half);
  damaged_entry(garbage);
  damaged_entry(foreign_identity);
  damaged_entry(foreign_binary);
}

/* A symbolic link in the entry's place is not followed; the store replaces the link itself. */
static void test_symlink_entry_ignored(void **state) {
  (void)state;
  char path[4096], target[4200];
  entry_path(path, sizeof path);
  snprintf(target, sizeof target, "%s.target", DIR_PATH);
  assert_int_equal(rename(path, target), 0);
  assert_int_equal(symlink(target, path), 0);
  same_samples();
  struct stat st;
  assert_int_equal(lstat(path, &st), 0);
  assert_true(S_ISREG(st.st_mode)); /* rebuilt and stored over the link */
  assert_int_equal(lstat(target, &st), 0);
  unlink(target);
}

/* A folder others may write is neither read nor written. */
static void test_unsafe_folder_unused(void **state) {
  (void)state;
  empty_dir();
  assert_int_equal(chmod(DIR_PATH, 0777), 0);
  same_samples();
  assert_int_equal(file_count(), 0);
  assert_int_equal(chmod(DIR_PATH, 0700), 0);
}

static void test_cache_off(void **state) {
  (void)state;
  empty_dir();
  setenv("CLRENDER_PROGRAM_CACHE", "0", 1);
  char dir[4096];
  assert_int_equal(clr_program_cache_dir(dir, sizeof dir), 0);
  same_samples();
  assert_int_equal(file_count(), 0);
  unsetenv("CLRENDER_PROGRAM_CACHE");
  assert_int_equal(clr_program_cache_dir(dir, sizeof dir), 1);
  assert_string_equal(dir, DIR_PATH);
  same_samples();
  assert_int_equal(file_count(), 1);
}

/* The default folder follows XDG_CACHE_HOME (absolute only), then HOME. */
static void test_default_folder(void **state) {
  (void)state;
  char dir[4096];
  unsetenv("CLRENDER_CACHE_DIR");
  setenv("XDG_CACHE_HOME", "/x/cache", 1);
  assert_int_equal(clr_program_cache_dir(dir, sizeof dir), 1);
  assert_string_equal(dir, "/x/cache/clrender");
  setenv("XDG_CACHE_HOME", "relative", 1);
  setenv("HOME", "/home/u", 1);
  assert_int_equal(clr_program_cache_dir(dir, sizeof dir), 1);
  assert_string_equal(dir, "/home/u/.cache/clrender");
  setenv("CLRENDER_CACHE_DIR", DIR_PATH, 1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_stored_then_loaded),
      cmocka_unit_test(test_corrupt_entries_ignored),
      cmocka_unit_test(test_symlink_entry_ignored),
      cmocka_unit_test(test_unsafe_folder_unused),
      cmocka_unit_test(test_cache_off),
      cmocka_unit_test(test_default_folder),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
