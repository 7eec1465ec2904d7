/* Lane arithmetic shared by the SIMD-shaped sampler kernels (OpenCL C only). */
#ifndef CLR_LANE_MATH_H
#define CLR_LANE_MATH_H

#include "halton_funcs.h"

/* Fully unrolls a loop with a compile-time trip count; LLVM must not vectorise it further. */
#define CLR_UNROLL _Pragma("clang loop vectorize(disable) interleave(disable) unroll(full)")
/* A loop whose trip count is a (uniform) argument: LLVM must not vectorise it further either. */
#define CLR_SCALAR_LOOP _Pragma("clang loop vectorize(disable) interleave(disable)")

/* any(m) by OR-ing halves (PoCL's any() tests the lanes one by one with branches). */
static inline __attribute__((always_inline)) int clr_any8(int8 m) {
  int4 m4 = m.lo | m.hi;
  int2 m2 = m4.lo | m4.hi;
  return (m2.x | m2.y) < 0;
}

/* (a * m) >> 32 per lane in four 64-bit products of even and of odd lanes (AVX2: two vpmuludq
 * and no repacking; the library's mul_hi(uint8) goes through 16-bit halves on PoCL). */
static inline __attribute__((always_inline)) uint8 clr_mul_hi8(uint8 a, uint m) {
  const ulong low_half = 0xFFFFFFFFul;
  ulong4 pairs = as_ulong4(a);
  ulong4 even = ((pairs & low_half) * (ulong)m) >> 32ul;
  ulong4 odd = ((pairs >> 32ul) * (ulong)m) & ~low_half;
  return as_uint8(even | odd);
}

/* Table lookup in every lane: table[index & 7] (one vpermd on AVX2). */
static inline __attribute__((always_inline)) uint8 clr_permute8(uint8 table, uint8 index) {
#if defined(__AVX2__)
  return as_uint8(__builtin_ia32_permvarsi256(as_int8(table), as_int8(index)));
#else
  return shuffle(table, index & 7u);
#endif
}

/* A Sobol' generator matrix times every lane's index (its `bits` <= 32, uniform), from the
 * matrix's 3-bit group tables `groups` (CLR_SOBOL_GROUP_ENTRIES per group: entry x of group g is
 * the XOR of the columns 3g + b over the bits b of x), one lookup per 3 bits. Four groups a step:
 * entry 0 of a group past the bits is 0, and a table has 18 groups. */
static inline __attribute__((always_inline)) uint8 clr_sobol_group_bits8(
    uint8 index, __global const uint *groups, int bits) {
  uint8 v = (uint8)0u;
  CLR_SCALAR_LOOP
  for (int g = 0; 3 * g < bits; g += 4, index >>= 12u) {
    v ^= clr_permute8(vload8(g, groups), index);
    v ^= clr_permute8(vload8(g + 1, groups), index >> 3u);
    v ^= clr_permute8(vload8(g + 2, groups), index >> 6u);
    v ^= clr_permute8(vload8(g + 3, groups), index >> 9u);
  }
  return v;
}

/* clr_sobol_xor_columns64 over the 64-bit VdC columns taken mod 2^32, in every lane: AND, XOR and
 * left shifts commute with that, so the low 32 index bits are exact, and those are all the bits
 * (the columns of row m - 1 are below 2^2m, and indices below 2^32). count <= 32 is uniform; four
 * columns a step (bits past count are zero, and a row has 52 columns to read). */
static inline __attribute__((always_inline)) uint8 clr_xor_columns_low8(uint8 bits,
                                                                        __global const ulong *cols,
                                                                        int count) {
  uint8 v = (uint8)0u;
  CLR_SCALAR_LOOP
  for (int i = 0; i < count; i += 4, bits >>= 4u) {
    v ^= (uint8)(uint)cols[i] & (0u - (bits & 1u));
    v ^= (uint8)(uint)cols[i + 1] & (0u - ((bits >> 1u) & 1u));
    v ^= (uint8)(uint)cols[i + 2] & (0u - ((bits >> 2u) & 1u));
    v ^= (uint8)(uint)cols[i + 3] & (0u - ((bits >> 3u) & 1u));
  }
  return v;
}

