// The float32 transform of instances and transformed meshes (kernels/shared/instance.h): the
// matrix rounded to float, and the world positions it gives, for the host's expansions
// (Scene::world_positions, the glTF loader's one-mesh flattening) and the ray path's instances.
#pragma once

#include "shared/instance.h"

#include <clvis/math.hpp>

#include <algorithm>
#include <array>
#include <cstddef>

namespace clvis::detail {

/// Rows 0-2 of `t` rounded to float, row by row (clvis_instance's m).
inline std::array<float, 12> instance_matrix(const Mat4& t)
{
    std::array<float, 12> m{};
    for (int i = 0; i < 12; ++i) m[std::size_t(i)] = float(t.m[std::size_t(i)]);
    return m;
}

/// Writes clvis_instance_point of `count` vertices (3 floats each) from `in` to `out`; an identity
/// `t` copies them unchanged (CONVENTIONS.md: a mesh without a transform keeps its bits).
inline void transform_positions(const Mat4& t, const float* in, std::size_t count, float* out)
{
    if (t.is_identity()) {
        std::copy(in, in + count * 3, out);
        return;
    }
    std::array<float, 12> m = instance_matrix(t);
    for (std::size_t i = 0; i < count * 3; i += 3) {
        clvis_vec3 w = clvis_instance_point(m.data(), in[i], in[i + 1], in[i + 2]);
        out[i] = w.x;
        out[i + 1] = w.y;
        out[i + 2] = w.z;
    }
}

} // namespace clvis::detail
