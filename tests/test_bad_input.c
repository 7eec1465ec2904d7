/* Bad-input catalogue (issue #8): CLI flags, scene files, PLY meshes, textures, merge inputs and
 * output paths run through the real `clrender` binary, plus API misuse. Every CLI case runs in a
 * fresh directory inside the build tree holding its fixture files and asserts the exit status,
 * that stderr names the problem (file:line, parameter or value), that nothing was written and
 * that existing files are untouched (directory snapshot before == after), and that no temporary
 * file was left in /dev. */
#define _GNU_SOURCE
#include <glob.h>
#include <math.h>
#include <setjmp.h>
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

/* ---- scene text: line 1 LookAt, 2 Camera, 3 Film, 4 Sampler, 5 Integrator, 6 WorldBegin,
 * 7 the case's first world line. ---- */
#define HEAD "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
#define FILM "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
#define SAMP "Sampler \"random\" \"integer pixelsamples\" [1]\n"
#define INTEG "Integrator \"ambientocclusion\" \"integer nsamples\" [1]\n"
#define SCENE(world) HEAD FILM SAMP INTEG "WorldBegin\n" world "\n"
#define SCENE_FILM(film) HEAD film "\n" SAMP INTEG "WorldBegin\nShape \"sphere\"\n"
#define SCENE_SAMP(samp) HEAD FILM samp "\n" INTEG "WorldBegin\nShape \"sphere\"\n"
#define SCENE_OPT(extra) HEAD FILM SAMP INTEG extra "\nWorldBegin\nShape \"sphere\"\n"
#define GOOD SCENE("Shape \"sphere\"")
#define PLY_SHAPE SCENE("Shape \"plymesh\" \"string filename\" \"t.ply\"")
#define IMAGEMAP(file)                                                        \
  SCENE("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"" file \
        "\"\n"                                                                \
        "Material \"matte\" \"texture Kd\" \"t\"\nShape \"sphere\"")

#define PLY_HEAD(count_type)                                                      \
  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" \
  "property float z\nelement face 1\nproperty list " count_type                   \
  " int vertex_indices\n"                                                         \
  "end_header\n0 0 0\n1 0 0\n0 1 0\n"

/* Fixture contents: plain text, or "@dir", "@fifo", "@link:TARGET", "@ro:TEXT" (mode 0444),
 * "@forged-png" (IHDR 1000000 x 1000000), "@forged-exr" (data window 1000000 x 1000000),
 * "@rgb-exr" (valid EXR without clrender metadata), "@binary" (bytes 1..31 and 128..255),
 * "@sparse:BYTES" (a sparse file of that size: costs no disk). */
typedef struct bad_case {
  const char *name;
  const char *files[4][2];
  const char *args; /* after "clrender", split at spaces */
  int status;
  const char *expect[2]; /* substrings of stderr (NULL: none) */
  const char *absent;    /* must not appear in stderr */
} bad_case;

#define LONG_SECRET "SECRETSECRETSECRETSECRETSECRETSECRET"

