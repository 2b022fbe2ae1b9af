// The one include of the OpenCL C++ bindings: CMake defines CL_HPP_ENABLE_EXCEPTIONS and the
// target and minimum version (1.2) for the whole library.
#pragma once

#include <CL/opencl.hpp>
