// Compiled alone by the CTest entry light_headers (never linked): every public header, the
// umbrella included, must preprocess without any OpenCL header, so that clvis neither drags
// <CL/cl.h> into its users nor picks their OpenCL version (device.hpp declares the handles it
// uses itself).
#include <clvis/clvis.hpp>
#include <clvis/multi_device.hpp> // outside the umbrella, light all the same
#include <clvis/primary_rays.hpp> // outside the umbrella (its name is common in callers' code)
#include <clvis/views_file.hpp>

#if defined(__OPENCL_CL_H) || defined(__CL_PLATFORM_H) || defined(CL_SUCCESS)
#error "a clvis header included an OpenCL header"
#endif

#ifdef CLVIS_LIGHT_HEADERS_SELF_TEST
#include <CL/cl.h>
#if defined(__OPENCL_CL_H) || defined(__CL_PLATFORM_H) || defined(CL_SUCCESS)
#error "the check sees OpenCL (self test)"
#endif
#endif
