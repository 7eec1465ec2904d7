/* fmaxf and fminf inline. libm's are calls, around which callers spill their floats. */
#ifndef CLR_RENDER_FLOAT_MINMAX_H
#define CLR_RENDER_FLOAT_MINMAX_H

/* The larger of x and y; y when they compare equal; the other operand when one is NaN; x + y
 * when both are: glibc's fmaxf on x86-64, bit for bit, for quiet NaNs. */
static inline float rs_fmaxf(float x, float y) {
  if (y != y) return x != x ? x + y : x;
  return x > y ? x : y;
}

/* The smaller, by the same rules (glibc's fminf on x86-64). */
static inline float rs_fminf(float x, float y) {
  if (y != y) return x != x ? x + y : x;
  return x < y ? x : y;
}

#endif
