// The binary BVH collapsed into the wide nodes (bvh_width children) the ray kernels walk (Wald et al., "Getting rid of
// packets", 2008), and the refit of those nodes from a refitted binary tree.
#include "ray/bvh_build.hpp"

#include "ray/bvh_box.hpp"

#include <algorithm>
#include <limits>

namespace clvis::detail {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

/// Appends the wide node for binary node `n` (interior) and its subtree; returns its depth.
/// `leaves` (aligned collapse only, else empty): per binary node, the leaves below it. `small`
/// (the other collapse, else empty): the same, at most 255.
int collapse(const Bvh& bvh, std::uint32_t n, const std::vector<std::uint32_t>& leaves,
             const std::vector<std::uint8_t>& small, BvhWide& out)
{
    std::uint32_t cap = 0; // aligned: children of at most `cap` leaves stay closed
    if (!leaves.empty())
        for (cap = 1; bvh_width * cap < leaves[n];) cap *= bvh_width;
    std::uint32_t kids[bvh_width] = {n + 1, bvh.nodes[n].first};
    int count = 2;
    while (count < bvh_width) {
        // the largest child, those that fit whole in the slots left first: a subtree of m leaves
        // opened all the way takes m - 1 more slots and spares a node of m children of its own
        // (at width 8 most such nodes were half empty: 11 bytes a triangle of a 1M sphere)
        int open = -1;
        bool open_fits = false;
        double largest = -1;
        for (int k = 0; k < count; ++k) {
            const clvis_bvh_node& c = bvh.nodes[kids[k]];
            if (c.count > 0 || (cap != 0 && leaves[kids[k]] <= cap)) continue;
            bool fits = !small.empty() && int(small[kids[k]]) <= bvh_width - count + 1;
            if ((fits && !open_fits) || (fits == open_fits && node_area(c) > largest)) {
                largest = node_area(c);
                open = k;
                open_fits = fits;
            }
        }
        if (open < 0) break;
        std::uint32_t c = kids[open];
        // the opened node's children take its slot and the next one, keeping the left-to-right order
        for (int k = count; k > open + 1; --k) kids[k] = kids[k - 1];
        kids[open] = c + 1;
        kids[open + 1] = bvh.nodes[c].first;
        ++count;
    }
    std::size_t self = out.nodes.size();
    out.nodes.emplace_back();
    out.source.insert(out.source.end(), std::size_t(bvh_width), ~0u);
    int depth = 1;
    for (int k = 0; k < bvh_width; ++k) {
        clvis_wide_node& w = out.nodes[self];
        if (k >= count) {
            w.lo_x[k] = w.lo_y[k] = w.lo_z[k] = inf;
            w.hi_x[k] = w.hi_y[k] = w.hi_z[k] = -inf;
            w.child[k] = 0;
            w.count[k] = 0;
            continue;
        }
        const clvis_bvh_node& c = bvh.nodes[kids[k]];
        out.source[self * bvh_width + std::size_t(k)] = kids[k];
        w.lo_x[k] = c.lo_x; w.lo_y[k] = c.lo_y; w.lo_z[k] = c.lo_z;
        w.hi_x[k] = c.hi_x; w.hi_y[k] = c.hi_y; w.hi_z[k] = c.hi_z;
        w.count[k] = c.count;
        if (c.count > 0) {
            w.child[k] = c.first;
        } else {
            std::uint32_t index = std::uint32_t(out.nodes.size());
            int d = collapse(bvh, kids[k], leaves, small, out); // may move out.nodes: w is not used after this
            out.nodes[self].child[k] = index;
            depth = std::max(depth, d + 1);
        }
    }
    return depth;
}

} // namespace

BvhWide collapse_wide(const Bvh& bvh, bool aligned)
{
    BvhWide out;
    if (bvh.nodes.empty()) return out;
    // At most one per interior node: never moved, and the room left unused is never touched.
    out.nodes.reserve(bvh.nodes.size() / 2 + 1);
    out.source.reserve(out.nodes.capacity() * bvh_width);
    const clvis_bvh_node& root = bvh.nodes[0];
    if (root.count > 0) { // a single leaf: one wide node with one child
        clvis_wide_node w{};
        for (int k = 0; k < bvh_width; ++k) {
            w.lo_x[k] = w.lo_y[k] = w.lo_z[k] = inf;
            w.hi_x[k] = w.hi_y[k] = w.hi_z[k] = -inf;
        }
        w.lo_x[0] = root.lo_x; w.lo_y[0] = root.lo_y; w.lo_z[0] = root.lo_z;
        w.hi_x[0] = root.hi_x; w.hi_y[0] = root.hi_y; w.hi_z[0] = root.hi_z;
        w.child[0] = root.first;
        w.count[0] = root.count;
        out.nodes.push_back(w);
        out.source.assign(std::size_t(bvh_width), ~0u);
        out.source[0] = 0;
        out.depth = 1;
        return out;
    }
    std::vector<std::uint32_t> leaves;
    std::vector<std::uint8_t> small;
    if (aligned) { // depth-first: children after their parent, so one backward pass
        leaves.resize(bvh.nodes.size());
        for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
            const clvis_bvh_node& b = bvh.nodes[i];
            leaves[i] = b.count > 0 ? 1 : leaves[i + 1] + leaves[b.first];
        }
    } else {
        small.resize(bvh.nodes.size());
        for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
            const clvis_bvh_node& b = bvh.nodes[i];
            small[i] = std::uint8_t(b.count > 0 ? 1 : std::min(255, int(small[i + 1]) + int(small[b.first])));
        }
    }
    out.depth = collapse(bvh, 0, leaves, small, out);
    return out;
}

void refit_wide(BvhWide& wide, const Bvh& bvh)
{
    for (std::size_t i = 0; i < wide.nodes.size(); ++i) {
        clvis_wide_node& w = wide.nodes[i];
        for (int k = 0; k < bvh_width; ++k) {
            std::uint32_t src = wide.source[i * bvh_width + std::size_t(k)];
            if (src == ~0u) continue;
            const clvis_bvh_node& c = bvh.nodes[src];
            w.lo_x[k] = c.lo_x; w.lo_y[k] = c.lo_y; w.lo_z[k] = c.lo_z;
            w.hi_x[k] = c.hi_x; w.hi_y[k] = c.hi_y; w.hi_z[k] = c.hi_z;
        }
    }
}

} // namespace clvis::detail
