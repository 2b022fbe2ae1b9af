// The two-level BVH of instanced scenes (bvh_instances.hpp): prototype trees cached by content,
// the plain meshes' tree, and a top level rebuilt over the instances' world boxes (each the
// prototype tree's root box through clvis_instance_box, which holds every vertex the kernels and
// the expansion compute).
#include "ray/bvh_instances.hpp"

#include "scene/instance_transform.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace clvis::detail {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void build_tree(InstanceBvh::Tree& tree, const BvhBuildOptions& options)
{
    tree.bvh = build_bvh(tree.positions.data(), tree.indices.data(), tree.indices.size() / 3, options, &tree.wide);
    tree.built = true;
}

/// Appends `wide`'s nodes with children moved by the arrays' offsets.
void append_nodes(std::vector<clvis_wide_node>& out, const BvhWide& wide, std::uint32_t node_base, std::uint32_t tri_base)
{
    for (clvis_wide_node n : wide.nodes) {
        for (int k = 0; k < bvh_width; ++k) n.child[k] += n.count[k] > 0 ? tri_base : node_base;
        out.push_back(n);
    }
}

} // namespace

void InstanceBvh::update(const Scene& scene, const BvhBuildOptions& options)
{
    auto t0 = std::chrono::steady_clock::now();
    const auto& protos = scene.prototypes();
    prototypes_.resize(protos.size());
    for (std::size_t p = 0; p < protos.size(); ++p) {
        Tree& t = prototypes_[p];
        if (t.built && t.positions == protos[p].positions && t.indices == protos[p].indices) continue;
        t.positions = protos[p].positions;
        t.indices = protos[p].indices;
        build_tree(t, options);
        ++prototype_builds_;
    }
    update_plain(scene, options);
    bottom_ms_ = ms_since(t0);
    t0 = std::chrono::steady_clock::now();
    build_top(scene, options);
    assemble();
    top_ms_ = ms_since(t0);
}

void InstanceBvh::update_plain(const Scene& scene, const BvhBuildOptions& options)
{
    std::vector<float> positions;
    std::vector<std::uint32_t> indices, ids;
    for (std::size_t item = 0; item < scene.meshes().size(); ++item) {
        const Scene::Mesh& m = scene.meshes()[item];
        if (m.prototype != Scene::no_prototype) continue;
        auto first = std::uint32_t(positions.size() / 3);
        std::size_t at = positions.size();
        positions.resize(at + m.data.positions.size());
        transform_positions(m.transform, m.data.positions.data(), m.data.vertex_count(), &positions[at]);
        for (std::size_t i = at; i < positions.size(); ++i)
            if (!std::isfinite(positions[i]))
                throw Error(Error::Kind::InvalidArgument,
                            "mesh '" + m.data.name + "': a transformed vertex overflows float32");
        for (std::uint32_t i : m.data.indices) indices.push_back(first + i);
        for (std::size_t t = 0; t < m.data.triangle_count(); ++t) ids.push_back(m.first_triangle + std::uint32_t(t));
    }
    plain_refitted_ = false;
    if (plain_.built && positions == plain_.positions && indices == plain_.indices && ids == plain_.ids) return;
    bool refit = plain_.built && indices == plain_.indices && ids == plain_.ids && !indices.empty() &&
                 options.update == BvhUpdate::Refit;
    plain_.positions = std::move(positions);
    if (refit) {
        refit_bvh(plain_.bvh, plain_.positions.data(), plain_.indices.data());
        refit_wide(plain_.wide, plain_.bvh);
        plain_refitted_ = true;
    } else {
        plain_.indices = std::move(indices);
        plain_.ids = std::move(ids);
        build_tree(plain_, options);
    }
}

