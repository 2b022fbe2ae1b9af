// Fixture for tests/include_rule.cmake (never compiled): a path reaching into the renderer, once
// by name and once by a relative path; the includes the rule allows are not reported.
#include "frame/frame.hpp"
#include "ray/bvh_build.hpp"
#include "render/renderer_impl.hpp"
#include "runtime/cl_runtime.hpp"
#include "scene/instance_transform.hpp"
#include "shared/ray.h"
#include "../render/renderer_probe.hpp"
#include "bvh_box.hpp"

#include <clvis/renderer.hpp>
