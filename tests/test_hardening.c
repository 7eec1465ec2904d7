/* Regression tests of issue #8's defects that need more than a failing command line (those are
 * in test_bad_input.c): clean error messages (3), film_write refusing non-regular targets and
 * the re-check right before the rename (1), merged files' sample counts (11), and
 * film_merge_sums dropping non-finite pixels. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "clrender.h"
#include "exr_io.h"
#include "loop_subdiv.h"
#include "ply_reader.h"
#include "renderer.h"
#include "scene_parser.h"
#include "hardening_util.h"

static int count_occurrences(const char *haystack, const char *needle) {
  int n = 0;
  for (const char *p = haystack; (p = strstr(p, needle)) != NULL; p += strlen(needle)) ++n;
  return n;
}

/* Builds `world` (one line, line 2 of a scene at dir/s.pbrt) and returns the error message. */
static char *scene_error(const char *dir, const char *world) {
  char scene[2048], path[700];
  snprintf(scene, sizeof scene,
           "Film \"image\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
           "WorldBegin\n%s\n",
           world);
  snprintf(path, sizeof path, "%s/s.pbrt", dir);
  assert_true(hu_write_file(path, scene, strlen(scene)));
  clr_scene_desc *d = NULL;
  assert_int_equal(clr_scene_parse_file(path, NULL, &d), CLR_SUCCESS);
  clr_render_options o;
  clr_render_options_init(&o);
  o.quiet = 1;
  assert_int_not_equal(clr_render_desc(d, &o, NULL, 0, NULL), CLR_SUCCESS);
  clr_scene_desc_free(d);
  return strdup(clr_last_error_message());
}

/* The message starts with FILE:LINE, and holds the reader's own message (`reason`) once. */
static void assert_clean(const char *message, const char *dir, const char *reason) {
  char where[700];
  snprintf(where, sizeof where, "%s/s.pbrt:3: ", dir);
  if (strncmp(message, where, strlen(where)) != 0 || count_occurrences(message, reason) != 1 ||
      count_occurrences(message, where) != 1)
    fprintf(stderr, "message: %s\nexpected start: %s\nreason once: %s\n", message, where, reason);
  assert_int_equal(strncmp(message, where, strlen(where)), 0);
  assert_int_equal(count_occurrences(message, where), 1);
  assert_int_equal(count_occurrences(message, reason), 1);
}