/* clr_sobol_interval_to_index at resolution 2^m in every lane, for sample numbers `frame` below
 * 2^frame_bits with 2m + frame_bits <= 32 (uniform): higher frame bits are zero and the pixel
 * bits b span 2m. */
static inline uint8 clr_sobol_index8(int m, int frame_bits, uint8 frame, int8 px, int8 py,
                                     __global const ulong *vdc, __global const ulong *vdc_inv) {
  if (m == 0) return frame;
  const uint row = (uint)(m - 1) * CLR_SOBOL_MATRIX_SIZE;
  uint8 delta = clr_xor_columns_low8(frame, vdc + row, frame_bits);
  const uint mask = (1u << (uint)m) - 1u;
  uint8 b = (((as_uint8(px) & mask) << (uint)m) | (as_uint8(py) & mask)) ^ delta;
  return (frame << (uint)(2 * m)) ^ clr_xor_columns_low8(b, vdc_inv + row, 2 * m);
}

/* t[i] in every lane, gathered as 16-bit lanes and widened once (each lane one load-and-insert
 * on x86). */
static inline __attribute__((always_inline)) uint8 clr_gather_u16(__global const ushort *t,
                                                                  uint8 i) {
  return convert_uint8(
      (ushort8)(t[i.s0], t[i.s1], t[i.s2], t[i.s3], t[i.s4], t[i.s5], t[i.s6], t[i.s7]));
}

#if defined(__AVX2__)
typedef char clr_bytes32 __attribute__((vector_size(32)));

/* Byte lookup in every 128-bit half: byte k of the result is byte (index byte k) & 15 of the
 * same half of table (vpshufb; index bytes below 128). */
static inline __attribute__((always_inline)) uint8 clr_shuffle_bytes8(uint8 table, uint8 index) {
  return __builtin_astype(__builtin_ia32_pshufb256(__builtin_astype(table, clr_bytes32),
                                                   __builtin_astype(index, clr_bytes32)),
                          uint8);
}
#endif

/* clr_reverse_bits32 in every lane. On AVX2: the bytes of each lane reversed, then each byte's
 * two nibbles reversed and swapped, by byte lookups; else nibble by nibble (no shift-and-mask
 * idiom that compilers turn into llvm.bitreverse, which Oclgrind cannot run). */
static inline uint8 clr_reverse_bits32x8(uint8 n) {
#if defined(__AVX2__)
  const uint8 byte_swap = (uint8)(0x00010203u, 0x04050607u, 0x08090A0Bu, 0x0C0D0E0Fu, 0x00010203u,
                                  0x04050607u, 0x08090A0Bu, 0x0C0D0E0Fu);
  const uint8 low_up = (uint8)(0xC0408000u, 0xE060A020u, 0xD0509010u, 0xF070B030u, 0xC0408000u,
                               0xE060A020u, 0xD0509010u, 0xF070B030u); /* rev4(i) << 4 */
  const uint8 high_down = (uint8)(0x0C040800u, 0x0E060A02u, 0x0D050901u, 0x0F070B03u, 0x0C040800u,
                                  0x0E060A02u, 0x0D050901u, 0x0F070B03u); /* rev4(i) */
  uint8 b = clr_shuffle_bytes8(n, byte_swap);
  return clr_shuffle_bytes8(low_up, b & 0x0F0F0F0Fu) |
         clr_shuffle_bytes8(high_down, (b >> 4u) & 0x0F0F0F0Fu);
#else
  uint8 r = (uint8)0u;
  CLR_UNROLL
  for (uint i = 0u; i < 8u; ++i) {
    uint8 x = (n >> (4u * i)) & 15u;
    uint8 rev = (((uint8)CLR_REV3_NIBBLES >> ((x & 7u) * 4u)) & 14u) | (x >> 3u);
    r |= rev << (28u - 4u * i);
  }
  return r;
#endif
}

#endif
