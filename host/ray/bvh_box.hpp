// The float box of the BVH build, its refit and its 4-wide collapse (bvh_build.cpp,
// bvh_collapse.cpp): the boxes of kernels/shared/bvh.h, grown and measured on the host.
#pragma once

#include "shared/bvh.h"

#include <algorithm>
#include <limits>

namespace clvis::detail {

/// An axis-aligned box of floats: trivial (arrays of them cost nothing to declare); Box::none()
/// has lo = +inf, hi = -inf.
struct Box {
    float lo[3], hi[3];

    static Box none()
    {
        constexpr float inf = std::numeric_limits<float>::infinity();
        return {{inf, inf, inf}, {-inf, -inf, -inf}};
    }

    void grow(const Box& b)
    {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], b.lo[a]);
            hi[a] = std::max(hi[a], b.hi[a]);
        }
    }
    void grow(const float p[3])
    {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
    /// Half the surface area, in double: float boxes of huge finite coordinates do not overflow.
    double half_area() const
    {
        if (empty()) return 0;
        double dx = double(hi[0]) - lo[0], dy = double(hi[1]) - lo[1], dz = double(hi[2]) - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }
};

/// Half the surface area of a node's box.
inline double node_area(const clvis_bvh_node& n)
{
    Box b;
    b.lo[0] = n.lo_x; b.lo[1] = n.lo_y; b.lo[2] = n.lo_z;
    b.hi[0] = n.hi_x; b.hi[1] = n.hi_y; b.hi[2] = n.hi_z;
    return b.half_area();
}

} // namespace clvis::detail
