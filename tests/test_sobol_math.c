/* Sobol sampler math (kernels/sobol_funcs.h on the host, and on the OpenCL device) against the
 * Joe-Kuo sequence computed here independently, pbrt-v3's tables, and exact stratification. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include "clrender.h"
#include "sobol_funcs.h"
#include "sobol_tables.h"

#define VDC (&clr_vdc_sobol_matrices[0][0])
#define VDC_INV (&clr_vdc_sobol_matrices_inv[0][0])

static clr_sampler_params bounds_params(int x0, int y0, int x1, int y1) {
  clr_sampler_params p;
  memset(&p, 0, sizeof p);
  p.type = CLR_SAMPLER_TYPE_SOBOL;
  p.sample_x0 = x0;
  p.sample_y0 = y0;
  p.sample_x1 = x1;
  p.sample_y1 = y1;
  clr_sobol_setup(&p);
  return p;
}

/* The raw 32-bit Sobol value, bit by bit as in pbrt-v3 (no set-bit tricks). */
static uint32_t raw_sobol32(uint64_t index, int dim) {
  uint32_t v = 0;
  for (int c = 0; index && c < CLR_SOBOL_MATRIX_SIZE; index >>= 1, ++c)
    if (index & 1) v ^= clr_sobol_matrices32[dim * CLR_SOBOL_MATRIX_SIZE + c];
  return v;
}

/* Entries copied from pbrt-v3 src/core/sobolmatrices.cpp (SobolMatrices32, VdCSobolMatrices,
 * VdCSobolMatricesInv): dimensions 0-4, 19 and 1023, m = 1, 2, 3, 5, 9, 17, 24, 25, 26. */
static void test_tables_match_pbrt_v3(void **state) {
  (void)state;
  static const struct {
    int index;
    uint32_t value;
  } m32[] = {
      {0, 0x80000000u},
      {31, 0x00000001u},
      {32, 0},
      {51, 0},
      {52, 0x80000000u},
      {53, 0xc0000000u},
      {59, 0xff000000u},
      {83, 0xffffffffu},
      {84, 0x80000000u},
      {103, 0xf000f000u},
      {104, 0x80000000u},
      {108, 0xe8000000u},
      {135, 0xc5005555u},
      {136, 0x68808000u},
      {155, 0x90000000u},
      {160, 0xf8000000u},
      {207, 0x25d93000u},
      {236, 0x800228f8u},
      {259, 0x2d02d040u},
      {19 * 52 + 0, 0x80000000u},
      {19 * 52 + 6, 0xce000000u},
      {19 * 52 + 28, 0x38000008u},
      {19 * 52 + 30, 0x2e00000eu},
      {1023 * 52 + 0, 0x80000000u},
      {1023 * 52 + 12, 0xf3f80000u},
      {1023 * 52 + 35, 0xc769c754u},
      {1023 * 52 + 48, 0x6d8253b0u},
      {1023 * 52 + 51, 0x1397876eu},
  };
  for (size_t i = 0; i < sizeof m32 / sizeof m32[0]; ++i)
    assert_int_equal(clr_sobol_matrices32[m32[i].index], m32[i].value);

  for (int c = 0; c < 50; ++c) assert_int_equal(clr_vdc_sobol_matrices[0][c], 1);
  assert_int_equal(clr_vdc_sobol_matrices[0][50], 0);
  static const uint64_t vdc5[8] = {0x14, 0x1e, 0x11, 0x19, 0x15, 0x1f, 0x10, 0x18};
  static const uint64_t vdc9[8] = {0x140, 0x1e0, 0x110, 0x198, 0x154, 0x1fe, 0x101, 0x181};
  for (int c = 0; c < 8; ++c) {
    assert_int_equal(clr_vdc_sobol_matrices[4][c], vdc5[c]);
    assert_int_equal(clr_vdc_sobol_matrices[8][c], vdc9[c]);
  }
  assert_int_equal(clr_vdc_sobol_matrices[8][33], 0x1e0);
  assert_int_equal(clr_vdc_sobol_matrices[8][34], 0);
  assert_int_equal(clr_vdc_sobol_matrices[16][13], 0x1fffe);
  assert_int_equal(clr_vdc_sobol_matrices[16][17], 0x1e001);
  assert_int_equal(clr_vdc_sobol_matrices[24][0], 0x1400140);
  assert_int_equal(clr_vdc_sobol_matrices[24][1], 0x1e001e0);
  assert_int_equal(clr_vdc_sobol_matrices[24][2], 0);
  for (int c = 0; c < CLR_SOBOL_MATRIX_SIZE; ++c)
    assert_int_equal(clr_vdc_sobol_matrices[25][c], 0);

  static const uint64_t inv1[2] = {0x2, 0x3}, inv2[4] = {0xc, 0x4, 0xa, 0x5};
  static const uint64_t inv3[6] = {0x28, 0x30, 0x10, 0x3c, 0x22, 0x11};
  static const uint64_t inv9[18] = {0x20200, 0x3fc00, 0x35600, 0x33000, 0x31200, 0x30c00,
                                    0x30600, 0x30000, 0x10000, 0x30300, 0x28280, 0x24240,
                                    0x22220, 0x21210, 0x20a08, 0x20604, 0x20002, 0x10001};
  for (int c = 0; c < 2; ++c) assert_int_equal(clr_vdc_sobol_matrices_inv[0][c], inv1[c]);
  for (int c = 0; c < 4; ++c) assert_int_equal(clr_vdc_sobol_matrices_inv[1][c], inv2[c]);
  for (int c = 0; c < 6; ++c) assert_int_equal(clr_vdc_sobol_matrices_inv[2][c], inv3[c]);
  for (int c = 0; c < 18; ++c) assert_int_equal(clr_vdc_sobol_matrices_inv[8][c], inv9[c]);
  assert_int_equal(clr_vdc_sobol_matrices_inv[0][2], 0);
  assert_int_equal(clr_vdc_sobol_matrices_inv[8][18], 0);
  assert_int_equal(clr_vdc_sobol_matrices_inv[16][0], 0x200020000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[16][4], 0x311120000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[16][22], 0x208020800u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[16][33], 0x100000001u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[23][0], 0xff00ff000000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[23][24], 0x808080800000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[24][0], 0x2020202000000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[24][30], 0x20a0a0a080000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[25][0], 0xc0c0c0c000000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[25][4], 0xf3c0f3c000000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[25][30], 0x8282828200000u);
  assert_int_equal(clr_vdc_sobol_matrices_inv[25][51], 0x100000001u);
}