/* Defect 3: PLY, loopsubdiv and imagemap errors prefixed once, never garbled. */
static void test_clean_messages(void **state) {
  (void)state;
  const char *dir = hu_workdir("messages", 0);
  char path[700];
  /* PLY: truncated data */
  static const char ply[] =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n";
  snprintf(path, sizeof path, "%s/t.ply", dir);
  assert_true(hu_write_file(path, ply, strlen(ply)));
  clr_mesh m;
  assert_int_equal(clr_ply_read(path, &m), CLR_ERROR_FILE_FORMAT);
  char *reason = strdup(clr_last_error_message() + strlen("clr_ply_read: \"") + strlen(path));
  char *msg = scene_error(dir, "Shape \"plymesh\" \"string filename\" \"t.ply\"");
  assert_non_null(strstr(reason, "truncated data"));
  assert_clean(msg, dir, reason);
  free(reason);
  free(msg);

  /* loopsubdiv: non-manifold input (an edge in three triangles) */
  int32_t ix[9] = {0, 1, 2, 0, 1, 3, 0, 1, 4};
  float p[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  clr_mesh in, out;
  assert_int_equal(clr_mesh_from_arrays("in", ix, 9, p, 15, NULL, 0, NULL, 0, &in), CLR_SUCCESS);
  assert_int_not_equal(clr_loop_subdivide(&in, 1, &out), CLR_SUCCESS);
  clr_mesh_free(&in);
  reason = strdup(clr_last_error_message());
  msg = scene_error(dir,
                    "Shape \"loopsubdiv\" \"integer nlevels\" [1] \"integer indices\" "
                    "[0 1 2 0 1 3 0 1 4] \"point P\" [0 0 0 1 0 0 0 1 0 0 -1 0 0 0 1]");
  assert_clean(msg, dir, reason);
  free(reason);
  free(msg);

  /* imagemap: a PNG that is not one */
  snprintf(path, sizeof path, "%s/g.png", dir);
  assert_true(hu_write_file(path, "not a png", 9));
  clr_image im;
  assert_int_equal(clr_image_read(path, &im), CLR_ERROR_FILE_FORMAT);
  reason = strdup(clr_last_error_message());
  msg = scene_error(dir, "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"g.png\"");
  assert_clean(msg, dir, reason);
  free(reason);
  free(msg);
  hu_sh("rm -rf '%s'", dir);
}

static clr_film small_film(clr_context *ctx, int w, int h) {
  clr_context_desc cd;
  clr_context_desc_init(&cd);
  assert_int_equal(clr_context_create(&cd, ctx), CLR_SUCCESS);
  clr_film_desc fd;
  clr_film_desc_init(&fd);
  fd.x_resolution = w;
  fd.y_resolution = h;
  clr_film film = NULL;
  assert_int_equal(film_create(*ctx, &fd, &film), CLR_SUCCESS);
  return film;
}

/* Defect 1 at the API: film_write / film_write_png refuse devices, FIFOs, symlinks and read-only
 * files themselves, leaving them as they were. */
static void test_film_write_refuses_special_targets(void **state) {
  (void)state;
  const char *dir = hu_workdir("film_write", 0);
  clr_context ctx = NULL;
  clr_film film = small_film(&ctx, 4, 4);
  char fifo[700], link[700], target[700], ro[700];
  snprintf(fifo, sizeof fifo, "%s/f.exr", dir);
  snprintf(link, sizeof link, "%s/l.exr", dir);
  snprintf(target, sizeof target, "%s/target.exr", dir);
  snprintf(ro, sizeof ro, "%s/ro.png", dir);
  assert_int_equal(mkfifo(fifo, 0666), 0);
  assert_true(hu_write_file(target, "keep", 4));
  assert_int_equal(symlink("target.exr", link), 0);
  assert_true(hu_write_file(ro, "old", 3));
  assert_int_equal(chmod(ro, 0444), 0);
  char *before = hu_snapshot(dir);
  assert_int_equal(film_write(film, "/dev/null", NULL), CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "not a regular file"));
  assert_int_equal(film_write(film, fifo, NULL), CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "not a regular file"));
  assert_int_equal(film_write(film, link, NULL), CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "symbolic link"));
  assert_int_equal(film_write_png(film, ro, 1.0f), CLR_ERROR_IO);
  assert_non_null(strstr(clr_last_error_message(), "read-only"));
  assert_int_equal(film_write_png(film, "/dev/full", 1.0f), CLR_ERROR_IO);
  char *after = hu_snapshot(dir);
  assert_string_equal(before, after);
  free(before);
  free(after);
  /* a regular writable file is replaced */
  assert_int_equal(film_write(film, target, NULL), CLR_SUCCESS);
  film_release(film);
  clr_context_release(ctx);
  hu_sh("rm -rf '%s'", dir);
}

/* Defect 1, the commit's re-check: the output name turns into a symlink while the render writes
 * its temporary file; the rename is refused and the symlink stays. */
