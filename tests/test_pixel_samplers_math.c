/* Host checks of the pixel samplers' shared kernel math (stratified, random): PCG32, strata and
 * Latin hypercube properties, and bit-exact agreement with a direct model of pbrt-v3's
 * StratifiedSampler/RandomSampler driven by SamplerIntegrator::Render's tile loop. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
/* GCC does not know C99's STDC FP_CONTRACT pragma (-ffp-contract=off does its work). */
#pragma GCC diagnostic ignored "-Wunknown-pragmas"
#include "pixel_sampler_funcs.h"

#define MAX_REQ 24
#define MAX_SPP 64
#define MAX_N 16
#define MAX_STREAMS 8
#define MAX_ARRAYS 6
#define MAX_VALUES 256

typedef struct {
  int dims, array_size;
} request;

/* ---------- the host side of the contract: params and slots from a request list ---------- */

static void fill_layout(clr_sampler_params *p, clr_request_slot *slots, const request *req,
                        int nreq) {
  int offset = 0, singles[3] = {0, 0, 0}, arrays[3] = {0, 0, 0}, draws = 0;
  for (int k = 0; k < nreq; ++k) {
    clr_request_slot *s = &slots[k];
    memset(s, 0, sizeof *s);
    s->dims = req[k].dims;
    s->array_size = req[k].array_size;
    s->first_value = offset;
    s->source = -1;
    if (s->array_size > 0) {
      s->source = arrays[s->dims]++;
      s->inv_array_size = 1.0f / (float)s->array_size;
      offset += s->array_size * s->dims;
      continue;
    }
    int stream = singles[s->dims]++;
    if (p->type == CLR_SAMPLER_TYPE_STRATIFIED && stream < p->dimensions) {
      s->source = stream;
    } else {
      s->rng_offset = draws;
      draws += s->dims;
    }
    offset += s->dims;
  }
  p->values_per_sample = offset;
  p->fallback_draws_per_sample = draws;
  p->request_count = nreq;
}

static clr_sampler_params make_params(int type, int xs, int ys, int spp, int jitter, int dims) {
  clr_sampler_params p;
  memset(&p, 0, sizeof p);
  p.type = type;
  p.x_samples = xs;
  p.y_samples = ys;
  p.spp = type == CLR_SAMPLER_TYPE_STRATIFIED ? xs * ys : spp;
  p.jitter = jitter;
  p.dimensions = type == CLR_SAMPLER_TYPE_STRATIFIED ? dims : 0;
  p.inv_x_samples = 1.0f / (float)xs;
  p.inv_y_samples = 1.0f / (float)ys;
  p.inv_spp = 1.0f / (float)p.spp;
  p.seeding = CLR_SEEDING_TYPE_PIXEL;
  p.seed = 7;
  p.sample_x0 = -1, p.sample_y0 = -1, p.sample_x1 = 37, p.sample_y1 = 21;
  p.pixel_x0 = 0, p.pixel_y0 = 0, p.pixel_x1 = 36, p.pixel_y1 = 20;
  p.tiles_x = (p.sample_x1 - p.sample_x0 + CLR_PBRT_TILE_SIZE - 1) / CLR_PBRT_TILE_SIZE;
  p.first_sample = 0;
  p.sample_count = p.spp;
  p.batch_width = p.batch_height = 1;
  return p;
}

static float scratch[2 * 4096];

/* ---------- a direct model of pbrt-v3's samplers, written independently of the kernels ---------- */

static float ref_uniform(clr_pcg32 *r) {
  float f = (float)clr_pcg32_next(r) * 0x1p-32f;
  return f < 0x1.fffffep-1f ? f : 0x1.fffffep-1f;
}

static uint32_t ref_uint(clr_pcg32 *r, uint32_t b) {
  uint32_t threshold = (0u - b) % b;
  for (;;) {
    uint32_t v = clr_pcg32_next(r);
    if (v >= threshold) return v % b;
  }
}

static float ref_min1(float v) { return v < 0x1.fffffep-1f ? v : 0x1.fffffep-1f; }

