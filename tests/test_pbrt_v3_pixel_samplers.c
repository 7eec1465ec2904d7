/* The pixel samplers (random, stratified, 02sequence) with --seeding pbrt-v3 against pbrt-v3's
 * algorithms written out here independently of kernels/: PCG32 with pbrt-v3's constants
 * (core/rng.h), StratifiedSampler / RandomSampler / ZeroTwoSequenceSampler::StartPixel with
 * sampling.cpp's and lowdiscrepancy.h's helpers (VanDerCorput, Sobol2D with CSobol, Shuffle,
 * LatinHypercube), PixelSampler's Get1D/Get2D and SamplerIntegrator::Render's tile loop
 * (Clone(tile index), pixels row-major, StartPixel for every pixel of the tile, the rendering
 * draws of those inside the pixel bounds). Pixels that are not their tile's first are checked,
 * with box (radius 0.5) and radius-2 filters, plus a few values pinned as numbers. Then the
 * (0,2)-sequence's promises: (0,k,2)-nets in the 2D dimensions and 1D stratification. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"

/* ---------- pbrt-v3's RNG (core/rng.h) ---------- */

typedef struct {
  uint64_t state, inc;
} pbrt_rng;

static uint32_t rng_u32(pbrt_rng *r) {
  uint64_t old = r->state;
  r->state = old * 0x5851f42d4c957f2dULL + r->inc;
  uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  uint32_t rot = (uint32_t)(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
}

static pbrt_rng rng_sequence(uint64_t initseq) {
  pbrt_rng r = {0u, (initseq << 1u) | 1u};
  rng_u32(&r);
  r.state += 0x853c49e6748fea9bULL;
  rng_u32(&r);
  return r;
}

static uint32_t rng_bounded(pbrt_rng *r, uint32_t b) {
  uint32_t threshold = (~b + 1u) % b;
  for (;;) {
    uint32_t v = rng_u32(r);
    if (v >= threshold) return v % b;
  }
}

static const float one_minus_epsilon = 0x1.fffffep-1f;

static float rng_float(pbrt_rng *r) {
  float f = (float)rng_u32(r) * 0x1p-32f;
  return f < one_minus_epsilon ? f : one_minus_epsilon;
}

/* ---------- sampling.cpp and lowdiscrepancy.h ---------- */

/* Shuffle(samp, count, nDimensions, rng) over items of nDimensions floats. */
static void shuffle(float *samp, int count, int ndim, pbrt_rng *r) {
  for (int i = 0; i < count; ++i) {
    int other = i + (int)rng_bounded(r, (uint32_t)(count - i));
    for (int j = 0; j < ndim; ++j) {
      float t = samp[ndim * i + j];
      samp[ndim * i + j] = samp[ndim * other + j];
      samp[ndim * other + j] = t;
    }
  }
}

static void stratified_1d(float *samp, int n, pbrt_rng *r, int jitter) {
  float inv = 1.0f / (float)n;
  for (int i = 0; i < n; ++i) {
    float delta = jitter ? rng_float(r) : 0.5f;
    float v = ((float)i + delta) * inv;
    samp[i] = v < one_minus_epsilon ? v : one_minus_epsilon;
  }
}

static void stratified_2d(float *samp, int nx, int ny, pbrt_rng *r, int jitter) {
  float dx = 1.0f / (float)nx, dy = 1.0f / (float)ny;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      float jx = jitter ? rng_float(r) : 0.5f;
      float jy = jitter ? rng_float(r) : 0.5f;
      float vx = ((float)x + jx) * dx, vy = ((float)y + jy) * dy;
      *samp++ = vx < one_minus_epsilon ? vx : one_minus_epsilon;
      *samp++ = vy < one_minus_epsilon ? vy : one_minus_epsilon;
    }
}

static void latin_hypercube(float *samples, int n, int ndim, pbrt_rng *r) {
  float inv = 1.0f / (float)n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < ndim; ++j) {
      float sj = ((float)i + rng_float(r)) * inv;
      samples[ndim * i + j] = sj < one_minus_epsilon ? sj : one_minus_epsilon;
    }
  for (int i = 0; i < ndim; ++i)
    for (int j = 0; j < n; ++j) {
      int other = j + (int)rng_bounded(r, (uint32_t)(n - j));
      float t = samples[ndim * j + i];
      samples[ndim * j + i] = samples[ndim * other + i];
      samples[ndim * other + i] = t;
    }
}

