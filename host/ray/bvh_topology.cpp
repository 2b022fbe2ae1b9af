// What a refit of the flat BVH keeps between refits (issue 37's memory): the binary tree's shape
// as one leaf count a node, from which its first and count and the wide nodes' source slots are
// derived again when a refit needs them (ray_pipeline.cpp's restore_host_tree).
#include "ray/bvh_build.hpp"

#include <clvis/error.hpp>

#include <string>
#include <utility>

namespace clvis::detail {

std::vector<std::uint8_t> bvh_leaf_counts(const std::vector<clvis_bvh_node>& nodes)
{
    std::vector<std::uint8_t> counts(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].count > 255)
            throw Error(Error::Kind::Limit, "BVH node " + std::to_string(i) + " is a leaf of " +
                                                std::to_string(nodes[i].count) + " triangles, more than 255");
        counts[i] = std::uint8_t(nodes[i].count);
    }
    return counts;
}

std::vector<clvis_bvh_node> bvh_from_leaf_counts(const std::vector<std::uint8_t>& counts)
{
    std::vector<clvis_bvh_node> nodes(counts.size(), clvis_bvh_node{});
    std::vector<std::uint32_t> pending; // interior nodes whose right child comes next after their left subtree
    std::uint32_t slot = 0;
    auto bad = [](const std::string& why) {
        throw Error(Error::Kind::InvalidArgument, "the BVH's leaf counts are no depth-first tree: " + why);
    };
    for (std::size_t i = 0; i < counts.size(); ++i) {
        if (i > 0 && counts[i - 1] > 0) { // a subtree ended: this node is the right child of the nearest pending one
            if (pending.empty()) bad("node " + std::to_string(i) + " follows a complete tree");
            nodes[pending.back()].first = std::uint32_t(i);
            pending.pop_back();
        }
        nodes[i].count = counts[i];
        if (counts[i] > 0) {
            nodes[i].first = slot;
            slot += counts[i];
        } else {
            pending.push_back(std::uint32_t(i));
        }
    }
    if (!pending.empty() || (!counts.empty() && counts.back() == 0))
        bad(std::to_string(pending.size()) + " interior node(s) lack a right child");
    return nodes;
}

std::vector<std::uint32_t> wide_source_of(const std::vector<clvis_bvh_node>& binary,
                                          const std::vector<clvis_wide_node>& wide)
{
    std::vector<std::uint32_t> source(wide.size() * bvh_width, ~0u);
    if (wide.empty()) return source;
    auto bad = [](const std::string& why) {
        throw Error(Error::Kind::InvalidArgument, "the wide BVH does not match its binary tree: " + why);
    };
    if (binary.empty()) bad("no binary nodes");
    using Range = std::pair<std::uint32_t, std::uint32_t>; // leaf slots [first, end)
    // Depth-first: children after their parent, so one backward pass over each tree.
    std::vector<Range> node_range(binary.size());
    for (std::size_t i = binary.size(); i-- > 0;) {
        const clvis_bvh_node& n = binary[i];
        if (n.count > 0) node_range[i] = {n.first, n.first + n.count};
        else if (i + 1 < binary.size() && n.first > i && n.first < binary.size())
            node_range[i] = {node_range[i + 1].first, node_range[n.first].second};
        else bad("binary node " + std::to_string(i) + " names no children");
    }
    auto used = [](const clvis_wide_node& w, int k) { return w.count[k] > 0 || w.child[k] != 0; };
    std::vector<Range> wide_range(wide.size());
    for (std::size_t i = wide.size(); i-- > 0;) {
        const clvis_wide_node& w = wide[i];
        Range r{~0u, 0};
        for (int k = 0; k < bvh_width; ++k) {
            if (!used(w, k)) continue;
            if (w.count[k] == 0 && (w.child[k] <= i || w.child[k] >= wide.size()))
                bad("wide node " + std::to_string(i) + " names child " + std::to_string(w.child[k]));
            Range c = w.count[k] > 0 ? Range{w.child[k], w.child[k] + w.count[k]} : wide_range[w.child[k]];
            if (r.first == ~0u) r.first = c.first;
            r.second = c.second;
        }
        wide_range[i] = r;
    }
    if (binary[0].count > 0) { // a single leaf: one wide node of one child (collapse_wide)
        source[0] = 0;
        return source;
    }
    std::vector<std::uint32_t> from(wide.size(), ~0u); // each wide node's binary node
    from[0] = 0;
    std::vector<std::uint32_t> open; // the cut of the binary subtree not yet matched, leftmost last
    for (std::size_t i = 0; i < wide.size(); ++i) {
        std::uint32_t b = from[i];
        if (b == ~0u || binary[b].count > 0) bad("wide node " + std::to_string(i) + " has no interior binary node");
        open = {binary[b].first, b + 1};
        for (int k = 0; k < bvh_width; ++k) {
            const clvis_wide_node& w = wide[i];
            if (!used(w, k)) continue;
            Range want = w.count[k] > 0 ? Range{w.child[k], w.child[k] + w.count[k]} : wide_range[w.child[k]];
            for (;;) {
                if (open.empty()) bad("wide node " + std::to_string(i) + " has more slots than its binary subtree");
                std::uint32_t c = open.back();
                open.pop_back();
                const Range& have = node_range[c];
                if (have.first != want.first || have.second < want.second)
                    bad("slot " + std::to_string(k) + " of wide node " + std::to_string(i) + " matches no binary node");
                if (have.second == want.second) {
                    if ((binary[c].count > 0) != (w.count[k] > 0))
                        bad("slot " + std::to_string(k) + " of wide node " + std::to_string(i) + " is a leaf on one side only");
                    source[i * bvh_width + std::size_t(k)] = c;
                    if (w.count[k] == 0) from[w.child[k]] = c;
                    break;
                }
                if (binary[c].count > 0) bad("a leaf of the binary tree is wider than its wide slot");
                open.push_back(binary[c].first); // opened: its children take its place, left first
                open.push_back(c + 1);
            }
        }
        if (!open.empty()) bad("wide node " + std::to_string(i) + " leaves binary nodes uncovered");
    }
    return source;
}

} // namespace clvis::detail
