/* The OpenCL headers as clrender uses them: OpenCL 1.2 API unless the includer chose a version. */
#ifndef CLRENDER_OPENCL_H
#define CLRENDER_OPENCL_H

#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

#endif
