/* Error reporting inside the renderer: through the library's per-thread last-error message. */
#ifndef CLR_RENDER_ERROR_H
#define CLR_RENDER_ERROR_H

#include "clrender/result.h"

/* Returns from the calling function when `expr` gives anything but CLR_SUCCESS. */
#define CLR_CHECK(expr)                       \
  do {                                        \
    clr_result clr_r_ = (expr);               \
    if (clr_r_ != CLR_SUCCESS) return clr_r_; \
  } while (0)

#endif