/* Joe-Kuo direction numbers V_1..V_32 (32-bit) of dimensions 0..dims-1, read here from the data
 * file with the recurrence in Joe & Kuo's own V-form. */
static void joe_kuo_directions(int dims, uint32_t v[][33]) {
  for (int i = 1; i <= 32; ++i) v[0][i] = 1u << (32 - i);
  FILE *f = fopen(CLR_SOURCE_DIR "/data/joe-kuo-sobol-1024.txt", "r");
  assert_non_null(f);
  char line[1024];
  assert_non_null(fgets(line, sizeof line, f)); /* header */
  for (int d = 1; d < dims; ++d) {
    assert_non_null(fgets(line, sizeof line, f));
    char *cur = line;
    long dd = strtol(cur, &cur, 10), s = strtol(cur, &cur, 10), a = strtol(cur, &cur, 10);
    assert_int_equal(dd, d + 1);
    for (int i = 1; i <= s; ++i) v[d][i] = (uint32_t)strtoul(cur, &cur, 10) << (32 - i);
    for (int i = (int)s + 1; i <= 32; ++i) {
      v[d][i] = v[d][i - s] ^ (v[d][i - s] >> s);
      for (int k = 1; k < s; ++k)
        if ((a >> (s - 1 - k)) & 1) v[d][i] ^= v[d][i - k];
    }
  }
  fclose(f);
}

static float as_unit_float(uint32_t x) {
  float f = (float)x * 0x1p-32f;
  return f < CLR_ONE_MINUS_EPSILON ? f : CLR_ONE_MINUS_EPSILON;
}

/* Point n of the Gray-code (Antonov-Saleev) Sobol sequence is index n ^ (n >> 1) in pbrt's
 * natural order; published listings use the Gray-code order. */
