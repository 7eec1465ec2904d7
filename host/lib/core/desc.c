/* Size-tagged descs: callers built against an older header pass a smaller struct_size. */
#include <string.h>
#include "clr_internal.h"

clr_result clr_desc_adopt(void *full, size_t full_size, const void *given, const char *what) {
  size_t given_size;
  memcpy(&given_size, given, sizeof given_size); /* struct_size is every desc's first field */
  if (given_size < sizeof(size_t) || given_size > full_size || given_size % sizeof(int32_t) != 0)
    return clr_fail(NULL, CLR_ERROR_INVALID_ARGUMENT,
                    "%s->struct_size is %zu, expected %zu or the size of an earlier version "
                    "(call its _init function)",
                    what, given_size, full_size);
  memcpy((char *)full + sizeof(size_t), (const char *)given + sizeof(size_t),
         given_size - sizeof(size_t));
  return CLR_SUCCESS;
}
