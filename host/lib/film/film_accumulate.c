/* The accumulator behind film_add_samples: the host checks a chunk's samples and bins them by
 * their first reached pixel (a stable sort by bin row, then by bin column: the canonical order of
 * film.h), the weigh kernel computes each binned sample's filter factors once, the gather kernel
 * sums every reached pixel over its neighbouring bins (on SIMD-shaped contexts both in 8 lanes
 * where the chunk's reach allows: use_lanes) and the chunk's float sums go back to the film,
 * which owns the double sums. Also the host reference, which sums the binned samples in the same
 * order. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "clr_internal.h"
#include "film_funcs.h"
#include "film_internal.h"
#include "film_screen.h"

/* Binning passes stay out of line, so profiles name them. */
#define CLR_PROFILE_NOINLINE __attribute__((noinline))
#define KEY_NONE 0xffffffffu
/* Keys count bins from this many pixels left of / above the pixel bounds: a binned sample's x0
 * is at least pixel_x0 - (x1 - x0) >= pixel_x0 - (2 * CLR_FILM_MAX_FILTER_RADIUS + 1). */
#define KEY_MARGIN 128

static int grow(void **ptr, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 1;
  size_t n = need + need / 2 + 16;
  void *p = realloc(*ptr, n * elem);
  if (!p) return 0;
  *ptr = p;
  *cap = n;
  return 1;
}

static clr_i32 prepare(clr_film film, const clr_film_sample *s, clr_film_prepared *out) {
  return clr_film_prepare(&film->params, &film->filter, s->x, s->y, s->r, s->g, s->b, s->weight,
                          out);
}

/* Whether prepared sample s reaches a pixel of the pixel bounds. */
static int reaches_film(const clr_film_params *p, const clr_film_prepared *s) {
  return s->x1 >= p->pixel_x0 && s->x0 < p->pixel_x1 && s->y1 >= p->pixel_y0 && s->y0 < p->pixel_y1;
}

/* Whether a binned sample's values are its own floats with 0.5 off x and y: without a luminance
 * clamp clr_film_prepare changes no other float. Then pass 2 takes them from the samples and
 * pass 1 stores none (bins.values stays unused). */
static int values_from_samples(const clr_film_params *p) { return !p->clamp_luminance; }

/* A sample between the two binning passes: its bin column (key) and binned values. */
typedef struct row_entry {
  uint32_t column;
  float v[CLR_FILM_BINNED_FLOATS];
} row_entry;

/* One thread's share of a chunk's binning: samples [begin, end) (passes 1 and 2) and grid rows
 * [row_begin, row_end) (pass 3). */
typedef struct bin_part {
  clr_film film;
  const clr_film_sample *samples;
  size_t begin, end;
  const clr_film_grid *grid;
  uint32_t *rows;    /* per key row: count (pass 1), then fill position (pass 2) */
  uint32_t *columns; /* pass 3: per bin column, bins_x + 1 */
  int32_t row_begin, row_end;
  float *dst; /* pass 3 */
  int pass;
  /* pass 1 results */
  int32_t bx0, by0, bx1, by1, reach_x, reach_y;
  size_t binned;
  uint64_t accepted, dropped, outside;
} bin_part;

/* Key rows: y0 - (pixel_y0 - KEY_MARGIN) for y0 in [pixel_y0 - KEY_MARGIN, pixel_y1). */
static size_t key_rows(const clr_film_params *p) {
  return (size_t)(p->pixel_y1 - p->pixel_y0) + KEY_MARGIN;
}

/* Raises *reach to the pixels x0 .. last a sample at d reaches along `axis`, counted up to its
 * last non-zero filter factor: past it the factors are 0, whose additions leave every sum as it
 * is (film_funcs.h, clr_film_add), so the gathers need not reach those pixels. Filters that
 * vanish at their radius (mitchell, triangle) then reach 4 pixels, not 5, at radius 2. */
static void raise_reach(int32_t *reach, clr_film film, int axis, float d, int32_t x0,
                        int32_t last) {
  while (last - x0 + 1 > *reach &&
         clr_film_filter_factor(&film->filter, film->factors, axis, d, last) == 0.0f)
    --last;
  if (last - x0 + 1 > *reach) *reach = last - x0 + 1;
}

/* A part's pass-1 bounds, reach and counts, kept in locals (no aliasing with the keys and
 * counts the loop stores). */
typedef struct key_stats {
  int32_t bx0, by0, bx1, by1, reach_x, reach_y;
  size_t binned;
  uint64_t accepted, dropped, outside;
} key_stats;

/* Pass 1 of sample i, one by one: checks it, stores its key (KEY_NONE when it reaches no pixel)
 * and binned values (unless values is NULL), counts it in its bin row, widens k's bounds and
 * reach. */
static inline void key_one(clr_film film, const clr_film_sample *sample, size_t i,
                           uint32_t *restrict keys, float *restrict values, uint32_t *restrict rows,
                           key_stats *k) {
  const clr_film_params *p = &film->params;
  const int32_t kx0 = p->pixel_x0 - KEY_MARGIN, ky0 = p->pixel_y0 - KEY_MARGIN;
  clr_film_prepared s = {0};
  clr_i32 status = prepare(film, sample, &s);
  k->accepted += status == CLR_FILM_SAMPLE_OK;
  k->dropped += status == CLR_FILM_SAMPLE_DROPPED;
  k->outside += status == CLR_FILM_SAMPLE_OUTSIDE;
  if (status != CLR_FILM_SAMPLE_OK || !reaches_film(p, &s)) {
    keys[i] = KEY_NONE;
    return;
  }
  keys[i] = (uint32_t)(s.y0 - ky0) << 16 | (uint32_t)(s.x0 - kx0);
  if (values) {
    float *v = values + i * CLR_FILM_BINNED_FLOATS;
    v[0] = s.dx;
    v[1] = s.dy;
    v[2] = s.r;
    v[3] = s.g;
    v[4] = s.b;
    v[5] = s.w;
  }
  ++rows[s.y0 - ky0];
  k->bx0 = s.x0 < k->bx0 ? s.x0 : k->bx0;
  k->bx1 = s.x0 > k->bx1 ? s.x0 : k->bx1;
  k->by0 = s.y0 < k->by0 ? s.y0 : k->by0;
  k->by1 = s.y0 > k->by1 ? s.y0 : k->by1;
  if (s.x1 - s.x0 + 1 > k->reach_x) raise_reach(&k->reach_x, film, 0, s.dx, s.x0, s.x1);
  if (s.y1 - s.y0 + 1 > k->reach_y) raise_reach(&k->reach_y, film, 1, s.dy, s.y0, s.y1);
  ++k->binned;
}