static void test_sequence_matches_joe_kuo(void **state) {
  (void)state;
  static const float published[5][8] = {
      {0, .5f, .75f, .25f, .375f, .875f, .625f, .125f},
      {0, .5f, .25f, .75f, .375f, .875f, .125f, .625f},
      {0, .5f, .25f, .75f, .625f, .125f, .875f, .375f},
      {0, .5f, .25f, .75f, .875f, .375f, .625f, .125f},
      {0, .5f, .75f, .25f, .375f, .875f, .625f, .125f},
  };
  for (int d = 0; d < 5; ++d)
    for (uint64_t n = 0; n < 8; ++n)
      assert_true(clr_sobol_sample_float(n ^ (n >> 1), d, clr_sobol_matrices32) == published[d][n]);
  /* Natural order, dimension 0 is the van der Corput sequence. */
  static const float vdc[8] = {0, .5f, .25f, .75f, .125f, .625f, .375f, .875f};
  for (uint64_t i = 0; i < 8; ++i)
    assert_true(clr_sobol_sample_float(i, 0, clr_sobol_matrices32) == vdc[i]);

  enum { DIMS = 40, POINTS = 1 << 12 };
  static uint32_t v[DIMS][33];
  joe_kuo_directions(DIMS, v);
  uint32_t x[DIMS] = {0};
  for (uint64_t n = 0; n < POINTS; ++n) {
    if (n > 0) {
      int c = __builtin_ctzll(~(n - 1)) + 1; /* rightmost zero bit of n-1, 1-based */
      for (int d = 0; d < DIMS; ++d) x[d] ^= v[d][c];
    }
    for (int d = 0; d < DIMS; ++d) {
      assert_int_equal(raw_sobol32(n ^ (n >> 1), d), x[d]);
      assert_true(clr_sobol_sample_float(n ^ (n >> 1), d, clr_sobol_matrices32) ==
                  as_unit_float(x[d]));
    }
  }
  /* Index bits past 31 use matrix columns 32..51. */
  uint64_t big = ((uint64_t)1 << 51) | ((uint64_t)1 << 40) | ((uint64_t)1 << 32) | 5u;
  for (int d = 0; d < CLR_SOBOL_DIMENSIONS; d += 97)
    assert_true(clr_sobol_sample_float(big, d, clr_sobol_matrices32) ==
                as_unit_float(raw_sobol32(big, d)));
  /* Rounding up to 1 is clamped: dimension 0 at index 2^32-1 is 0xffffffff * 2^-32. */
  assert_true(clr_sobol_sample_float(0xffffffffu, 0, clr_sobol_matrices32) ==
              CLR_ONE_MINUS_EPSILON);
}

/* The first 2^k points of dimensions (0, 1) form a (0, k, 2)-net. */
static void test_elementary_intervals(void **state) {
  (void)state;
  static unsigned char count[1 << 12];
  for (int k = 0; k <= 12; ++k)
    for (int i = 0; i <= k; ++i) {
      memset(count, 0, sizeof count);
      for (uint64_t n = 0; n < ((uint64_t)1 << k); ++n) {
        float x = clr_sobol_sample_float(n, 0, clr_sobol_matrices32);
        float y = clr_sobol_sample_float(n, 1, clr_sobol_matrices32);
        int cx = (int)(x * (float)(1 << i)), cy = (int)(y * (float)(1 << (k - i)));
        ++count[(cx << (k - i)) | cy];
      }
      for (int c = 0; c < (1 << k); ++c) assert_int_equal(count[c], 1);
    }
}

static void test_setup(void **state) {
  (void)state;
  static const struct {
    int x0, y0, x1, y1, log2;
  } cases[] = {
      {0, 0, 1, 1, 0},   {5, 7, 6, 8, 0},  {0, 0, 2, 1, 1},        {-3, 0, 0, 3, 2},
      {0, 0, 64, 10, 6}, {0, 0, 65, 1, 7}, {-2, -1, 35, 20, 6},    {0, 0, 1280, 720, 11},
      {0, 0, 3, 0, 2},   {0, 0, 0, 0, 0},  {0, 0, 1 << 26, 1, 26}, {0, 0, (1 << 26) + 1, 1, 27},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    clr_sampler_params p = bounds_params(cases[i].x0, cases[i].y0, cases[i].x1, cases[i].y1);
    assert_int_equal(p.sobol_log2_resolution, cases[i].log2);
    assert_true(p.sobol_resolution == (float)(1 << cases[i].log2));
  }
  assert_int_equal(clr_sobol_max_samples(0), (int64_t)1 << 52);
  assert_int_equal(clr_sobol_max_samples(6), (int64_t)1 << 40);
  assert_int_equal(clr_sobol_max_samples(26), 1);
  assert_int_equal(clr_sobol_max_samples(27), 0);
}

