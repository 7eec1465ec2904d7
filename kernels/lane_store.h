/* Stores of 8 lanes whose values belong to different places: lane j writes at out[j] + offset
 * (the SIMD-shaped sampler kernels, one pixel per lane; OpenCL C only). */
#ifndef CLR_LANE_STORE_H
#define CLR_LANE_STORE_H

/* The lanes' pixels: values of lane j go to values[out[j] + offset]. */
static inline __attribute__((always_inline)) void clr_store_lanes8(__global float *values,
                                                                   const ulong *out, size_t offset,
                                                                   float8 v) {
  values[out[0] + offset] = v.s0;
  values[out[1] + offset] = v.s1;
  values[out[2] + offset] = v.s2;
  values[out[3] + offset] = v.s3;
  values[out[4] + offset] = v.s4;
  values[out[5] + offset] = v.s5;
  values[out[6] + offset] = v.s6;
  values[out[7] + offset] = v.s7;
}

/* Lane j's (x, y) to values[out[j] + offset], one 8-byte store per lane. */
static inline __attribute__((always_inline)) void clr_store_pairs8(__global float *values,
                                                                   const ulong *out, size_t offset,
                                                                   float8 x, float8 y) {
  vstore2((float2)(x.s0, y.s0), 0, values + out[0] + offset);
  vstore2((float2)(x.s1, y.s1), 0, values + out[1] + offset);
  vstore2((float2)(x.s2, y.s2), 0, values + out[2] + offset);
  vstore2((float2)(x.s3, y.s3), 0, values + out[3] + offset);
  vstore2((float2)(x.s4, y.s4), 0, values + out[4] + offset);
  vstore2((float2)(x.s5, y.s5), 0, values + out[5] + offset);
  vstore2((float2)(x.s6, y.s6), 0, values + out[6] + offset);
  vstore2((float2)(x.s7, y.s7), 0, values + out[7] + offset);
}

#endif