/* lowdiscrepancy.h's CSobol[1] as pbrt-v3 lists it (CSobol[0] is CVanDerCorput: 2^31 >> i). */
static const uint32_t csobol1[32] = {
    0x80000000, 0xc0000000, 0xa0000000, 0xf0000000, 0x88000000, 0xcc000000, 0xaa000000, 0xff000000,
    0x80800000, 0xc0c00000, 0xa0a00000, 0xf0f00000, 0x88880000, 0xcccc0000, 0xaaaa0000, 0xffff0000,
    0x80008000, 0xc000c000, 0xa000a000, 0xf000f000, 0x88008800, 0xcc00cc00, 0xaa00aa00, 0xff00ff00,
    0x80808080, 0xc0c0c0c0, 0xa0a0a0a0, 0xf0f0f0f0, 0x88888888, 0xcccccccc, 0xaaaaaaaa, 0xffffffff};

static int count_trailing_zeros(uint32_t v) {
  int n = 0;
  for (; !(v & 1u); v >>= 1) ++n;
  return n;
}

/* VanDerCorput (ndim 1) / Sobol2D (ndim 2) of nPixelSamples groups of nSamplesPerPixelSample. */
static void zerotwo(int per, int spp, float *samples, int ndim, pbrt_rng *r) {
  uint32_t v[2];
  v[0] = rng_u32(r);
  if (ndim == 2) v[1] = rng_u32(r);
  for (uint32_t i = 0; i < (uint32_t)(per * spp); ++i) {
    for (int c = 0; c < ndim; ++c) samples[(int)i * ndim + c] = (float)v[c] * 0x1p-32f;
    int z = count_trailing_zeros(i + 1);
    v[0] ^= 0x80000000u >> z;
    if (ndim == 2) v[1] ^= csobol1[z];
  }
  for (int i = 0; i < spp; ++i) shuffle(samples + i * per * ndim, per, ndim, r);
  shuffle(samples, spp, per * ndim, r);
}

/* ---------- the samplers (random.cpp, stratified.cpp, zerotwosequence.cpp, sampler.cpp) ---------- */

enum { MAX_SPP = 16, MAX_DIMS = 4, MAX_ARRAYS = 4, MAX_ARRAY = 8, MAX_VALUES = 64 };

typedef struct model {
  clr_sampler_type type;
  int spp, xs, ys, jitter, dims;
  const clr_sample_request *req;
  int nreq;
  pbrt_rng rng;
  float s1[MAX_DIMS][MAX_SPP], s2[MAX_DIMS][2 * MAX_SPP];
  int n1, n2, size1[MAX_ARRAYS], size2[MAX_ARRAYS];
  float a1[MAX_ARRAYS][MAX_SPP * MAX_ARRAY], a2[MAX_ARRAYS][2 * MAX_SPP * MAX_ARRAY];
} model;

static void model_start_pixel(model *m) {
  pbrt_rng *r = &m->rng;
  if (m->type == CLR_SAMPLER_RANDOM) {
    for (int i = 0; i < m->n1; ++i)
      for (int j = 0; j < m->size1[i] * m->spp; ++j) m->a1[i][j] = rng_float(r);
    for (int i = 0; i < m->n2; ++i)
      for (int j = 0; j < 2 * m->size2[i] * m->spp; ++j) m->a2[i][j] = rng_float(r);
  } else if (m->type == CLR_SAMPLER_STRATIFIED) {
    for (int i = 0; i < m->dims; ++i) {
      stratified_1d(m->s1[i], m->spp, r, m->jitter);
      shuffle(m->s1[i], m->spp, 1, r);
    }
    for (int i = 0; i < m->dims; ++i) {
      stratified_2d(m->s2[i], m->xs, m->ys, r, m->jitter);
      shuffle(m->s2[i], m->spp, 2, r);
    }
    for (int i = 0; i < m->n1; ++i)
      for (int j = 0; j < m->spp; ++j) {
        int count = m->size1[i];
        stratified_1d(&m->a1[i][j * count], count, r, m->jitter);
        shuffle(&m->a1[i][j * count], count, 1, r);
      }
    for (int i = 0; i < m->n2; ++i)
      for (int j = 0; j < m->spp; ++j)
        latin_hypercube(&m->a2[i][2 * j * m->size2[i]], m->size2[i], 2, r);
  } else {
    int first2d = 0;
    if (m->type == CLR_SAMPLER_MAXMINDIST) { /* maxmin.cpp: CMaxMinDist[2] for 4 samples */
      static const uint32_t cpixel[2] = {0xc0000000, 0x80000000};
      assert_int_equal(m->spp, 4);
      float inv = 1.0f / (float)m->spp;
      for (int i = 0; i < m->spp; ++i) {
        uint32_t v = (i & 1 ? cpixel[0] : 0u) ^ (i & 2 ? cpixel[1] : 0u);
        m->s2[0][2 * i] = (float)i * inv;
        m->s2[0][2 * i + 1] = (float)v * 0x1p-32f;
      }
      shuffle(m->s2[0], m->spp, 2, r);
      first2d = 1;
    }
    for (int i = 0; i < m->dims; ++i) zerotwo(1, m->spp, m->s1[i], 1, r);
    for (int i = first2d; i < m->dims; ++i) zerotwo(1, m->spp, m->s2[i], 2, r);
    for (int i = 0; i < m->n1; ++i) zerotwo(m->size1[i], m->spp, m->a1[i], 1, r);
    for (int i = 0; i < m->n2; ++i) zerotwo(m->size2[i], m->spp, m->a2[i], 2, r);
  }
}

