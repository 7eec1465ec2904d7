/* A 5x7 bitmap font: 7 rows per glyph, bit 4 the leftmost column. */
#ifndef CLR_PLOT_FONT_H
#define CLR_PLOT_FONT_H

#include <stdint.h>

/* The glyph of c (lower case as upper case), or of '?' when the font has none. */
const uint8_t *plot_font_glyph(char c);

#endif