static const bad_case cases[] = {
    /* ---- CLI flags: usage errors, status 2 ---- */
    {"no-command", {{0}}, "", 2, {"usage", NULL}, NULL},
    {"unknown-command", {{0}}, "bogus", 2, {"unknown command \"bogus\"", NULL}, NULL},
    {"render-no-scene", {{0}}, "render", 2, {"no scene file given", NULL}, NULL},
    {"spp-zero", {{"s.pbrt", GOOD}}, "render s.pbrt --spp 0", 2, {"\"--spp\"", NULL}, NULL},
    {"spp-negative", {{"s.pbrt", GOOD}}, "render s.pbrt --spp -3", 2, {"\"--spp\"", NULL}, NULL},
    {"spp-text", {{"s.pbrt", GOOD}}, "render s.pbrt --spp abc", 2, {"\"--spp\"", NULL}, NULL},
    {"spp-missing", {{"s.pbrt", GOOD}}, "render s.pbrt --spp", 2, {"\"--spp\"", NULL}, NULL},
    {"spp-huge",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --spp 99999999999",
     2,
     {"\"--spp\"", NULL},
     NULL},
    {"nthreads-negative",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --nthreads -1",
     2,
     {"\"--nthreads\"", NULL},
     NULL},
    {"nthreads-huge",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --nthreads 99999",
     2,
     {"\"--nthreads\"", NULL},
     NULL},
    {"tile-size-zero",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --tile-size 0",
     2,
     {"\"--tile-size\"", NULL},
     NULL},
    {"seed-negative", {{"s.pbrt", GOOD}}, "render s.pbrt --seed -1", 2, {"\"--seed\"", NULL}, NULL},
    {"seed-huge",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --seed 5000000000",
     2,
     {"\"--seed\"", NULL},
     NULL},
    {"crop-3-values",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --cropwindow 0 1 0",
     2,
     {"\"--cropwindow\"", NULL},
     NULL},
    {"crop-text",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --cropwindow 0 1 0 x",
     2,
     {"\"--cropwindow\"", NULL},
     NULL},
    {"crop-reversed",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --cropwindow 1 0 0 1",
     2,
     {"\"--cropwindow\"", NULL},
     NULL},
    {"crop-outside",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --cropwindow 0 1.5 0 1",
     2,
     {"\"--cropwindow\"", NULL},
     NULL},
    {"crop-nan",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --cropwindow nan 1 0 1",
     2,
     {"\"--cropwindow\"", NULL},
     NULL},
    {"crop-empty",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --cropwindow 0.5 0.5 0 1",
     2,
     {"\"--cropwindow\"", NULL},
     NULL},
    {"sampler-unknown",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --sampler bogus",
     2,
     {"\"--sampler\"", NULL},
     NULL},
    {"filter-unknown",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --filter bogus",
     2,
     {"\"--filter\"", NULL},
     NULL},
    {"seeding-unknown",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --seeding foo",
     2,
     {"\"--seeding\"", NULL},
     NULL},
    {"randomization-unknown",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --randomization bogus",
     2,
     {"\"--randomization\"", NULL},
     NULL},
    {"device-list-empty-entry",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --device 0,,1",
     2,
     {"\"--device\" \"0,,1\"", "empty entry"},
     NULL},
    {"device-list-trailing-comma",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --device=0,",
     2,
     {"\"--device\" \"0,\"", "empty entry"},
     NULL},
    {"device-list-leading-comma",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --device ,1",
     2,
     {"\"--device\" \",1\"", "empty entry"},
     NULL},
    {"time-limit-not-a-number",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --time-limit abc",
     2,
     {"\"--time-limit\"", NULL},
     NULL},
    {"checkpoint-trailing-junk",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --checkpoint -5x",
     2,
     {"\"--checkpoint\"", NULL},
     NULL},
    {"pass-spp-zero",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --pass-spp 0",
     2,
     {"\"--pass-spp\"", NULL},
     NULL},
    {"noise-threshold-negative",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --noise-threshold -1",
     2,
     {"\"--noise-threshold\"", NULL},
     NULL},
    {"noise-threshold-nan",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --noise-threshold nan",
     2,
     {"\"--noise-threshold\"", NULL},
     NULL},
    {"error-map-without-threshold",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --error-map e.exr",
     2,
     {"--error-map needs --noise-threshold", NULL},
     NULL},
    {"resume-missing-file",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --resume missing.exr",
     1,
     {"missing.exr", NULL},
     NULL},
    {"seeding-pbrt-v4-02sequence",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --seeding pbrt-v4 --sampler 02sequence",
     1,
     {"render options", "not a pbrt-v4 sampler"},
     NULL},
    {"option-unknown",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --bogus",
     2,
     {"unknown option \"--bogus\"", NULL},
     NULL},
    {"two-scenes", {{"s.pbrt", GOOD}}, "render s.pbrt s.pbrt", 2, {"\"s.pbrt\"", NULL}, NULL},
    {"merge-no-output", {{0}}, "merge a.exr", 2, {"-o OUT.exr is required", NULL}, NULL},
    {"merge-no-inputs", {{0}}, "merge -o m.exr", 2, {"no input films", NULL}, NULL},
    {"merge-option-unknown", {{0}}, "merge --bogus a.exr -o m.exr", 2, {"\"--bogus\"", NULL}, NULL},
    {"samples-sampler-unknown",
     {{0}},
     "samples --sampler bogus",
     2,
     {"unknown sampler \"bogus\"", NULL},
     NULL},

    /* ---- scene files: status 1, FILE[:LINE] and the reason ---- */
    {"scene-missing", {{0}}, "render missing.pbrt", 1, {"missing.pbrt", "No such file"}, NULL},
    {"scene-empty", {{"s.pbrt", ""}}, "render s.pbrt", 1, {"s.pbrt", "expected WorldBegin"}, NULL},
    {"scene-no-world",
     {{"s.pbrt", HEAD FILM SAMP}},
     "render s.pbrt",
     1,
     {"s.pbrt", "not a pbrt scene"},
     NULL},
    {"scene-dev-null", {{0}}, "render /dev/null", 1, {"/dev/null", "is not a regular file"}, NULL},
    {"scene-dev-zero", {{0}}, "render /dev/zero", 1, {"/dev/zero", "is not a regular file"}, NULL},
    {"scene-directory", {{"d", "@dir"}}, "render d", 1, {"'d'", "is a directory"}, NULL},
    {"scene-fifo",
     {{"f.pbrt", "@fifo"}},
     "render f.pbrt",
     1,
     {"f.pbrt", "is not a regular file"},
     NULL},
    {"scene-binary",
     {{"s.pbrt", "@binary"}},
     "render s.pbrt",
     1,
     {"s.pbrt:1:1", "binary data"},
     NULL},
    {"scene-too-large",
     {{"s.pbrt", "@sparse:1073741825"}},
     "render s.pbrt",
     1,
     {"'s.pbrt' is too large (1073741825 bytes, at most 1073741824)", NULL},
     "memory"},
    {"include-too-large",
     {{"s.pbrt", SCENE("Include \"big.pbrt\"")}, {"big.pbrt", "@sparse:1073741825"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1: Include", "is too large"},
     "memory"},
    {"include-dev-zero",
     {{"s.pbrt", SCENE("Include \"/dev/zero\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1: Include", "is not a regular file"},
     NULL},
    {"include-directory",
     {{"s.pbrt", SCENE("Include \"d\"")}, {"d", "@dir"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1: Include", "is a directory"},
     NULL},
    {"include-missing",
     {{"s.pbrt", SCENE("Include \"nope.pbrt\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1: Include", "nope.pbrt"},
     NULL},
    {"include-fifo",
     {{"s.pbrt", SCENE("Include \"f\"")}, {"f", "@fifo"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1: Include", "is not a regular file"},
     NULL},
    {"include-binary",
     {{"s.pbrt", SCENE("Include \"b.bin\"")}, {"b.bin", "@binary"}},
     "render s.pbrt",
     1,
     {"b.bin:1:1", "binary data"},
     NULL},
    {"include-secret",
     {{"s.pbrt", SCENE("Include \"secret.txt\"")}, {"secret.txt", LONG_SECRET " rest\n"}},
     "render s.pbrt",
     1,
     {"secret.txt:1:1: expected a directive", "'SECRETSECRETSECR...'"},
     "SECRETSECRETSECRETS"},
    {"include-recursive",
     {{"s.pbrt", SCENE("Include \"s.pbrt\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1", "nested at most 32"},
     NULL},
    {"unterminated-string",
     {{"s.pbrt", SCENE("Shape \"sphere")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:7", "closing the string"},
     NULL},
    {"unknown-directive",
     {{"s.pbrt", SCENE("Bogus")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1", "expected a directive, got 'Bogus'"},
     NULL},
    {"shape-no-type",
     {{"s.pbrt", SCENE("Shape")}},
     "render s.pbrt",
     1,
     {"s.pbrt:8:1", "quoted type name after Shape"},
     NULL},
    {"param-bad-type",
     {{"s.pbrt", SCENE("Shape \"sphere\" \"foo radius\" [1]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:16", "parameter type"},
     NULL},
    {"param-not-number",
     {{"s.pbrt", SCENE("Shape \"sphere\" \"float radius\" [abc]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:", "got 'abc'"},
     NULL},
    {"translate-short",
     {{"s.pbrt", SCENE("Translate 1 2\nWorldEnd")}},
     "render s.pbrt",
     1,
     {"s.pbrt:8:1", "expected a number"},
     NULL},
    {"scale-zero",
     {{"s.pbrt", SCENE("Scale 0 0 0\nShape \"sphere\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1", "non-zero Scale factors, got 0 0 0"},
     NULL},
    {"scale-one-zero",
     {{"s.pbrt", SCENE("Scale 1 0 1\nShape \"sphere\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7:1", "got 1 0 1"},
     NULL},
    {"sphere-radius-negative",
     {{"s.pbrt", SCENE("Shape \"sphere\" \"float radius\" [-1]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "\"radius\" must be positive, got -1"},
     NULL},
    {"sphere-radius-zero",
     {{"s.pbrt", SCENE("Shape \"sphere\" \"float radius\" [0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "\"radius\" must be positive, got 0"},
     NULL},
    {"pixelsamples-zero",
     {{"s.pbrt", SCENE_SAMP("Sampler \"halton\" \"integer pixelsamples\" [0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:4", "\"pixelsamples\" must be positive, got 0"},
     NULL},
    {"pixelsamples-negative",
     {{"s.pbrt", SCENE_SAMP("Sampler \"sobol\" \"integer pixelsamples\" [-5]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:4", "got -5"},
     NULL},
    {"xsamples-zero",
     {{"s.pbrt", SCENE_SAMP("Sampler \"stratified\" \"integer xsamples\" [0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:4", "\"xsamples\" must be positive"},
     NULL},
    {"sampler-unknown-scene",
     {{"s.pbrt", SCENE_SAMP("Sampler \"bogus\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:4", "unknown sampler \"bogus\""},
     NULL},
    {"randomization-unknown-scene",
     {{"s.pbrt", SCENE_SAMP("Sampler \"zsobol\" \"string randomization\" \"bogus\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:4", "unknown randomization \"bogus\""},
     NULL},
    {"randomization-halton-fastowen",
     {{"s.pbrt", SCENE_SAMP("Sampler \"halton\" \"string randomization\" \"fastowen\"")}},
     "render s.pbrt --seeding pbrt-v4",
     1,
     {"s.pbrt:4", "\"fastowen\" randomization not supported by Halton sampler"},
     NULL},
    {"randomization-not-pbrt-v4",
     {{"s.pbrt", SCENE_SAMP("Sampler \"halton\" \"string randomization\" \"owen\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:4", "applies only to pbrt-v4's"},
     NULL},
    {"xresolution-zero",
     {{"s.pbrt", SCENE_FILM("Film \"image\" \"integer xresolution\" [0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:3", "\"xresolution\" 0"},
     NULL},
    {"yresolution-negative",
     {{"s.pbrt", SCENE_FILM("Film \"image\" \"integer yresolution\" [-1]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:3", "\"yresolution\" -1"},
     NULL},
    {"xresolution-huge",
     {{"s.pbrt", SCENE_FILM("Film \"image\" \"integer xresolution\" [100000]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:3", "\"xresolution\" 100000"},
     NULL},
    {"cropwindow-3",
     {{"s.pbrt", SCENE_FILM("Film \"image\" \"float cropwindow\" [0 1 0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:3", "\"cropwindow\" needs 4 values (x0 x1 y0 y1), got 3"},
     NULL},
    {"cropwindow-5",
     {{"s.pbrt", SCENE_FILM("Film \"image\" \"float cropwindow\" [0 1 0 1 1]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:3", "got 5"},
     NULL},
    {"filter-width-zero",
     {{"s.pbrt", SCENE_OPT("PixelFilter \"gaussian\" \"float xwidth\" [0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:6", "\"xwidth\" must be in (0, 32], got 0"},
     NULL},
    {"filter-width-negative",
     {{"s.pbrt", SCENE_OPT("PixelFilter \"box\" \"float ywidth\" [-1]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:6", "\"ywidth\" must be in (0, 32], got -1"},
     NULL},
    {"filter-width-huge",
     {{"s.pbrt", SCENE_OPT("PixelFilter \"mitchell\" \"float xwidth\" [100]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:6: PixelFilter \"mitchell\"", "\"xwidth\" must be in (0, 32], got 100"},
     NULL},
    {"mesh-no-P",
     {{"s.pbrt", SCENE("Shape \"trianglemesh\" \"integer indices\" [0 1 2]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "\"P\" parameter not provided"},
     NULL},
    {"mesh-index-range",
     {{"s.pbrt",
       SCENE(
           "Shape \"trianglemesh\" \"integer indices\" [0 1 7] \"point P\" [0 0 0 1 0 0 0 1 0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "vertex index"},
     NULL},
    {"mesh-indices-not-3",
     {{"s.pbrt",
       SCENE("Shape \"trianglemesh\" \"integer indices\" [0 1] \"point P\" [0 0 0 1 0 0 0 1 0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "not a multiple of 3"},
     NULL},
    {"loopsubdiv-nlevels-40",
     {{"s.pbrt", SCENE("Shape \"loopsubdiv\" \"integer nlevels\" [40] \"integer indices\" [0 1 2] "
                       "\"point P\" [0 0 0 1 0 0 0 1 0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: Shape \"loopsubdiv\"", "\"nlevels\" 40"},
     NULL},
    {"loopsubdiv-nlevels-negative",
     {{"s.pbrt", SCENE("Shape \"loopsubdiv\" \"integer nlevels\" [-1] \"integer indices\" [0 1 2] "
                       "\"point P\" [0 0 0 1 0 0 0 1 0]")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: Shape \"loopsubdiv\"", "nlevels is -1"},
     NULL},

    /* ---- PLY meshes ---- */
    {"ply-no-filename",
     {{"s.pbrt", SCENE("Shape \"plymesh\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: Shape \"plymesh\"", "parameter \"filename\" is required"},
     NULL},
    {"ply-directory",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", "@dir"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "is a directory"},
     "memory"},
    {"ply-missing", {{"s.pbrt", PLY_SHAPE}}, "render s.pbrt", 1, {"s.pbrt:7", "t.ply"}, NULL},
    {"ply-fifo",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", "@fifo"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "is not a regular file"},
     NULL},
    {"ply-count-1e30",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("int") "1e30 0 1 2\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "bad list count"},
     NULL},
    {"ply-count-inf",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("int") "inf 0 1 2\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "bad list count"},
     NULL},
    {"ply-count-nan",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("int") "nan 0 1 2\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "bad list count"},
     NULL},
    {"ply-count-negative",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("int") "-3 0 1 2\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "bad list count"},
     NULL},
    {"ply-count-fraction",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("int") "2.5 0 1 2\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "bad list count"},
     NULL},
    {"ply-uchar-count-1000",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("uchar") "1000 0 1 2\n"}},
     "render s.pbrt",
     1,
     {"t.ply", "bad list count"},
     NULL},
    {"ply-no-triangles",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("uchar") "2 0 1\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "\"t.ply\": no triangles"},
     NULL},
    {"ply-too-large",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", "@sparse:4294967297"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "'t.ply' is too large (4294967297 bytes"},
     "memory"},
    {"ply-not-ply",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", "hello\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "not a PLY file"},
     NULL},
    {"ply-truncated",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("uchar") "3 0 1\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "truncated data"},
     NULL},
    {"ply-index-range",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", PLY_HEAD("uchar") "3 0 1 9\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "vertex_indices[2] = 9 is outside [0, 3)"},
     NULL},
    {"ply-huge-count",
     {{"s.pbrt", PLY_SHAPE},
      {"t.ply",
       "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float "
       "y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 "
       "0 0\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "declares 99999999999 instances"},
     "memory"},
    {"ply-bad-format",
     {{"s.pbrt", PLY_SHAPE}, {"t.ply", "ply\nformat weird 1.0\nend_header\n"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7", "unknown format \"weird\""},
     NULL},

    /* ---- textures ---- */
    {"imagemap-no-filename",
     {{"s.pbrt", SCENE("Texture \"t\" \"spectrum\" \"imagemap\"\nShape \"sphere\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "parameter \"filename\" is required"},
     NULL},
    {"imagemap-missing",
     {{"s.pbrt", IMAGEMAP("nope.png")}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "nope.png"},
     NULL},
    {"imagemap-directory",
     {{"s.pbrt", IMAGEMAP("d.png")}, {"d.png", "@dir"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "is a directory"},
     NULL},
    {"imagemap-fifo",
     {{"s.pbrt", IMAGEMAP("f.png")}, {"f.png", "@fifo"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "is not a regular file"},
     NULL},
    {"imagemap-forged-png",
     {{"s.pbrt", IMAGEMAP("big.png")}, {"big.png", "@forged-png"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "is corrupt: its header declares 1000000x1000000"},
     "memory"},
    {"imagemap-forged-exr",
     {{"s.pbrt", IMAGEMAP("big.exr")}, {"big.exr", "@forged-exr"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "corrupt EXR"},
     "memory"},
    {"imagemap-garbage-png",
     {{"s.pbrt", IMAGEMAP("g.png")}, {"g.png", "not a png at all"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "g.png"},
     NULL},
    {"imagemap-extension",
     {{"s.pbrt", IMAGEMAP("t.txt")}, {"t.txt", "text"}},
     "render s.pbrt",
     1,
     {"s.pbrt:7: imagemap", "unknown extension"},
     NULL},

    /* ---- merge inputs ---- */
    {"merge-same-file",
     {{"a.exr", "@rgb-exr"}},
     "merge a.exr a.exr -o m.exr",
     1,
     {"a.exr and a.exr are the same file", NULL},
     NULL},
    {"merge-same-file-other-name",
     {{"a.exr", "@rgb-exr"}},
     "merge a.exr ./a.exr -o m.exr",
     1,
     {"same file", "./a.exr"},
     NULL},
    {"merge-missing", {{0}}, "merge nope.exr -o m.exr", 1, {"nope.exr", NULL}, NULL},
    {"merge-garbage",
     {{"g.exr", "definitely not an EXR file, just text"}},
     "merge g.exr -o m.exr",
     1,
     {"g.exr", NULL},
     NULL},
    {"merge-forged",
     {{"f.exr", "@forged-exr"}},
     "merge f.exr -o m.exr",
     1,
     {"f.exr", "corrupt EXR: data window 1000000x1000000"},
     "memory"},
    {"merge-no-metadata",
     {{"a.exr", "@rgb-exr"}},
     "merge a.exr -o m.exr",
     1,
     {"a.exr has no clrender film metadata", NULL},
     NULL},
    {"merge-directory",
     {{"d.exr", "@dir"}},
     "merge d.exr -o m.exr",
     1,
     {"d.exr", "is a directory"},
     NULL},
    {"merge-dev-zero",
     {{0}},
     "merge /dev/zero -o m.exr",
     1,
     {"/dev/zero", "is not a regular file"},
     NULL},
    {"merge-output-device",
     {{"a.exr", "@rgb-exr"}},
     "merge a.exr -o /dev/full",
     1,
     {"/dev/full", "not a regular file"},
     NULL},
    {"merge-output-read-only",
     {{"a.exr", "@rgb-exr"}, {"ro.exr", "@ro:old"}},
     "merge a.exr -o ro.exr",
     1,
     {"ro.exr", "read-only"},
     NULL},

    /* ---- output paths ---- */
    {"out-dev-full",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --outfile /dev/full",
     1,
     {"'/dev/full'", "not a regular file"},
     NULL},
    {"out-dev-null",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --outfile /dev/null",
     1,
     {"'/dev/null'", "not a regular file"},
     NULL},
    {"out-symlink",
     {{"s.pbrt", GOOD}, {"target.txt", "keep me"}, {"l.exr", "@link:target.txt"}},
     "render s.pbrt --outfile l.exr",
     1,
     {"'l.exr'", "symbolic link"},
     NULL},
    {"out-dangling-symlink",
     {{"s.pbrt", GOOD}, {"l.exr", "@link:nowhere.exr"}},
     "render s.pbrt --outfile l.exr",
     1,
     {"'l.exr'", "symbolic link"},
     NULL},
    {"out-fifo",
     {{"s.pbrt", GOOD}, {"f.exr", "@fifo"}},
     "render s.pbrt --outfile f.exr",
     1,
     {"'f.exr'", "not a regular file"},
     NULL},
    {"out-read-only",
     {{"s.pbrt", GOOD}, {"ro.exr", "@ro:old image"}},
     "render s.pbrt --outfile ro.exr",
     1,
     {"'ro.exr'", "read-only"},
     NULL},
    {"out-read-only-png",
     {{"s.pbrt", GOOD}, {"ro.png", "@ro:old png"}},
     "render s.pbrt --outfile ro.png",
     1,
     {"'ro.png'", "read-only"},
     NULL},
    {"out-png-beside-fifo",
     {{"s.pbrt", GOOD}, {"o.png", "@fifo"}},
     "render s.pbrt --outfile o.exr",
     1,
     {"'o.png'", "not a regular file"},
     NULL},
    {"out-png-beside-read-only",
     {{"s.pbrt", GOOD}, {"o.png", "@ro:old"}, {"o.exr", "old exr"}},
     "render s.pbrt --outfile o.exr",
     1,
     {"'o.png'", "read-only"},
     NULL},
    {"out-png-beside-directory",
     {{"s.pbrt", GOOD}, {"o.png", "@dir"}},
     "render s.pbrt --outfile o.exr",
     1,
     {"'o.png'", "directory"},
     NULL},
    {"out-directory",
     {{"s.pbrt", GOOD}, {"d", "@dir"}},
     "render s.pbrt --outfile d",
     1,
     {"'d'", "directory"},
     NULL},
    {"out-no-folder",
     {{"s.pbrt", GOOD}},
     "render s.pbrt --outfile nodir/o.exr",
     1,
     {"nodir/o.exr", "No such file"},
     NULL},
    {"film-filename-device",
     {{"s.pbrt", SCENE_FILM(FILM "Film \"image\" \"string filename\" \"/dev/null\"")}},
     "render s.pbrt",
     1,
     {"s.pbrt:4: Film \"filename\"", "not a regular file"},
     NULL},
    {"film-filename-symlink",
     {{"s.pbrt",
       SCENE_FILM("Film \"image\" \"integer xresolution\" [8] \"string filename\" \"l.exr\"")},
      {"t.exr", "keep"},
      {"l.exr", "@link:t.exr"}},
     "render s.pbrt",
     1,
     {"s.pbrt:3: Film \"filename\"", "symbolic link"},
     NULL},
};

static const char *fixture_root(void) {
  static char root[512];
  snprintf(root, sizeof root, "%s/hardening", CLR_BINARY_DIR);
  return root;
}

static void make_fixture(const char *dir, const char *name, const char *content) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (strcmp(content, "@dir") == 0) {
    assert_int_equal(mkdir(path, 0777), 0);
  } else if (strcmp(content, "@fifo") == 0) {
    assert_int_equal(mkfifo(path, 0666), 0);
  } else if (strncmp(content, "@link:", 6) == 0) {
    assert_int_equal(symlink(content + 6, path), 0);
  } else if (strncmp(content, "@ro:", 4) == 0) {
    assert_true(hu_write_file(path, content + 4, strlen(content + 4)));
    assert_int_equal(chmod(path, 0444), 0);
  } else if (strcmp(content, "@forged-png") == 0) {
    unsigned char png[64];
    size_t n = hu_forged_png(png, 1000000, 1000000);
    assert_true(hu_write_file(path, png, n));
  } else if (strcmp(content, "@forged-exr") == 0 || strcmp(content, "@rgb-exr") == 0) {
    assert_true(hu_small_exr(path, content[1] == 'f'));
  } else if (strncmp(content, "@sparse:", 8) == 0) {
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(fd >= 0);
    assert_int_equal(ftruncate(fd, (off_t)strtoll(content + 8, NULL, 10)), 0);
    close(fd);
  } else if (strcmp(content, "@binary") == 0) {
    unsigned char bytes[160];
    int n = 0;
    for (int b = 1; b < 32; ++b) bytes[n++] = (unsigned char)b;
    for (int b = 128; b < 256; ++b) bytes[n++] = (unsigned char)b;
    assert_true(hu_write_file(path, bytes, (size_t)n));
  } else {
    assert_true(hu_write_file(path, content, strlen(content)));
  }
}

static int dev_temp_files(void) {
  glob_t g;
  int n = glob("/dev/*.tmp-*", 0, NULL, &g) == 0 ? (int)g.gl_pathc : 0;
  if (n) globfree(&g);
  return n;
}

static void run_case(const bad_case *c, int index) {
  char name[64];
  snprintf(name, sizeof name, "case%03d", index);
  const char *dir = hu_workdir(name, 0);
  for (int i = 0; i < 4 && c->files[i][0]; ++i) make_fixture(dir, c->files[i][0], c->files[i][1]);
  char args[1024], *argv[32];
  int argc = 0;
  argv[argc++] = "clrender";
  snprintf(args, sizeof args, "%s", c->args);
  for (char *save = NULL, *tok = strtok_r(args, " ", &save); tok && argc < 31;
       tok = strtok_r(NULL, " ", &save))
    argv[argc++] = tok;
  argv[argc] = NULL;
  char err_path[600];
  snprintf(err_path, sizeof err_path, "%s/%s.stderr", fixture_root(), name);
  char *before = hu_snapshot(dir);
  int status = hu_run_cli(dir, argv, err_path);
  char *after = hu_snapshot(dir);
  char *err = hu_read_file(err_path, NULL);
  int ok = status == c->status && err && strcmp(before, after) == 0 && dev_temp_files() == 0;
  for (int k = 0; ok && k < 2; ++k) ok = !c->expect[k] || strstr(err, c->expect[k]) != NULL;
  if (ok && c->absent) ok = strstr(err, c->absent) == NULL;
  if (ok && c->status == 1) ok = strstr(err, "clrender") == err; /* one clean message */
  if (!ok)
    fprintf(stderr,
            "case %s (clrender %s): status %d (want %d)\nstderr: %s\nexpect: %s | %s%s%s\n"
            "before:\n%safter:\n%s",
            c->name, c->args, status, c->status, err ? err : "(none)", c->expect[0],
            c->expect[1] ? c->expect[1] : "", c->absent ? " | absent: " : "",
            c->absent ? c->absent : "", before, after);
  free(before);
  free(after);
  free(err);
  assert_true(ok);
  hu_sh("rm -rf '%s'", dir);
}

static void test_cli_catalogue(void **state) {
  (void)state;
  int n = (int)(sizeof cases / sizeof cases[0]);
  for (int i = 0; i < n; ++i) run_case(&cases[i], i);
  printf("%d CLI cases checked\n", n);
}

/* ---- API misuse: result code and message ---- */

typedef struct api_case {
  const char *name;
  clr_result (*call)(const char *dir); /* dir holds the fixtures of api_fixtures */
  clr_result code;
  const char *expect;
} api_case;

static clr_result api_render_file_null(const char *dir) {
  (void)dir;
  return clr_render_file(NULL, NULL, NULL);
}
static clr_result api_parse_null_out(const char *dir) {
  (void)dir;
  return clr_scene_parse_file("x.pbrt", NULL, NULL);
}
static clr_result api_parse_dev_zero(const char *dir) {
  (void)dir;
  clr_scene_desc *d = NULL;
  return clr_scene_parse_file("/dev/zero", NULL, &d);
}
static clr_result api_render_desc_struct_size(const char *dir) {
  (void)dir;
  clr_scene_desc *d = NULL;
  clr_result r = clr_scene_parse_string(GOOD, "api.pbrt", NULL, &d);
  if (r != CLR_SUCCESS) return CLR_ERROR_INTERNAL;
  clr_render_options o;
  clr_render_options_init(&o);
  o.struct_size = 3;
  r = clr_render_desc(d, &o, NULL, 0, NULL);
  clr_scene_desc_free(d);
  return r;
}
static clr_result api_render_desc_bad_spp(const char *dir) {
  (void)dir;
  clr_scene_desc *d = NULL;
  clr_result r = clr_scene_parse_string(
      SCENE_SAMP("Sampler \"halton\" \"integer pixelsamples\" [0]"), "api.pbrt", NULL, &d);
  if (r != CLR_SUCCESS) return CLR_ERROR_INTERNAL;
  r = clr_render_desc(d, NULL, NULL, 0, NULL);
  clr_scene_desc_free(d);
  return r;
}
static clr_result api_check_output_null(const char *dir) {
  (void)dir;
  return film_check_output_path(NULL);
}
static clr_result api_check_output_device(const char *dir) {
  (void)dir;
  return film_check_output_path("/dev/null");
}
/* Fixtures of the API cases, made before the snapshot. */
static void api_fixtures(const char *dir) {
  char path[600];
  unsigned char png[64];
  snprintf(path, sizeof path, "%s/ro.exr", dir);
  assert_true(hu_write_file(path, "x", 1));
  assert_int_equal(chmod(path, 0444), 0);
  snprintf(path, sizeof path, "%s/big.png", dir);
  assert_true(hu_write_file(path, png, hu_forged_png(png, 1000000, 1000000)));
  snprintf(path, sizeof path, "%s/big.exr", dir);
  assert_true(hu_small_exr(path, 1));
}
static clr_result api_check_output_read_only(const char *dir) {
  char path[600];
  snprintf(path, sizeof path, "%s/ro.exr", dir);
  return film_check_output_path(path);
}
static clr_result api_image_forged_png(const char *dir) {
  char path[600];
  snprintf(path, sizeof path, "%s/big.png", dir);
  clr_image im;
  return clr_image_read(path, &im);
}
static clr_result api_image_forged_exr(const char *dir) {
  char path[600];
  snprintf(path, sizeof path, "%s/big.exr", dir);
  clr_image im;
  return clr_image_read(path, &im);
}
static clr_result api_exr_read_directory(const char *dir) {
  clr_exr_image *im = NULL;
  return clr_exr_read(dir, &im);
}
static clr_result api_image_read_null(const char *dir) {
  (void)dir;
  return clr_image_read(NULL, NULL);
}
static clr_result api_ply_directory(const char *dir) {
  clr_mesh m;
  return clr_ply_read(dir, &m);
}
static clr_result api_ply_null(const char *dir) {
  (void)dir;
  return clr_ply_read("x.ply", NULL);
}
static clr_result api_loop_levels(const char *dir) {
  (void)dir;
  float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  int32_t ix[3] = {0, 1, 2};
  clr_mesh in, out;
  if (clr_mesh_from_arrays("api", ix, 3, p, 9, NULL, 0, NULL, 0, &in) != CLR_SUCCESS)
    return CLR_ERROR_INTERNAL;
  clr_result r = clr_loop_subdivide(&in, 40, &out);
  clr_mesh_free(&in);
  if (r == CLR_SUCCESS) clr_mesh_free(&out);
  return r;
}
static clr_result api_loop_null(const char *dir) {
  (void)dir;
  clr_mesh out;
  return clr_loop_subdivide(NULL, 1, &out);
}
static clr_result api_merge_null_ctx(const char *dir) {
  (void)dir;
  const char *paths[1] = {"a.exr"};
  return film_merge_files(NULL, paths, 1, "m.exr");
}
static clr_result api_film_write_null(const char *dir) {
  (void)dir;
  return film_write(NULL, "x.exr", NULL);
}
static clr_result api_merge_sums_null(const char *dir) {
  (void)dir;
  return film_merge_sums(NULL, (clr_bounds2i){0, 0, 1, 1}, NULL, NULL, NULL);
}

/* Cases on a film: one context for all (created by test_api_catalogue). */
static clr_context api_ctx;
static clr_result api_film_with(float scale, float radius, clr_film *out) {
  clr_film_desc fd;
  clr_film_desc_init(&fd);
  fd.x_resolution = 4;
  fd.y_resolution = 2;
  fd.scale = scale;
  fd.filter.radius[0] = radius;
  return film_create(api_ctx, &fd, out);
}
static clr_result api_film_scale_nan(const char *dir) {
  (void)dir;
  clr_film f = NULL;
  return api_film_with(NAN, 0.5f, &f);
}
static clr_result api_film_radius_nan(const char *dir) {
  (void)dir;
  clr_film f = NULL;
  return api_film_with(1.0f, NAN, &f);
}
static clr_result api_film_out_null(const char *dir) {
  (void)dir;
  return api_film_with(1.0f, 0.5f, NULL);
}
static clr_result api_film_call(int which) {
  clr_film f = NULL;
  if (api_film_with(1.0f, 0.5f, &f) != CLR_SUCCESS) return CLR_ERROR_INTERNAL;
  float rgb[24];
  double sums[3] = {1, 1, 1};
  clr_result r = which == 0   ? film_get_rgb(f, rgb, NAN)
                 : which == 1 ? film_merge_sums(f, (clr_bounds2i){3, 0, 5, 1}, sums, NULL, NULL)
                 : which == 2 ? film_add_samples(f, NULL, 4)
                              : film_write(f, "", NULL);
  film_release(f);
  return r;
}
static clr_result api_film_rgb_nan_scale(const char *dir) {
  (void)dir;
  return api_film_call(0);
}
static clr_result api_film_merge_outside(const char *dir) {
  (void)dir;
  return api_film_call(1);
}
static clr_result api_film_samples_null(const char *dir) {
  (void)dir;
  return api_film_call(2);
}
static clr_result api_film_write_empty_path(const char *dir) {
  (void)dir;
  return api_film_call(3);
}

static const api_case api_cases[] = {
    {"film_create(scale NaN)", api_film_scale_nan, CLR_ERROR_INVALID_ARGUMENT, "scale = nan"},
    {"film_create(radius NaN)", api_film_radius_nan, CLR_ERROR_INVALID_RADIUS, "radius[0] = nan"},
    {"film_create(out NULL)", api_film_out_null, CLR_ERROR_NULL_POINTER, "out is NULL"},
    {"film_get_rgb(splat_scale NaN)", api_film_rgb_nan_scale, CLR_ERROR_INVALID_ARGUMENT,
     "splat_scale = nan"},
    {"film_merge_sums(outside)", api_film_merge_outside, CLR_ERROR_INVALID_PIXEL_RANGE,
     "[3,5)x[0,1)"},
    {"film_add_samples(NULL, 4)", api_film_samples_null, CLR_ERROR_NULL_POINTER, "NULL"},
    {"film_write(\"\")", api_film_write_empty_path, CLR_ERROR_INVALID_ARGUMENT,
     "output path is empty"},
    {"clr_render_file(NULL)", api_render_file_null, CLR_ERROR_NULL_POINTER, "scene_path is NULL"},
    {"clr_scene_parse_file(out NULL)", api_parse_null_out, CLR_ERROR_NULL_POINTER, "out is NULL"},
    {"clr_scene_parse_file(/dev/zero)", api_parse_dev_zero, CLR_ERROR_IO, "is not a regular file"},
    {"clr_render_desc(struct_size 3)", api_render_desc_struct_size, CLR_ERROR_INVALID_ARGUMENT,
     "struct_size 3"},
    {"clr_render_desc(pixelsamples 0)", api_render_desc_bad_spp, CLR_ERROR_INVALID_SPP,
     "api.pbrt:4"},
    {"film_check_output_path(NULL)", api_check_output_null, CLR_ERROR_NULL_POINTER, "path is NULL"},
    {"film_check_output_path(/dev/null)", api_check_output_device, CLR_ERROR_IO,
     "not a regular file"},
    {"film_check_output_path(read-only)", api_check_output_read_only, CLR_ERROR_IO, "read-only"},
    {"clr_image_read(forged PNG)", api_image_forged_png, CLR_ERROR_FILE_FORMAT, "corrupt"},
    {"clr_image_read(forged EXR)", api_image_forged_exr, CLR_ERROR_FILE_FORMAT, "corrupt EXR"},
    {"clr_exr_read(directory)", api_exr_read_directory, CLR_ERROR_IO, "is a directory"},
    {"clr_image_read(NULL)", api_image_read_null, CLR_ERROR_NULL_POINTER, "NULL"},
    {"clr_ply_read(directory)", api_ply_directory, CLR_ERROR_IO, "is a directory"},
    {"clr_ply_read(out NULL)", api_ply_null, CLR_ERROR_NULL_POINTER, "out is NULL"},
    {"clr_loop_subdivide(nlevels 40)", api_loop_levels, CLR_ERROR_SCENE, "\"nlevels\" 40"},
    {"clr_loop_subdivide(NULL)", api_loop_null, CLR_ERROR_NULL_POINTER, "in is NULL"},
    {"film_merge_files(ctx NULL)", api_merge_null_ctx, CLR_ERROR_NULL_POINTER, "NULL argument"},
    {"film_write(NULL)", api_film_write_null, CLR_ERROR_NULL_POINTER, "film is NULL"},
    {"film_merge_sums(NULL)", api_merge_sums_null, CLR_ERROR_NULL_POINTER, "dst is NULL"},
};

static void test_api_catalogue(void **state) {
  (void)state;
  clr_context_desc cd;
  clr_context_desc_init(&cd);
  assert_int_equal(clr_context_create(&cd, &api_ctx), CLR_SUCCESS);
  int n = (int)(sizeof api_cases / sizeof api_cases[0]);
  for (int i = 0; i < n; ++i) {
    const char *dir = hu_workdir("api", 0);
    api_fixtures(dir);
    char *before = hu_snapshot(dir);
    clr_result r = api_cases[i].call(dir);
    const char *msg = clr_last_error_message();
    char *after = hu_snapshot(dir);
    int same = strcmp(before, after) == 0;
    int ok = r == api_cases[i].code && strstr(msg, api_cases[i].expect) != NULL && same;
    if (!ok)
      fprintf(stderr, "API case %s: %s (want %s), message \"%s\" (want \"%s\")\n",
              api_cases[i].name, clr_result_name(r), clr_result_name(api_cases[i].code), msg,
              api_cases[i].expect);
    free(before);
    free(after);
    assert_true(ok);
  }
  hu_sh("rm -rf '%s'", hu_workdir("api", 0));
  clr_context_release(api_ctx);
  printf("%d API cases checked\n", n);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_cli_catalogue),
      cmocka_unit_test(test_api_catalogue),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
