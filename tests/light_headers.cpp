// Compiled alone by the CTest entry light_headers (never linked): the plain-data headers must
// preprocess without any OpenCL header, so that the host-only referee and image files, and the
// options and timings, do not drag <CL/cl.h> into their users.
#include <clvis/host_visibility.hpp>
#include <clvis/image.hpp>
#include <clvis/image_io.hpp>
#include <clvis/ray_files.hpp>
#include <clvis/rays.hpp>
#include <clvis/referee.hpp>
#include <clvis/render_options.hpp>

#if defined(__OPENCL_CL_H) || defined(__CL_PLATFORM_H) || defined(CL_SUCCESS)
#error "a light clvis header included an OpenCL header"
#endif

#ifdef CLVIS_LIGHT_HEADERS_SELF_TEST
#include <clvis/visibility.hpp>
#if defined(__OPENCL_CL_H) || defined(__CL_PLATFORM_H) || defined(CL_SUCCESS)
#error "the check sees OpenCL (self test)"
#endif
#endif
