/* The renderer's one growth helper for realloc'ed arrays. */
#ifndef CLR_RENDER_GROW_H
#define CLR_RENDER_GROW_H

#include <stddef.h>
#include "clrender/result.h"

/* Makes *items hold at least `needed` elements of elem_size bytes: the capacity doubles from a
 * minimum of 8. CLR_ERROR_OUT_OF_MEMORY (items unchanged) when realloc fails or sizes overflow;
 * `max_capacity` bounds the element count (e.g. INT32_MAX for int counters). */
clr_result clr_grow(void **items, size_t *capacity, size_t needed, size_t elem_size,
                    size_t max_capacity);
/* The same for an int capacity (at most INT32_MAX elements). */
clr_result clr_grow_array(void **items, int *capacity, int needed, size_t elem_size);

#endif