static void ref_stratified_1d(float *samp, int n, clr_pcg32 *r, int jitter) {
  float inv = 1.0f / (float)n;
  for (int i = 0; i < n; ++i) {
    float delta = jitter ? ref_uniform(r) : 0.5f;
    samp[i] = ref_min1(((float)i + delta) * inv);
  }
}

typedef struct {
  float x, y;
} point2;

static void ref_stratified_2d(point2 *samp, int nx, int ny, clr_pcg32 *r, int jitter) {
  float dx = 1.0f / (float)nx, dy = 1.0f / (float)ny;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      float jx = jitter ? ref_uniform(r) : 0.5f;
      float jy = jitter ? ref_uniform(r) : 0.5f;
      samp->x = ref_min1(((float)x + jx) * dx);
      samp->y = ref_min1(((float)y + jy) * dy);
      ++samp;
    }
}

static void ref_shuffle(void *samp, int count, size_t elem, clr_pcg32 *r) {
  unsigned char *b = samp, tmp[64];
  for (int i = 0; i < count; ++i) {
    int other = i + (int)ref_uint(r, (uint32_t)(count - i));
    memcpy(tmp, b + elem * i, elem);
    memcpy(b + elem * i, b + elem * other, elem);
    memcpy(b + elem * other, tmp, elem);
  }
}

static void ref_latin_hypercube(float *samples, int n, int ndim, clr_pcg32 *r) {
  float inv = 1.0f / (float)n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < ndim; ++j)
      samples[ndim * i + j] = ref_min1(((float)i + ref_uniform(r)) * inv);
  for (int i = 0; i < ndim; ++i)
    for (int j = 0; j < n; ++j) {
      int other = j + (int)ref_uint(r, (uint32_t)(n - j));
      float t = samples[ndim * j + i];
      samples[ndim * j + i] = samples[ndim * other + i];
      samples[ndim * other + i] = t;
    }
}

typedef struct {
  const clr_sampler_params *p;
  const request *req;
  int nreq;
  clr_pcg32 rng;
  float s1[MAX_STREAMS][MAX_SPP];
  point2 s2[MAX_STREAMS][MAX_SPP];
  int n_arr[3], arr_size[3][MAX_ARRAYS];
  float a1[MAX_ARRAYS][MAX_SPP * MAX_N];
  point2 a2[MAX_ARRAYS][MAX_SPP * MAX_N];
} ref_sampler;

static ref_sampler ref;

static void ref_init(const clr_sampler_params *p, const request *req, int nreq, clr_pcg32 rng) {
  memset(&ref, 0, sizeof ref);
  ref.p = p;
  ref.req = req;
  ref.nreq = nreq;
  ref.rng = rng;
  for (int k = 0; k < nreq; ++k)
    if (req[k].array_size > 0)
      ref.arr_size[req[k].dims][ref.n_arr[req[k].dims]++] = req[k].array_size;
}

/* StratifiedSampler::StartPixel / RandomSampler::StartPixel. */
static void ref_start_pixel(void) {
  const clr_sampler_params *p = ref.p;
  clr_pcg32 *r = &ref.rng;
  int spp = p->spp;
  if (p->type == CLR_SAMPLER_TYPE_RANDOM) {
    for (int i = 0; i < ref.n_arr[1]; ++i)
      for (int j = 0; j < ref.arr_size[1][i] * spp; ++j) ref.a1[i][j] = ref_uniform(r);
    for (int i = 0; i < ref.n_arr[2]; ++i)
      for (int j = 0; j < ref.arr_size[2][i] * spp; ++j) {
        ref.a2[i][j].x = ref_uniform(r);
        ref.a2[i][j].y = ref_uniform(r);
      }
    return;
  }
  for (int i = 0; i < p->dimensions; ++i) {
    ref_stratified_1d(ref.s1[i], spp, r, p->jitter);
    ref_shuffle(ref.s1[i], spp, sizeof(float), r);
  }
  for (int i = 0; i < p->dimensions; ++i) {
    ref_stratified_2d(ref.s2[i], p->x_samples, p->y_samples, r, p->jitter);
    ref_shuffle(ref.s2[i], spp, sizeof(point2), r);
  }
  for (int i = 0; i < ref.n_arr[1]; ++i)
    for (int j = 0; j < spp; ++j) {
      int count = ref.arr_size[1][i];
      ref_stratified_1d(&ref.a1[i][j * count], count, r, p->jitter);
      ref_shuffle(&ref.a1[i][j * count], count, sizeof(float), r);
    }
  for (int i = 0; i < ref.n_arr[2]; ++i)
    for (int j = 0; j < spp; ++j) {
      int count = ref.arr_size[2][i];
      ref_latin_hypercube(&ref.a2[i][j * count].x, count, 2, r);
    }
}

