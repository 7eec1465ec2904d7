/* Lane arithmetic shared by the SIMD-shaped sampler kernels (OpenCL C only). */
#ifndef CLR_LANE_MATH_H
#define CLR_LANE_MATH_H

/* (a * m) >> 32 per lane in four 64-bit products of even and of odd lanes (AVX2: two vpmuludq
 * and no repacking; the library's mul_hi(uint8) goes through 16-bit halves on PoCL). */
static inline __attribute__((always_inline)) uint8 clr_mul_hi8(uint8 a, uint m) {
  const ulong low_half = 0xFFFFFFFFul;
  ulong4 pairs = as_ulong4(a);
  ulong4 even = ((pairs & low_half) * (ulong)m) >> 32ul;
  ulong4 odd = ((pairs >> 32ul) * (ulong)m) & ~low_half;
  return as_uint8(even | odd);
}

#endif
