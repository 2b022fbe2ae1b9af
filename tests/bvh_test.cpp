// The BVH build (host/ray/bvh_build.cpp) on its own: every triangle in exactly one leaf, boxes that
// hold what is below them, SAH no worse than a median split, the same bits whatever the threads,
// degenerate scenes that build quickly, refits that keep the invariants.
#include "catch.hpp"

#include "ray/bvh_build.hpp"

#include <clvis/clvis.hpp>

#include <chrono>
#include <cmath>
#include <cstring>
#include <random>

using namespace clvis;
using namespace clvis::detail;

namespace {

struct Mesh {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::size_t triangles() const { return indices.size() / 3; }
};

Mesh from(const MeshData& m) { return {m.positions, m.indices}; }

/// Random small triangles in a box, some of them slivers.
Mesh soup(std::size_t n, std::uint32_t seed, float extent = 1.0f)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-extent, extent), small(-0.02f * extent, 0.02f * extent);
    Mesh m;
    for (std::size_t i = 0; i < n; ++i) {
        float cx = u(rng), cy = u(rng), cz = u(rng);
        for (int v = 0; v < 3; ++v) {
            m.positions.insert(m.positions.end(), {cx + small(rng), cy + small(rng), cz + small(rng)});
            m.indices.push_back(std::uint32_t(i * 3 + v));
        }
    }
    return m;
}

/// A flat grid in z = 0: (n x n) quads, two triangles each.
Mesh flat_grid(int n)
{
    Mesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.positions.insert(m.positions.end(), {float(i), float(j), 0.0f});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n) + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    return m;
}

Bvh build(const Mesh& m, BvhBuildOptions o = {}) { return build_bvh(m.positions.data(), m.indices.data(), m.triangles(), o); }

bool box_holds(const clvis_bvh_node& outer, const clvis_bvh_node& inner)
{
    return outer.lo_x <= inner.lo_x && outer.lo_y <= inner.lo_y && outer.lo_z <= inner.lo_z &&
           outer.hi_x >= inner.hi_x && outer.hi_y >= inner.hi_y && outer.hi_z >= inner.hi_z;
}

bool box_holds(const clvis_bvh_node& n, float x, float y, float z)
{
    return n.lo_x <= x && x <= n.hi_x && n.lo_y <= y && y <= n.hi_y && n.lo_z <= z && z <= n.hi_z;
}

/// Walks the tree from the root and checks every invariant the kernels rely on; returns the
/// number of failures (0 when the tree is sound).
std::size_t check_invariants(const Bvh& bvh, const Mesh& m, int max_leaf)
{
    std::size_t failures = 0;
    std::size_t n = m.triangles();
    if (n == 0) return bvh.nodes.empty() && bvh.tris.empty() ? 0 : 1;
    if (bvh.tris.size() != n) return 1;
    std::vector<int> seen_slot(n, 0), seen_id(n, 0);
    std::size_t leaves = 0;
    int deepest = 0;
    std::vector<std::pair<std::uint32_t, int>> pending{{0, 1}};
    std::vector<int> visited(bvh.nodes.size(), 0);
    while (!pending.empty()) {
        auto [i, depth] = pending.back();
        pending.pop_back();
        if (i >= bvh.nodes.size() || visited[i]++) return failures + 1; // out of range or shared
        const clvis_bvh_node& node = bvh.nodes[i];
        deepest = std::max(deepest, depth);
        if (node.count > 0) {
            ++leaves;
            failures += node.count > std::uint32_t(max_leaf);
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                if (k >= n) return failures + 1;
                ++seen_slot[k];
                const clvis_bvh_tri& t = bvh.tris[k];
                if (t.id >= n) return failures + 1;
                ++seen_id[t.id];
                for (int v = 0; v < 3; ++v) {
                    const float* p = &m.positions[std::size_t(m.indices[std::size_t(t.id) * 3 + v]) * 3];
                    const float* q = v == 0 ? &t.v0_x : v == 1 ? &t.v1_x : &t.v2_x;
                    failures += std::memcmp(p, q, 12) != 0; // the scene's own vertices, in order
                    failures += !box_holds(node, p[0], p[1], p[2]);
                }
            }
        } else {
            std::uint32_t a = i + 1, b = node.first;
            if (a >= bvh.nodes.size() || b >= bvh.nodes.size() || b <= a) return failures + 1;
            failures += !box_holds(node, bvh.nodes[a]) + !box_holds(node, bvh.nodes[b]);
            pending.push_back({a, depth + 1});
            pending.push_back({b, depth + 1});
        }
    }
    for (std::size_t k = 0; k < n; ++k) failures += (seen_slot[k] != 1) + (seen_id[k] != 1);
    for (int v : visited) failures += v != 1; // every node reachable
    failures += leaves != bvh.leaves;
    failures += deepest != bvh.depth;
    return failures;
}

