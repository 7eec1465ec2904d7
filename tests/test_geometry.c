/* Host geometry: meshes, pbrt "trianglemesh" validation, PLY reading, Loop subdivision. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>
#include "loop_subdiv.h"
#include "mesh.h"
#include "ply_reader.h"

/* ---- temporary files ---- */

/* Under the build tree (tests write no file outside the repository and its build). */
#define TEMP_PATH_MAX 1024
static char temp_dir[TEMP_PATH_MAX - 64];
static char temp_files[32][TEMP_PATH_MAX];
static int temp_count;

static int make_temp_dir(void **state) {
  (void)state;
  snprintf(temp_dir, sizeof temp_dir, "%s/test_geometry_XXXXXX", CLR_BINARY_DIR);
  return mkdtemp(temp_dir) ? 0 : -1;
}

static int remove_temp_dir(void **state) {
  (void)state;
  for (int i = 0; i < temp_count; ++i) remove(temp_files[i]);
  return rmdir(temp_dir);
}

/* Opens a new file in the temporary directory; its path goes to `path`. */
static FILE *temp_file(const char *name, char *path) {
  assert_true(temp_count < 32);
  snprintf(temp_files[temp_count], sizeof temp_files[0], "%s/%s", temp_dir, name);
  strcpy(path, temp_files[temp_count++]);
  FILE *fp = fopen(path, "wb");
  assert_non_null(fp);
  return fp;
}

static void write_text(const char *name, const char *text, char *path) {
  FILE *fp = temp_file(name, path);
  assert_int_equal(fputs(text, fp) >= 0, 1);
  assert_int_equal(fclose(fp), 0);
}

/* Writes `value` as PLY type `type` in the given byte order. */
static void put(FILE *fp, const char *type, double value, int big_endian) {
  unsigned char b[8];
  size_t size;
  if (!strcmp(type, "char")) {
    int8_t v = (int8_t)value;
    memcpy(b, &v, size = 1);
  } else if (!strcmp(type, "uchar")) {
    uint8_t v = (uint8_t)value;
    memcpy(b, &v, size = 1);
  } else if (!strcmp(type, "short")) {
    int16_t v = (int16_t)value;
    memcpy(b, &v, size = 2);
  } else if (!strcmp(type, "ushort")) {
    uint16_t v = (uint16_t)value;
    memcpy(b, &v, size = 2);
  } else if (!strcmp(type, "int")) {
    int32_t v = (int32_t)value;
    memcpy(b, &v, size = 4);
  } else if (!strcmp(type, "uint")) {
    uint32_t v = (uint32_t)value;
    memcpy(b, &v, size = 4);
  } else if (!strcmp(type, "float")) {
    float v = (float)value;
    memcpy(b, &v, size = 4);
  } else {
    memcpy(b, &value, size = 8);
  }
  const uint16_t one = 1;
  unsigned char first;
  memcpy(&first, &one, 1);
  if ((first == 1) == big_endian)
    for (size_t i = 0; i < size / 2; ++i) {
      unsigned char t = b[i];
      b[i] = b[size - 1 - i];
      b[size - 1 - i] = t;
    }
  assert_int_equal(fwrite(b, 1, size, fp), size);
}

static void assert_floats(const float *got, const float *expected, int n) {
  for (int i = 0; i < n; ++i) assert_true(got[i] == expected[i]);
}

static void assert_uints(const uint32_t *got, const uint32_t *expected, int n) {
  for (int i = 0; i < n; ++i) assert_int_equal(got[i], expected[i]);
}

static void assert_message_has(const char *needle) {
  if (!strstr(clr_last_error_message(), needle))
    fail_msg("\"%s\" not in error message \"%s\"", needle, clr_last_error_message());
}

/* ---- PLY ---- */

static const float quad_p[] = {0, 0, 0, 1.5f, 0, 0, 1.5f, 2, 0, 0, 2, -0.25f, 3, 3, 3};
static const float quad_n[] = {0, 0, 1, 0, 0, 1, 0.5f, 0, 1, 0, 0, -1, 1, 0, 0};
static const float quad_uv[] = {0, 0, 1, 0, 1, 1, 0, 1, 0.125f, 0.75f};
/* pbrt-v3 splits quad (a,b,c,d) into (a,b,c) and (d,a,c). */
static const uint32_t quad_indices[] = {0, 1, 2, 3, 0, 2, 4, 0, 1};

