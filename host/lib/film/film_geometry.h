/* pbrt-v3's film geometry: cropped pixel bounds and the sample bounds grown by the filter radius. */
#ifndef CLR_FILM_GEOMETRY_H
#define CLR_FILM_GEOMETRY_H

#include "clrender/film.h"
#include "clrender/sampler.h"

/* Largest accepted film side and pixel count (documented in film.h). */
#define CLR_MAX_RESOLUTION CLR_FILM_MAX_SIDE
#define CLR_MAX_PIXELS CLR_FILM_MAX_PIXELS
#define CLR_MAX_FILTER_RADIUS 64.0f

/* Validates resolution, crop window and radius (messages name `who` and the bad value) and
 * computes pbrt-v3's croppedPixelBounds and GetSampleBounds. */
clr_result clr_film_geometry_bounds(const clr_film_geometry *g, const char *who,
                                    clr_bounds2i *pixel_bounds, clr_bounds2i *sample_bounds);

#endif