/// The wide form holds every leaf of the binary tree exactly once, with its box, each interior
/// child's box holds its own children, and unused slots have empty boxes; returns failures.
std::size_t check_wide(const BvhWide& wide, const Bvh& bvh)
{
    if (bvh.nodes.empty()) return wide.nodes.empty() ? 0 : 1;
    std::size_t failures = 0;
    std::vector<int> slot_seen(bvh.tris.size(), 0), node_seen(wide.nodes.size(), 0);
    std::size_t leaves = 0;
    int deepest = 0;
    std::vector<std::pair<std::uint32_t, int>> pending{{0, 1}};
    while (!pending.empty()) {
        auto [i, depth] = pending.back();
        pending.pop_back();
        if (i >= wide.nodes.size() || node_seen[i]++) return failures + 1;
        deepest = std::max(deepest, depth);
        const clvis_wide_node& w = wide.nodes[i];
        int used = 0;
        for (int k = 0; k < bvh_width; ++k) {
            bool empty = !(w.lo_x[k] <= w.hi_x[k]);
            if (empty) {
                failures += w.lo_y[k] <= w.hi_y[k] || w.lo_z[k] <= w.hi_z[k];
                continue;
            }
            ++used;
            if (w.count[k] > 0) {
                ++leaves;
                for (std::uint32_t s = w.child[k]; s < w.child[k] + w.count[k]; ++s) {
                    if (s >= bvh.tris.size()) return failures + 1;
                    ++slot_seen[s];
                    const clvis_bvh_tri& t = bvh.tris[s];
                    for (const float* v : {&t.v0_x, &t.v1_x, &t.v2_x})
                        failures += !(w.lo_x[k] <= v[0] && v[0] <= w.hi_x[k] && w.lo_y[k] <= v[1] && v[1] <= w.hi_y[k] &&
                                      w.lo_z[k] <= v[2] && v[2] <= w.hi_z[k]);
                }
            } else {
                if (w.child[k] <= i || w.child[k] >= wide.nodes.size()) return failures + 1;
                const clvis_wide_node& c = wide.nodes[w.child[k]];
                for (int j = 0; j < bvh_width; ++j) {
                    if (!(c.lo_x[j] <= c.hi_x[j])) continue;
                    failures += !(w.lo_x[k] <= c.lo_x[j] && c.hi_x[j] <= w.hi_x[k] && w.lo_y[k] <= c.lo_y[j] &&
                                  c.hi_y[j] <= w.hi_y[k] && w.lo_z[k] <= c.lo_z[j] && c.hi_z[j] <= w.hi_z[k]);
                }
                pending.push_back({w.child[k], depth + 1});
            }
        }
        failures += used < (bvh.nodes.size() == 1 ? 1 : 2);
    }
    for (int v : slot_seen) failures += v != 1;
    for (int v : node_seen) failures += v != 1;
    failures += leaves != bvh.leaves;
    failures += deepest != wide.depth;
    return failures;
}

} // namespace

TEST_CASE("the wide form keeps every leaf once and boxes that hold what is below them", "[bvh]")
{
    std::vector<std::pair<std::string, Mesh>> meshes;
    meshes.emplace_back("sphere", from(make_uv_sphere(5000)));
    meshes.emplace_back("soup", soup(3000, 7));
    meshes.emplace_back("flat grid", flat_grid(30));
    Mesh one;
    one.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    one.indices = {0, 1, 2};
    meshes.emplace_back("one triangle", one);
    meshes.emplace_back("none", Mesh{});
    for (auto& [name, mesh] : meshes) {
        for (int leaf : {1, 4}) {
            INFO(name << ", leaf size " << leaf);
            BvhBuildOptions o;
            o.max_leaf_size = leaf;
            Bvh bvh = build(mesh, o);
            BvhWide wide = collapse_wide(bvh);
            CHECK(check_wide(wide, bvh) == 0);
            CHECK(wide.depth <= bvh.depth);
            // every node but a lone root holds at least two children: at most leaves - 1 nodes
            CHECK(wide.nodes.size() <= std::max<std::size_t>(1, bvh.leaves - 1));
            // the greedy collapse fills a node unless all its children are leaves
            std::size_t partial = 0;
            for (const clvis_wide_node& w : wide.nodes) {
                int used = 0, interior = 0;
                for (int k = 0; k < bvh_width; ++k) {
                    used += w.lo_x[k] <= w.hi_x[k];
                    interior += w.lo_x[k] <= w.hi_x[k] && w.count[k] == 0;
                }
                partial += used < bvh_width && interior > 0;
            }
            CHECK(partial == 0);
        }
    }
}