static void test_ply_ascii(void **state) {
  (void)state;
  char path[TEMP_PATH_MAX];
  write_text("ascii.ply",
             "ply\r\nformat ascii 1.0\r\ncomment made by test_geometry\r\nobj_info none\r\n"
             "element vertex 5\r\nproperty float x\r\nproperty float y\r\nproperty double z\r\n"
             "property uchar red\r\nproperty float nx\r\nproperty float ny\r\nproperty float nz\r\n"
             "property list uchar float extra\r\nproperty float s\r\nproperty float t\r\n"
             "element material 1\r\nproperty int id\r\nelement empty 9000000000000000000\r\n"
             "element face 3\r\nproperty int flags\r\nproperty list uchar int vertex_indices\r\n"
             "end_header\r\n"
             "0 0 0 255 0 0 1 0 0 0\n1.5 0 0 1 0 0 1 2 7 8 1 0\n1.5 2 0 0 0.5 0 1 0 1 1\n"
             "0 2 -0.25 0 0 0 -1 0 0 1\n3 3 3 0 1 0 0 1 9 0.125 0.75\n"
             "42\n"
             "7 4 0 1 2 3\n0 2 0 1 \n1 3 4 0 1\n",
             path);
  clr_mesh mesh;
  assert_int_equal(clr_ply_read(path, &mesh), CLR_SUCCESS);
  assert_int_equal(mesh.vertex_count, 5);
  assert_int_equal(mesh.triangle_count, 3); /* the 2-vertex face is skipped, as in pbrt */
  assert_non_null(mesh.n);
  assert_non_null(mesh.uv);
  assert_floats(mesh.p, quad_p, 15);
  assert_floats(mesh.n, quad_n, 15);
  assert_floats(mesh.uv, quad_uv, 10);
  assert_uints(mesh.indices, quad_indices, 9);
  clr_mesh_free(&mesh);
  assert_null(mesh.p);
}

/* The same mesh in binary, with mixed property types, a double x, no normals. */
static void write_binary(const char *name, int big_endian, char *path) {
  FILE *fp = temp_file(name, path);
  fprintf(fp,
          "ply\nformat %s 1.0\nelement vertex 5\nproperty double x\nproperty float y\n"
          "property float z\nproperty short junk\nproperty float texture_u\n"
          "property float texture_v\nproperty float nx\nelement face 3\n"
          "property list ushort uint vertex_index\nproperty list uchar char labels\n"
          "element edge 2\nproperty list uint ushort ends\nend_header\n",
          big_endian ? "binary_big_endian" : "binary_little_endian");
  for (int v = 0; v < 5; ++v) {
    put(fp, "double", quad_p[3 * v], big_endian);
    put(fp, "float", quad_p[3 * v + 1], big_endian);
    put(fp, "float", quad_p[3 * v + 2], big_endian);
    put(fp, "short", -v, big_endian);
    put(fp, "float", quad_uv[2 * v], big_endian);
    put(fp, "float", quad_uv[2 * v + 1], big_endian);
    put(fp, "float", 9, big_endian);
  }
  const int counts[3] = {4, 3, 1}, faces[3][4] = {{0, 1, 2, 3}, {4, 0, 1}, {0}};
  for (int f = 0; f < 3; ++f) {
    put(fp, "ushort", counts[f], big_endian);
    for (int k = 0; k < counts[f]; ++k) put(fp, "uint", faces[f][k], big_endian);
    put(fp, "uchar", 2, big_endian);
    put(fp, "char", -1, big_endian);
    put(fp, "char", -2, big_endian);
  }
  for (int e = 0; e < 2; ++e) {
    put(fp, "uint", 2, big_endian);
    put(fp, "ushort", e, big_endian);
    put(fp, "ushort", e + 1, big_endian);
  }
  assert_int_equal(fclose(fp), 0);
}