/* Sample s as an integrator renders it: Get1D/Get2D/Get*Array in request order. */
static void model_render_sample(model *m, int s, float *vec) {
  int pixel_sampler = m->type != CLR_SAMPLER_RANDOM;
  int cur1 = 0, cur2 = 0, arr1 = 0, arr2 = 0, o = 0;
  for (int k = 0; k < m->nreq; ++k) {
    const clr_sample_request *q = &m->req[k];
    if (q->array_size > 0 && q->dims == 1) {
      for (int j = 0; j < q->array_size; ++j) vec[o++] = m->a1[arr1][s * q->array_size + j];
      ++arr1;
    } else if (q->array_size > 0) {
      for (int j = 0; j < 2 * q->array_size; ++j) vec[o++] = m->a2[arr2][2 * s * q->array_size + j];
      ++arr2;
    } else if (q->dims == 1) {
      vec[o++] = pixel_sampler && cur1 < m->dims ? m->s1[cur1++][s] : rng_float(&m->rng);
    } else if (pixel_sampler && cur2 < m->dims) {
      vec[o++] = m->s2[cur2][2 * s];
      vec[o++] = m->s2[cur2++][2 * s + 1];
    } else {
      vec[o++] = rng_float(&m->rng); /* Point2f(x, y): x drawn first, as clrender defines */
      vec[o++] = rng_float(&m->rng);
    }
  }
}

/* SamplerIntegrator::Render over the tile holding (want_x, want_y): the pixel's vectors. */
static void model_pixel(model *m, clr_bounds2i sample_bounds, clr_bounds2i pixel_bounds, int want_x,
                        int want_y, float *vecs) {
  int tiles_x = (sample_bounds.x1 - sample_bounds.x0 + 15) / 16;
  int tx = (want_x - sample_bounds.x0) / 16, ty = (want_y - sample_bounds.y0) / 16;
  m->rng = rng_sequence((uint64_t)(ty * tiles_x + tx));
  m->n1 = m->n2 = 0;
  for (int k = 0; k < m->nreq; ++k)
    if (m->req[k].array_size > 0) {
      if (m->req[k].dims == 1)
        m->size1[m->n1++] = m->req[k].array_size;
      else
        m->size2[m->n2++] = m->req[k].array_size;
    }
  int x0 = sample_bounds.x0 + 16 * tx, y0 = sample_bounds.y0 + 16 * ty;
  int x1 = x0 + 16 < sample_bounds.x1 ? x0 + 16 : sample_bounds.x1;
  int y1 = y0 + 16 < sample_bounds.y1 ? y0 + 16 : sample_bounds.y1;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      model_start_pixel(m);
      int inside = x >= pixel_bounds.x0 && x < pixel_bounds.x1 && y >= pixel_bounds.y0 &&
                   y < pixel_bounds.y1;
      if (x == want_x && y == want_y) {
        for (int s = 0; s < m->spp; ++s) model_render_sample(m, s, vecs + s * MAX_VALUES);
        return;
      }
      if (inside)
        for (int s = 0; s < m->spp; ++s) {
          float scratch[MAX_VALUES];
          model_render_sample(m, s, scratch);
        }
    }
  fail_msg("pixel (%d, %d) not found", want_x, want_y);
}

