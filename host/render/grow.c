/* Growth of realloc'ed arrays: doubling capacity, overflow-checked. */
#include "grow.h"
#include <stdint.h>
#include <stdlib.h>

clr_result clr_grow(void **items, size_t *capacity, size_t needed, size_t elem_size,
                    size_t max_capacity) {
  if (needed <= *capacity) return CLR_SUCCESS;
  if (needed > max_capacity || elem_size == 0) return CLR_ERROR_OUT_OF_MEMORY;
  size_t grown_capacity = *capacity < 8 ? 8 : *capacity;
  while (grown_capacity < needed) grown_capacity *= 2;
  if (grown_capacity > max_capacity) grown_capacity = max_capacity;
  if (grown_capacity > SIZE_MAX / elem_size) return CLR_ERROR_OUT_OF_MEMORY;
  void *grown = realloc(*items, grown_capacity * elem_size);
  if (!grown) return CLR_ERROR_OUT_OF_MEMORY;
  *items = grown;
  *capacity = grown_capacity;
  return CLR_SUCCESS;
}

clr_result clr_grow_array(void **items, int *capacity, int needed, size_t elem_size) {
  if (needed < 0 || *capacity < 0) return CLR_ERROR_OUT_OF_MEMORY;
  size_t cap = (size_t)*capacity;
  clr_result r = clr_grow(items, &cap, (size_t)needed, elem_size, INT32_MAX);
  if (r == CLR_SUCCESS) *capacity = (int)cap;
  return r;
}