static void check_binary(int big_endian) {
  char path[TEMP_PATH_MAX];
  write_binary(big_endian ? "big.ply" : "little.ply", big_endian, path);
  clr_mesh mesh;
  assert_int_equal(clr_ply_read(path, &mesh), CLR_SUCCESS);
  assert_int_equal(mesh.vertex_count, 5);
  assert_int_equal(mesh.triangle_count, 3); /* the 1-vertex face is skipped */
  assert_null(mesh.n);                      /* nx alone is not a normal */
  assert_non_null(mesh.uv);
  assert_floats(mesh.p, quad_p, 15);
  assert_floats(mesh.uv, quad_uv, 10);
  assert_uints(mesh.indices, quad_indices, 9);
  clr_mesh_free(&mesh);
}

static void test_ply_binary_little_endian(void **state) {
  (void)state;
  check_binary(0);
}

static void test_ply_binary_big_endian(void **state) {
  (void)state;
  check_binary(1);
}

static const char small_header[] =
    "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";

/* A binary triangle mesh whose second face references vertex `bad_index`, cut to `keep` bytes. */
static void write_small(const char *name, int bad_index, long keep, char *path) {
  FILE *fp = temp_file(name, path);
  fputs(small_header, fp);
  for (int i = 0; i < 9; ++i) put(fp, "float", i, 0);
  const int faces[2][3] = {{0, 1, 2}, {2, 1, bad_index}};
  for (int f = 0; f < 2; ++f) {
    put(fp, "uchar", 3, 0);
    for (int k = 0; k < 3; ++k) put(fp, "int", faces[f][k], 0);
  }
  assert_int_equal(fclose(fp), 0);
  if (keep >= 0) assert_int_equal(truncate(path, keep), 0);
}