void InstanceBvh::build_top(const Scene& scene, const BvhBuildOptions& options)
{
    entries_.clear();
    entry_tree_.clear();
    std::vector<float> corners; // lo and hi of each entry's world box: the top level's "triangles"
    auto add = [&](const clvis_instance& e, std::size_t tree, const float lo[3], const float hi[3]) {
        entries_.push_back(e);
        entry_tree_.push_back(tree);
        corners.insert(corners.end(), lo, lo + 3);
        corners.insert(corners.end(), hi, hi + 3);
    };
    auto root_box = [](const Bvh& b, float lo[3], float hi[3]) {
        const clvis_bvh_node& r = b.nodes[0];
        lo[0] = r.lo_x; lo[1] = r.lo_y; lo[2] = r.lo_z;
        hi[0] = r.hi_x; hi[1] = r.hi_y; hi[2] = r.hi_z;
    };
    float lo[3], hi[3];
    if (!plain_.bvh.nodes.empty()) {
        clvis_instance e{}; // walked as a flat tree: no matrix, global ids
        root_box(plain_.bvh, lo, hi);
        add(e, no_tree, lo, hi);
    }
    for (std::size_t item = 0; item < scene.meshes().size(); ++item) {
        const Scene::Mesh& m = scene.meshes()[item];
        if (m.prototype == Scene::no_prototype || prototypes_[m.prototype].bvh.nodes.empty()) continue;
        clvis_instance e{};
        auto matrix = instance_matrix(m.transform);
        std::copy(matrix.begin(), matrix.end(), e.m);
        e.first_id = m.first_triangle;
        float olo[3], ohi[3];
        root_box(prototypes_[m.prototype].bvh, olo, ohi);
        clvis_instance_box(e.m, olo, ohi, lo, hi);
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]))
                throw Error(Error::Kind::InvalidArgument, "mesh '" + scene.data_of(item).name +
                                                              "': the instance's world box overflows float32");
        add(e, m.prototype, lo, hi);
    }
    std::vector<std::uint32_t> indices;
    for (std::uint32_t e = 0; e < entries_.size(); ++e) indices.insert(indices.end(), {2 * e, 2 * e + 1, 2 * e});
    BvhBuildOptions o = options;
    o.max_leaf_size = top_leaf_size;
    o.full_leaves = true; // leaves of four entries: a quarter of the top level's boxes
    top_ = build_bvh(corners.data(), indices.data(), entries_.size(), o);
    top_wide_ = collapse_wide(top_, true);
}

void InstanceBvh::assemble()
{
    nodes_ = top_wide_.nodes;
    tris_.clear();
    auto place = [&](const Tree& t, bool global_ids) {
        auto root = std::uint32_t(nodes_.size());
        auto tri_base = std::uint32_t(tris_.size());
        append_nodes(nodes_, t.wide, root, tri_base);
        for (clvis_bvh_tri tri : t.bvh.tris) {
            if (global_ids) tri.id = plain_.ids[tri.id];
            tris_.push_back(tri);
        }
        return root;
    };
    std::uint32_t plain_root = place(plain_, true);
    std::vector<std::uint32_t> roots;
    binary_nodes_ = top_.nodes.size() + plain_.bvh.nodes.size();
    leaves_ = top_.leaves + plain_.bvh.leaves;
    int bottom_depth = plain_.bvh.depth, bottom_wide = plain_.wide.depth;
    for (const Tree& t : prototypes_) {
        roots.push_back(place(t, false));
        binary_nodes_ += t.bvh.nodes.size();
        leaves_ += t.bvh.leaves;
        bottom_depth = std::max(bottom_depth, t.bvh.depth);
        bottom_wide = std::max(bottom_wide, t.wide.depth);
    }
    instances_.clear();
    for (const clvis_bvh_tri& slot : top_.tris) {
        clvis_instance e = entries_[slot.id];
        std::size_t tree = entry_tree_[slot.id];
        e.tree = tree == no_tree ? plain_root | CLVIS_INSTANCE_PLAIN : roots[tree];
        instances_.push_back(e);
    }
    depth_ = top_.depth + bottom_depth;
    stack_entries_ = (bvh_width - 1) * top_wide_.depth + (top_leaf_size - 1) + (bvh_width - 1) * bottom_wide + 1;
}

} // namespace clvis::detail