/* Renders sample s the way an integrator would: Get1D/Get2D/Get*Array in request order. */
static void ref_render_sample(int s, float *vec) {
  int stratified = ref.p->type == CLR_SAMPLER_TYPE_STRATIFIED;
  int cur1 = 0, cur2 = 0, arr1 = 0, arr2 = 0, o = 0;
  for (int k = 0; k < ref.nreq; ++k) {
    const request *q = &ref.req[k];
    if (q->array_size > 0 && q->dims == 1) {
      for (int j = 0; j < q->array_size; ++j) vec[o++] = ref.a1[arr1][s * q->array_size + j];
      ++arr1;
    } else if (q->array_size > 0) {
      for (int j = 0; j < q->array_size; ++j) {
        vec[o++] = ref.a2[arr2][s * q->array_size + j].x;
        vec[o++] = ref.a2[arr2][s * q->array_size + j].y;
      }
      ++arr2;
    } else if (q->dims == 1) {
      vec[o++] = stratified && cur1 < ref.p->dimensions ? ref.s1[cur1++][s] : ref_uniform(&ref.rng);
    } else if (stratified && cur2 < ref.p->dimensions) {
      vec[o++] = ref.s2[cur2][s].x;
      vec[o++] = ref.s2[cur2++][s].y;
    } else {
      vec[o++] = ref_uniform(&ref.rng);
      vec[o++] = ref_uniform(&ref.rng);
    }
  }
}

/* All spp sample vectors of the current pixel; `render` says whether pbrt renders it (draws). */
static void ref_pixel_vectors(int render, float *vecs) {
  ref_start_pixel();
  clr_pcg32 saved = ref.rng;
  for (int s = 0; s < ref.p->spp; ++s) ref_render_sample(s, vecs + s * MAX_VALUES);
  if (!render) ref.rng = saved;
}

static float ref_vecs[MAX_SPP * MAX_VALUES];

/* Compares a kernel pixel output (samples first_sample..) with the reference vectors. */
static void expect_pixel_equals_ref(const clr_sampler_params *p, const float *out) {
  for (int s = 0; s < p->sample_count; ++s)
    for (int v = 0; v < p->values_per_sample; ++v) {
      float want = ref_vecs[(p->first_sample + s) * MAX_VALUES + v];
      float got = out[s * p->values_per_sample + v];
      if (clr_as_uint(want) != clr_as_uint(got))
        fail_msg("sample %d value %d: got %a want %a", p->first_sample + s, v, (double)got,
                 (double)want);
      assert_true(got >= 0.0f && got < 1.0f);
    }
}

/* ---------- PCG32 ---------- */

static void test_pcg32_reference_outputs(void **state) {
  (void)state;
  /* pcg32_srandom_r(42, 54): state 0, inc (54 << 1) | 1, step, state += 42, step. */
  clr_pcg32 r = {0u, (54u << 1) | 1u};
  clr_pcg32_next(&r);
  r.state += 42u;
  clr_pcg32_next(&r);
  const uint32_t expected[6] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
  for (int i = 0; i < 6; ++i) assert_int_equal(clr_pcg32_next(&r), expected[i]);
  /* pbrt's SetSequence is the same with initstate = its default state. */
  clr_pcg32 a = clr_pcg32_sequence(54u), b = {0u, (54u << 1) | 1u};
  clr_pcg32_next(&b);
  b.state += 0x853c49e6748fea9bULL;
  clr_pcg32_next(&b);
  assert_true(a.state == b.state && a.inc == b.inc);
}

