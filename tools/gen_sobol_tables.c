/* Build tool: turns the Joe-Kuo direction numbers (new-joe-kuo-6.21201 format) into pbrt-v3's
 * Sobol tables: the 32-bit generator matrices (52 columns per dimension) and the per-resolution
 * matrices that map (pixel, sample number) to a global Sobol index. Usage:
 *   clr_gen_sobol DIRECTION_NUMBERS.txt OUTPUT.c */
#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DIMENSIONS 1024 /* CLR_SOBOL_DIMENSIONS */
#define COLUMNS 52      /* CLR_SOBOL_MATRIX_SIZE: indices up to 2^52 */
#define VDC_MATRICES 26 /* CLR_SOBOL_VDC_MATRICES: resolutions up to 2^26 */
#define MAX_DEGREE 52

static const char *input_path;
static const char *output_path;
static char temp_path[4096];
static FILE *output;

static void die(long line, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  if (line > 0)
    fprintf(stderr, "clr_gen_sobol: %s:%ld: ", input_path, line);
  else
    fprintf(stderr, "clr_gen_sobol: ");
  vfprintf(stderr, fmt, args);
  fputc('\n', stderr);
  va_end(args);
  if (output) {
    fclose(output);
    remove(temp_path);
  }
  exit(1);
}

/* Column k (0-based) of the matrix as 32-bit fixed point: direction number m_(k+1) scaled by
 * 2^-(k+1), truncated to 32 bits. */
static uint32_t fixed_point_column(uint64_t m, int k) {
  int bits = k + 1;
  return bits <= 32 ? (uint32_t)(m << (32 - bits)) : (uint32_t)(m >> (bits - 32));
}

/* Reads the next non-empty line; returns 0 at end of file. */
static int read_line(FILE *f, char *buf, size_t size, long *line) {
  while (fgets(buf, (int)size, f)) {
    ++*line;
    size_t len = strlen(buf);
    if (len + 1 == size && buf[len - 1] != '\n' && !feof(f)) die(*line, "line too long");
    if (strspn(buf, " \t\r\n") != len) return 1;
  }
  if (ferror(f)) die(*line, "read error: %s", strerror(errno));
  return 0;
}

static uint64_t parse_number(char **cursor, long line, const char *what) {
  char *s = *cursor, *end;
  while (*s == ' ' || *s == '\t') ++s;
  if (*s < '0' || *s > '9') die(line, "expected %s", what);
  errno = 0;
  unsigned long long v = strtoull(s, &end, 10);
  if (errno) die(line, "%s out of range", what);
  *cursor = end;
  return (uint64_t)v;
}

/* Parses one "d s a m_1 .. m_s" line and extends the recurrence to all 52 columns. */
static void parse_dimension(char *text, long line, int expected_d, uint32_t *columns) {
  char *cursor = text;
  uint64_t d = parse_number(&cursor, line, "dimension d");
  uint64_t s = parse_number(&cursor, line, "degree s");
  uint64_t a = parse_number(&cursor, line, "polynomial a");
  if (d != (uint64_t)expected_d)
    die(line, "dimension %" PRIu64 " where %d was expected", d, expected_d);
  if (s < 1 || s > MAX_DEGREE) die(line, "degree s = %" PRIu64 " outside [1, %d]", s, MAX_DEGREE);
  if (a >> (s - 1))
    die(line, "polynomial a = %" PRIu64 " needs more than s-1 = %" PRIu64 " bits", a, s - 1);
  uint64_t m[COLUMNS + 1];
  for (uint64_t i = 1; i <= s; ++i) {
    m[i] = parse_number(&cursor, line, "direction number m_i");
    if (!(m[i] & 1) || m[i] >= ((uint64_t)1 << i))
      die(line, "m_%" PRIu64 " = %" PRIu64 " must be odd and below 2^%" PRIu64, i, m[i], i);
  }
  while (*cursor == ' ' || *cursor == '\t' || *cursor == '\r' || *cursor == '\n') ++cursor;
  if (*cursor) die(line, "unexpected text after %" PRIu64 " direction numbers", s);
  /* Bratley-Fox: m_i = 2^s m_(i-s) ^ m_(i-s) ^ sum_k a_k 2^k m_(i-k), a_k = bit s-1-k of a. */
  for (int i = (int)s + 1; i <= COLUMNS; ++i) {
    uint64_t v = (m[i - s] << s) ^ m[i - s];
    for (int k = 1; k < (int)s; ++k)
      if ((a >> (s - 1 - k)) & 1) v ^= m[i - k] << k;
    m[i] = v;
  }
  for (int k = 0; k < COLUMNS; ++k) columns[k] = fixed_point_column(m[k + 1], k);
}

static void read_matrices(uint32_t *matrices) {
  FILE *f = fopen(input_path, "r");
  if (!f) die(0, "cannot open %s: %s", input_path, strerror(errno));
  char buf[4096];
  long line = 0;
  if (!read_line(f, buf, sizeof buf, &line))
    die(line, "empty file, expected the header \"d s a m_i\"");
  char d[8], s[8], a[8], mi[8];
  if (sscanf(buf, "%7s %7s %7s %7s", d, s, a, mi) != 4 || strcmp(d, "d") || strcmp(s, "s") ||
      strcmp(a, "a") || strcmp(mi, "m_i"))
    die(line, "expected the header \"d s a m_i\"");
  /* Dimension 0: van der Corput, the identity matrix bit-reversed. */
  for (int k = 0; k < COLUMNS; ++k) matrices[k] = fixed_point_column(1, k);
  for (int dim = 1; dim < DIMENSIONS; ++dim) {
    if (!read_line(f, buf, sizeof buf, &line))
      die(line, "file ends after dimension %d, %d are needed", dim, DIMENSIONS);
    parse_dimension(buf, line, dim + 1, matrices + dim * COLUMNS);
  }
  fclose(f);
}