/* ---------- clrender against the model ---------- */

/* Camera, a 1D array, a 2D array, then singles past dimensions = 2 (RNG fallbacks). */
static const clr_sample_request layout[] = {{2, 0}, {1, 0}, {2, 0}, {1, 3}, {2, 4},
                                            {1, 0}, {2, 0}, {2, 0}, {1, 0}, {1, 0}};
#define LAYOUT_COUNT ((int)(sizeof layout / sizeof layout[0]))

static clr_sampler make(clr_sampler_type type, float radius, int spp) {
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, type);
  d.seeding = CLR_SEEDING_PBRT_V3;
  d.pixel_samples = spp;
  d.x_samples = 2;
  d.y_samples = 2;
  d.dimensions = 2;
  d.film.x_resolution = 40;
  d.film.y_resolution = 24;
  d.film.filter_radius[0] = d.film.filter_radius[1] = radius;
  clr_sampler s = NULL;
  assert_int_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
  return s;
}

static uint32_t bits(float f) {
  uint32_t u;
  memcpy(&u, &f, 4);
  return u;
}

/* clrender's values of pixel (x, y) into out[s * MAX_VALUES + v]. */
static void generate(clr_sampler s, int x, int y, const clr_sample_request *req, int nreq,
                     float *out) {
  int32_t per = 0;
  assert_int_equal(clr_sample_layout_values(req, nreq, &per), CLR_SUCCESS);
  assert_true(per <= MAX_VALUES);
  int spp = clr_sampler_spp(s);
  float *values = malloc(sizeof(float) * (size_t)spp * (size_t)per);
  assert_non_null(values);
  clr_sample_batch b;
  clr_sample_batch_init(&b);
  b.pixels = (clr_bounds2i){x, y, x + 1, y + 1};
  b.requests = req;
  b.request_count = nreq;
  clr_sample_output o;
  clr_sample_output_init(&o);
  o.host_values = values;
  assert_int_equal(clr_sampler_generate_reference(s, &b, &o), CLR_SUCCESS);
  for (int i = 0; i < spp; ++i)
    memcpy(out + i * MAX_VALUES, values + i * per, sizeof(float) * (size_t)per);
  free(values);
}

static void check_pixel(clr_sampler_type type, float radius, int x, int y) {
  clr_sampler s = make(type, radius, type == CLR_SAMPLER_ZEROTWO ? 3 : 4); /* 02: 3 -> 4 */
  if (type == CLR_SAMPLER_MAXMINDIST) assert_int_equal(clr_sampler_spp(s), 4);
  model m;
  memset(&m, 0, sizeof m);
  m.type = type;
  m.spp = clr_sampler_spp(s);
  assert_int_equal(m.spp, 4);
  m.xs = m.ys = 2;
  m.jitter = 1;
  m.dims = 2;
  m.req = layout;
  m.nreq = LAYOUT_COUNT;
  static float want[MAX_SPP * MAX_VALUES], got[MAX_SPP * MAX_VALUES];
  model_pixel(&m, clr_sampler_sample_bounds(s), clr_sampler_pixel_bounds(s), x, y, want);
  generate(s, x, y, layout, LAYOUT_COUNT, got);
  int32_t per = 0;
  clr_sample_layout_values(layout, LAYOUT_COUNT, &per);
  for (int i = 0; i < m.spp; ++i)
    for (int v = 0; v < per; ++v)
      if (bits(want[i * MAX_VALUES + v]) != bits(got[i * MAX_VALUES + v]))
        fail_msg("%s radius %g pixel (%d, %d) sample %d value %d: got %a, pbrt-v3 %a",
                 clr_sampler_type_name(type), (double)radius, x, y, i, v,
                 (double)got[i * MAX_VALUES + v], (double)want[i * MAX_VALUES + v]);
  clr_sampler_release(s);
}

static void test_later_pixels_of_a_tile_match_pbrt_v3(void **state) {
  (void)state;
  const clr_sampler_type types[] = {CLR_SAMPLER_RANDOM, CLR_SAMPLER_STRATIFIED, CLR_SAMPLER_ZEROTWO,
                                    CLR_SAMPLER_MAXMINDIST};
  for (int t = 0; t < 4; ++t) {
    /* Radius 2: sample bounds [-2, 42) x [-2, 26); pixel (0, 0) is pixel 34 of tile 0. */
    check_pixel(types[t], 2.0f, 0, 0);
    check_pixel(types[t], 2.0f, 1, 0);
    check_pixel(types[t], 2.0f, 13, 13); /* the last pixel of tile 0 */
    check_pixel(types[t], 2.0f, 20, 17); /* tile 4 */
    /* Box: sample bounds = pixel bounds; the tile's first pixel and later ones. */
    check_pixel(types[t], 0.5f, 0, 0);
    check_pixel(types[t], 0.5f, 3, 2);
    check_pixel(types[t], 0.5f, 39, 23); /* tile 5, clipped */
  }
}