TEST_CASE("every triangle lies in exactly one leaf and every box holds what is below it", "[bvh]")
{
    std::vector<std::pair<std::string, Mesh>> meshes;
    meshes.emplace_back("sphere", from(make_uv_sphere(5000)));
    meshes.emplace_back("terrain", from(make_grid(4000, 3)));
    meshes.emplace_back("soup", soup(3000, 7));
    meshes.emplace_back("flat grid", flat_grid(40));
    meshes.emplace_back("spot", from(load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj")));
    for (auto& [name, mesh] : meshes) {
        for (int leaf : {1, 4, 9}) {
            for (int bins : {2, 16, 64}) {
                INFO(name << ", leaf size " << leaf << ", " << bins << " bins");
                BvhBuildOptions o;
                o.max_leaf_size = leaf;
                o.sah_bins = bins;
                Bvh bvh = build(mesh, o);
                CHECK(check_invariants(bvh, mesh, leaf) == 0);
                CHECK(bvh.nodes.size() == 2 * bvh.leaves - 1);
            }
        }
    }
}

TEST_CASE("the SAH tree costs no more than a median split tree", "[bvh]")
{
    std::vector<std::pair<std::string, Mesh>> meshes;
    meshes.emplace_back("sphere", from(make_uv_sphere(20000)));
    meshes.emplace_back("terrain", from(make_grid(20000, 5)));
    meshes.emplace_back("soup", soup(20000, 11));
    meshes.emplace_back("spot", from(load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj")));
    for (auto& [name, mesh] : meshes) {
        BvhBuildOptions sah, median;
        median.split = BvhSplit::Median;
        double cost_sah = build(mesh, sah).sah_cost, cost_median = build(mesh, median).sah_cost;
        INFO(name << ": SAH " << cost_sah << ", median " << cost_median);
        CHECK(cost_sah <= cost_median);
        CHECK(cost_sah > 0);
    }
}

TEST_CASE("the same scene builds the same bits whatever the threads", "[bvh]")
{
    // Large enough that the top of the tree is split into parallel tasks and binned in parts.
    Mesh mesh = soup(300000, 21);
    BvhBuildOptions o;
    o.threads = 1;
    Bvh one = build(mesh, o);
    for (unsigned threads : {2u, 3u, 8u}) {
        o.threads = threads;
        Bvh many = build(mesh, o);
        INFO(threads << " threads");
        REQUIRE(many.nodes.size() == one.nodes.size());
        CHECK(std::memcmp(many.nodes.data(), one.nodes.data(), one.nodes.size() * sizeof(clvis_bvh_node)) == 0);
        CHECK(std::memcmp(many.tris.data(), one.tris.data(), one.tris.size() * sizeof(clvis_bvh_tri)) == 0);
    }
    CHECK(check_invariants(one, mesh, o.max_leaf_size) == 0);
}

TEST_CASE("degenerate scenes build correctly and quickly", "[bvh]")
{
    auto timed = [](const Mesh& m, const char* what) {
        auto t0 = std::chrono::steady_clock::now();
        Bvh bvh = build(m);
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        INFO(what << ": " << s << " s, depth " << bvh.depth);
        CHECK(s < 5.0);
        CHECK(check_invariants(bvh, m, 4) == 0);
        // Median splits take over where the SAH cannot split or the tree grows too deep.
        CHECK(bvh.depth <= bvh_max_sah_depth + 1 + int(std::ceil(std::log2(double(m.triangles()) + 1))));
        return bvh;
    };
    SECTION("every triangle in one point")
    {
        Mesh m;
        m.positions = {0.25f, -1.5f, 3.0f};
        for (int i = 0; i < 200000 * 3; ++i) m.indices.push_back(0);
        Bvh bvh = timed(m, "one point");
        CHECK(bvh.nodes[0].lo_x == 0.25f);
        CHECK(bvh.nodes[0].hi_x == 0.25f);
    }
    SECTION("zero-area triangles along a line")
    {
        Mesh m;
        for (int i = 0; i < 100000; ++i) {
            float x = float(i % 977);
            m.positions.insert(m.positions.end(), {x, 0, 0, x + 1, 0, 0, x + 2, 0, 0});
            m.indices.insert(m.indices.end(), {std::uint32_t(3 * i), std::uint32_t(3 * i + 1), std::uint32_t(3 * i + 2)});
        }
        timed(m, "collinear");
    }
    SECTION("huge finite coordinates")
    {
        Mesh m = soup(50000, 3, 1.0e38f);
        for (float& p : m.positions) p *= 3.0f; // up to about 3.06e38, near FLT_MAX
        Bvh bvh = timed(m, "huge");
        CHECK(std::isfinite(bvh.nodes[0].lo_x));
        CHECK(std::isfinite(bvh.nodes[0].hi_z));
        CHECK(std::isfinite(bvh.sah_cost));
    }
    SECTION("exponentially spaced triangles, where the SAH peels one at a time")
    {
        Mesh m;
        for (int i = 0; i < 3000; ++i) {
            float x = std::ldexp(1.0f, i % 200 - 100);
            m.positions.insert(m.positions.end(), {x, 0, 0, x, 1, 0, x, 0, 1});
            m.indices.insert(m.indices.end(), {std::uint32_t(3 * i), std::uint32_t(3 * i + 1), std::uint32_t(3 * i + 2)});
        }
        timed(m, "exponential");
    }
    SECTION("one triangle, and none")
    {
        Mesh one;
        one.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        one.indices = {0, 1, 2};
        Bvh bvh = timed(one, "one");
        CHECK(bvh.nodes.size() == 1);
        CHECK(bvh.leaves == 1);
        Bvh none = build(Mesh{});
        CHECK(none.nodes.empty());
        CHECK(none.tris.empty());
        CHECK(none.depth == 0);
    }
}

TEST_CASE("a refit follows moved vertices with the same topology", "[bvh]")
{
    Mesh mesh = from(make_uv_sphere(3000));
    Bvh bvh = build(mesh);
    BvhWide wide = collapse_wide(bvh);
    Bvh before = bvh;
    BvhWide wide_before = wide;
    for (std::size_t i = 0; i < mesh.positions.size(); i += 3) {
        mesh.positions[i] = mesh.positions[i] * 2.0f + 3.0f;                  // stretch and slide in x
        mesh.positions[i + 2] = mesh.positions[i + 2] * std::fabs(mesh.positions[i + 1]); // pinch in z
    }
    refit_bvh(bvh, mesh.positions.data(), mesh.indices.data());
    refit_wide(wide, bvh);
    CHECK(check_invariants(bvh, mesh, 4) == 0);
    CHECK(check_wide(wide, bvh) == 0);
    REQUIRE(wide.nodes.size() == wide_before.nodes.size());
    for (std::size_t i = 0; i < wide.nodes.size(); ++i)
        for (int k = 0; k < bvh_width; ++k) {
            CHECK(wide.nodes[i].child[k] == wide_before.nodes[i].child[k]);
            CHECK(wide.nodes[i].count[k] == wide_before.nodes[i].count[k]);
        }
    REQUIRE(bvh.nodes.size() == before.nodes.size());
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
        CHECK(bvh.nodes[i].count == before.nodes[i].count);
        CHECK(bvh.nodes[i].first == before.nodes[i].first);
    }
    CHECK(bvh.nodes[0].lo_x == Approx(1.0f));
    CHECK(bvh.nodes[0].hi_x == Approx(5.0f));
}

TEST_CASE("full leaves pack bvh_width^2 leaves of 4 under bvh_width + 1 full wide nodes", "[bvh]")
{
    const std::uint32_t leaves = std::uint32_t(bvh_width * bvh_width), triangles = 4 * leaves;
    Mesh same; // every centroid in one point: the split still goes by whole leaves
    for (std::uint32_t i = 0; i < triangles; ++i) {
        same.positions.insert(same.positions.end(), {0, 0, 0, 1, 0, 0, 0, 1, 0});
        same.indices.insert(same.indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
    }
    std::vector<std::pair<std::string, Mesh>> meshes;
    meshes.emplace_back("soup", soup(triangles, 5));
    meshes.emplace_back("one point", same);
    for (auto& [name, mesh] : meshes) {
        INFO(name);
        BvhBuildOptions o;
        o.max_leaf_size = 4;
        o.full_leaves = true;
        Bvh bvh = build(mesh, o);
        CHECK(check_invariants(bvh, mesh, 4) == 0);
        CHECK(bvh.leaves == leaves);
        BvhWide wide = collapse_wide(bvh, true);
        CHECK(check_wide(wide, bvh) == 0);
        CHECK(wide.nodes.size() == std::size_t(bvh_width) + 1);
    }
    Mesh big = soup(3000, 9);
    BvhBuildOptions o;
    o.max_leaf_size = 4;
    o.full_leaves = true;
    Bvh bvh = build(big, o);
    CHECK(check_invariants(bvh, big, 4) == 0);
    CHECK(bvh.leaves < 3000 / 4 + 3000 / 100); // nearly all leaves full
    BvhWide wide = collapse_wide(bvh, true), plain = collapse_wide(bvh);
    CHECK(check_wide(wide, bvh) == 0);
    INFO(wide.nodes.size() << " wide nodes aligned, " << plain.nodes.size() << " not, " << bvh.leaves << " leaves");
    CHECK(wide.nodes.size() < plain.nodes.size());
    CHECK(wide.nodes.size() < bvh.leaves * 2 / 5); // 1 / (bvh_width - 1) when every node is full
}
