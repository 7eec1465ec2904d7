/* Device-only, 8 lanes: clr_filter_eval_1d of filter_funcs.h in OpenCL vector types for the
 * film's SIMD weigh kernel. Box, triangle, mitchell, catmullrom and every filter in table mode
 * mirror the scalar code step for step (same float operations in the same order, so the same
 * bits); the other filters run the scalar function lane by lane. */
#ifndef CLR_FILTER_SIMD_H
#define CLR_FILTER_SIMD_H

#include "filter_funcs.h"

#define CLR_FILTER_SIMD_INLINE static inline __attribute__((always_inline))

/* clr_flush_subnormal per lane. */
CLR_FILTER_SIMD_INLINE float8 clr_flush_subnormal8(float8 v) {
  return select(v, (float8)(0.0f), fabs(v) < CLR_FLT_MIN_NORMAL);
}

/* clr_mitchell_1d per lane. */
CLR_FILTER_SIMD_INLINE float8 clr_mitchell_1d8(float8 u, float b, float c) {
  float8 t = 2.0f * u;
  float8 inner = (((12.0f - 9.0f * b) - 6.0f * c) * t + ((-18.0f + 12.0f * b) + 6.0f * c)) * t * t +
                 (6.0f - 2.0f * b);
  float8 w = 2.0f - t;
  float8 outer = w * w * ((2.0f * b + 6.0f * c) - (b + 6.0f * c) * t);
  return select(inner, outer, t > 1.0f) * 0x1.555556p-3f;
}

/* Whether clr_filter_eval_1d8 has vector code for f (else it runs lane by lane). */
CLR_FILTER_SIMD_INLINE int clr_filter_simd(const clr_filter_params *f) {
  return f->use_table || f->type == CLR_FILTER_TYPE_BOX || f->type == CLR_FILTER_TYPE_TRIANGLE ||
         f->type == CLR_FILTER_TYPE_MITCHELL || f->type == CLR_FILTER_TYPE_CATMULLROM;
}

/* clr_filter_1d per lane (each lane with its axis' radius) for the filters clr_filter_simd
 * accepts in exact mode. */
CLR_FILTER_SIMD_INLINE float8 clr_filter_1d8(const clr_filter_params *f, float8 a, float8 radius,
                                             float8 inv_radius) {
  if (f->type == CLR_FILTER_TYPE_BOX) return (float8)(1.0f);
  if (f->type == CLR_FILTER_TYPE_TRIANGLE) return fmax((float8)(0.0f), radius - a);
  return clr_mitchell_1d8(fmin(a * inv_radius, (float8)(1.0f)), f->b, f->c);
}

/* pbrt's table lookup per lane (clr_filter_table_index, then the factor at t + offset, the
 * lane's axis). */
CLR_FILTER_SIMD_INLINE float8 clr_filter_table8(CLR_GLOBAL const float *t, float8 d,
                                                float8 inv_radius, int8 offset) {
  float8 scaled = fabs(d * inv_radius * (float)CLR_FILTER_TABLE_SIZE);
  int8 i = convert_int8(floor(fmin(scaled, (float8)(CLR_FILTER_TABLE_SIZE - 1)))) + offset;
  return (float8)(t[i.s0], t[i.s1], t[i.s2], t[i.s3], t[i.s4], t[i.s5], t[i.s6], t[i.s7]);
}

/* The other filters: the scalar function lane by lane, out of line (keeps the vector code
 * small). */
static __attribute__((noinline)) float8 clr_filter_eval_1d_lanes(const clr_filter_params *f,
                                                                 clr_i32 axis, float8 d,
                                                                 CLR_GLOBAL const float *factors) {
  float v[8];
  vstore8(d, 0, v);
  for (int i = 0; i < 8; ++i) v[i] = clr_filter_eval_1d(f, axis, v[i], factors);
  return vload8(0, v);
}

/* clr_filter_eval_1d per lane along the lane's axis (axis: 0 or -1 per lane, x or y): the same
 * bits as the scalar function at every lane's d. */
CLR_FILTER_SIMD_INLINE float8 clr_filter_eval_axes8(const clr_filter_params *f, int8 axis, float8 d,
                                                    CLR_GLOBAL const float *factors) {
  float8 radius = select((float8)(f->radius_x), (float8)(f->radius_y), axis);
  float8 inv_radius = select((float8)(f->inv_radius_x), (float8)(f->inv_radius_y), axis);
  if (f->use_table)
    return select((float8)(0.0f),
                  clr_filter_table8(factors, d, inv_radius, axis & CLR_FILTER_TABLE_SIZE),
                  fabs(d) <= radius);
  float8 a = fabs(clr_flush_subnormal8(d));
  return select((float8)(0.0f), clr_flush_subnormal8(clr_filter_1d8(f, a, radius, inv_radius)),
                a <= radius);
}

/* clr_filter_eval_1d per lane: the same bits as the scalar function at every lane's d. */
CLR_FILTER_SIMD_INLINE float8 clr_filter_eval_1d8(const clr_filter_params *f, clr_i32 axis,
                                                  float8 d, CLR_GLOBAL const float *factors) {
  if (!clr_filter_simd(f)) return clr_filter_eval_1d_lanes(f, axis, d, factors);
  return clr_filter_eval_axes8(f, (int8)(-axis), d, factors);
}

/* clr_filter_eval_1d of 4 x-offsets (lanes 0-3) and 4 y-offsets (lanes 4-7) in one vector. */
CLR_FILTER_SIMD_INLINE float8 clr_filter_eval_xy8(const clr_filter_params *f, float8 d,
                                                  CLR_GLOBAL const float *factors) {
  if (!clr_filter_simd(f))
    return (float8)(clr_filter_eval_1d_lanes(f, 0, d, factors).lo,
                    clr_filter_eval_1d_lanes(f, 1, d, factors).hi);
  return clr_filter_eval_axes8(f, (int8)(0, 0, 0, 0, -1, -1, -1, -1), d, factors);
}

#endif