static void test_pcg32_advance_matches_stepping(void **state) {
  (void)state;
  const uint64_t deltas[] = {0, 1, 2, 3, 17, 64, 1000, 4097};
  for (size_t d = 0; d < sizeof deltas / sizeof deltas[0]; ++d) {
    clr_pcg32 a = clr_pcg32_sequence(12345u), b = a;
    for (uint64_t i = 0; i < deltas[d]; ++i) clr_pcg32_next(&a);
    clr_pcg32_advance(&b, deltas[d]);
    assert_true(a.state == b.state);
    assert_int_equal(clr_pcg32_next(&a), clr_pcg32_next(&b));
  }
  /* Advancing 2^64 - 1 is stepping back once. */
  clr_pcg32 c = clr_pcg32_sequence(3u), d = c;
  clr_pcg32_next(&c);
  clr_pcg32_advance(&c, UINT64_MAX);
  assert_true(c.state == d.state);
}

/* ---------- strata and Latin hypercube properties ---------- */

static const request property_layout[] = {{1, 0}, {2, 0},  {1, 0}, {2, 0},  {1, 0}, {2, 0},
                                          {1, 1}, {1, 3},  {1, 7}, {1, 16}, {2, 1}, {2, 3},
                                          {2, 7}, {2, 16}, {1, 0}, {2, 0}};

static int stratum(float v, int n) { return (int)floor((double)v * n); }

static void expect_permutation(const int *cells, int n) {
  int seen[MAX_SPP * MAX_N] = {0};
  for (int i = 0; i < n; ++i) {
    assert_in_range(cells[i], 0, n - 1);
    assert_int_equal(seen[cells[i]]++, 0);
  }
}

static void check_properties(int jitter) {
  clr_sampler_params p = make_params(CLR_SAMPLER_TYPE_STRATIFIED, 4, 3, 0, jitter, 3);
  clr_request_slot slots[MAX_REQ];
  int nreq = (int)(sizeof property_layout / sizeof property_layout[0]);
  fill_layout(&p, slots, property_layout, nreq);
  assert_int_equal(p.fallback_draws_per_sample, 3);
  p.scratch_floats = clr_pixel_sampler_scratch_need(&p, slots);
  assert_int_equal(p.scratch_floats, 32);
  static float out[MAX_SPP * MAX_VALUES];
  for (int pixel = 0; pixel < 5; ++pixel) {
    clr_pixel_sampler_pixel(&p, slots, pixel, 2 * pixel, out, scratch);
    int n = p.spp, cells[MAX_SPP * MAX_N];
    for (int k = 0; k < nreq; ++k) {
      const clr_request_slot *s = &slots[k];
      for (int j = 0; j < n * p.values_per_sample; ++j)
        assert_true(out[j] >= 0.0f && out[j] < 1.0f);
      if (s->array_size == 0 && s->source >= 0 && s->dims == 1) {
        for (int i = 0; i < n; ++i)
          cells[i] = stratum(out[i * p.values_per_sample + s->first_value], n);
        expect_permutation(cells, n);
        if (!jitter)
          for (int i = 0; i < n; ++i) {
            float v = out[i * p.values_per_sample + s->first_value];
            assert_true(v == ((float)cells[i] + 0.5f) * p.inv_spp);
          }
      } else if (s->array_size == 0 && s->source >= 0) {
        for (int i = 0; i < n; ++i) {
          const float *v = &out[i * p.values_per_sample + s->first_value];
          int cx = stratum(v[0], p.x_samples), cy = stratum(v[1], p.y_samples);
          cells[i] = cy * p.x_samples + cx;
          if (!jitter) {
            assert_true(v[0] == ((float)cx + 0.5f) * p.inv_x_samples);
            assert_true(v[1] == ((float)cy + 0.5f) * p.inv_y_samples);
          }
        }
        expect_permutation(cells, n);
      } else if (s->array_size > 0) {
        int m = s->array_size;
        for (int i = 0; i < n; ++i) {
          const float *v = &out[i * p.values_per_sample + s->first_value];
          for (int c = 0; c < s->dims; ++c) {
            for (int j = 0; j < m; ++j) cells[j] = stratum(v[j * s->dims + c], m);
            expect_permutation(cells, m);
            if (s->dims == 1 && !jitter)
              for (int j = 0; j < m; ++j)
                assert_true(v[j] == ((float)cells[j] + 0.5f) * s->inv_array_size);
          }
        }
      }
    }
  }
}