/* Every sample index of a pixel lands in that pixel; values of dimensions 0/1 are its offset. */
static void test_samples_land_in_their_pixel(void **state) {
  (void)state;
  clr_sampler_params p = bounds_params(-2, -1, 35, 20); /* 37 x 21 -> resolution 64 */
  assert_int_equal(p.sobol_log2_resolution, 6);
  static const int pixels[][2] = {{-2, -1}, {34, 19}, {0, 0}, {17, 5}, {-1, 19}, {33, -1}};
  for (size_t k = 0; k < sizeof pixels / sizeof pixels[0]; ++k) {
    int px = pixels[k][0], py = pixels[k][1];
    uint64_t seen[64];
    for (int64_t i = 0; i < 64; ++i) {
      uint64_t index = clr_sobol_sampler_index(&p, VDC, VDC_INV, px, py, i);
      assert_true(index < ((uint64_t)1 << 18));
      assert_int_equal(index >> 12, i); /* the sample number is the index's top bits */
      for (int64_t j = 0; j < i; ++j) assert_true(seen[j] != index);
      seen[i] = index;
      float x = clr_sobol_sample_float(index, 0, clr_sobol_matrices32);
      float y = clr_sobol_sample_float(index, 1, clr_sobol_matrices32);
      assert_int_equal((int)(x * 64.0f), px + 2);
      assert_int_equal((int)(y * 64.0f), py + 1);
      float u = clr_sobol_sampler_value(&p, clr_sobol_matrices32, index, 0, px, py);
      float w = clr_sobol_sampler_value(&p, clr_sobol_matrices32, index, 1, px, py);
      assert_true(u >= 0.0f && u < 1.0f && w >= 0.0f && w < 1.0f);
      assert_true(u == x * 64.0f - (float)(px + 2)); /* exact: all values have few bits */
      assert_true(w == y * 64.0f - (float)(py + 1));
      for (int d = 2; d < 8; ++d)
        assert_true(clr_sobol_sampler_value(&p, clr_sobol_matrices32, index, d, px, py) ==
                    clr_sobol_sample_float(index, d, clr_sobol_matrices32));
    }
  }
  /* pbrt-v3's clamp: a value that rounds up onto the pixel's far edge becomes 1 - epsilon
   * (dimension 0 at index 0xffffffc0 is 0x03ffffff * 2^-32, which rounds to 1/64). */
  clr_sampler_params q = bounds_params(0, 0, 64, 64);
  assert_true(clr_sobol_sampler_value(&q, clr_sobol_matrices32, 0xffffffc0u, 0, 0, 0) ==
              CLR_ONE_MINUS_EPSILON);
}

/* At resolution 2^m, (pixel, frame < F) -> index is a bijection onto [0, F * 4^m), and the top m
 * bits of dimensions 0/1 are the pixel, for every table row. */
static void test_interval_to_index_is_exact(void **state) {
  (void)state;
  static unsigned char hit[4 << 12];
  for (uint32_t m = 1; m <= 6; ++m) {
    uint32_t res = 1u << m;
    memset(hit, 0, sizeof hit);
    for (uint32_t py = 0; py < res; ++py)
      for (uint32_t px = 0; px < res; ++px)
        for (uint64_t f = 0; f < 4; ++f) {
          uint64_t index = clr_sobol_interval_to_index(m, f, (int)px, (int)py, VDC, VDC_INV);
          assert_true(index < ((uint64_t)4 << (2 * m)));
          ++hit[index];
          assert_int_equal(raw_sobol32(index, 0) >> (32 - m), px);
          assert_int_equal(raw_sobol32(index, 1) >> (32 - m), py);
        }
    for (uint64_t i = 0; i < ((uint64_t)4 << (2 * m)); ++i) assert_int_equal(hit[i], 1);
  }
  for (uint32_t m = 7; m <= CLR_SOBOL_MAX_LOG2_RESOLUTION; ++m) {
    uint64_t frames = (uint64_t)clr_sobol_max_samples((int32_t)m);
    uint32_t mask = (1u << m) - 1u;
    for (uint32_t k = 0; k < 16; ++k) {
      uint32_t px = (k * 2654435761u) & mask, py = (k * 40503u + 7u) & mask;
      static const uint64_t samples[] = {0, 1, 2, 3, 5, 1000, 123456789};
      for (size_t s = 0; s < sizeof samples / sizeof samples[0]; ++s) {
        uint64_t f = samples[s] % frames;
        uint64_t index = clr_sobol_interval_to_index(m, f, (int)px, (int)py, VDC, VDC_INV);
        assert_int_equal(index >> (2 * m), f);
        assert_int_equal(raw_sobol32(index, 0) >> (32 - m), px);
        assert_int_equal(raw_sobol32(index, 1) >> (32 - m), py);
      }
    }
  }
}