/* The top m bits of dimensions 0 and 1 of column j, packed as (x << m) | y: the pixel that
 * index bit j moves a point by at resolution 2^m. */
static uint64_t pixel_bits(const uint32_t *matrices, int m, int j) {
  uint64_t x = matrices[j] >> (32 - m), y = matrices[COLUMNS + j] >> (32 - m);
  return (x << m) | y;
}

/* Row m-1: columns c = frame bit c's pixel bits (index bit 2m + c, 52 - 2m of them); inverse:
 * column c = the low 2m index bits that move a point by pixel bit c, the GF(2) inverse of the
 * square matrix of index bits 0 .. 2m-1. */
static void vdc_matrices(const uint32_t *matrices, int m, uint64_t *vdc, uint64_t *inv) {
  int n = 2 * m;
  for (int c = 0; c < COLUMNS; ++c) vdc[c] = inv[c] = 0;
  for (int c = 0; c + n < COLUMNS; ++c) vdc[c] = pixel_bits(matrices, m, n + c);
  /* Gauss-Jordan on rows [A | I]: row r holds pixel bit r's dependence on index bits. */
  uint64_t a[2 * VDC_MATRICES], id[2 * VDC_MATRICES];
  for (int r = 0; r < n; ++r) {
    a[r] = 0;
    id[r] = (uint64_t)1 << r;
    for (int j = 0; j < n; ++j) a[r] |= ((pixel_bits(matrices, m, j) >> r) & 1) << j;
  }
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    while (pivot < n && !((a[pivot] >> col) & 1)) ++pivot;
    if (pivot == n) die(0, "dimensions 0/1 are singular at m = %d", m);
    uint64_t t = a[col];
    a[col] = a[pivot];
    a[pivot] = t;
    t = id[col];
    id[col] = id[pivot];
    id[pivot] = t;
    for (int r = 0; r < n; ++r)
      if (r != col && ((a[r] >> col) & 1)) {
        a[r] ^= a[col];
        id[r] ^= id[col];
      }
  }
  /* Now row j of id is index bit j as a function of pixel bits. */
  for (int c = 0; c < n; ++c)
    for (int j = 0; j < n; ++j) inv[c] |= ((id[j] >> c) & 1) << j;
}

static void emit(const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  int written = vfprintf(output, fmt, args);
  va_end(args);
  if (written < 0) die(0, "cannot write %s: %s", temp_path, strerror(errno));
}

static void emit_u64_table(const char *name, uint64_t table[][COLUMNS]) {
  emit("const uint64_t %s[CLR_SOBOL_VDC_MATRICES][CLR_SOBOL_MATRIX_SIZE] = {\n", name);
  for (int m = 1; m <= VDC_MATRICES; ++m) {
    emit("  { /* m = %d */\n", m);
    for (int c = 0; c < COLUMNS; ++c)
      emit("%s0x%" PRIx64 "u,%s", c % 4 ? " " : "    ", table[m - 1][c], c % 4 == 3 ? "\n" : "");
    emit("  },\n");
  }
  emit("};\n\n");
}

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: clr_gen_sobol DIRECTION_NUMBERS.txt OUTPUT.c\n");
    return 2;
  }
  input_path = argv[1];
  output_path = argv[2];
  static uint32_t matrices[DIMENSIONS * COLUMNS];
  static uint64_t vdc[VDC_MATRICES][COLUMNS], inv[VDC_MATRICES][COLUMNS];
  read_matrices(matrices);
  for (int m = 1; m <= VDC_MATRICES; ++m) vdc_matrices(matrices, m, vdc[m - 1], inv[m - 1]);

  if (snprintf(temp_path, sizeof temp_path, "%s.tmp", output_path) >= (int)sizeof temp_path)
    die(0, "output path too long: %s", output_path);
  output = fopen(temp_path, "w");
  if (!output) die(0, "cannot create %s: %s", temp_path, strerror(errno));
  const char *input_name = strrchr(input_path, '/') ? strrchr(input_path, '/') + 1 : input_path;
  emit("/* Generated by tools/gen_sobol_tables.c from %s: do not edit. */\n", input_name);
  emit("#include \"sobol_tables.h\"\n\n");
  emit(
      "_Static_assert(CLR_SOBOL_DIMENSIONS == %d && CLR_SOBOL_MATRIX_SIZE == %d &&\n"
      "               CLR_SOBOL_VDC_MATRICES == %d, \"tables and headers disagree\");\n\n",
      DIMENSIONS, COLUMNS, VDC_MATRICES);
  emit("const uint32_t clr_sobol_matrices32[CLR_SOBOL_DIMENSIONS * CLR_SOBOL_MATRIX_SIZE] = {\n");
  for (int dim = 0; dim < DIMENSIONS; ++dim) {
    emit("  /* dimension %d */\n", dim);
    for (int c = 0; c < COLUMNS; ++c)
      emit("%s0x%08" PRIx32 "u,%s", c % 6 ? " " : "  ", matrices[dim * COLUMNS + c],
           c % 6 == 5 || c == COLUMNS - 1 ? "\n" : "");
  }
  emit("};\n\n");
  emit_u64_table("clr_vdc_sobol_matrices", vdc);
  emit_u64_table("clr_vdc_sobol_matrices_inv", inv);
  FILE *done = output;
  output = NULL;
  if (fclose(done) != 0) {
    remove(temp_path);
    die(0, "cannot write %s: %s", temp_path, strerror(errno));
  }
  if (rename(temp_path, output_path) != 0) {
    remove(temp_path);
    die(0, "cannot rename %s to %s: %s", temp_path, output_path, strerror(errno));
  }
  return 0;
}