#if defined(__SSE2__)
/* The bounds of the samples key_four binned, per lane. */
typedef struct key_lanes {
  __m128i bx0, by0, bx1, by1;
} key_lanes;

static inline __m128i min_i32(__m128i a, __m128i b) {
  __m128i gt = _mm_cmpgt_epi32(a, b);
  return _mm_or_si128(_mm_and_si128(gt, b), _mm_andnot_si128(gt, a));
}
static inline __m128i max_i32(__m128i a, __m128i b) {
  __m128i gt = _mm_cmpgt_epi32(a, b);
  return _mm_or_si128(_mm_and_si128(gt, a), _mm_andnot_si128(gt, b));
}

/* The film's limits key_four compares against, four lanes each. */
typedef struct key_limits {
  clr_screen_limits sc;
  __m128i kx0, ky0;           /* the key origin */
  __m128i px0, py0, px1, py1; /* pixel bounds, inclusive */
} key_limits;

static void key_limits_init(key_limits *l, clr_film film) {
  const clr_film_params *p = &film->params;
  clr_film_screen sc;
  clr_film_screen_init(&sc, p, &film->filter);
  l->sc = clr_screen_limits_of(&sc);
  l->kx0 = _mm_set1_epi32(p->pixel_x0 - KEY_MARGIN);
  l->ky0 = _mm_set1_epi32(p->pixel_y0 - KEY_MARGIN);
  l->px0 = _mm_set1_epi32(p->pixel_x0);
  l->py0 = _mm_set1_epi32(p->pixel_y0);
  l->px1 = _mm_set1_epi32(p->pixel_x1 - 1);
  l->py1 = _mm_set1_epi32(p->pixel_y1 - 1);
}

/* key_one of samples i..i + 3 at once when all four pass clr_film_prepare unchanged
 * (film_screen.h), reach the film and reach no more pixels than k's reach (the common case):
 * their binned values (stored unless values is NULL) are the samples' floats with 0.5 off x and
 * y. Else 0, nothing written. */
static inline int key_four(const key_limits *l, const clr_film_sample *samples, size_t i,
                           uint32_t *restrict keys, float *restrict values, uint32_t *restrict rows,
                           const key_stats *k, key_lanes *b) {
  __m128 v[6];
  if (!clr_screen_load(samples + i, v)) return 0;
  clr_screen_fields f = clr_screen_transpose(v);
  if (!clr_screen_plain(&l->sc, &f)) return 0;
  clr_screen_footprint p = clr_screen_reach(&l->sc, f.x, f.y);
  const __m128i one = _mm_set1_epi32(1);
  __m128i off = _mm_or_si128(_mm_cmpgt_epi32(l->px0, p.x1), _mm_cmpgt_epi32(p.x0, l->px1));
  off =
      _mm_or_si128(off, _mm_or_si128(_mm_cmpgt_epi32(l->py0, p.y1), _mm_cmpgt_epi32(p.y0, l->py1)));
  __m128i wide =
      _mm_cmpgt_epi32(_mm_add_epi32(_mm_sub_epi32(p.x1, p.x0), one), _mm_set1_epi32(k->reach_x));
  wide = _mm_or_si128(wide, _mm_cmpgt_epi32(_mm_add_epi32(_mm_sub_epi32(p.y1, p.y0), one),
                                            _mm_set1_epi32(k->reach_y)));
  if (_mm_movemask_epi8(_mm_or_si128(off, wide))) return 0;
  __m128i row = _mm_sub_epi32(p.y0, l->ky0);
  _mm_storeu_si128((__m128i *)(keys + i),
                   _mm_or_si128(_mm_slli_epi32(row, 16), _mm_sub_epi32(p.x0, l->kx0)));
  if (values) {
    const __m128 d01 = _mm_setr_ps(0.5f, 0.5f, 0.0f, 0.0f);
    const __m128 d23 = _mm_setr_ps(0.0f, 0.0f, 0.5f, 0.5f);
    float *out = values + i * CLR_FILM_BINNED_FLOATS;
    _mm_storeu_ps(out, _mm_sub_ps(v[0], d01));
    _mm_storeu_ps(out + 4, _mm_sub_ps(v[1], d23));
    _mm_storeu_ps(out + 8, v[2]);
    _mm_storeu_ps(out + 12, _mm_sub_ps(v[3], d01));
    _mm_storeu_ps(out + 16, _mm_sub_ps(v[4], d23));
    _mm_storeu_ps(out + 20, v[5]);
  }
  uint32_t r[4];
  _mm_storeu_si128((__m128i *)r, row);
  ++rows[r[0]];
  ++rows[r[1]];
  ++rows[r[2]];
  ++rows[r[3]];
  b->bx0 = min_i32(b->bx0, p.x0);
  b->bx1 = max_i32(b->bx1, p.x0);
  b->by0 = min_i32(b->by0, p.y0);
  b->by1 = max_i32(b->by1, p.y0);
  return 1;
}

/* Folds the lanes' bounds into k. */
static void key_lanes_fold(const key_lanes *b, key_stats *k) {
  int32_t x0[4], y0[4], x1[4], y1[4];
  _mm_storeu_si128((__m128i *)x0, b->bx0);
  _mm_storeu_si128((__m128i *)y0, b->by0);
  _mm_storeu_si128((__m128i *)x1, b->bx1);
  _mm_storeu_si128((__m128i *)y1, b->by1);
  for (int j = 0; j < 4; ++j) {
    k->bx0 = x0[j] < k->bx0 ? x0[j] : k->bx0;
    k->by0 = y0[j] < k->by0 ? y0[j] : k->by0;
    k->bx1 = x1[j] > k->bx1 ? x1[j] : k->bx1;
    k->by1 = y1[j] > k->by1 ? y1[j] : k->by1;
  }
}
#endif

/* Pass 1: checks the part's samples, stores each one's packed bin (KEY_NONE when it reaches no
 * pixel) and binned values (none where values_from_samples), counts them per bin row, records
 * their bounds and the largest reach: four at a time where key_four takes them, else one by one
 * (key_one). */
