/* The film's sums are zero and already written when film_create returns (every page resident), so
 * the first merges do not fault on the kernel's shared zero page; a splat's sums likewise. */
#define _DEFAULT_SOURCE
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include <cmocka.h>
#include "clrender.h"
#include "clrender/film.h"
#include "film_internal.h"

/* Counts the pages of [p, p + bytes) that are not resident (mincore). */
static size_t pages_not_resident(const void *p, size_t bytes) {
  size_t page = (size_t)sysconf(_SC_PAGESIZE);
  uintptr_t first = (uintptr_t)p & ~(uintptr_t)(page - 1);
  size_t span = (uintptr_t)p + bytes - first, pages = (span + page - 1) / page;
  unsigned char *resident = malloc(pages);
  assert_non_null(resident);
  assert_int_equal(mincore((void *)first, span, resident), 0);
  size_t missing = 0;
  for (size_t i = 0; i < pages; ++i) missing += !(resident[i] & 1);
  free(resident);
  return missing;
}

static int all_zero(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (v[i] != 0.0) return 0;
  return 1;
}

static void test_sums_written_at_creation(void **state) {
  (void)state;
  clr_film_desc d;
  clr_film_desc_init(&d);
  d.x_resolution = 512; /* 2 MiB of rgb sums: served by mmap, untouched unless written */
  d.y_resolution = 256;
  clr_film film = NULL;
  assert_int_equal(film_create(NULL, &d, &film), CLR_SUCCESS);
  assert_int_equal(film->pixel_count, (size_t)512 * 256);
  assert_int_equal(pages_not_resident(film->rgb_sum, film->pixel_count * 3 * sizeof(double)), 0);
  assert_int_equal(pages_not_resident(film->weight_sum, film->pixel_count * sizeof(double)), 0);
  assert_true(all_zero(film->rgb_sum, film->pixel_count * 3));
  assert_true(all_zero(film->weight_sum, film->pixel_count));
  assert_null(film->splat_rgb);
  assert_int_equal(film_add_splat(film, 3.5f, 2.5f, 1.0f, 2.0f, 4.0f), CLR_SUCCESS);
  assert_non_null(film->splat_rgb);
  assert_int_equal(pages_not_resident(film->splat_rgb, film->pixel_count * 3 * sizeof(double)), 0);
  size_t at = 3 * (size_t)(2 * 512 + 3); /* the splat's pixel (3, 2) */
  assert_true(film->splat_rgb[at] == 1.0 && film->splat_rgb[at + 1] == 2.0 &&
              film->splat_rgb[at + 2] == 4.0);
  film->splat_rgb[at] = film->splat_rgb[at + 1] = film->splat_rgb[at + 2] = 0.0;
  assert_true(all_zero(film->splat_rgb, film->pixel_count * 3)); /* the rest stayed zero */
  film_release(film);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_sums_written_at_creation)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