static void test_commit_rechecks_target(void **state) {
  (void)state;
  const char *dir = hu_workdir("recheck", 0);
  char path[700];
  static const char scene[] =
      "Film \"image\" \"integer xresolution\" [4] \"integer yresolution\" [4]\n"
      "Sampler \"random\" \"integer pixelsamples\" [1]\nWorldBegin\nShape \"sphere\"\n";
  snprintf(path, sizeof path, "%s/s.pbrt", dir);
  assert_true(hu_write_file(path, scene, strlen(scene)));
  snprintf(path, sizeof path, "%s/target.txt", dir);
  assert_true(hu_write_file(path, "keep", 4));
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    if (chdir(dir) != 0) _exit(126);
    hu_stop_before_commit();
    int null = open("/dev/null", O_RDWR);
    dup2(null, 1);
    dup2(null, 2);
    execl(CLR_CLI_PATH, "clrender", "render", "s.pbrt", "--quiet", "--outfile", "o.exr",
          (char *)NULL);
    _exit(127);
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, WUNTRACED), pid);
  assert_true(WIFSTOPPED(status));
  snprintf(path, sizeof path, "%s/o.exr", dir);
  assert_int_equal(symlink("target.txt", path), 0);
  assert_int_equal(kill(pid, SIGCONT), 0);
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 1);
  struct stat st;
  assert_int_equal(lstat(path, &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  snprintf(path, sizeof path, "%s/target.txt", dir);
  size_t size = 0;
  char *content = hu_read_file(path, &size);
  assert_non_null(content);
  assert_int_equal(size, 4);
  assert_memory_equal(content, "keep", 4);
  free(content);
  char *snap = hu_snapshot(dir);
  assert_null(strstr(snap, ".tmp-")); /* the temporary file was removed */
  assert_null(strstr(snap, "o.png"));
  free(snap);
  hu_sh("rm -rf '%s'", dir);
}

/* Defect 11: a merged file records the inputs' sample count, not 0. */
static void test_merge_records_samples(void **state) {
  (void)state;
  const char *dir = hu_workdir("merge_samples", 0);
  static const char scene[] =
      "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
      "Sampler \"random\" \"integer pixelsamples\" [2]\nWorldBegin\nShape \"sphere\"\n";
  char path[700], err[700];
  snprintf(path, sizeof path, "%s/s.pbrt", dir);
  assert_true(hu_write_file(path, scene, strlen(scene)));
  snprintf(err, sizeof err, "%s/stderr.txt", dir);
  char *left[] = {"clrender", "render", "s.pbrt", "--quiet",   "--cropwindow", "0",
                  "0.5",      "0",      "1",      "--outfile", "a.exr",        NULL};
  char *right[] = {"clrender", "render", "s.pbrt", "--quiet",   "--cropwindow", "0.5",
                   "1",        "0",      "1",      "--outfile", "b.exr",        NULL};
  char *merge[] = {"clrender", "merge", "a.exr", "b.exr", "-o", "m.exr", NULL};
  assert_int_equal(hu_run_cli(dir, left, err), 0);
  assert_int_equal(hu_run_cli(dir, right, err), 0);
  assert_int_equal(hu_run_cli(dir, merge, err), 0);
  int32_t s[3] = {0, 0, 0};
  const char *names[3] = {"a.exr", "b.exr", "m.exr"};
  for (int i = 0; i < 3; ++i) {
    clr_exr_image *im = NULL;
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    assert_int_equal(clr_exr_read(path, &im), CLR_SUCCESS);
    assert_true(clr_exr_image_int_attr(im, "clrender.samples", &s[i]));
    clr_exr_image_free(im);
  }
  assert_true(s[0] > 0 && s[1] > 0);
  assert_int_equal(s[2], s[0] + s[1]);
  hu_sh("rm -rf '%s'", dir);
}

/* film_merge_sums drops (and counts) pixels with a NaN/Inf sum or weight, as film_add_samples
 * drops such samples; the finite pixels are added. */
static void test_merge_sums_drops_non_finite(void **state) {
  (void)state;
  clr_context ctx = NULL;
  clr_film film = small_film(&ctx, 4, 1);
  double rgb[12], weight[4], splat[12];
  for (int i = 0; i < 4; ++i) {
    weight[i] = 1.0 + i;
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = 0.5 * (i + 1), splat[3 * i + c] = 0.0;
  }
  weight[1] = NAN;
  rgb[3 * 2 + 1] = INFINITY;
  splat[3 * 3 + 2] = -INFINITY;
  assert_int_equal(film_merge_sums(film, (clr_bounds2i){0, 0, 4, 1}, rgb, weight, splat),
                   CLR_SUCCESS);
  assert_int_equal(film_dropped_samples(film), 3);
  double out_rgb[12], out_w[4], out_splat[12];
  assert_int_equal(film_get_sums(film, out_rgb, out_w, out_splat), CLR_SUCCESS);
  assert_true(out_w[0] == 1.0 && out_rgb[0] == 0.5);
  for (int i = 1; i < 4; ++i) {
    assert_true(out_w[i] == 0.0);
    for (int c = 0; c < 3; ++c)
      assert_true(out_rgb[3 * i + c] == 0.0 && out_splat[3 * i + c] == 0.0);
  }
  /* weight-only merges are checked too */
  double w_only[4] = {INFINITY, 2.0, 2.0, 2.0};
  assert_int_equal(film_merge_sums(film, (clr_bounds2i){0, 0, 4, 1}, NULL, w_only, NULL),
                   CLR_SUCCESS);
  assert_int_equal(film_dropped_samples(film), 4);
  assert_int_equal(film_get_sums(film, out_rgb, out_w, out_splat), CLR_SUCCESS);
  assert_true(out_w[0] == 1.0 && out_w[1] == 2.0);
  film_release(film);
  clr_context_release(ctx);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_clean_messages),
      cmocka_unit_test(test_film_write_refuses_special_targets),
      cmocka_unit_test(test_commit_rechecks_target),
      cmocka_unit_test(test_merge_records_samples),
      cmocka_unit_test(test_merge_sums_drops_non_finite),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