CLR_PROFILE_NOINLINE static void key_part(bin_part *t) {
  clr_film film = t->film;
  uint32_t *restrict keys = film->bins.keys;
  float *restrict values = values_from_samples(&film->params) ? NULL : film->bins.values;
  uint32_t *restrict rows = t->rows;
  memset(rows, 0, key_rows(&film->params) * sizeof *rows);
  key_stats k = {INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN, 1, 1, 0, 0, 0, 0};
  size_t i = t->begin;
#if defined(__SSE2__)
  key_limits l;
  key_limits_init(&l, film);
  key_lanes b = {_mm_set1_epi32(INT32_MAX), _mm_set1_epi32(INT32_MAX), _mm_set1_epi32(INT32_MIN),
                 _mm_set1_epi32(INT32_MIN)};
  uint64_t fours = 0;
  for (; i + 4 <= t->end; i += 4) {
    if (key_four(&l, t->samples, i, keys, values, rows, &k, &b)) {
      ++fours;
      continue;
    }
    for (size_t j = i; j < i + 4; ++j) key_one(film, &t->samples[j], j, keys, values, rows, &k);
  }
  key_lanes_fold(&b, &k);
  k.accepted += 4 * fours;
  k.binned += 4 * (size_t)fours;
#endif
  for (; i < t->end; ++i) key_one(film, &t->samples[i], i, keys, values, rows, &k);
  t->bx0 = k.bx0;
  t->by0 = k.by0;
  t->bx1 = k.bx1;
  t->by1 = k.by1;
  t->reach_x = k.reach_x;
  t->reach_y = k.reach_y;
  t->binned = k.binned;
  t->accepted = k.accepted;
  t->dropped = k.dropped;
  t->outside = k.outside;
}

/* Pass 2: moves the part's keyed samples to their bin row's range of bins.rowed (stable), with
 * their binned values from pass 1 or, where values_from_samples, from the samples. */
CLR_PROFILE_NOINLINE static void row_part(bin_part *t) {
  clr_film film = t->film;
  const uint32_t *keys = film->bins.keys;
  const float *values = film->bins.values;
  row_entry *rowed = film->bins.rowed;
  const uint32_t column0 = (uint32_t)(t->grid->bin_x0 - (film->params.pixel_x0 - KEY_MARGIN));
  const int from_samples = values_from_samples(&film->params);
  for (size_t i = t->begin; i < t->end; ++i) {
    uint32_t key = keys[i];
    if (key == KEY_NONE) continue;
    row_entry *e = &rowed[t->rows[key >> 16]++];
    e->column = (key & 0xffffu) - column0;
    if (from_samples) {
      const clr_film_sample *s = &t->samples[i];
      e->v[0] = s->x - 0.5f; /* clr_film_prepare's dx, dy */
      e->v[1] = s->y - 0.5f;
      e->v[2] = s->r;
      e->v[3] = s->g;
      e->v[4] = s->b;
      e->v[5] = s->weight;
    } else {
      memcpy(e->v, values + i * CLR_FILM_BINNED_FLOATS, sizeof e->v);
    }
  }
}

/* Exclusive prefix of a row's n column counts from `at`: into columns[0..n) (the fill positions)
 * and starts[1..n) (starts[0] is the previous row part's to read). */
static void column_prefix(uint32_t *restrict columns, uint32_t *restrict starts, size_t n,
                          uint32_t at) {
  if (!n) return;
  uint32_t count = columns[0];
  columns[0] = at;
  at += count;
  size_t c = 1;
#if defined(__SSE2__)
  __m128i carry = _mm_set1_epi32((int)at); /* four at a time: a shifted-add scan */
  for (; c + 4 <= n; c += 4) {
    __m128i v = _mm_loadu_si128((const __m128i *)(columns + c));
    __m128i sum = _mm_add_epi32(v, _mm_slli_si128(v, 4));
    sum = _mm_add_epi32(sum, _mm_slli_si128(sum, 8));
    __m128i before = _mm_add_epi32(carry, _mm_sub_epi32(sum, v));
    _mm_storeu_si128((__m128i *)(columns + c), before);
    _mm_storeu_si128((__m128i *)(starts + c), before);
    carry = _mm_add_epi32(carry, _mm_shuffle_epi32(sum, _MM_SHUFFLE(3, 3, 3, 3)));
  }
  at = (uint32_t)_mm_cvtsi128_si32(carry);
#endif
  for (; c < n; ++c) {
    count = columns[c];
    columns[c] = at;
    starts[c] = at;
    at += count;
  }
}

/* Pass 3: sorts each of the part's grid rows by bin column (stable) into dst
 * (CLR_FILM_BINNED_FLOATS per sample) and fills the rows' bin starts. */
CLR_PROFILE_NOINLINE static void column_part(bin_part *t) {
  clr_film_bins *b = &t->film->bins;
  const clr_film_grid *g = t->grid;
  const size_t bins_x = (size_t)g->bins_x;
  const row_entry *restrict rowed = b->rowed;
  uint32_t *restrict columns = t->columns;
  float *restrict dst = t->dst;
  for (int32_t row = t->row_begin; row < t->row_end; ++row) {
    uint32_t *restrict starts = b->starts + (size_t)row * bins_x;
    const uint32_t first = starts[0], last = b->starts[(size_t)(row + 1) * bins_x];
    memset(columns, 0, bins_x * sizeof *columns);
    for (uint32_t i = first; i < last; ++i) ++columns[rowed[i].column];
    /* starts[0] is set (and read by the previous row's part) already */
    column_prefix(columns, starts, bins_x, first);
    for (uint32_t i = first; i < last; ++i) {
      const row_entry *e = &rowed[i];
      memcpy(dst + (size_t)columns[e->column]++ * CLR_FILM_BINNED_FLOATS, e->v, sizeof e->v);
    }
  }
}

/* A chunk's parts, from bin_chunk to scatter_chunk. */
typedef struct bin_set {
  bin_part parts[CLR_FILM_BIN_THREADS_MAX];
  int count;
} bin_set;

static void *run_part(void *arg) {
  bin_part *t = arg;
  if (t->pass == 1)
    key_part(t);
  else if (t->pass == 2)
    row_part(t);
  else
    column_part(t);
  return NULL;
}

/* Runs `pass` on every part: the last on this thread, the others on helper threads (on this
 * thread too when a thread cannot start). The parts write disjoint memory. */
static void run_parts(bin_part *parts, int n, int pass) {
  pthread_t threads[CLR_FILM_BIN_THREADS_MAX];
  int started[CLR_FILM_BIN_THREADS_MAX] = {0};
  for (int i = 0; i < n; ++i) parts[i].pass = pass;
  for (int i = 0; i + 1 < n; ++i)
    started[i] = pthread_create(&threads[i], NULL, run_part, &parts[i]) == 0;
  run_part(&parts[n - 1]);
  for (int i = 0; i + 1 < n; ++i) {
    if (started[i])
      pthread_join(threads[i], NULL);
    else
      run_part(&parts[i]);
  }
}

/* The grid of the parts' pass-1 results; returns the number of binned samples, or 0 when they
 * give the film's pixels no non-zero factor (an empty output region). */
