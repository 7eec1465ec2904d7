/* TEMPORARY (film branch only, discarded at merge): the filter contract comes from
 * clrender/filter.h; this private header only gathers it for the stub implementation. */
#ifndef CLR_FILTER_STUB_H
#define CLR_FILTER_STUB_H
#include "clrender/filter.h"
#endif
