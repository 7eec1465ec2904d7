/* Test helpers over whole files' bytes; every step is a cmocka assertion. Include after cmocka.h. */
#ifndef CLR_READ_FILE_TEST_UTIL_H
#define CLR_READ_FILE_TEST_UTIL_H

#include <stdio.h>
#include <stdlib.h>

/* The file's bytes (malloc'ed, at least one) and their count in *size. */
static inline unsigned char *read_file_bytes(const char *path, size_t *size) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  assert_int_equal(fseek(f, 0, SEEK_END), 0);
  long n = ftell(f);
  assert_true(n > 0);
  rewind(f);
  unsigned char *bytes = malloc((size_t)n);
  assert_non_null(bytes);
  assert_int_equal(fread(bytes, 1, (size_t)n, f), (size_t)n);
  fclose(f);
  *size = (size_t)n;
  return bytes;
}

/* Files a and b hold the same bytes. */
static inline void assert_files_equal(const char *a, const char *b) {
  size_t na = 0, nb = 0;
  unsigned char *fa = read_file_bytes(a, &na), *fb = read_file_bytes(b, &nb);
  assert_int_equal(na, nb);
  assert_memory_equal(fa, fb, na);
  free(fa);
  free(fb);
}

#endif