static void test_stratified_strata_jittered(void **state) {
  (void)state;
  check_properties(1);
}

static void test_stratified_strata_centred(void **state) {
  (void)state;
  check_properties(0);
}

/* ---------- bit-exact agreement with the pbrt-v3 model ---------- */

static const request mixed_layout[] = {{2, 0},  {1, 0}, {2, 0}, {1, 3}, {2, 7}, {1, 0}, {2, 0},
                                       {1, 16}, {1, 0}, {2, 0}, {2, 1}, {2, 0}, {1, 0}, {1, 0}};

static void check_pixel_against_ref(clr_sampler_params p) {
  clr_request_slot slots[MAX_REQ];
  int nreq = (int)(sizeof mixed_layout / sizeof mixed_layout[0]);
  fill_layout(&p, slots, mixed_layout, nreq);
  p.scratch_floats = clr_pixel_sampler_scratch_need(&p, slots);
  static float out[MAX_SPP * MAX_VALUES];
  const int pixels[3][2] = {{0, 0}, {5, -3}, {123, 45}};
  for (int i = 0; i < 3; ++i) {
    clr_pcg32 rng = clr_pixel_stream(&p, pixels[i][0], pixels[i][1]);
    ref_init(&p, mixed_layout, nreq, rng);
    ref_pixel_vectors(1, ref_vecs);
    clr_pcg32 after = rng;
    clr_pixel_sampler_start_pixel(&p, slots, &after, out, scratch);
    expect_pixel_equals_ref(&p, out);
    /* RNG consumption: the state after StartPixel plus the rendering draws is the model's. */
    clr_pcg32_advance(&after, (uint64_t)p.spp * (uint64_t)p.fallback_draws_per_sample);
    assert_true(after.state == ref.rng.state);
    /* A sub-range of samples is the same slice. */
    clr_sampler_params q = p;
    q.first_sample = p.spp > 2 ? 1 : 0;
    q.sample_count = p.spp > 2 ? p.spp - 2 : p.spp;
    memset(out, 0, sizeof out);
    clr_pixel_sampler_pixel(&q, slots, pixels[i][0], pixels[i][1], out, scratch);
    expect_pixel_equals_ref(&q, out);
  }
}

static void test_stratified_matches_pbrt_model(void **state) {
  (void)state;
  check_pixel_against_ref(make_params(CLR_SAMPLER_TYPE_STRATIFIED, 3, 2, 0, 1, 2));
  check_pixel_against_ref(make_params(CLR_SAMPLER_TYPE_STRATIFIED, 3, 2, 0, 0, 2));
  check_pixel_against_ref(make_params(CLR_SAMPLER_TYPE_STRATIFIED, 5, 5, 0, 1, 4));
  check_pixel_against_ref(make_params(CLR_SAMPLER_TYPE_STRATIFIED, 1, 1, 0, 1, 0));
}

static void test_random_matches_pbrt_model(void **state) {
  (void)state;
  check_pixel_against_ref(make_params(CLR_SAMPLER_TYPE_RANDOM, 1, 1, 5, 1, 0));
  check_pixel_against_ref(make_params(CLR_SAMPLER_TYPE_RANDOM, 1, 1, 1, 1, 0));
}

/* pbrt-v3's render loop for one tile: writes the model's vectors of (want_x, want_y). */
static void ref_tile_pixel(const clr_sampler_params *p, int nreq, int tx, int ty, int want_x,
                           int want_y) {
  ref_init(p, mixed_layout, nreq, clr_pcg32_sequence((uint64_t)(ty * p->tiles_x + tx)));
  int x0 = p->sample_x0 + tx * 16, y0 = p->sample_y0 + ty * 16;
  int x1 = x0 + 16 < p->sample_x1 ? x0 + 16 : p->sample_x1;
  int y1 = y0 + 16 < p->sample_y1 ? y0 + 16 : p->sample_y1;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      int inside = x >= p->pixel_x0 && x < p->pixel_x1 && y >= p->pixel_y0 && y < p->pixel_y1;
      ref_pixel_vectors(inside, ref_vecs);
      if (x == want_x && y == want_y) return;
    }
  fail_msg("pixel (%d, %d) not in tile (%d, %d)", want_x, want_y, tx, ty);
}

