/* Fuzz target, differential, host only: film tiles (film_get_tile, film_tile_add_samples,
 * serialize, deserialize, merge). For any film, filter, sample region and samples:
 *  - the tile's fast path (clr_tile_add_samples) gives the bits and counts of the per-pixel path;
 *  - film_tile_add_samples, in one call or two, fills the tile with those sums and counts;
 *  - a serialized tile deserialized into a second film serializes to the same bytes, and both
 *    tiles merge into equal sums, counts and images; a second merge is refused.
 * With FUZZ_FLAG_BUFFER the rest of the input is untrusted tile bytes: film_tile_deserialize
 * accepts them or names the problem, and an accepted tile serializes back to the same bytes and
 * merges and resolves without harm. A difference aborts. The input's layout: fuzz_film_input.h,
 * then 4 bytes of sample region (read_region), then samples or tile bytes. */
#include "clrender.h"
#include "film_internal.h"
#include "film_tile_add.h"
#include "fuzz_film_input.h"

static void fail(const char *what) {
  fprintf(stderr, "fuzz_tile: %s\n", what);
  abort();
}

static void *checked_calloc(size_t n, size_t size) {
  void *p = calloc(n ? n : 1, size);
  if (!p) abort();
  return p;
}

/* A region over the film's sample bounds, reaching one pixel past them on each side. */
static clr_bounds2i read_region(fuzz_reader *r, clr_bounds2i sample_bounds) {
  const int32_t w = sample_bounds.x1 - sample_bounds.x0 + 2;
  const int32_t h = sample_bounds.y1 - sample_bounds.y0 + 2;
  clr_bounds2i region;
  region.x0 = sample_bounds.x0 - 1 + fuzz_next(r) % w;
  region.x1 = region.x0 + 1 + fuzz_next(r) % w;
  region.y0 = sample_bounds.y0 - 1 + fuzz_next(r) % h;
  region.y1 = region.y0 + 1 + fuzz_next(r) % h;
  return region;
}

static size_t pixels_of(clr_bounds2i b) { return (size_t)(b.x1 - b.x0) * (size_t)(b.y1 - b.y0); }

/* The fast path against the per-pixel path over the tile's bounds; their sums. */
static float *check_fast_path(clr_film film, clr_bounds2i bounds, const clr_film_sample *s,
                              size_t n, size_t first, clr_tile_counts *counts) {
  size_t floats = pixels_of(bounds) * CLR_FILM_SUM_FLOATS;
  float *fast = checked_calloc(floats, sizeof(float));
  float *general = checked_calloc(floats, sizeof(float));
  clr_tile_adder a;
  clr_tile_adder_init(&a, &film->params, &film->filter, film->factors);
  clr_tile_counts general_counts = {0, 0, 0};
  *counts = general_counts;
  clr_tile_add_samples(&a, s, first, bounds, fast, counts);
  clr_tile_add_samples(&a, s + first, n - first, bounds, fast, counts);
  clr_tile_add_samples_per_pixel(&a, s, n, bounds, general, &general_counts);
  if (memcmp(fast, general, floats * sizeof(float)) != 0)
    fail("the fast path's sums differ from the per-pixel path's");
  if (memcmp(counts, &general_counts, sizeof *counts) != 0)
    fail("the fast path's counts differ from the per-pixel path's");
  free(general);
  return fast;
}

static uint8_t *serialize(clr_film_tile tile, size_t *size) {
  *size = film_tile_serialized_size(tile);
  uint8_t *bytes = checked_calloc(*size, 1);
  if (film_tile_serialize(tile, bytes, *size) != CLR_SUCCESS) fail(clr_last_error_message());
  return bytes;
}

/* Serialized header fields: u32 magic, u32 reserved, 4 x i32 bounds, 3 x u64 counters. */
enum { HEADER_BYTES = 48, COUNTERS_AT = 24 };

static void merge_once(clr_film film, clr_film_tile tile) {
  if (film_merge_tile(film, tile) != CLR_SUCCESS) fail(clr_last_error_message());
  if (film_merge_tile(film, tile) != CLR_ERROR_INVALID_TILE) fail("a tile merged twice");
}