static size_t merge_parts(clr_film film, const bin_part *parts, int n, clr_film_grid *g) {
  const clr_film_params *p = &film->params;
  int32_t bx0 = INT32_MAX, by0 = INT32_MAX, bx1 = INT32_MIN, by1 = INT32_MIN, kx = 1, ky = 1;
  size_t binned = 0;
  for (int i = 0; i < n; ++i) {
    const bin_part *t = &parts[i];
    film->accepted += t->accepted;
    film->dropped += t->dropped;
    film->outside += t->outside;
    binned += t->binned;
    if (!t->binned) continue;
    bx0 = t->bx0 < bx0 ? t->bx0 : bx0;
    by0 = t->by0 < by0 ? t->by0 : by0;
    bx1 = t->bx1 > bx1 ? t->bx1 : bx1;
    by1 = t->by1 > by1 ? t->by1 : by1;
    kx = t->reach_x > kx ? t->reach_x : kx;
    ky = t->reach_y > ky ? t->reach_y : ky;
  }
  memset(g, 0, sizeof *g);
  if (!binned) return 0;
  g->bin_x0 = bx0;
  g->bin_y0 = by0;
  g->bins_x = bx1 - bx0 + 1;
  g->bins_y = by1 - by0 + 1;
  g->reach_x = kx;
  g->reach_y = ky;
  g->out_x0 = bx0 > p->pixel_x0 ? bx0 : p->pixel_x0;
  g->out_y0 = by0 > p->pixel_y0 ? by0 : p->pixel_y0;
  int32_t ox1 = bx1 + kx < p->pixel_x1 ? bx1 + kx : p->pixel_x1;
  int32_t oy1 = by1 + ky < p->pixel_y1 ? by1 + ky : p->pixel_y1;
  g->out_w = ox1 - g->out_x0;
  g->out_h = oy1 - g->out_y0;
  if (g->out_w <= 0 || g->out_h <= 0) { /* every factor the film's pixels get is 0: no work */
    memset(g, 0, sizeof *g);
    return 0;
  }
  g->weighed_floats = (CLR_FILM_WEIGHED_HEAD + kx + ky + 3) / 4 * 4;
  return binned;
}

/* Bins samples[0..count) with `threads` threads (1..CLR_FILM_BIN_THREADS_MAX; the result does not
 * depend on it), a stable sort by bin row then by bin column: checks and counts the samples,
 * fills *g, moves them to their bin rows (bins.rowed) and sets every row's first bin start, for
 * scatter_chunk; *binned gets the number of binned samples. Caller holds the lock. */
static clr_result bin_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                            int threads, bin_set *set, clr_film_grid *g, size_t *binned) {
  clr_film_bins *b = &film->bins;
  const size_t rows = key_rows(&film->params);
  const size_t values = values_from_samples(&film->params) ? 0 : count * CLR_FILM_BINNED_FLOATS;
  if (!grow((void **)&b->keys, &b->keys_cap, count, sizeof *b->keys) ||
      !grow((void **)&b->values, &b->values_cap, values, sizeof *b->values) ||
      !grow((void **)&b->cursor, &b->cursor_cap, rows * (size_t)threads, sizeof *b->cursor))
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_add_samples: no memory for keys");
  int n = threads; /* each part gets at least CLR_FILM_BIN_PART_MIN samples */
  if ((size_t)n > count / CLR_FILM_BIN_PART_MIN) n = (int)(count / CLR_FILM_BIN_PART_MIN);
  if (n < 1) n = 1;
  bin_part *parts = set->parts;
  memset(set, 0, sizeof *set);
  for (int i = 0; i < n; ++i) {
    parts[i].film = film;
    parts[i].samples = samples;
    parts[i].begin = count * (size_t)i / (size_t)n;
    parts[i].end = count * (size_t)(i + 1) / (size_t)n;
    parts[i].grid = g;
    parts[i].rows = b->cursor + rows * (size_t)i;
  }
  set->count = n;
  run_parts(parts, n, 1);
  *binned = merge_parts(film, parts, n, g);
  if (!*binned) return CLR_SUCCESS;
  size_t nbins = (size_t)g->bins_x * (size_t)g->bins_y;
  if (!grow((void **)&b->starts, &b->starts_cap, nbins + 1, sizeof *b->starts) ||
      !grow((void **)&b->rowed, &b->rowed_cap, *binned, sizeof *b->rowed) ||
      !grow((void **)&b->columns, &b->columns_cap, ((size_t)g->bins_x + 1) * (size_t)n,
            sizeof *b->columns))
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_add_samples: no memory for %zu bins",
                    nbins);
  /* Exclusive prefix over key rows; inside a row, part i's samples follow part i - 1's. */
  const size_t row0 = (size_t)(g->bin_y0 - (film->params.pixel_y0 - KEY_MARGIN));
  uint32_t at = 0;
  for (size_t r = 0; r < rows; ++r) {
    if (r >= row0 && r < row0 + (size_t)g->bins_y) b->starts[(r - row0) * (size_t)g->bins_x] = at;
    for (int i = 0; i < n; ++i) {
      uint32_t c = parts[i].rows[r];
      parts[i].rows[r] = at;
      at += c;
    }
  }
  b->starts[nbins] = at;
  run_parts(parts, n, 2);
  for (int i = 0; i < n; ++i) {
    parts[i].columns = b->columns + ((size_t)g->bins_x + 1) * (size_t)i;
    parts[i].row_begin = (int32_t)((size_t)g->bins_y * (size_t)i / (size_t)n);
    parts[i].row_end = (int32_t)((size_t)g->bins_y * (size_t)(i + 1) / (size_t)n);
  }
  return CLR_SUCCESS;
}

/* Writes the binned samples in bin order, batch order inside a bin, to dst and fills the bin
 * starts (after bin_chunk). */
static void scatter_chunk(bin_set *set, float *dst) {
  for (int i = 0; i < set->count; ++i) set->parts[i].dst = dst;
  run_parts(set->parts, set->count, 3);
}

/* Device buffer of at least `bytes`, replaced when too small. */
static clr_result ensure_buffer(clr_film film, cl_mem *buf, size_t *have, size_t bytes,
                                cl_mem_flags flags, const char *what) {
  if (*buf && *have >= bytes) return CLR_SUCCESS;
  if (*buf) clReleaseMemObject(*buf);
  *buf = NULL;
  *have = 0;
  size_t size = bytes + bytes / 2 + 256;
  cl_int err = CL_SUCCESS;
  *buf = clCreateBuffer(clr_context_cl_context(film->ctx), flags, size, NULL, &err);
  if (err != CL_SUCCESS) {
    *buf = NULL;
    return clr_fail(film->ctx, CLR_ERROR_OPENCL,
                    "film_add_samples: clCreateBuffer(%s, %zu bytes) "
                    "failed: %s (%d)",
                    what, size, clr_cl_error_name(err), (int)err);
  }
  *have = size;
  return CLR_SUCCESS;
}

