/* Lets the kernel headers compile both as OpenCL C 1.2 and as C11 with identical arithmetic:
 * fixed-width integer names, address-space qualifiers, and no floating-point contraction. */
#ifndef CLR_PLATFORM_H
#define CLR_PLATFORM_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF
typedef uchar clr_u8;
typedef ushort clr_u16;
typedef int clr_i32;
typedef uint clr_u32;
typedef long clr_i64;
typedef ulong clr_u64;
#define CLR_GLOBAL __global
#define CLR_CONSTANT __constant
#define CLR_LOCAL __local
#define CLR_INLINE static inline
/* For hot helpers with a switch the device compiler would keep out of line. */
#define CLR_ALWAYS_INLINE static inline __attribute__((always_inline))
#define CLR_DEVICE 1
#define clr_as_float(u) as_float(u)
#define clr_as_uint(f) as_uint(f)
#define clr_floorf(x) floor(x)
#define clr_ceilf(x) ceil(x)
#define clr_fabsf(x) fabs(x)
#define clr_fminf(a, b) fmin(a, b)
#define clr_fmaxf(a, b) fmax(a, b)
#define clr_clz32(x) clz(x)
#define clr_popcount32(x) popcount(x)
#else
#include <math.h>
#include <stdint.h>
#include <string.h>
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF /* GCC: -ffp-contract=off in CMakeLists.txt */
#endif
typedef uint8_t clr_u8;
typedef uint16_t clr_u16;
typedef int32_t clr_i32;
typedef uint32_t clr_u32;
typedef int64_t clr_i64;
typedef uint64_t clr_u64;
#define CLR_GLOBAL
#define CLR_CONSTANT const
#define CLR_LOCAL
#define CLR_INLINE static inline
#define CLR_ALWAYS_INLINE static inline
#define CLR_DEVICE 0
static inline float clr_as_float(clr_u32 u) {
  float f;
  memcpy(&f, &u, 4);
  return f;
}
static inline clr_u32 clr_as_uint(float f) {
  clr_u32 u;
  memcpy(&u, &f, 4);
  return u;
}
#define clr_floorf(x) floorf(x)
#define clr_ceilf(x) ceilf(x)
#define clr_fabsf(x) fabsf(x)
#define clr_fminf(a, b) fminf(a, b)
#define clr_fmaxf(a, b) fmaxf(a, b)
static inline clr_u32 clr_clz32(clr_u32 x) { return x ? (clr_u32)__builtin_clz(x) : 32u; }
static inline clr_u32 clr_popcount32(clr_u32 x) { return (clr_u32)__builtin_popcount(x); }
#endif

/* pbrt-v3's OneMinusEpsilon for float: 0x1.fffffep-1. */
#define CLR_ONE_MINUS_EPSILON 0x1.fffffep-1f

#endif
