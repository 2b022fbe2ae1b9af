// Builds the BVH of a scene on the host (binned SAH, Wald 2007), in parallel and deterministically,
// and flattens it into the layout of kernels/shared/bvh.h; refits it after vertices move. Consumed
// by ray_pipeline.cpp, which uploads the result for ray_trace.cl.
#pragma once

#include "shared/bvh.h"

#include <clvis/render_options.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace clvis::detail {

enum class BvhSplit {
    Sah,    ///< binned surface area heuristic; object median where it cannot split
    Median, ///< object median on the widest centroid axis (a reference for tests)
};

/// The Renderer's BvhOptions (leaf size 1..64, SAH bins 2..256), plus what only the host build
/// and its tests choose.
struct BvhBuildOptions : BvhOptions {
    BvhSplit split = BvhSplit::Sah;
    unsigned threads = 0;    ///< worker threads; 0: the machine's hardware threads
    /// Every range of at most max_leaf_size becomes a leaf, and ranges of up to bvh_width^2 leaves
    /// split where the left side is whole leaves, or whole groups of bvh_width leaves past
    /// bvh_width: with collapse_wide's `aligned`, most wide nodes are full, as the instances' top
    /// level wants it (bvh_instances.cpp).
    bool full_leaves = false;
    /// false: build_bvh leaves Bvh::tris empty and gives the leaf slots' triangle ids in
    /// Bvh::ids instead (4 bytes a triangle, not 40), freeing its build scratch before the
    /// collapse; the caller gathers the slots where it needs them (gather_bvh_tris), e.g. straight
    /// into a device buffer a block at a time (ray_pipeline.cpp, issue 37's memory).
    bool gather = true;
};

/// Depth (nodes on a root-to-leaf path) past which the build splits at the median, so that a
/// pathological scene cannot make the tree (and the traversal stack) deeper than about
/// max_sah_depth + log2(triangles).
constexpr int bvh_max_sah_depth = 48;

struct Bvh {
    std::vector<clvis_bvh_node> nodes;   ///< depth-first; empty for a scene without triangles
    std::vector<clvis_bvh_tri> tris;     ///< leaf slots: each leaf's triangles contiguous
    std::vector<std::uint32_t> ids;      ///< built without gather: the leaf slots' triangle ids (tris empty)
    std::size_t leaves = 0;
    int depth = 0;                       ///< nodes on the longest root-to-leaf path
    double sah_cost = 0;                 ///< see bvh_sah_cost
};

/// Children per wide node (kernels/shared/bvh.h's CLVIS_BVH_WIDTH): the collapse, the aligned
/// top level of the instances and the traversal stack's size follow it.
constexpr int bvh_width = CLVIS_BVH_WIDTH;

/// The binary tree collapsed to wide nodes for the kernel, depth-first from the root (node 0).
struct BvhWide {
    std::vector<clvis_wide_node> nodes; ///< empty for a scene without triangles
    std::vector<std::uint32_t> source;  ///< per slot (bvh_width per node): the binary node it copies, or ~0u
    int depth = 0;                      ///< wide nodes on the longest root-to-leaf path
};

/// Collapses `bvh`: each wide node takes a binary node's children and opens the largest
/// interior ones until it holds bvh_width (Wald et al., "Getting rid of packets", 2008; Embree's
/// and tinybvh's BVH8). The leaves and triangle slots stay those of `bvh`. `aligned` (a tree built
/// with full_leaves): a node of m leaves opens only children of more than c leaves, c the largest
/// power of bvh_width below m, so that each group of bvh_width^k leaves the build made becomes one
/// full wide subtree.
BvhWide collapse_wide(const Bvh& bvh, bool aligned = false);

/// Copies the boxes of a refitted `bvh` into the wide nodes collapsed from it (same grouping).
void refit_wide(BvhWide& wide, const Bvh& bvh);

/// What a refit needs of the binary tree's shape, kept between refits (issue 37's memory): each
/// node's leaf triangle count in depth-first order (0 for an interior node), one byte a node.
/// Throws Error(Limit) for a leaf of more than 255 triangles (the build makes at most 64).
std::vector<std::uint8_t> bvh_leaf_counts(const std::vector<clvis_bvh_node>& nodes);

/// The binary nodes `counts` describes, boxes zero: each leaf's first slot follows the previous
/// leaf's, each interior node's right child follows its left subtree (depth-first order), so the
/// first and count of every node are the built tree's. Throws Error(InvalidArgument) where
/// `counts` is no depth-first tree.
std::vector<clvis_bvh_node> bvh_from_leaf_counts(const std::vector<std::uint8_t>& counts);

/// BvhWide::source of `wide`, collapsed from the binary tree whose first and count `binary` holds
/// (boxes not read): each used slot's binary node, found by its leaf slot range, which names one
/// node (every interior node has two non-empty children), in the binary node's subtree that the
/// wide node was collapsed from. Throws Error(InvalidArgument) where the trees disagree.
std::vector<std::uint32_t> wide_source_of(const std::vector<clvis_bvh_node>& binary,
                                          const std::vector<clvis_wide_node>& wide);

/// Builds the BVH of `triangle_count` triangles given by `indices` (3 per triangle, id order)
/// into `positions` (3 floats per vertex). Same input, same bits, whatever the threads do. With
/// `wide`, also collapses it there (collapse_wide, aligned as options.full_leaves): on the pool,
/// beside the copy of the leaf triangles, so the same result as the two calls in less time.
Bvh build_bvh(const float* positions, const std::uint32_t* indices, std::size_t triangle_count,
              const BvhBuildOptions& options, BvhWide* wide = nullptr);

/// Writes leaf slots [0, count) of `ids` to `out` as build_bvh gathers Bvh::tris (the same bits),
/// on `threads` threads (0: the machine's hardware threads).
void gather_bvh_tris(const float* positions, const std::uint32_t* indices, const std::uint32_t* ids,
                     std::size_t count, clvis_bvh_tri* out, unsigned threads = 0);

/// Recomputes every box bottom-up and the leaf triangles' vertices from moved `positions`
/// (same indices): the topology stays.
void refit_bvh(Bvh& bvh, const float* positions, const std::uint32_t* indices);

/// SAH cost relative to the root: sum over interior nodes of area, plus over leaves of area times
/// triangles, divided by the root's area (1 traversal step and 1 triangle test cost the same).
double bvh_sah_cost(const std::vector<clvis_bvh_node>& nodes);

} // namespace clvis::detail