static void check_tiles_against_ref(clr_sampler_params p, int bx, int by, int bw, int bh) {
  clr_request_slot slots[MAX_REQ];
  int nreq = (int)(sizeof mixed_layout / sizeof mixed_layout[0]);
  p.seeding = CLR_SEEDING_TYPE_PBRT_V3;
  fill_layout(&p, slots, mixed_layout, nreq);
  p.scratch_floats = clr_pixel_sampler_scratch_need(&p, slots);
  p.batch_x0 = bx, p.batch_y0 = by, p.batch_width = bw, p.batch_height = bh;
  p.first_sample = 1;
  p.sample_count = p.spp - 1;
  size_t pixel_floats = (size_t)p.sample_count * (size_t)p.values_per_sample;
  size_t total = (size_t)bw * (size_t)bh * pixel_floats;
  float *out = malloc((total + 1) * sizeof *out);
  assert_non_null(out);
  for (size_t i = 0; i <= total; ++i) out[i] = -1.0f;
  int tiles_y = (p.sample_y1 - p.sample_y0 + 15) / 16;
  for (int ty = 0; ty < tiles_y; ++ty)
    for (int tx = 0; tx < p.tiles_x; ++tx) clr_pixel_sampler_tile(&p, slots, tx, ty, out, scratch);
  assert_true(out[total] == -1.0f);
  for (int y = by; y < by + bh; ++y)
    for (int x = bx; x < bx + bw; ++x) {
      ref_tile_pixel(&p, nreq, (x - p.sample_x0) / 16, (y - p.sample_y0) / 16, x, y);
      expect_pixel_equals_ref(
          &p, out + ((size_t)(y - by) * (size_t)bw + (size_t)(x - bx)) * pixel_floats);
    }
  free(out);
}

static void test_tiles_match_pbrt_render_loop(void **state) {
  (void)state;
  clr_sampler_params st = make_params(CLR_SAMPLER_TYPE_STRATIFIED, 2, 3, 0, 1, 2);
  clr_sampler_params rnd = make_params(CLR_SAMPLER_TYPE_RANDOM, 1, 1, 4, 1, 0);
  /* Across four tiles; and over the sample-bounds border, outside the pixel bounds. */
  check_tiles_against_ref(st, 13, 12, 7, 6);
  check_tiles_against_ref(st, -1, -1, 4, 3);
  check_tiles_against_ref(st, 33, 18, 4, 3);
  check_tiles_against_ref(rnd, 13, 12, 7, 6);
  check_tiles_against_ref(rnd, 31, 17, 6, 4);
}

static void test_tile_equals_manual_start_pixels(void **state) {
  (void)state;
  clr_sampler_params p = make_params(CLR_SAMPLER_TYPE_STRATIFIED, 3, 3, 0, 1, 3);
  p.seeding = CLR_SEEDING_TYPE_PBRT_V3;
  clr_request_slot slots[MAX_REQ];
  int nreq = (int)(sizeof mixed_layout / sizeof mixed_layout[0]);
  fill_layout(&p, slots, mixed_layout, nreq);
  p.scratch_floats = clr_pixel_sampler_scratch_need(&p, slots);
  p.batch_x0 = 20, p.batch_y0 = 17, p.batch_width = 1, p.batch_height = 1;
  static float tile_out[MAX_SPP * MAX_VALUES], manual_out[MAX_SPP * MAX_VALUES];
  clr_pixel_sampler_tile(&p, slots, 1, 1, tile_out, scratch);
  /* Tile (1, 1) starts at (15, 15); every preceding pixel is inside the pixel bounds. */
  clr_pcg32 rng = clr_pcg32_sequence(1u * 3u + 1u);
  for (int y = 15; y <= 17; ++y)
    for (int x = 15; x < 31 && !(y == 17 && x == 20); ++x) {
      clr_pixel_sampler_start_pixel(&p, slots, &rng, NULL, scratch);
      clr_pcg32_advance(&rng, (uint64_t)p.spp * (uint64_t)p.fallback_draws_per_sample);
    }
  clr_pixel_sampler_start_pixel(&p, slots, &rng, manual_out, scratch);
  assert_memory_equal(tile_out, manual_out,
                      (size_t)p.spp * (size_t)p.values_per_sample * sizeof(float));
}

