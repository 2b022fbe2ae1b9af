// The float box of the BVH build, its refit and its wide collapse (bvh_build.cpp,
// bvh_collapse.cpp): the boxes of kernels/shared/bvh.h, grown and measured on the host.
#pragma once

#include "shared/bvh.h"

#include <algorithm>
#include <cstdint>
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

// Four floats in one SSE register (GCC/Clang vector extensions, so other targets get plain code):
// the build handles a box's three axes at once. Lane 3 is unused.
typedef float v4f __attribute__((vector_size(16)));
typedef std::int32_t v4i __attribute__((vector_size(16)));
typedef double v4d __attribute__((vector_size(32)));

/// std::min(cur, x) and std::max(cur, x) lane by lane, with the same operands and the same
/// comparison (so the same bits, signed zeros included) as Box::grow.
inline v4f vmin(v4f cur, v4f x) { return x < cur ? x : cur; }
inline v4f vmax(v4f cur, v4f x) { return cur < x ? x : cur; }

/// a where the mask's lane is all ones, b where it is zero (masks of comparisons or of 0 - bool).
inline v4f select(v4i mask, v4f a, v4f b)
{
    return reinterpret_cast<v4f>((reinterpret_cast<v4i>(a) & mask) | (reinterpret_cast<v4i>(b) & ~mask));
}

/// A box as two registers; none() has lo = +inf, hi = -inf.
struct VBox {
    v4f lo, hi;
    static VBox none()
    {
        constexpr float inf = std::numeric_limits<float>::infinity();
        return {v4f{inf, inf, inf, inf}, v4f{-inf, -inf, -inf, -inf}};
    }
    void grow(const VBox& b)
    {
        lo = vmin(lo, b.lo);
        hi = vmax(hi, b.hi);
    }
    void grow(v4f p)
    {
        lo = vmin(lo, p);
        hi = vmax(hi, p);
    }
    Box box() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
    /// Box::half_area() of a box that is not empty, with the same operations in the same order.
    double half_area() const
    {
        v4d d = __builtin_convertvector(hi, v4d) - __builtin_convertvector(lo, v4d);
        v4d next = __builtin_shufflevector(d, d, 1, 2, 0, 3);
        v4d products = d * next; // dx dy, dy dz, dz dx
        return (products[0] + products[1]) + products[2];
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
