// The split of BvhBuildOptions::full_leaves (bvh_build.cpp): an exact SAH sweep over a range sorted
// by centroid on each axis, where the left side may only hold whole groups of leaves, so that the
// leaves come out full and in groups of bvh_width, bvh_width^2, ... that collapse_wide's `aligned`
// makes full wide subtrees (the instances' top level, bvh_instances.cpp).
#pragma once

#include "ray/bvh_box.hpp"
#include "ray/bvh_build.hpp"

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <limits>
#include <vector>

namespace clvis::detail {

/// Reorders [first, last) (more than `leaf` items) by centroid on the best axis and returns the
/// left side's count: a multiple of `leaf` times the largest power of bvh_width below a
/// bvh_width-th of the
/// range's leaves, at the least SAH cost. box_of(item) gives an item's Box; less(axis) a strict
/// order of items by centroid on that axis (ties by id, so the result is fully determined).
template <class It, class BoxOf, class Less>
std::size_t full_leaves_split(It first, It last, std::size_t leaf, BoxOf box_of, Less less)
{
    using Item = typename std::iterator_traits<It>::value_type;
    std::size_t n = std::size_t(last - first), step = leaf;
    while (std::size_t(bvh_width) * step < n) step *= std::size_t(bvh_width);
    std::vector<Item> order(first, last);
    std::vector<double> right_area(n + 1, 0.0);
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_k = n / step / 2 * step; // only if no cost is finite (not for finite boxes)
    int best_axis = -1;
    for (int a = 0; a < 3; ++a) {
        std::sort(order.begin(), order.end(), less(a));
        Box acc = Box::none();
        for (std::size_t i = n; i-- > 0;) {
            acc.grow(box_of(order[i]));
            right_area[i] = acc.half_area();
        }
        acc = Box::none();
        for (std::size_t k = 1; k < n; ++k) {
            acc.grow(box_of(order[k - 1]));
            double cost = k % step == 0 ? acc.half_area() * double(k) + right_area[k] * double(n - k) : best;
            if (cost < best) {
                best = cost;
                best_k = k;
                best_axis = a;
            }
        }
    }
    if (best_axis >= 0) std::sort(first, last, less(best_axis));
    return std::max(best_k, step);
}

} // namespace clvis::detail
