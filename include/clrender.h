/* clrender: sampling and reconstruction for physically based rendering, as OpenCL kernels. */
#ifndef CLRENDER_H
#define CLRENDER_H

#include "clrender/version.h"
#include "clrender/result.h"
#include "clrender/context.h"
#include "clrender/kernels.h"
#include "clrender/sampler.h"
#include "clrender/filter.h"
#include "clrender/film.h"
#include "clrender/image.h"

#endif