/* Numbers from a separate (Python) transcription of pbrt-v3: pixel (0,0) with the radius-2 filter,
 * sample 0, the film offset (2D request 0) and time. */
static void test_pinned_values(void **state) {
  (void)state;
  static const struct {
    clr_sampler_type type;
    float v[3];
  } pinned[] = {
      {CLR_SAMPLER_RANDOM, {0x1.e4344ap-2f, 0x1.79d2f8p-1f, 0x1.789304p-1f}},
      {CLR_SAMPLER_ZEROTWO, {0x1.50925ap-1f, 0x1.94f2cep-2f, 0x1.517802p-4f}},
      {CLR_SAMPLER_MAXMINDIST, {0x1.8p-1f, 0x1p-2f, 0x1.0c323cp-2f}},
  };
  static float got[MAX_SPP * MAX_VALUES];
  for (size_t i = 0; i < sizeof pinned / sizeof pinned[0]; ++i) {
    clr_sampler s = make(pinned[i].type, 2.0f, 4); /* 40x24, dimensions 2, `layout` */
    generate(s, 0, 0, layout, LAYOUT_COUNT, got);
    for (int v = 0; v < 3; ++v)
      if (bits(got[v]) != bits(pinned[i].v[v]))
        fail_msg("%s value %d: got %a, pinned %a", clr_sampler_type_name(pinned[i].type), v,
                 (double)got[v], (double)pinned[i].v[v]);
    clr_sampler_release(s);
  }
}

/* ---------- (0,2)-sequence properties ---------- */

/* Every elementary interval of area 1/n (n = 2^k, shapes 2^-j x 2^-(k-j)) holds one point. */
static void expect_02_net(const float *pts, int stride, int n, const char *what) {
  int k = 0;
  while ((1 << k) < n) ++k;
  assert_int_equal(1 << k, n);
  int *cells = malloc(sizeof(int) * (size_t)n);
  assert_non_null(cells);
  for (int j = 0; j <= k; ++j) {
    memset(cells, 0, sizeof(int) * (size_t)n);
    int nx = 1 << j, ny = 1 << (k - j);
    for (int i = 0; i < n; ++i) {
      float x = pts[i * stride], y = pts[i * stride + 1];
      assert_true(x >= 0.0f && x < 1.0f && y >= 0.0f && y < 1.0f);
      int cx = (int)floor((double)x * nx), cy = (int)floor((double)y * ny);
      if (cells[cy * nx + cx]++)
        fail_msg("%s: n %d, interval %dx%d: two points in (%d, %d)", what, n, nx, ny, cx, cy);
    }
  }
  free(cells);
}

static void expect_stratified_1d(const float *vals, int stride, int n, const char *what) {
  int *cells = calloc((size_t)n, sizeof(int));
  assert_non_null(cells);
  for (int i = 0; i < n; ++i) {
    float v = vals[i * stride];
    assert_true(v >= 0.0f && v < 1.0f);
    if (cells[(int)floor((double)v * n)]++)
      fail_msg("%s: two values in stratum of %g", what, (double)v);
  }
  free(cells);
}

