// The reference renderers of `clvis bench`, in one include: Embree (rays) and Mesa's llvmpipe
// through EGL (rasterization), each optional at build time (embree_available, gl_available).
#pragma once

#include "reference_embree.hpp"
#include "reference_gl.hpp"
#include "reference_result.hpp"