/* pbrt-v3 returns index 0 for every sample of a 1x1 image; we return the sample number. */
static void test_one_pixel_bounds(void **state) {
  (void)state;
  clr_sampler_params p = bounds_params(5, 7, 6, 8);
  assert_int_equal(p.sobol_log2_resolution, 0);
  for (int64_t i = 0; i < 40; ++i) {
    uint64_t index = clr_sobol_sampler_index(&p, VDC, VDC_INV, 5, 7, i);
    assert_int_equal(index, i);
    for (int d = 0; d < 2; ++d) {
      float s = clr_sobol_sampler_value(&p, clr_sobol_matrices32, index, d, 5, 7);
      assert_true(s >= 0.0f && s < 1.0f);
    }
  }
  assert_int_equal(clr_sobol_interval_to_index(0, 123456789012345u, 0, 0, VDC, VDC_INV),
                   123456789012345u);
}

/* Past 1024 dimensions pbrt-v3 aborts; we return a hash of (index, dimension). */
static void test_dimensions_past_the_tables(void **state) {
  (void)state;
  for (uint64_t index = 0; index < 200; index += 7) {
    float prev = -1.0f;
    int distinct = 0;
    for (int d = CLR_SOBOL_DIMENSIONS; d < CLR_SOBOL_DIMENSIONS + 64; ++d) {
      float s = clr_sobol_sample_float(index, d, clr_sobol_matrices32);
      assert_true(s >= 0.0f && s < 1.0f);
      assert_true(s == clr_sobol_sample_float(index, d, clr_sobol_matrices32));
      distinct += s != prev;
      prev = s;
    }
    assert_true(distinct >= 60);
    float neg = clr_sobol_sample_float(index, -1, clr_sobol_matrices32);
    assert_true(neg >= 0.0f && neg < 1.0f);
    assert_true(clr_sobol_sample_float(index, 5000, clr_sobol_matrices32) !=
                clr_sobol_sample_float(index + 1, 5000, clr_sobol_matrices32));
  }
  /* Mean of many values is near 1/2. */
  double sum = 0;
  for (uint64_t index = 0; index < 4096; ++index)
    sum += clr_sobol_sample_float(index, 2000, clr_sobol_matrices32);
  assert_true(sum / 4096 > 0.48 && sum / 4096 < 0.52);
}

/* The same header compiled as OpenCL C gives the same bits on the device. */
static const char *device_source =
    "#include \"sobol_funcs.h\"\n"
    "__kernel void sobol_check(__global const clr_sampler_params *pp, __global const uint *m32,\n"
    "    __global const ulong *vdc, __global const ulong *inv, __global const long *items,\n"
    "    __global const int *dims, int ndims, __global ulong *index_out, __global float *out) {\n"
    "  size_t g = get_global_id(0);\n"
    "  clr_sampler_params p = *pp;\n"
    "  int px = (int)items[3 * g], py = (int)items[3 * g + 1];\n"
    "  ulong index = clr_sobol_sampler_index(&p, vdc, inv, px, py, items[3 * g + 2]);\n"
    "  index_out[g] = index;\n"
    "  for (int k = 0; k < ndims; ++k)\n"
    "    out[g * ndims + k] = clr_sobol_sampler_value(&p, m32, index, dims[k], px, py);\n"
    "}\n";

static cl_mem make_buffer(cl_context cl, cl_mem_flags flags, size_t bytes, const void *data) {
  cl_int err = 0;
  cl_mem b =
      clCreateBuffer(cl, flags | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes, (void *)data, &err);
  assert_int_equal(err, CL_SUCCESS);
  return b;
}