static clr_result upload_table(clr_film film) {
  clr_film_device *d = &film->dev;
  size_t have = 0;
  CLR_CHECK(ensure_buffer(film, &d->table, &have, sizeof film->factors, CL_MEM_READ_ONLY,
                          "filter table factors"));
  CLR_CL_CHECK(film->ctx,
               clEnqueueWriteBuffer(clr_context_cl_queue(film->ctx), d->table, CL_TRUE, 0,
                                    sizeof film->factors, film->factors, 0, NULL, NULL));
  return CLR_SUCCESS;
}

static clr_result ensure_kernel(clr_film film) {
  clr_film_device *d = &film->dev;
  if (d->kernel) return CLR_SUCCESS;
  cl_kernel k = NULL;
  CLR_CHECK(clr_context_kernel(film->ctx, "film_kernels.cl", NULL, "clr_film_gather", &k));
  /* Work-items (runs of pixels) per group: 8 on the SIMD shape's CPU devices, a warp or more
   * otherwise; within the device's and the kernel's limits either way. */
  size_t g = clr_context_group_size(film->ctx, k, clr_context_portable(film->ctx) ? 64 : 8);
  cl_kernel weigh = NULL;
  clr_result r = clr_context_kernel(film->ctx, "film_kernels.cl", NULL, "clr_film_weigh", &weigh);
  if (r == CLR_SUCCESS && !d->table) r = upload_table(film);
  if (r != CLR_SUCCESS) {
    if (weigh) clReleaseKernel(weigh);
    clReleaseKernel(k);
    return r;
  }
  d->weigh = weigh;
  d->kernel = k;
  d->group_size = g ? g : 1;
  return CLR_SUCCESS;
}

/* Uploads the chunk's binned samples (scattered straight into the mapped device buffer) and bin
 * starts. */
static clr_result upload_bins(clr_film film, bin_set *set, const clr_film_grid *g, size_t binned) {
  clr_film_device *d = &film->dev;
  cl_command_queue q = clr_context_cl_queue(film->ctx);
  size_t nbins = (size_t)g->bins_x * (size_t)g->bins_y;
  size_t bytes = binned * CLR_FILM_BINNED_FLOATS * sizeof(float);
  CLR_CHECK(ensure_buffer(film, &d->binned, &d->binned_bytes, bytes, CL_MEM_READ_ONLY, "binned"));
  CLR_CHECK(ensure_buffer(film, &d->starts, &d->starts_bytes, (nbins + 1) * sizeof(uint32_t),
                          CL_MEM_READ_ONLY, "starts"));
  cl_int err = CL_SUCCESS;
  float *dst = clEnqueueMapBuffer(q, d->binned, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, bytes,
                                  0, NULL, NULL, &err);
  CLR_CL_CHECK_ERR(film->ctx, err, "film_add_samples: clEnqueueMapBuffer(binned)");
  scatter_chunk(set, dst);
  CLR_CL_CHECK(film->ctx, clEnqueueUnmapMemObject(q, d->binned, dst, 0, NULL, NULL));
  clr_film_bins *b = &film->bins;
  CLR_CL_CHECK(film->ctx,
               clEnqueueWriteBuffer(q, d->starts, CL_FALSE, 0, (nbins + 1) * sizeof(uint32_t),
                                    b->starts, 0, NULL, NULL));
  /* The next chunk bins into the other array while this write may be pending; the one after
   * finds it done (its sums were waited for, later in the same in-order queue). */
  uint32_t *sent = b->starts;
  size_t sent_cap = b->starts_cap;
  b->starts = b->starts_sent;
  b->starts_cap = b->starts_sent_cap;
  b->starts_sent = sent;
  b->starts_sent_cap = sent_cap;
  return CLR_SUCCESS;
}

/* Whether the chunk runs the SIMD shape's 8-lane kernels (clr_film_weigh8, clr_film_gather8):
 * on SIMD-shaped contexts when no sample reaches more than 8 pixels along an axis. */
static int use_lanes(clr_film film, const clr_film_grid *g) {
  return !clr_context_portable(film->ctx) && g->reach_x <= CLR_FILM_LANES &&
         g->reach_y <= CLR_FILM_LANES;
}

static clr_result ensure_lane_kernels(clr_film film) {
  clr_film_device *d = &film->dev;
  if (!d->weigh8)
    CLR_CHECK(
        clr_context_kernel(film->ctx, "film_kernels.cl", NULL, "clr_film_weigh8", &d->weigh8));
  if (!d->gather8)
    CLR_CHECK(
        clr_context_kernel(film->ctx, "film_kernels.cl", NULL, "clr_film_gather8", &d->gather8));
  return CLR_SUCCESS;
}

/* Runs the weigh kernel (clr_film_weigh, or clr_film_weigh8 with `lanes`) over the chunk's
 * binned samples. */
static clr_result weigh(clr_film film, const clr_film_grid *g, size_t binned, int lanes) {
  clr_film_device *d = &film->dev;
  size_t bytes = binned * (size_t)g->weighed_floats * sizeof(float);
  CLR_CHECK(
      ensure_buffer(film, &d->weighed, &d->weighed_bytes, bytes, CL_MEM_READ_WRITE, "weighed"));
  cl_kernel k = lanes ? d->weigh8 : d->weigh;
  cl_uint n = (cl_uint)binned;
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 0, sizeof film->filter, &film->filter));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 1, sizeof *g, g));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 2, sizeof(cl_mem), &d->table));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 3, sizeof(cl_mem), &d->binned));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 4, sizeof n, &n));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 5, sizeof(cl_mem), &d->weighed));
  return clr_context_launch(film->ctx, k, binned, 64, lanes ? "clr_film_weigh8" : "clr_film_weigh");
}

/* Enqueues a SIMD-shape kernel whose work-items are 8-pixel runs of two rows of the grid's output
 * region (its arguments set); *done, when not NULL, gets its event. */
static clr_result enqueue_runs8(clr_film film, cl_kernel k, const clr_film_grid *g,
                                cl_event *done) {
  size_t group = film->group_size_override ? film->group_size_override : film->dev.group_size;
  size_t runs = ((size_t)g->out_w + CLR_FILM_LANES - 1) / CLR_FILM_LANES;
  size_t global[2] = {(runs + group - 1) / group * group, ((size_t)g->out_h + 1) / 2};
  size_t local[2] = {group, 1};
  CLR_CL_CHECK(film->ctx, clEnqueueNDRangeKernel(clr_context_cl_queue(film->ctx), k, 2, NULL,
                                                 global, local, 0, NULL, done));
  return CLR_SUCCESS;
}

/* Enqueues the SIMD shape's 8-lane gather over the grid's output region. */
static clr_result enqueue_gather8(clr_film film, const clr_film_grid *g) {
  clr_film_device *d = &film->dev;
  cl_kernel k = d->gather8;
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 0, sizeof *g, g));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 1, sizeof(cl_mem), &d->weighed));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 2, sizeof(cl_mem), &d->starts));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 3, sizeof(cl_mem), &d->sums));
  return enqueue_runs8(film, k, g, NULL);
}

