/* Resume checks: the image's header must describe the render being continued. */
#include "resume.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const clr_resume_attributes[] = {
    "clrender.sampler",      "integrator",          "clrender.scene",
    "clrender.seed",         "clrender.seeding",    "clrender.randomization",
    "clrender.spp",          "clrender.spp_target", "clrender.partial",
    "clrender.whole_passes", "clrender.layout"};
const int32_t clr_resume_attribute_count =
    (int32_t)(sizeof clr_resume_attributes / sizeof clr_resume_attributes[0]);

enum {
  A_SAMPLER,
  A_INTEGRATOR,
  A_SCENE,
  A_SEED,
  A_SEEDING,
  A_RANDOMIZATION,
  A_SPP,
  A_TARGET,
  A_PARTIAL,
  A_WHOLE,
  A_LAYOUT
};

clr_result clr_scene_file_hash(const char *path, char out[17]) {
  FILE *f = fopen(path, "rb");
  if (!f) return clr_set_last_error(CLR_ERROR_IO, "%s: cannot read the scene to hash it", path);
  uint64_t h = 0xcbf29ce484222325ull;
  unsigned char buf[1 << 14];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, f)) > 0)
    for (size_t i = 0; i < n; ++i) h = (h ^ buf[i]) * 0x100000001b3ull;
  fclose(f);
  snprintf(out, 17, "%016llx", (unsigned long long)h);
  return CLR_SUCCESS;
}

static const char *value(const char *values, int k) { return values + k * CLR_RESUME_VALUE; }

/* A recorded text value that differs from this render's. */
static clr_result mismatch(const char *path, const char *what, const char *then, const char *now) {
  return clr_set_last_error(
      CLR_ERROR_INVALID_ARGUMENT,
      "--resume %s: it was rendered with %s \"%s\", this render has \"%s\": "
      "resume only the same scene, sampler, integrator, seed, seeding and randomization",
      path, what, then[0] ? then : "(not recorded)", now);
}

/* A recorded count: decimal digits only, 0..INT32_MAX. */
static int parse_count(const char *text, int32_t *out) {
  if (text[0] < '0' || text[0] > '9') return 0;
  errno = 0;
  char *end = NULL;
  long v = strtol(text, &end, 10);
  if (*end || errno || v > INT32_MAX) return 0;
  *out = (int32_t)v;
  return 1;
}

/* The recorded counts the checks read; refuses one that is not a count (or a flag, 0 or 1),
 * naming the attribute and its text. An image without clrender.whole_passes has whole 0. */
static clr_result read_counts(const char *path, const char *values, int32_t c[4]) {
  static const int attr[4] = {A_SPP, A_TARGET, A_PARTIAL, A_WHOLE};
  for (int k = 0; k < 4; ++k) {
    const char *text = value(values, attr[k]);
    int flag = attr[k] == A_PARTIAL || attr[k] == A_WHOLE;
    c[k] = 0;
    if (flag && !text[0]) continue;
    if (!parse_count(text, &c[k]) || (flag && c[k] > 1))
      return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                                "--resume %s: its %s attribute is \"%s\", not %s", path,
                                clr_resume_attributes[attr[k]], text,
                                flag ? "0 or 1" : "a whole number from 0 to 2147483647");
  }
  return CLR_SUCCESS;
}

clr_result clr_resume_check(const char *path, const char *values, const clr_resume_identity *now,
                            int32_t *spp_done) {
  const char *names[A_SPP] = {"sampler", "integrator", "scene (content hash)",
                              "seed",    "seeding",    "randomization"};
  const char *mine[A_SPP] = {now->sampler, now->integrator, now->scene,
                             now->seed,    now->seeding,    now->randomization};
  for (int k = 0; k < A_SPP; ++k)
    if (strcmp(value(values, k), mine[k]) != 0)
      return mismatch(path, names[k], value(values, k), mine[k]);
  if (strcmp(value(values, A_LAYOUT), now->layout) != 0) /* e.g. written by an older clrender */
    return mismatch(path, "sample layout", value(values, A_LAYOUT), now->layout);
  int32_t counts[4];
  clr_result r = read_counts(path, values, counts);
  if (r != CLR_SUCCESS) return r;
  const int32_t spp = counts[0], target = counts[1], partial = counts[2], whole = counts[3];
  if (!whole || spp <= 0)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "--resume %s: the image does not hold whole passes (%s): it cannot "
                              "be continued sample for sample (render with --checkpoint or "
                              "--time-limit to make interrupted renders resumable)",
                              path,
                              partial ? "interrupted in the middle of its only pass"
                                      : "no clrender.whole_passes attribute");
  if (spp >= now->spp_target)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "--resume %s: the image already holds %d spp, --spp asks for %d: "
                              "nothing to add",
                              path, spp, (int)now->spp_target);
  if (!now->global_sampler && target != now->spp_target)
    return clr_set_last_error(CLR_ERROR_INVALID_ARGUMENT,
                              "--resume %s: the %s sampler's samples depend on the total spp: the "
                              "image was started for %d spp, this render asks for %d (resume it "
                              "with --spp %d, or use halton or sobol, whose samples do not)",
                              path, now->sampler, target, (int)now->spp_target, target);
  *spp_done = spp;
  return CLR_SUCCESS;
}