static void test_device_matches_host(void **state) {
  (void)state;
  clr_context ctx = NULL;
  assert_int_equal(clr_context_create(NULL, &ctx), CLR_SUCCESS);
  cl_context cl = clr_context_cl_context(ctx);
  cl_device_id dev = clr_context_cl_device(ctx);
  cl_int err = 0;
  cl_program prog = clCreateProgramWithSource(cl, 1, &device_source, NULL, &err);
  assert_int_equal(err, CL_SUCCESS);
  err = clBuildProgram(prog, 1, &dev, "-cl-std=CL1.2 -I " CLR_SOURCE_DIR "/kernels", NULL, NULL);
  if (err != CL_SUCCESS) {
    char log[8192] = {0};
    clGetProgramBuildInfo(prog, dev, CL_PROGRAM_BUILD_LOG, sizeof log - 1, log, NULL);
    fprintf(stderr, "build log:\n%s\n", log);
  }
  assert_int_equal(err, CL_SUCCESS);
  cl_kernel k = clCreateKernel(prog, "sobol_check", &err);
  assert_int_equal(err, CL_SUCCESS);

  clr_sampler_params p = bounds_params(-2, -1, 35, 20);
  enum { N = 512, NDIMS = 12 };
  static const int dims[NDIMS] = {0, 1, 2, 3, 4, 5, 17, 511, 1023, 1024, 1500, -3};
  static int64_t items[3 * N];
  for (int g = 0; g < N; ++g) {
    items[3 * g] = -2 + (g * 7) % 37;
    items[3 * g + 1] = -1 + (g * 3) % 21;
    items[3 * g + 2] = g < 256 ? g % 64 : ((int64_t)g << 28) + g; /* up to 2^37 */
  }
  cl_mem bp = make_buffer(cl, CL_MEM_READ_ONLY, sizeof p, &p);
  cl_mem bm = make_buffer(cl, CL_MEM_READ_ONLY, sizeof clr_sobol_matrices32, clr_sobol_matrices32);
  cl_mem bv = make_buffer(cl, CL_MEM_READ_ONLY, sizeof clr_vdc_sobol_matrices, VDC);
  cl_mem bi = make_buffer(cl, CL_MEM_READ_ONLY, sizeof clr_vdc_sobol_matrices_inv, VDC_INV);
  cl_mem bitems = make_buffer(cl, CL_MEM_READ_ONLY, sizeof items, items);
  cl_mem bdims = make_buffer(cl, CL_MEM_READ_ONLY, sizeof dims, dims);
  cl_mem bidx = make_buffer(cl, CL_MEM_WRITE_ONLY, N * sizeof(uint64_t), NULL);
  cl_mem bout = make_buffer(cl, CL_MEM_WRITE_ONLY, N * NDIMS * sizeof(float), NULL);
  cl_int nd = NDIMS;
  cl_mem args[] = {bp, bm, bv, bi, bitems, bdims};
  for (cl_uint a = 0; a < 6; ++a)
    assert_int_equal(clSetKernelArg(k, a, sizeof(cl_mem), &args[a]), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 6, sizeof nd, &nd), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 7, sizeof(cl_mem), &bidx), CL_SUCCESS);
  assert_int_equal(clSetKernelArg(k, 8, sizeof(cl_mem), &bout), CL_SUCCESS);
  size_t global = N;
  cl_command_queue q = clr_context_cl_queue(ctx);
  assert_int_equal(clEnqueueNDRangeKernel(q, k, 1, NULL, &global, NULL, 0, NULL, NULL), CL_SUCCESS);
  static uint64_t dev_index[N];
  static float dev_out[N * NDIMS];
  assert_int_equal(
      clEnqueueReadBuffer(q, bidx, CL_TRUE, 0, sizeof dev_index, dev_index, 0, NULL, NULL),
      CL_SUCCESS);
  assert_int_equal(clEnqueueReadBuffer(q, bout, CL_TRUE, 0, sizeof dev_out, dev_out, 0, NULL, NULL),
                   CL_SUCCESS);
  for (int g = 0; g < N; ++g) {
    int px = (int)items[3 * g], py = (int)items[3 * g + 1];
    uint64_t index = clr_sobol_sampler_index(&p, VDC, VDC_INV, px, py, items[3 * g + 2]);
    assert_int_equal(dev_index[g], index);
    for (int d = 0; d < NDIMS; ++d) {
      float host = clr_sobol_sampler_value(&p, clr_sobol_matrices32, index, dims[d], px, py);
      assert_int_equal(clr_as_uint(dev_out[g * NDIMS + d]), clr_as_uint(host));
    }
  }
  cl_mem all[] = {bp, bm, bv, bi, bitems, bdims, bidx, bout};
  for (size_t i = 0; i < 8; ++i) clReleaseMemObject(all[i]);
  clReleaseKernel(k);
  clReleaseProgram(prog);
  clr_context_release(ctx);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_tables_match_pbrt_v3),
      cmocka_unit_test(test_sequence_matches_joe_kuo),
      cmocka_unit_test(test_elementary_intervals),
      cmocka_unit_test(test_setup),
      cmocka_unit_test(test_samples_land_in_their_pixel),
      cmocka_unit_test(test_interval_to_index_is_exact),
      cmocka_unit_test(test_one_pixel_bounds),
      cmocka_unit_test(test_dimensions_past_the_tables),
      cmocka_unit_test(test_device_matches_host),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