/* Enqueues clr_film_gather8_add over the grid's output region (the call's double-sum buffers are
 * open); *done gets its event. */
static clr_result enqueue_gather8_add(clr_film film, const clr_film_grid *g, cl_event *done) {
  clr_film_device *d = &film->dev;
  cl_kernel k = d->gather8_add;
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 0, sizeof film->params, &film->params));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 1, sizeof *g, g));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 2, sizeof(cl_mem), &d->weighed));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 3, sizeof(cl_mem), &d->starts));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 4, sizeof(cl_mem), &d->rgb_sums));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 5, sizeof(cl_mem), &d->weight_sums));
  return enqueue_runs8(film, k, g, done);
}

/* The portable shape's gather: one work-item per output pixel (clr_film_gather_pixels), 2D
 * work-groups of the device's size (a warp or more where the device allows it). Enqueues it only;
 * gather() reads the sums back as for the run kernel. */
static clr_result enqueue_gather_pixels(clr_film film, const clr_film_grid *g) {
  clr_film_device *d = &film->dev;
  if (!d->pixel_gather)
    CLR_CHECK(clr_context_kernel(film->ctx, "film_kernels.cl", NULL, "clr_film_gather_pixels",
                                 &d->pixel_gather));
  cl_kernel k = d->pixel_gather;
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 0, sizeof *g, g));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 1, sizeof(cl_mem), &d->weighed));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 2, sizeof(cl_mem), &d->starts));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 3, sizeof(cl_mem), &d->sums));
  size_t group = film->group_size_override ? film->group_size_override
                                           : clr_context_group_size(film->ctx, k, 64);
  size_t local[2] = {group < 32 ? group : 32, 1};
  if (!film->group_size_override) local[1] = group / local[0];
  size_t global[2] = {((size_t)g->out_w + local[0] - 1) / local[0] * local[0],
                      ((size_t)g->out_h + local[1] - 1) / local[1] * local[1]};
  CLR_CL_CHECK(film->ctx, clEnqueueNDRangeKernel(clr_context_cl_queue(film->ctx), k, 2, NULL,
                                                 global, local, 0, NULL, NULL));
  return CLR_SUCCESS;
}

/* Waits for a chunk's kernels when it has an event (ready), then releases the event. */
static clr_result chunk_wait(clr_film film, clr_film_chunk_sums *chunk) {
  if (!chunk->ready) return CLR_SUCCESS;
  cl_int err = clWaitForEvents(1, &chunk->ready);
  cl_int status = CL_COMPLETE;
  if (err == CL_SUCCESS)
    err = clGetEventInfo(chunk->ready, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status,
                         NULL);
  clReleaseEvent(chunk->ready);
  chunk->ready = NULL;
  if (err == CL_SUCCESS && status >= 0) return CLR_SUCCESS;
  return clr_fail(film->ctx, CLR_ERROR_OPENCL, "film_add_samples: chunk sums failed: %s (%d)",
                  clr_cl_error_name(err != CL_SUCCESS ? err : status),
                  (int)(err != CL_SUCCESS ? err : status));
}

/* Runs the gather over the grid's output region (clr_film_gather8 with `lanes`); *out maps its
 * sums, at once when `blocking`, else once out->ready completes. */
static clr_result gather(clr_film film, const clr_film_grid *g, int lanes, int blocking,
                         clr_film_chunk_sums *out) {
  clr_film_device *d = &film->dev;
  if (d->rgb_sums) {
    if (!lanes) /* clr_film_open_device_sums admits only filters that keep every chunk in lanes */
      return clr_fail(film->ctx, CLR_ERROR_INTERNAL,
                      "film_add_samples: a chunk reaches %d x %d pixels, more than %d", g->reach_x,
                      g->reach_y, CLR_FILM_LANES);
    out->block = (clr_bounds2i){g->out_x0, g->out_y0, g->out_x0 + g->out_w, g->out_y0 + g->out_h};
    CLR_CHECK(enqueue_gather8_add(film, g, &out->ready));
    return blocking ? chunk_wait(film, out) : CLR_SUCCESS;
  }
  cl_command_queue q = clr_context_cl_queue(film->ctx);
  size_t group = film->group_size_override ? film->group_size_override : d->group_size;
  size_t bytes = (size_t)g->out_w * (size_t)g->out_h * CLR_FILM_SUM_FLOATS * sizeof(float);
  CLR_CHECK(ensure_buffer(film, &d->sums, &d->sums_bytes, bytes, CL_MEM_WRITE_ONLY, "sums"));
  cl_kernel k = d->kernel;
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 0, sizeof film->params, &film->params));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 1, sizeof *g, g));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 2, sizeof(cl_mem), &d->weighed));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 3, sizeof(cl_mem), &d->starts));
  CLR_CL_CHECK(film->ctx, clSetKernelArg(k, 4, sizeof(cl_mem), &d->sums));
  size_t tile = (size_t)film->params.tile_size;
  size_t runs = ((size_t)g->out_w + tile - 1) / tile;
  size_t global[2] = {(runs + group - 1) / group * group, (size_t)g->out_h};
  size_t local[2] = {group, 1};
  if (lanes)
    CLR_CHECK(enqueue_gather8(film, g));
  else if (clr_context_portable(film->ctx))
    CLR_CHECK(enqueue_gather_pixels(film, g));
  else
    CLR_CL_CHECK(film->ctx, clEnqueueNDRangeKernel(q, k, 2, NULL, global, local, 0, NULL, NULL));
  cl_int err = CL_SUCCESS;
  cl_event ready = NULL;
  float *sums = clEnqueueMapBuffer(q, d->sums, blocking ? CL_TRUE : CL_FALSE, CL_MAP_READ, 0, bytes,
                                   0, NULL, blocking ? NULL : &ready, &err);
  CLR_CL_CHECK_ERR(film->ctx, err, "film_add_samples: clEnqueueMapBuffer(sums)");
  out->ready = ready;
  out->block = (clr_bounds2i){g->out_x0, g->out_y0, g->out_x0 + g->out_w, g->out_y0 + g->out_h};
  out->sums = sums;
  out->mapped = 1;
  return CLR_SUCCESS;
}

/* As set, else the online CPUs, at most 8 (2 on the 2-core machine the figures were measured
 * on). */
int clr_film_host_threads(clr_film film) {
  if (film->bin_threads) return film->bin_threads;
  long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  return cpus < 1 ? 1 : cpus > 8 ? 8 : (int)cpus;
}

/* Uploads a binned chunk (bin_chunk) and enqueues its kernels; *out maps its sums (see
 * gather). */