/* Samples through a tile, a serialized copy of it into a second film, both merged. */
static void check_samples(clr_film film, clr_film twin, clr_bounds2i region,
                          const fuzz_film_input *in, fuzz_reader *r) {
  clr_film_tile tile = NULL, copy = NULL;
  if (film_get_tile(film, region, &tile) != CLR_SUCCESS) fail(clr_last_error_message());
  const clr_bounds2i bounds = film_tile_pixel_bounds(tile);
  size_t n = 0;
  clr_film_sample *samples = fuzz_read_samples(r, in, &n);
  size_t first = fuzz_first_call(in, n);
  clr_tile_counts counts;
  float *sums = check_fast_path(film, bounds, samples, n, first, &counts);
  if (first && film_tile_add_samples(tile, samples, first) != CLR_SUCCESS)
    fail(clr_last_error_message());
  if (first < n && film_tile_add_samples(tile, samples + first, n - first) != CLR_SUCCESS)
    fail(clr_last_error_message());
  if (fuzz_verbose())
    fprintf(stderr, "  tile [%d,%d)x[%d,%d): %zu samples, %llu accepted\n", bounds.x0, bounds.x1,
            bounds.y0, bounds.y1, n, (unsigned long long)counts.accepted);
  size_t size = 0, copy_size = 0;
  uint8_t *bytes = serialize(tile, &size);
  uint64_t counters[3];
  memcpy(counters, bytes + COUNTERS_AT, sizeof counters);
  if (counters[0] != counts.accepted || counters[1] != counts.dropped ||
      counters[2] != counts.outside)
    fail("film_tile_add_samples counted otherwise than the fast path");
  if (size != HEADER_BYTES + pixels_of(bounds) * CLR_FILM_SUM_FLOATS * sizeof(float) ||
      memcmp(bytes + HEADER_BYTES, sums, size - HEADER_BYTES) != 0)
    fail("film_tile_add_samples summed otherwise than the fast path");
  if (film_tile_deserialize(twin, bytes, size, &copy) != CLR_SUCCESS)
    fail(clr_last_error_message());
  uint8_t *copy_bytes = serialize(copy, &copy_size);
  if (copy_size != size || memcmp(bytes, copy_bytes, size) != 0)
    fail("a deserialized tile serializes to other bytes");
  merge_once(film, tile);
  merge_once(twin, copy);
  const char *differ = fuzz_films_differ(film, twin);
  if (differ) fail(differ); /* the films that merged the tile and its copy */
  free(copy_bytes);
  free(bytes);
  free(sums);
  free(samples);
  film_tile_release(copy);
  film_tile_release(tile);
}

/* Untrusted tile bytes: refused with a reason, or a tile that round-trips and merges. */
static void check_tile_bytes(clr_film film, fuzz_reader *r) {
  clr_film_tile tile = NULL;
  clr_result made = film_tile_deserialize(film, r->p, r->n, &tile);
  fuzz_report("film_tile_deserialize", made);
  if (made != CLR_SUCCESS) {
    if (tile) fail("a refused tile was returned");
    if (!*clr_last_error_message()) fail("a refused tile without a message");
    return;
  }
  size_t size = 0;
  uint8_t *bytes = serialize(tile, &size);
  /* The reserved word is written as 0, whatever was read. */
  if (size != r->n || memcmp(bytes, r->p, 4) != 0 || memcmp(bytes + 8, r->p + 8, size - 8) != 0)
    fail("an accepted tile serializes to other bytes");
  merge_once(film, tile);
  size_t pixels = pixels_of(film_pixel_bounds(film));
  float *rgb = checked_calloc(pixels * 3, sizeof *rgb);
  if (film_get_rgb(film, rgb, 1.0f) != CLR_SUCCESS) fail(clr_last_error_message());
  free(rgb);
  free(bytes);
  film_tile_release(tile);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_reader r = {data, size};
  fuzz_film_input in;
  fuzz_read_film(&r, &in);
  clr_film film = NULL, twin = NULL;
  if (!fuzz_create_films(NULL, &in.desc, &film, &twin)) return 0;
  clr_bounds2i region = read_region(&r, film_sample_bounds(film));
  if (in.flags & FUZZ_FLAG_BUFFER)
    check_tile_bytes(film, &r);
  else
    check_samples(film, twin, region, &in, &r);
  film_release(twin);
  film_release(film);
  return 0;
}
