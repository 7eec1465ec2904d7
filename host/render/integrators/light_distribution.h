/* pbrt-v3's SpatialLightDistribution (lightsamplestrategy "spatial", the path tracer's default):
 * the scene bounds cut into up to 64 voxels along the longest axis; each voxel's light choice
 * probabilities are the summed Li.y / pdf of every light sampled from 128 Halton points in the
 * voxel (no visibility), with a floor of 0.001 of the average, computed on first use. */
#ifndef CLR_RENDER_LIGHT_DISTRIBUTION_H
#define CLR_RENDER_LIGHT_DISTRIBUTION_H

#include "clrender/result.h"
#include "render_scene.h"

typedef struct clr_light_distribution clr_light_distribution;

clr_result clr_light_distribution_create(const clr_render_scene *scene,
                                         clr_light_distribution **out);
void clr_light_distribution_free(clr_light_distribution *d);
/* The cdf (light count + 1 values, 0 to 1) of the voxel holding p; NULL when out of memory
 * (the caller then uses its own). Safe to call from several threads. */
const float *clr_light_distribution_lookup(clr_light_distribution *d, const float p[3]);
/* The same by the voxel's index (clr_light_distribution_voxel of p). */
const float *clr_light_distribution_lookup_voxel(clr_light_distribution *d, size_t index);
size_t clr_light_distribution_voxel(const clr_light_distribution *d, const float p[3]);
/* Asks the cache for a voxel's slot ahead of its lookup (the grid is too big to stay cached). */
void clr_light_distribution_prefetch(const clr_light_distribution *d, size_t index);

#endif