/* ---------- per-pixel seeding and fallbacks ---------- */

static void test_pixel_seeding_ignores_batch(void **state) {
  (void)state;
  clr_sampler_params p = make_params(CLR_SAMPLER_TYPE_STRATIFIED, 4, 4, 0, 1, 2);
  clr_request_slot slots[MAX_REQ];
  int nreq = (int)(sizeof mixed_layout / sizeof mixed_layout[0]);
  fill_layout(&p, slots, mixed_layout, nreq);
  p.scratch_floats = clr_pixel_sampler_scratch_need(&p, slots);
  static float a[MAX_SPP * MAX_VALUES], b[MAX_SPP * MAX_VALUES], c[MAX_SPP * MAX_VALUES];
  clr_sampler_params q = p;
  q.batch_x0 = 9, q.batch_y0 = 9, q.batch_width = 30, q.batch_height = 2;
  q.tiles_x = 99;
  clr_pixel_sampler_pixel(&p, slots, 10, 10, a, scratch);
  clr_pixel_sampler_pixel(&q, slots, 10, 10, b, scratch);
  size_t bytes = (size_t)p.spp * (size_t)p.values_per_sample * sizeof(float);
  assert_memory_equal(a, b, bytes);
  clr_pixel_sampler_pixel(&p, slots, 11, 10, c, scratch);
  assert_memory_not_equal(a, c, bytes);
  q.seed = p.seed + 1;
  clr_pixel_sampler_pixel(&q, slots, 10, 10, c, scratch);
  assert_memory_not_equal(a, c, bytes);
  /* Streams differ in x, y and seed: no collisions over a small image. */
  clr_pcg32 seen[64];
  for (int i = 0; i < 64; ++i) {
    seen[i] = clr_pixel_stream(&p, i % 8 - 4, i / 8 - 4);
    for (int j = 0; j < i; ++j) assert_true(seen[i].inc != seen[j].inc);
  }
}

static void test_fallbacks_follow_the_rng(void **state) {
  (void)state;
  for (int type = 0; type < 2; ++type) {
    clr_sampler_params p = type ? make_params(CLR_SAMPLER_TYPE_STRATIFIED, 2, 2, 0, 1, 1)
                                : make_params(CLR_SAMPLER_TYPE_RANDOM, 1, 1, 3, 1, 0);
    clr_request_slot slots[MAX_REQ];
    int nreq = (int)(sizeof mixed_layout / sizeof mixed_layout[0]);
    fill_layout(&p, slots, mixed_layout, nreq);
    assert_int_equal(p.fallback_draws_per_sample, type ? 12 : 15);
    p.scratch_floats = clr_pixel_sampler_scratch_need(&p, slots);
    static float out[MAX_SPP * MAX_VALUES];
    clr_pcg32 rng = clr_pixel_stream(&p, 3, 4);
    clr_pixel_sampler_start_pixel(&p, slots, &rng, out, scratch);
    /* Step through the rendering draws one by one: sample after sample, in request order. */
    for (int s = 0; s < p.spp; ++s)
      for (int k = 0; k < nreq; ++k) {
        if (slots[k].array_size != 0 || slots[k].source >= 0) continue;
        for (int c = 0; c < slots[k].dims; ++c) {
          float v = out[s * p.values_per_sample + slots[k].first_value + c];
          assert_true(v >= 0.0f && v < 1.0f);
          assert_true(v == ref_uniform(&rng));
        }
      }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pcg32_reference_outputs),
      cmocka_unit_test(test_pcg32_advance_matches_stepping),
      cmocka_unit_test(test_stratified_strata_jittered),
      cmocka_unit_test(test_stratified_strata_centred),
      cmocka_unit_test(test_stratified_matches_pbrt_model),
      cmocka_unit_test(test_random_matches_pbrt_model),
      cmocka_unit_test(test_tiles_match_pbrt_render_loop),
      cmocka_unit_test(test_tile_equals_manual_start_pixels),
      cmocka_unit_test(test_pixel_seeding_ignores_batch),
      cmocka_unit_test(test_fallbacks_follow_the_rng),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