static clr_result launch_chunk(clr_film film, bin_set *set, clr_film_grid *g, size_t binned,
                               int blocking, clr_film_chunk_sums *out) {
  int lanes = use_lanes(film, g);
  if (lanes) {
    CLR_CHECK(ensure_lane_kernels(film));
    g->weighed_floats = CLR_FILM_WEIGHED8_FLOATS;
  }
  CLR_CHECK(upload_bins(film, set, g, binned));
  CLR_CHECK(weigh(film, g, binned, lanes));
  return gather(film, g, lanes, blocking, out);
}

static clr_result device_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                               clr_film_chunk_sums *out) {
  clr_film_grid g;
  size_t binned = 0;
  bin_set set;
  CLR_CHECK(ensure_kernel(film));
  CLR_CHECK(bin_chunk(film, samples, count, clr_film_host_threads(film), &set, &g, &binned));
  if (!binned) return CLR_SUCCESS;
  return launch_chunk(film, &set, &g, binned, 1, out);
}

/* Waits for a launched chunk's sums, adds them into the film's double sums and releases them;
 * *pending is empty after. */
static clr_result finish_chunk(clr_film film, clr_film_chunk_sums *pending) {
  clr_result r = chunk_wait(film, pending);
  if (r == CLR_SUCCESS && pending->sums)
    clr_film_add_block(film, pending->block, pending->sums, clr_film_host_threads(film));
  clr_result released = clr_film_chunk_sums_release(film, pending);
  memset(pending, 0, sizeof *pending);
  return r != CLR_SUCCESS ? r : released;
}

/* Whether a call's kernels add into the film's double sums themselves (clr_film_gather8_add, no
 * float sums to add on the host): SIMD-shaped contexts on a device that shares the host's memory
 * and computes in double, with a filter whose every chunk runs in lanes (2 r + 1 <= 8 pixels). */
static int adds_on_device(clr_film film) {
  const float most = (float)(CLR_FILM_LANES - 1) / 2.0f;
  return !clr_context_portable(film->ctx) && clr_context_unified_memory(film->ctx) &&
         clr_context_fp64(film->ctx) && film->filter.radius_x <= most &&
         film->filter.radius_y <= most;
}

/* A buffer over `count` of the film's double sums, or NULL where the device refuses one (the
 * call then adds on the host, as on other devices). */
static cl_mem sums_buffer(clr_film film, double *sums, size_t count) {
  cl_int err = CL_SUCCESS;
  cl_mem buf =
      clCreateBuffer(clr_context_cl_context(film->ctx), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR,
                     count * sizeof *sums, sums, &err);
  return err == CL_SUCCESS ? buf : NULL;
}

clr_result clr_film_open_device_sums(clr_film film) {
  clr_film_device *d = &film->dev;
  if (!adds_on_device(film)) return CLR_SUCCESS;
  CLR_CHECK(ensure_lane_kernels(film));
  if (!d->gather8_add)
    CLR_CHECK(clr_context_kernel(film->ctx, "film_kernels.cl", NULL, "clr_film_gather8_add",
                                 &d->gather8_add));
  d->rgb_sums = sums_buffer(film, film->rgb_sum, film->pixel_count * 3);
  d->weight_sums = d->rgb_sums ? sums_buffer(film, film->weight_sum, film->pixel_count) : NULL;
  if (!d->weight_sums && d->rgb_sums) {
    clReleaseMemObject(d->rgb_sums);
    d->rgb_sums = NULL;
  }
  return CLR_SUCCESS;
}

/* Maps and unmaps a double-sum buffer, after which the host reads the device's additions
 * (OpenCL's rule for CL_MEM_USE_HOST_PTR; no copy on a device that wrote them in place). */
static clr_result sync_sums(clr_film film, cl_mem buf, size_t bytes) {
  cl_command_queue q = clr_context_cl_queue(film->ctx);
  cl_int err = CL_SUCCESS;
  void *at = clEnqueueMapBuffer(q, buf, CL_TRUE, CL_MAP_READ, 0, bytes, 0, NULL, NULL, &err);
  CLR_CL_CHECK_ERR(film->ctx, err, "film_add_samples: clEnqueueMapBuffer(double sums)");
  CLR_CL_CHECK(film->ctx, clEnqueueUnmapMemObject(q, buf, at, 0, NULL, NULL));
  return CLR_SUCCESS;
}

clr_result clr_film_close_device_sums(clr_film film) {
  clr_film_device *d = &film->dev;
  clr_result r = CLR_SUCCESS;
  if (d->rgb_sums) r = sync_sums(film, d->rgb_sums, film->pixel_count * 3 * sizeof(double));
  if (d->weight_sums && r == CLR_SUCCESS)
    r = sync_sums(film, d->weight_sums, film->pixel_count * sizeof(double));
  cl_int err = d->rgb_sums && r == CLR_SUCCESS ? clFinish(clr_context_cl_queue(film->ctx))
                                               : CL_SUCCESS; /* the unmaps done */
  if (err != CL_SUCCESS)
    r = clr_fail(film->ctx, CLR_ERROR_OPENCL, "film_add_samples: clFinish failed: %s (%d)",
                 clr_cl_error_name(err), (int)err);
  if (d->rgb_sums) clReleaseMemObject(d->rgb_sums);
  if (d->weight_sums) clReleaseMemObject(d->weight_sums);
  d->rgb_sums = d->weight_sums = NULL;
  return r;
}

clr_result clr_film_accumulate_overlapped(clr_film film, const clr_film_sample *samples,
                                          size_t count) {
  clr_film_chunk_sums pending = {0};
  clr_result r = ensure_kernel(film);
  if (r == CLR_SUCCESS) r = clr_film_open_device_sums(film);
  for (size_t at = 0; at < count && r == CLR_SUCCESS; at += CLR_FILM_CHUNK_SAMPLES) {
    size_t n = count - at < CLR_FILM_CHUNK_SAMPLES ? count - at : CLR_FILM_CHUNK_SAMPLES;
    clr_film_grid g;
    size_t binned = 0;
    bin_set set;
    r = bin_chunk(film, samples + at, n, clr_film_host_threads(film), &set, &g, &binned);
    clr_result done = finish_chunk(film, &pending); /* the previous chunk's, in chunk order */
    if (r == CLR_SUCCESS) r = done;
    if (r == CLR_SUCCESS && binned) r = launch_chunk(film, &set, &g, binned, 0, &pending);
  }
  clr_result done = finish_chunk(film, &pending);
  clr_result closed = clr_film_close_device_sums(film);
  return r != CLR_SUCCESS ? r : done != CLR_SUCCESS ? done : closed;
}

