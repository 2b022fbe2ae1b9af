// The ray path's two-level BVH for scenes with instances (CONVENTIONS.md "Instances"): one tree
// per prototype, built once in the prototype's own space, one tree over the plain meshes (world
// space, global ids), and a top level over the instances' world boxes. Moving an instance
// rebuilds only the top level. The arrays are what ray_trace.cl reads (shared/instance.h).
#pragma once

#include "ray/bvh_build.hpp"
#include "shared/instance.h"

#include <clvis/scene.hpp>

#include <cstddef>
#include <vector>

namespace clvis::detail {

class InstanceBvh {
public:
    /// Brings the trees up to `scene`: a prototype's tree is built when the prototype is new or
    /// differs from the one it was built from; the plain meshes' tree is kept, refitted (same
    /// triangles, options.update == Refit) or rebuilt; the top level is always rebuilt.
    void update(const Scene& scene, const BvhBuildOptions& options);

    /// Top level from node 0, then the plain meshes' tree, then each prototype's.
    const std::vector<clvis_wide_node>& nodes() const { return nodes_; }
    /// The plain meshes' leaf triangles (global ids), then each prototype's (local ids).
    const std::vector<clvis_bvh_tri>& tris() const { return tris_; }
    /// The top level's leaf entries, in slot order.
    const std::vector<clvis_instance>& instances() const { return instances_; }
    /// Traversal stack entries a walk may need: both levels' paths and a top-level leaf's instances.
    int stack_entries() const { return stack_entries_; }

    std::size_t prototype_builds() const { return prototype_builds_; } ///< trees built for prototypes so far
    double top_ms() const { return top_ms_; }          ///< the last top-level build
    double bottom_ms() const { return bottom_ms_; }    ///< the last update's prototype and plain builds
    std::size_t binary_nodes() const { return binary_nodes_; } ///< all trees' binary nodes
    std::size_t leaves() const { return leaves_; }
    int depth() const { return depth_; }               ///< binary nodes on the longest path, both levels
    bool plain_refitted() const { return plain_refitted_; }

    /// The top level's leaf size: leaves are full (BvhBuildOptions::full_leaves), so the top
    /// level stores one box per four instances. A ray that meets a leaf enters all of them, each
    /// culled by its root's world boxes; leaves of 8 made the 10,000-bunny frame slower (4-wide).
    static constexpr int top_leaf_size = 4;

    struct Tree {
        std::vector<float> positions;        ///< what it was built from (object or world space)
        std::vector<std::uint32_t> indices;
        std::vector<std::uint32_t> ids;      ///< the plain meshes' global id per input triangle
        Bvh bvh;
        BvhWide wide;
        bool built = false;
    };

private:
    void update_plain(const Scene& scene, const BvhBuildOptions& options);
    void build_top(const Scene& scene, const BvhBuildOptions& options);
    void assemble();

    std::vector<Tree> prototypes_;
    Tree plain_;
    Bvh top_;
    BvhWide top_wide_;
    static constexpr std::size_t no_tree = std::size_t(-1);
    std::vector<clvis_instance> entries_; ///< per top-level input: the instance, or the plain tree
    std::vector<std::size_t> entry_tree_; ///< per entry: its prototype, or no_tree (the plain meshes)
    std::vector<clvis_wide_node> nodes_;
    std::vector<clvis_bvh_tri> tris_;
    std::vector<clvis_instance> instances_;
    int stack_entries_ = 0;
    std::size_t prototype_builds_ = 0, binary_nodes_ = 0, leaves_ = 0;
    int depth_ = 0;
    double top_ms_ = 0, bottom_ms_ = 0;
    bool plain_refitted_ = false;
};

} // namespace clvis::detail
