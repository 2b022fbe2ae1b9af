// The scene as the per-sample kernels (shade, resolve, ray generation) read it: the resident
// expansion for a plain scene; for a scene with instances only the triangles a buffer's keys name,
// in float32 world space (the expansion's bits), with the keys' ids renumbered into them, so that
// nothing the size of the expansion is ever made (CONVENTIONS.md "Instances").
#pragma once

#include "frame/frame.hpp"

#include <clvis/math.hpp>
#include <clvis/renderer.hpp>
#include <clvis/visibility.hpp>

namespace clvis::detail {

/// A world-space vertex normal: `n` through the inverse transpose of `t`'s linear part (its
/// cofactors, in double), unit length in float; zero where that is the zero vector.
void world_normal(const Mat4& t, const float n[3], float out[3]);

struct SampleScene {
    DeviceScene scene; ///< what the kernel takes through DeviceScene::set_args
    cl::Buffer keys;   ///< the keys it reads: the buffer's own, or renumbered into `scene`
};

/// The scene `vis`'s keys are read against by a kernel that uses a key's id only to find its
/// triangle's corners. `geometry` false: the kernel reads no corner (shade's id and depth modes),
/// so a scene with instances gets its true triangle count and no arrays at all.
SampleScene sample_scene(Renderer::Impl& r, const VisibilityBuffer& vis, bool geometry);

} // namespace clvis::detail
