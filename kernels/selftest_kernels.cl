/* Runtime self-test: proves the embedded-program path and, with -DCLR_SELFTEST_BREAK, that a
 * build failure reports the device's build log. */
#include "clr_platform.h"

#ifdef CLR_SELFTEST_BREAK
this_is_not_opencl_c;
#endif

__kernel void clr_selftest_fill(__global uint *out, uint value) {
  size_t i = get_global_id(0);
  out[i] = value + (uint)i;
}