/* Host reference of one chunk: the same binning; each binned sample, in bin order, adds to every
 * pixel it reaches, so every pixel sees its samples in the gather's order. */
static clr_result reference_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                                  clr_film_chunk_sums *out) {
  clr_film_bins *b = &film->bins;
  clr_film_grid g;
  size_t binned = 0;
  bin_set set;
  CLR_CHECK(bin_chunk(film, samples, count, 1, &set, &g, &binned));
  if (!binned) return CLR_SUCCESS;
  size_t pixels = (size_t)g.out_w * (size_t)g.out_h;
  if (!grow((void **)&b->binned, &b->binned_cap, binned * CLR_FILM_BINNED_FLOATS, sizeof(float)) ||
      !grow((void **)&b->sums, &b->sums_cap, pixels * CLR_FILM_SUM_FLOATS, sizeof(float)))
    return clr_fail(film->ctx, CLR_ERROR_OUT_OF_MEMORY, "film_add_samples_reference: no memory");
  scatter_chunk(&set, b->binned);
  memset(b->sums, 0, pixels * CLR_FILM_SUM_FLOATS * sizeof(float));
  const clr_film_params *p = &film->params;
  for (size_t i = 0; i < binned; ++i) {
    const float *v = b->binned + i * CLR_FILM_BINNED_FLOATS;
    clr_film_prepared s = {v[0],
                           v[1],
                           v[2],
                           v[3],
                           v[4],
                           v[5],
                           clr_film_first_pixel(v[0], film->filter.radius_x),
                           clr_film_last_pixel(v[0], film->filter.radius_x),
                           clr_film_first_pixel(v[1], film->filter.radius_y),
                           clr_film_last_pixel(v[1], film->filter.radius_y)};
    /* The output region holds every pixel a binned sample reaches (its first pixel is inside;
     * past the chunk's reach its factors are 0, raise_reach): the kernels stop there, so does
     * the reference, and no index leaves b->sums. */
    const int32_t last_x = g.out_x0 + g.out_w - 1, last_y = g.out_y0 + g.out_h - 1;
    int32_t x0 = s.x0 > p->pixel_x0 ? s.x0 : p->pixel_x0;
    int32_t x1 = s.x1 < last_x ? s.x1 : last_x;
    int32_t y0 = s.y0 > p->pixel_y0 ? s.y0 : p->pixel_y0;
    int32_t y1 = s.y1 < last_y ? s.y1 : last_y;
    for (int32_t y = y0; y <= y1; ++y)
      for (int32_t x = x0; x <= x1; ++x) {
        size_t pix = (size_t)(y - g.out_y0) * (size_t)g.out_w + (size_t)(x - g.out_x0);
        clr_film_accumulate(&film->filter, film->factors, &s, x, y,
                            b->sums + pix * CLR_FILM_SUM_FLOATS);
      }
  }
  out->block = (clr_bounds2i){g.out_x0, g.out_y0, g.out_x0 + g.out_w, g.out_y0 + g.out_h};
  out->sums = b->sums;
  return CLR_SUCCESS;
}

clr_result clr_film_accumulate_chunk(clr_film film, const clr_film_sample *samples, size_t count,
                                     int reference, clr_film_chunk_sums *out) {
  memset(out, 0, sizeof *out);
  return reference || !film->ctx ? reference_chunk(film, samples, count, out)
                                 : device_chunk(film, samples, count, out);
}

clr_result clr_film_chunk_sums_release(clr_film film, clr_film_chunk_sums *sums) {
  if (!sums->mapped) return CLR_SUCCESS;
  sums->mapped = 0;
  cl_command_queue q = clr_context_cl_queue(film->ctx);
  CLR_CL_CHECK(film->ctx,
               clEnqueueUnmapMemObject(q, film->dev.sums, (void *)sums->sums, 0, NULL, NULL));
  return CLR_SUCCESS;
}

clr_result film_set_group_size(clr_film film, size_t group_size) {
  if (!film) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "film_set_group_size: film is NULL");
  if (group_size > CLR_FILM_GROUP_MAX)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT, "film_set_group_size: %zu > %d",
                    group_size, CLR_FILM_GROUP_MAX);
  pthread_mutex_lock(&film->lock);
  film->group_size_override = group_size;
  pthread_mutex_unlock(&film->lock);
  return CLR_SUCCESS;
}

clr_result film_set_bin_threads(clr_film film, int threads) {
  if (!film) return clr_fail(NULL, CLR_ERROR_NULL_POINTER, "film_set_bin_threads: film is NULL");
  if (threads < 0 || threads > CLR_FILM_BIN_THREADS_MAX)
    return clr_fail(film->ctx, CLR_ERROR_INVALID_ARGUMENT,
                    "film_set_bin_threads: threads = %d (must be 0..%d)", threads,
                    CLR_FILM_BIN_THREADS_MAX);
  pthread_mutex_lock(&film->lock);
  film->bin_threads = threads;
  pthread_mutex_unlock(&film->lock);
  return CLR_SUCCESS;
}

size_t clr_film_sums_bytes(clr_film film) {
  return film->pixel_count * (film->splat_rgb ? 7 : 4) * sizeof(double) + sizeof film->table;
}

size_t clr_film_scratch_bytes(clr_film film) {
  const clr_film_device *d = &film->dev;
  const clr_film_bins *b = &film->bins;
  size_t bytes = d->binned_bytes + d->weighed_bytes + d->starts_bytes + d->sums_bytes;
  bytes +=
      b->keys_cap * sizeof *b->keys + b->values_cap * sizeof *b->values +
      b->rowed_cap * sizeof(row_entry) +
      (b->starts_cap + b->starts_sent_cap + b->cursor_cap + b->columns_cap) * sizeof(uint32_t) +
      b->binned_cap * sizeof *b->binned + b->sums_cap * sizeof *b->sums;
  return bytes;
}

void clr_film_accumulate_release(clr_film film) {
  clr_film_device *d = &film->dev;
  cl_mem *bufs[] = {&d->table, &d->binned, &d->weighed, &d->starts, &d->sums};
  for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; ++i)
    if (*bufs[i]) clReleaseMemObject(*bufs[i]);
  if (d->kernel) clReleaseKernel(d->kernel);
  if (d->weigh) clReleaseKernel(d->weigh);
  if (d->pixel_gather) clReleaseKernel(d->pixel_gather);
  if (d->weigh8) clReleaseKernel(d->weigh8);
  if (d->gather8) clReleaseKernel(d->gather8);
  if (d->gather8_add) clReleaseKernel(d->gather8_add);
  clr_film_bins *b = &film->bins;
  free(b->keys);
  free(b->values);
  free(b->starts);
  free(b->starts_sent);
  free(b->cursor);
  free(b->rowed);
  free(b->columns);
  free(b->binned);
  free(b->sums);
}
