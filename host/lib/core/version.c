/* The library's version, as built. */
#include "clrender/version.h"

const char *clr_version(void) { return CLR_VERSION_STRING; }

int clr_version_number(void) { return CLR_VERSION_NUMBER; }