static void test_ply_errors(void **state) {
  (void)state;
  char path[TEMP_PATH_MAX];
  clr_mesh mesh;
  long full = (long)strlen(small_header) + 36 + 2 * 13;
  write_small("ok.ply", 0, -1, path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_SUCCESS);
  assert_int_equal(mesh.triangle_count, 2);
  clr_mesh_free(&mesh);

  write_small("truncated.ply", 0, full - 2, path); /* inside the last face's indices */
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has(path);
  assert_message_has("truncated data in element \"face\" instance 1");
  assert_null(mesh.p);

  write_small("truncated_vertices.ply", 0, (long)strlen(small_header) + 20, path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has(path);
  assert_message_has("truncated");

  write_small("bad_index.ply", 3, -1, path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has(path);
  assert_message_has("\"face\" instance 1, vertex_indices[2] = 3 is outside [0, 3)");

  write_small("negative_index.ply", -1, -1, path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("= -1 is outside");

  write_text(
      "ascii_truncated.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
      path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("truncated data in element \"face\" instance 0");

  write_text(
      "ascii_garbage.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",
      path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("bad value in element \"vertex\" instance 1");

  write_text("bad_format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("malformed header, line 2: unknown format \"binary_middle_endian\"");

  write_text("bad_type.ply",
             "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("line 4: unknown property type \"float128\"");

  write_text("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("end of file before \"end_header\"");

  write_text("not_ply.ply", "OFF\n3 1 0\n", path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("not a PLY file");

  write_text("no_z.ply",
             "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
             "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n0\n",
             path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("x, y, z");

  write_text("huge_count.ply",
             "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
             "property float x\nproperty float y\nproperty float z\nelement face 1\n"
             "property list uchar int vertex_indices\nend_header\n",
             path);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_FILE_FORMAT);
  assert_message_has("declares 2000000000 instances");

  snprintf(path, sizeof path, "%s/missing.ply", temp_dir);
  assert_int_equal(clr_ply_read(path, &mesh), CLR_ERROR_IO);
  assert_message_has(path);
}

/* ---- meshes and "trianglemesh" ---- */

static void test_mesh_from_arrays(void **state) {
  (void)state;
  const float P[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const float N[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const float uv[] = {0, 0, 1, 0, 0, 1, 1, 1};
  const int32_t indices[] = {0, 1, 2, 2, 1, 3};
  clr_mesh mesh;
  assert_int_equal(clr_mesh_from_arrays("quad", indices, 6, P, 12, N, 12, uv, 8, &mesh),
                   CLR_SUCCESS);
  assert_int_equal(mesh.vertex_count, 4);
  assert_int_equal(mesh.triangle_count, 2);
  assert_floats(mesh.p, P, 12);
  assert_floats(mesh.n, N, 12);
  assert_floats(mesh.uv, uv, 8);
  const uint32_t expected[] = {0, 1, 2, 2, 1, 3};
  assert_uints(mesh.indices, expected, 6);
  clr_mesh_free(&mesh);

  /* Without indices, exactly three points make one triangle, as in pbrt. */
  assert_int_equal(clr_mesh_from_arrays("tri", NULL, 0, P, 9, NULL, 0, NULL, 0, &mesh),
                   CLR_SUCCESS);
  assert_int_equal(mesh.triangle_count, 1);
  assert_int_equal(mesh.indices[2], 2);
  assert_null(mesh.n);
  clr_mesh_free(&mesh);

  const int32_t bad[] = {0, 1, 2, 2, 1, 4};
  assert_int_equal(clr_mesh_from_arrays("m1", bad, 6, P, 12, NULL, 0, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("m1: vertex index 4 at position 5 (triangle 1) is out of range: 4 \"P\"");
  assert_null(mesh.p);
  const int32_t negative[] = {0, -1, 2};
  assert_int_equal(clr_mesh_from_arrays("m2", negative, 3, P, 12, NULL, 0, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("vertex index -1 at position 1");
  assert_int_equal(clr_mesh_from_arrays("m3", indices, 5, P, 12, NULL, 0, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("5 is not a multiple of 3");
  assert_int_equal(clr_mesh_from_arrays("m4", indices, 6, P, 11, NULL, 0, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("11 values given for \"point P\"");
  assert_int_equal(clr_mesh_from_arrays("m5", indices, 6, P, 12, N, 9, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("\"normal N\"");
  assert_int_equal(clr_mesh_from_arrays("m6", indices, 6, P, 12, NULL, 0, uv, 7, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("\"uv\"");
  assert_int_equal(clr_mesh_from_arrays("m7", NULL, 0, P, 12, NULL, 0, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("\"indices\" not provided");
  assert_int_equal(clr_mesh_from_arrays("m8", indices, 6, NULL, 0, NULL, 0, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("\"P\" parameter not provided");
  const float nan_p[] = {0, 0, 0, 1, NAN, 0, 0, 1, 0};
  assert_int_equal(clr_mesh_from_arrays("m9", NULL, 0, nan_p, 9, NULL, 0, NULL, 0, &mesh),
                   CLR_ERROR_SCENE);
  assert_message_has("m9: position of vertex 1 is not finite");
}

static void test_mesh_validate(void **state) {
  (void)state;
  float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  uint32_t idx[6] = {0, 1, 2, 0, 7, 1};
  clr_mesh mesh = {3, 2, p, NULL, NULL, idx};
  assert_int_equal(clr_mesh_validate(&mesh, "shape 3"), CLR_ERROR_SCENE);
  assert_message_has(
      "shape 3: vertex index 7 at position 4 (triangle 1) is out of range: the mesh has 3 "
      "vertices");
  mesh.triangle_count = 1;
  assert_int_equal(clr_mesh_validate(&mesh, "shape 3"), CLR_SUCCESS);
  p[8] = INFINITY;
  assert_int_equal(clr_mesh_validate(&mesh, "shape 3"), CLR_ERROR_SCENE);
  assert_message_has("vertex 2 is not finite");
}

static void test_mesh_transform(void **state) {
  (void)state;
  clr_mesh mesh;
  const float P[] = {1, 2, 3, 0, 0, 0, -1, 0, 1};
  const float N[] = {1, 1, 0, 0, 0, 1, 0, 1, 0};
  assert_int_equal(clr_mesh_from_arrays("t", NULL, 0, P, 9, N, 9, NULL, 0, &mesh), CLR_SUCCESS);
  /* Scale x by 2, then translate by (10, 20, 30). */
  const float m[16] = {2, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, 30, 0, 0, 0, 1};
  assert_int_equal(clr_mesh_transform(&mesh, m), CLR_SUCCESS);
  const float p_expected[] = {12, 22, 33, 10, 20, 30, 8, 20, 31};
  const float n_expected[] = {0.5f, 1, 0, 0, 0, 1, 0, 1, 0}; /* inverse transpose */
  assert_floats(mesh.p, p_expected, 9);
  assert_floats(mesh.n, n_expected, 9);
  /* A 90 degree rotation about z keeps normals perpendicular to the rotated surface. */
  const float rot[16] = {0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  assert_int_equal(clr_mesh_transform(&mesh, rot), CLR_SUCCESS);
  assert_true(mesh.p[0] == -22 && mesh.p[1] == 12 && mesh.n[0] == -1 && mesh.n[1] == 0.5f);
  const float singular[16] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  assert_int_equal(clr_mesh_transform(&mesh, singular), CLR_ERROR_SCENE);
  assert_true(mesh.p[0] == -22); /* unchanged */
  clr_mesh_free(&mesh);
}

/* ---- Loop subdivision ---- */

static void make_mesh(clr_mesh *mesh, const float *p, int nv, const int32_t *indices, int nt) {
  assert_int_equal(clr_mesh_from_arrays("test mesh", indices, 3 * (size_t)nt, p, 3 * (size_t)nv,
                                        NULL, 0, NULL, 0, mesh),
                   CLR_SUCCESS);
}

/* Regular tetrahedron centred at the origin, wound counter-clockwise seen from outside. */
static const float tetra_p[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const int32_t tetra_i[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

static void build_icosahedron(clr_mesh *mesh) {
  const float g = 1.6180339887f;
  const float p[] = {-1, g,  0,  1, g, 0,  -1, -g, 0,  1, -g, 0, 0,  -1, g,  0,  1, g,
                     0,  -1, -g, 0, 1, -g, g,  0,  -1, g, 0,  1, -g, 0,  -1, -g, 0, 1};
  const int32_t t[] = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                       4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                       6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  make_mesh(mesh, p, 12, t, 20);
}

static float dot3(const float *a, const float *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static float len3(const float *a) { return sqrtf(dot3(a, a)); }

/* Asserts that p lies behind every face plane of a convex control mesh centred at the origin
 * whose face centroids point along the face normals (regular polyhedra). */
static void assert_in_hull(const float *p, const clr_mesh *control) {
  for (int f = 0; f < control->triangle_count; ++f) {
    float centroid[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        centroid[c] += control->p[3 * control->indices[3 * f + k] + c] / 3;
    float d[3] = {p[0] - centroid[0], p[1] - centroid[1], p[2] - centroid[2]};
    assert_true(dot3(d, centroid) <= 1e-5f * dot3(centroid, centroid));
  }
}

static void test_loop_counts(void **state) {
  (void)state;
  clr_mesh tetra, ico, out;
  make_mesh(&tetra, tetra_p, 4, tetra_i, 4);
  build_icosahedron(&ico);
  /* Closed meshes: V' = V + E, F' = 4F, E' = 2E + 3F. */
  const int tetra_v[] = {4, 10, 34, 130}, ico_v[] = {12, 42, 162, 642};
  for (int level = 0; level < 4; ++level) {
    assert_int_equal(clr_loop_subdivide(&tetra, level, &out), CLR_SUCCESS);
    assert_int_equal(out.vertex_count, tetra_v[level]);
    assert_int_equal(out.triangle_count, 4 << (2 * level));
    assert_non_null(out.n);
    assert_null(out.uv);
    assert_int_equal(clr_mesh_validate(&out, "subdivided tetrahedron"), CLR_SUCCESS);
    clr_mesh_free(&out);
    assert_int_equal(clr_loop_subdivide(&ico, level, &out), CLR_SUCCESS);
    assert_int_equal(out.vertex_count, ico_v[level]);
    assert_int_equal(out.triangle_count, 20 << (2 * level));
    clr_mesh_free(&out);
  }
  clr_mesh_free(&tetra);
  clr_mesh_free(&ico);
}

static void test_loop_tetrahedron_limit(void **state) {
  (void)state;
  clr_mesh tetra, out;
  make_mesh(&tetra, tetra_p, 4, tetra_i, 4);
  /* Valence 3: gamma = 1/5, so the limit of vertex p is 2/5 p + 1/5 (sum of the others) = p / 5. */
  for (int level = 0; level < 4; ++level) {
    assert_int_equal(clr_loop_subdivide(&tetra, level, &out), CLR_SUCCESS);
    for (int v = 0; v < 4; ++v)
      for (int c = 0; c < 3; ++c)
        assert_float_equal(out.p[3 * v + c], 0.2f * tetra_p[3 * v + c], 2e-6);
    /* Inside the tetrahedron, and by symmetry the normals at the original vertices are radial. */
    for (int v = 0; v < out.vertex_count; ++v) {
      const float *p = out.p + 3 * v, *n = out.n + 3 * v;
      assert_in_hull(p, &tetra);
      if (v < 4) assert_float_equal(dot3(n, p) / (len3(n) * len3(p)), -1.0f, 1e-5);
    }
    clr_mesh_free(&out);
  }
  clr_mesh_free(&tetra);
}

static void test_loop_icosahedron(void **state) {
  (void)state;
  clr_mesh ico, out[4];
  build_icosahedron(&ico);
  for (int level = 0; level < 4; ++level)
    assert_int_equal(clr_loop_subdivide(&ico, level, &out[level]), CLR_SUCCESS);
  /* Limit positions of the original vertices do not depend on the number of levels. */
  for (int level = 1; level < 4; ++level)
    for (int i = 0; i < 36; ++i) assert_float_equal(out[level].p[i], out[0].p[i], 2e-6);
  const clr_mesh *m = &out[3];
  float r0 = len3(m->p), r_edge = len3(m->p + 3 * 12);
  assert_true(r0 < len3(ico.p)); /* limit points move inside the control mesh */
  for (int v = 0; v < m->vertex_count; ++v) {
    const float *p = m->p + 3 * v, *n = m->n + 3 * v;
    assert_in_hull(p, &ico);
    /* Symmetry: vertices of one class share a radius; normals at the original and first-level
     * vertices are radial. As in pbrt-v3, counter-clockwise winding gives inward normals. */
    if (v < 12)
      assert_float_equal(len3(p), r0, 2e-6);
    else if (v < 42)
      assert_float_equal(len3(p), r_edge, 2e-6);
    if (v < 42)
      assert_float_equal(dot3(n, p) / (len3(n) * len3(p)), -1.0f, 1e-5);
    else
      assert_true(dot3(n, p) < 0);
  }
  for (int level = 0; level < 4; ++level) clr_mesh_free(&out[level]);
  clr_mesh_free(&ico);
}

static void test_loop_flat_grid(void **state) {
  (void)state;
  enum { N = 4 }; /* N x N vertices on [0,3]^2 */
  float p[3 * N * N];
  int32_t t[6 * (N - 1) * (N - 1)], nt = 0;
  for (int y = 0; y < N; ++y)
    for (int x = 0; x < N; ++x)
      p[3 * (y * N + x)] = (float)x, p[3 * (y * N + x) + 1] = (float)y, p[3 * (y * N + x) + 2] = 0;
  for (int y = 0; y < N - 1; ++y)
    for (int x = 0; x < N - 1; ++x) {
      int32_t a = y * N + x, b = a + 1, c = a + N + 1, d = a + N;
      if ((x + y) % 2)
        t[nt++] = a, t[nt++] = b, t[nt++] = c, t[nt++] = a, t[nt++] = c, t[nt++] = d;
      else
        t[nt++] = a, t[nt++] = b, t[nt++] = d, t[nt++] = b, t[nt++] = c, t[nt++] = d;
    }
  clr_mesh grid, out;
  make_mesh(&grid, p, N * N, t, nt / 3);
  assert_int_equal(clr_loop_subdivide(&grid, 2, &out), CLR_SUCCESS);
  /* V = 16, E = 33, F = 18 -> V = 49, E = 120, F = 72 -> V = 169, F = 288. */
  assert_int_equal(out.vertex_count, 169);
  assert_int_equal(out.triangle_count, 288);
  /* pbrt-v3 has no corner rule: boundary curves are cubic B-splines of the boundary polygon,
   * so the sides stay exactly on their lines away from the rounded corners (t in [1, 2]). */
  int on_lines = 0, found[4][5] = {{0}};
  for (int v = 0; v < out.vertex_count; ++v) {
    const float *q = out.p + 3 * v, *n = out.n + 3 * v;
    assert_true(q[2] == 0.0f);                             /* stays planar */
    assert_true(n[0] == 0.0f && n[1] == 0.0f && n[2] < 0); /* perpendicular to the plane */
    assert_true(q[0] >= 0 && q[0] <= 3 && q[1] >= 0 && q[1] <= 3);
    const float side_coord[4] = {q[1], q[0], 3 - q[1], 3 - q[0]},
                along[4] = {q[0], q[1], q[0], q[1]};
    for (int side = 0; side < 4; ++side) {
      if (side_coord[side] != 0.0f) continue;
      ++on_lines;
      for (int k = 0; k < 5; ++k)
        found[side][k] += fabsf(along[side] - (1.0f + 0.25f * (float)k)) < 1e-6f;
    }
  }
  assert_int_equal(on_lines, 20);
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < 5; ++k) assert_int_equal(found[side][k], 1);
  clr_mesh_free(&out);
  clr_mesh_free(&grid);
}

static void test_loop_bad_input(void **state) {
  (void)state;
  const float p[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, -1, 0, 0};
  clr_mesh mesh, out;
  const int32_t fin[] = {0, 1, 2, 1, 0, 3, 0, 1, 4}; /* edge (0,1) in three triangles */
  make_mesh(&mesh, p, 7, fin, 3);
  assert_int_equal(clr_loop_subdivide(&mesh, 1, &out), CLR_ERROR_SCENE);
  assert_message_has("non-manifold mesh: edge (0, 1)");
  assert_null(out.p);
  clr_mesh_free(&mesh);
  const int32_t flipped[] = {0, 1, 2, 0, 1, 3}; /* opposite windings across edge (0,1) */
  make_mesh(&mesh, p, 7, flipped, 2);
  assert_int_equal(clr_loop_subdivide(&mesh, 1, &out), CLR_ERROR_SCENE);
  clr_mesh_free(&mesh);
  const int32_t bowtie[] = {0, 1, 2, 0, 4, 5}; /* two fans meet at vertex 0 */
  make_mesh(&mesh, p, 7, bowtie, 2);
  assert_int_equal(clr_loop_subdivide(&mesh, 1, &out), CLR_ERROR_SCENE);
  assert_message_has("vertex 0 joins 2 triangles that do not form a single fan");
  clr_mesh_free(&mesh);
  const int32_t repeat[] = {0, 1, 1};
  make_mesh(&mesh, p, 7, repeat, 1);
  assert_int_equal(clr_loop_subdivide(&mesh, 1, &out), CLR_ERROR_SCENE);
  assert_message_has("triangle 0 repeats a vertex");
  assert_int_equal(clr_loop_subdivide(&mesh, -1, &out), CLR_ERROR_INVALID_ARGUMENT);
  clr_mesh_free(&mesh);
  /* Unused vertices are dropped; a single triangle is all boundary. */
  const int32_t one[] = {6, 1, 2};
  make_mesh(&mesh, p, 7, one, 1);
  assert_int_equal(clr_loop_subdivide(&mesh, 0, &out), CLR_SUCCESS);
  assert_int_equal(out.vertex_count, 3); /* vertices 1, 2, 6 in order */
  /* pbrt-v3's boundary limit rule: 3/5 p + 1/5 (each boundary neighbour). */
  const float limit0[3] = {0.6f * 1 + 0.2f * (0 - 1), 0.2f * 1, 0};
  for (int c = 0; c < 3; ++c) assert_float_equal(out.p[c], limit0[c], 1e-6);
  for (int v = 0; v < 3; ++v)
    assert_true(out.n[3 * v + 2] < 0 && out.n[3 * v] == 0 && out.n[3 * v + 1] == 0);
  clr_mesh_free(&out);
  assert_int_equal(clr_loop_subdivide(&mesh, 1, &out), CLR_SUCCESS);
  assert_int_equal(out.vertex_count, 6);
  assert_int_equal(out.triangle_count, 4);
  clr_mesh_free(&out);
  clr_mesh_free(&mesh);
  mesh.triangle_count = 0;
  assert_int_equal(clr_loop_subdivide(NULL, 1, &out), CLR_ERROR_NULL_POINTER);
}

/* ---- the killeroo scene's loopsubdiv shape ---- */

/* Reads the numbers in the [ ] after `name` in `text`; returns how many (0 if absent). */
static size_t read_array(const char *text, const char *name, double **values) {
  const char *s = strstr(text, name);
  if (!s || !(s = strchr(s, '['))) return 0;
  size_t count = 0, cap = 1024;
  *values = malloc(cap * sizeof **values);
  char *end;
  for (++s;;) {
    double v = strtod(s, &end);
    if (end == s) break;
    if (count == cap) *values = realloc(*values, (cap *= 2) * sizeof **values);
    assert_non_null(*values);
    (*values)[count++] = v;
    s = end;
  }
  return count;
}

static int compare_u64(const void *a, const void *b) {
  uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return (x > y) - (x < y);
}

/* Number of distinct undirected edges of a mesh. */
static int count_edges(const clr_mesh *mesh) {
  size_t n = 3 * (size_t)mesh->triangle_count;
  uint64_t *keys = malloc(n * sizeof *keys);
  assert_non_null(keys);
  for (size_t i = 0; i < n; ++i) {
    uint32_t a = mesh->indices[i], b = mesh->indices[i % 3 == 2 ? i - 2 : i + 1];
    keys[i] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
  }
  qsort(keys, n, sizeof *keys, compare_u64);
  int count = 0;
  for (size_t i = 0; i < n; ++i) count += i == 0 || keys[i] != keys[i - 1];
  free(keys);
  return count;
}

static void test_loop_killeroo(void **state) {
  (void)state;
  FILE *fp = fopen(CLR_SOURCE_DIR "/scenes/killeroo-simple/geometry/killeroo.pbrt", "rb");
  assert_non_null(fp); /* ships in scenes/ */
  static char text[1 << 20];
  size_t size = fread(text, 1, sizeof text - 1, fp);
  fclose(fp);
  text[size] = 0;
  double *levels = NULL, *idx = NULL, *pts = NULL;
  assert_int_equal(read_array(text, "\"integer nlevels\"", &levels), 1);
  size_t ni = read_array(text, "\"integer indices\"", &idx),
         np = read_array(text, "\"point P\"", &pts);
  assert_true(ni > 0 && ni % 3 == 0 && np > 0 && np % 3 == 0);
  int32_t *indices = malloc(ni * sizeof *indices);
  float *P = malloc(np * sizeof *P);
  for (size_t i = 0; i < ni; ++i) indices[i] = (int32_t)idx[i];
  for (size_t i = 0; i < np; ++i) P[i] = (float)pts[i];
  clr_mesh mesh, out;
  assert_int_equal(clr_mesh_from_arrays("killeroo", indices, ni, P, np, NULL, 0, NULL, 0, &mesh),
                   CLR_SUCCESS);
  int nlevels = (int)levels[0];
  assert_int_equal(nlevels, 1);
  assert_int_equal(clr_loop_subdivide(&mesh, nlevels, &out), CLR_SUCCESS);
  /* V' = V + E (the killeroo is open: some edges have one triangle), F' = 4F. */
  assert_int_equal(out.triangle_count, 4 * mesh.triangle_count);
  assert_int_equal(out.vertex_count, mesh.vertex_count + count_edges(&mesh));
  assert_int_equal(clr_mesh_validate(&out, "killeroo"), CLR_SUCCESS);
  for (int v = 0; v < out.vertex_count; ++v) assert_true(len3(out.n + 3 * v) > 0);
  clr_mesh_free(&out);
  clr_mesh_free(&mesh);
  free(indices);
  free(P);
  free(levels);
  free(idx);
  free(pts);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ply_ascii),
      cmocka_unit_test(test_ply_binary_little_endian),
      cmocka_unit_test(test_ply_binary_big_endian),
      cmocka_unit_test(test_ply_errors),
      cmocka_unit_test(test_mesh_from_arrays),
      cmocka_unit_test(test_mesh_validate),
      cmocka_unit_test(test_mesh_transform),
      cmocka_unit_test(test_loop_counts),
      cmocka_unit_test(test_loop_tetrahedron_limit),
      cmocka_unit_test(test_loop_icosahedron),
      cmocka_unit_test(test_loop_flat_grid),
      cmocka_unit_test(test_loop_bad_input),
      cmocka_unit_test(test_loop_killeroo),
  };
  return cmocka_run_group_tests(tests, make_temp_dir, remove_temp_dir);
}