/* 02sequence and maxmindist (whose first 2D stream is its own (0,m,2)-net). */
static void test_zerotwo_nets_and_strata(void **state) {
  (void)state;
  /* film 2D, time 1D, lens 2D, a 2D array of 8, a 1D array of 4. */
  static const clr_sample_request req[] = {{2, 0}, {1, 0}, {2, 0}, {2, 8}, {1, 4}};
  const int per = 2 + 1 + 2 + 16 + 4;
  for (int type = CLR_SAMPLER_ZEROTWO; type <= CLR_SAMPLER_MAXMINDIST; ++type)
    for (int spp = 1; spp <= 128; spp = spp == 1 ? 4 : 2 * spp) /* maxmindist: not 2 */
      for (int seeding = 0; seeding < 2; ++seeding) {
        clr_sampler_desc d;
        clr_sampler_desc_init(&d, (clr_sampler_type)type);
        d.pixel_samples = spp;
        d.seeding = seeding ? CLR_SEEDING_PIXEL : CLR_SEEDING_PBRT_V3;
        d.film.x_resolution = 20;
        d.film.y_resolution = 18;
        clr_sampler s = NULL;
        assert_int_equal(clr_sampler_create(NULL, &d, &s), CLR_SUCCESS);
        clr_sample_batch b;
        clr_sample_batch_init(&b);
        b.pixels = (clr_bounds2i){14, 13, 19, 17};
        b.requests = req;
        b.request_count = 5;
        size_t pixels = 5 * 4;
        float *v = malloc(sizeof(float) * pixels * (size_t)spp * (size_t)per);
        assert_non_null(v);
        clr_sample_output o;
        clr_sample_output_init(&o);
        o.host_values = v;
        assert_int_equal(clr_sampler_generate_reference(s, &b, &o), CLR_SUCCESS);
        for (size_t p = 0; p < pixels; ++p) {
          const float *pv = v + p * (size_t)spp * (size_t)per;
          expect_02_net(pv + 0, per, spp, "film offset");
          expect_02_net(pv + 3, per, spp, "lens");
          expect_stratified_1d(pv + 2, per, spp, "time");
          for (int k = 0; k < 5; ++k) expect_stratified_1d(pv + k, per, spp, "camera dimension");
          for (int i = 0; i < spp; ++i) {
            expect_02_net(pv + i * per + 5, 2, 8, "2D array of one sample");
            expect_stratified_1d(pv + i * per + 21, 1, 4, "1D array of one sample");
          }
        }
        free(v);
        clr_sampler_release(s);
      }
}

static void test_zerotwo_names_and_rounding(void **state) {
  (void)state;
  clr_sampler_type t = CLR_SAMPLER_RANDOM;
  assert_int_equal(clr_sampler_type_from_name("02sequence", &t), CLR_SUCCESS);
  assert_int_equal(t, CLR_SAMPLER_ZEROTWO);
  t = CLR_SAMPLER_RANDOM;
  assert_int_equal(clr_sampler_type_from_name("lowdiscrepancy", &t), CLR_SUCCESS);
  assert_int_equal(t, CLR_SAMPLER_ZEROTWO);
  assert_int_equal((int)CLR_SAMPLER_ZEROTWO, 4);
  assert_string_equal(clr_sampler_type_name(CLR_SAMPLER_ZEROTWO), "02sequence");
  assert_int_equal(clr_sampler_round_count(CLR_SAMPLER_ZEROTWO, 5), 8);
  assert_int_equal(clr_sampler_round_count(CLR_SAMPLER_ZEROTWO, 8), 8);
  assert_int_equal(clr_sampler_round_count(CLR_SAMPLER_STRATIFIED, 5), 5);
  clr_sampler s = make(CLR_SAMPLER_ZEROTWO, 0.5f, 17);
  assert_int_equal(clr_sampler_spp(s), 32);
  assert_int_equal(clr_sampler_has_global_index(s), 0);
  clr_sampler_release(s);
  assert_int_equal(clr_sampler_type_from_name("maxmindist", &t), CLR_SUCCESS);
  assert_int_equal(t, CLR_SAMPLER_MAXMINDIST);
  assert_int_equal((int)CLR_SAMPLER_MAXMINDIST, 5);
  assert_int_equal(clr_sampler_round_count(CLR_SAMPLER_MAXMINDIST, 9), 16);
  s = make(CLR_SAMPLER_MAXMINDIST, 0.5f, (1 << 17) - 1); /* pbrt-v3's most */
  assert_int_equal(clr_sampler_spp(s), 1 << 17);
  clr_sampler_release(s);
  clr_sampler_desc d;
  clr_sampler_desc_init(&d, CLR_SAMPLER_MAXMINDIST);
  d.pixel_samples = 1 << 17; /* pbrt-v3 aborts */
  s = NULL;
  assert_int_equal(clr_sampler_create(NULL, &d, &s), CLR_ERROR_INVALID_SPP);
  assert_null(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_later_pixels_of_a_tile_match_pbrt_v3),
      cmocka_unit_test(test_pinned_values),
      cmocka_unit_test(test_zerotwo_nets_and_strata),
      cmocka_unit_test(test_zerotwo_names_and_rounding),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
