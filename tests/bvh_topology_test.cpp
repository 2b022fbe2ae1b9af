// What the ray path keeps of its flat BVH between refits (issue 37's memory): a leaf count a
// binary node (bvh_leaf_counts), from which bvh_from_leaf_counts gives every node's first and
// count again and wide_source_of the wide nodes' source slots, as the build made them; and a
// Renderer's refit from that, with the leaf slots and wide nodes read back from the device,
// leaves on the device the bits a refit of the whole host tree gives.
#include "catch.hpp"

#include "ray/bvh_build.hpp"
#include "test_meshes.hpp"
#include "render/renderer_impl.hpp"

#include <clvis/clvis.hpp>
#include <clvis/procedural.hpp>

#include <vector>

using namespace clvis;
using namespace clvis::detail;
using clvis::test::same_bytes;

namespace {

/// Every node's first and count equal (boxes not compared).
bool same_shape(const std::vector<clvis_bvh_node>& a, const std::vector<clvis_bvh_node>& b)
{
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].first != b[i].first || a[i].count != b[i].count) return false;
    return true;
}

template <class T>
std::vector<T> read_back(Renderer::Impl& m, const cl::Buffer& buffer, std::size_t count)
{
    std::vector<T> out(count);
    if (count) m.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(T), out.data());
    return out;
}

} // namespace

TEST_CASE("a BVH's leaf counts give its binary nodes' first and count and its wide source again", "[bvh]")
{
    for (const MeshData& m : {make_uv_sphere(20000), make_soup(30000, 7), make_grid(5000, 3), make_uv_sphere(8)}) {
        for (int leaf : {1, 4, 64}) {
            for (bool full : {false, true}) {
                INFO(m.name << " " << m.triangle_count() << " triangles, leaf size " << leaf << ", full leaves " << full);
                BvhBuildOptions o;
                o.max_leaf_size = leaf;
                o.full_leaves = full;
                BvhWide wide;
                Bvh bvh = build_bvh(m.positions.data(), m.indices.data(), m.triangle_count(), o, &wide);
                std::vector<std::uint8_t> counts = bvh_leaf_counts(bvh.nodes);
                REQUIRE(counts.size() == bvh.nodes.size());
                std::vector<clvis_bvh_node> shape = bvh_from_leaf_counts(counts);
                CHECK(same_shape(shape, bvh.nodes));
                CHECK(wide_source_of(shape, wide.nodes) == wide.source);
            }
        }
    }
}

TEST_CASE("a BVH of one leaf or none keeps its shape", "[bvh]")
{
    MeshData m = make_uv_sphere(8);
    BvhBuildOptions o;
    o.max_leaf_size = 64;
    o.full_leaves = true; // no split below the leaf size: every triangle in the root
    BvhWide wide;
    Bvh bvh = build_bvh(m.positions.data(), m.indices.data(), m.triangle_count(), o, &wide);
    REQUIRE(bvh.nodes.size() == 1);
    std::vector<clvis_bvh_node> shape = bvh_from_leaf_counts(bvh_leaf_counts(bvh.nodes));
    CHECK(same_shape(shape, bvh.nodes));
    CHECK(wide_source_of(shape, wide.nodes) == wide.source);
    CHECK(bvh_from_leaf_counts({}).empty());
    CHECK(wide_source_of({}, {}).empty());
}

TEST_CASE("leaf counts or wide nodes that are no tree are refused", "[bvh]")
{
    CHECK_THROWS_AS(bvh_from_leaf_counts({0, 2}), Error);       // an interior node without a right child
    CHECK_THROWS_AS(bvh_from_leaf_counts({0, 2, 1, 3}), Error); // a node after a complete tree
    CHECK_THROWS_AS(bvh_from_leaf_counts({0, 0, 1, 1}), Error); // the root's right child missing

    MeshData m = make_uv_sphere(2000);
    BvhWide wide;
    Bvh bvh = build_bvh(m.positions.data(), m.indices.data(), m.triangle_count(), BvhBuildOptions(), &wide);
    REQUIRE(wide.nodes.size() > 1);
    std::vector<clvis_wide_node> swapped = wide.nodes;
    // Two used slots of the root exchanged: their ranges no longer follow the binary tree's order.
    std::swap(swapped[0].child[0], swapped[0].child[1]);
    std::swap(swapped[0].count[0], swapped[0].count[1]);
    CHECK_THROWS_AS(wide_source_of(bvh.nodes, swapped), Error);
    std::vector<clvis_bvh_node> other = bvh.nodes;
    other.pop_back();
    CHECK_THROWS_AS(wide_source_of(other, wide.nodes), Error);
}

TEST_CASE("a Renderer's refits from the kept leaf counts leave the whole host tree's refit on the device",
          "[device][ray]")
{
    Device d = Device::open();
    Scene s;
    s.add_mesh(make_uv_sphere(3000));
    s.add_mesh(make_grid(1000, 2));
    RenderOptions o;
    o.bvh.update = BvhUpdate::Refit;
    Renderer r(d, s, o);
    Camera cam = Camera::perspective({0.5, 2, 4}, {0, 0, 0}, {0, 1, 0}, 50, 0.1, 50);
    r.render(cam, 8, 8, Path::Ray);

    // The host tree as the pipeline builds it, refitted on the host after each move.
    BvhBuildOptions bo;
    static_cast<BvhOptions&>(bo) = o.bvh;
    BvhWide wide;
    Bvh bvh = build_bvh(s.world_positions().data(), s.world_indices().data(), s.triangle_count(), bo, &wide);
    Renderer::Impl& m = RendererAccess::of(r, "the test");
    REQUIRE(m.ray);
    REQUIRE(m.ray->node_count() == wide.nodes.size());
    CHECK(same_bytes(read_back<clvis_wide_node>(m, m.ray->nodes(), wide.nodes.size()), wide.nodes));
    CHECK(same_bytes(read_back<clvis_bvh_tri>(m, m.ray->triangles(), bvh.tris.size()), bvh.tris));

    for (int step = 1; step <= 2; ++step) {
        INFO("refit " << step);
        std::vector<float> moved = s.meshes()[0].data.positions;
        for (std::size_t i = 0; i < moved.size(); ++i) moved[i] *= 1.0f + 0.01f * float(step) * float(i % 7);
        s.set_positions(0, moved.data(), moved.size() / 3);
        r.update(s);
        CHECK(r.bvh_stats().refitted);
        refit_bvh(bvh, s.world_positions().data(), s.world_indices().data());
        refit_wide(wide, bvh);
        CHECK(r.bvh_stats().nodes == bvh.nodes.size());
        CHECK(r.bvh_stats().sah_cost == bvh.sah_cost);
        CHECK(same_bytes(read_back<clvis_wide_node>(m, m.ray->nodes(), wide.nodes.size()), wide.nodes));
        CHECK(same_bytes(read_back<clvis_bvh_tri>(m, m.ray->triangles(), bvh.tris.size()), bvh.tris));
    }
}
