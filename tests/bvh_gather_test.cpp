// The flat BVH built without its leaf triangles (BvhBuildOptions::gather false, issue 37's memory):
// the same tree, wide nodes and stats as the build that gathers, the leaf slots' ids those of
// its triangles, and gather_bvh_tris (what ray_pipeline.cpp writes to the device a block at a
// time) the same bits as Bvh::tris, whole or in blocks.
#include "catch.hpp"

#include "ray/bvh_build.hpp"
#include "test_meshes.hpp"

#include <clvis/procedural.hpp>

#include <vector>

using namespace clvis;
using namespace clvis::detail;
using clvis::test::same_bytes;

TEST_CASE("a BVH built without gathering gives the gathered one's tree and triangles", "[bvh]")
{
    for (const MeshData& m : {make_uv_sphere(20000), make_soup(30000, 7), make_grid(5000, 3), make_uv_sphere(8)}) {
        for (int leaf : {1, 4}) {
            INFO(m.name << " " << m.triangle_count() << " triangles, leaf size " << leaf);
            BvhBuildOptions with;
            with.max_leaf_size = leaf;
            BvhBuildOptions without = with;
            without.gather = false;
            BvhWide wide_with, wide_without;
            Bvh a = build_bvh(m.positions.data(), m.indices.data(), m.triangle_count(), with, &wide_with);
            Bvh b = build_bvh(m.positions.data(), m.indices.data(), m.triangle_count(), without, &wide_without);
            CHECK(a.ids.empty());
            CHECK(b.tris.empty());
            REQUIRE(b.ids.size() == a.tris.size());
            CHECK(same_bytes(a.nodes, b.nodes));
            CHECK(same_bytes(wide_with.nodes, wide_without.nodes));
            CHECK(wide_with.source == wide_without.source);
            CHECK(wide_with.depth == wide_without.depth);
            CHECK(a.leaves == b.leaves);
            CHECK(a.depth == b.depth);
            CHECK(a.sah_cost == b.sah_cost);
            bool ids_match = true;
            for (std::size_t i = 0; i < a.tris.size(); ++i) ids_match &= a.tris[i].id == b.ids[i];
            CHECK(ids_match);

            std::vector<clvis_bvh_tri> whole(b.ids.size());
            gather_bvh_tris(m.positions.data(), m.indices.data(), b.ids.data(), b.ids.size(), whole.data());
            CHECK(same_bytes(whole, a.tris));
            // In blocks of an odd size, on one thread: the same bits.
            std::vector<clvis_bvh_tri> blocks(b.ids.size());
            for (std::size_t at = 0; at < b.ids.size(); at += 777) {
                std::size_t n = std::min<std::size_t>(777, b.ids.size() - at);
                gather_bvh_tris(m.positions.data(), m.indices.data(), b.ids.data() + at, n, blocks.data() + at, 1);
            }
            CHECK(same_bytes(blocks, a.tris));
        }
    }
}

TEST_CASE("a BVH of no triangles built without gathering is empty", "[bvh]")
{
    BvhBuildOptions o;
    o.gather = false;
    BvhWide wide;
    Bvh b = build_bvh(nullptr, nullptr, 0, o, &wide);
    CHECK(b.nodes.empty());
    CHECK(b.ids.empty());
    CHECK(b.tris.empty());
    CHECK(wide.nodes.empty());
}
