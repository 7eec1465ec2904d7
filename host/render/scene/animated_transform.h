/* pbrt-v3 AnimatedTransform: two transforms at a start and an end time, decomposed into
 * translation, rotation (a quaternion, by polar decomposition) and scale, and interpolated
 * (lerp, slerp, lerp) at a time in between; clamped outside. */
#ifndef CLR_RENDER_ANIMATED_TRANSFORM_H
#define CLR_RENDER_ANIMATED_TRANSFORM_H

#include "transform.h"

typedef struct rs_animated_transform {
  clr_transform start, end;
  float start_time, end_time;
  int animated;                       /* the two transforms differ */
  float t[2][3], q[2][4], s[2][4][4]; /* decompositions: translation, quaternion (x y z w), scale */
} rs_animated_transform;

void rs_animated_transform_init(rs_animated_transform *a, const clr_transform *start,
                                const clr_transform *end, float start_time, float end_time);
/* pbrt-v3 AnimatedTransform::Interpolate. */
void rs_animated_transform_at(const rs_animated_transform *a, float time, clr_transform *out);

#endif
