// Ray queries through leaves of 1 to 8 triangles (max_leaf_size 1, 4 and 8), with rays through
// shared vertices and edges (the scalar test's exact edge recompute) and a triangle near 1e30
// sharing leaves with small ones (its re-scaled projection): every answer of the BVH walk equals
// brute force bit for bit.
#include "catch.hpp"
#include "ray_query_check.hpp"

#include <clvis/clvis.hpp>
#include <clvis/ray_query.hpp>

#include <limits>
#include <random>

using namespace clvis;

namespace {

const float inf = std::numeric_limits<float>::infinity();

/// n triangles fanned around the origin in the plane z = 0 (integer rim vertices, so rays at
/// integer x, y pass exactly through vertices and edges), and `tilted` more at z = 1 + x / 8.
MeshData fan(int n, int tilted)
{
    MeshData m;
    m.name = "fan";
    const int rim[8][2] = {{4, 0}, {3, 3}, {0, 4}, {-3, 3}, {-4, 0}, {-3, -3}, {0, -4}, {3, -3}};
    for (int i = 0; i < n + tilted; ++i) {
        float z = i < n ? 0.0f : 1.0f;
        auto lift = [&](int x) { return i < n ? z : z + float(x) / 8; };
        const int* a = rim[i % 8];
        const int* b = rim[(i + 1) % 8];
        std::uint32_t v = std::uint32_t(m.positions.size() / 3);
        m.positions.insert(m.positions.end(), {0.0f, 0.0f, lift(0), float(a[0]), float(a[1]), lift(a[0]), float(b[0]),
                                               float(b[1]), lift(b[0])});
        m.indices.insert(m.indices.end(), {v, v + 1, v + 2});
    }
    return m;
}

/// One triangle spanning +-1e30 at z = 5 (its edge functions overflow: the re-scaled projection)
/// beside small ones at z = 1 and 2 that it shares leaves with.
MeshData huge_and_small()
{
    MeshData m;
    m.name = "huge";
    m.positions = {-1e30f, -1e30f, 5, 1e30f, -1e30f, 5, 0, 1e30f, 5,   // huge
                   0, 0, 1, 2, 0, 1, 0, 2, 1,                            // small, z = 1
                   -1, -1, 2, 1, -1, 2, 0, 1, 2};                        // small, z = 2
    m.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    return m;
}

/// Rays from above and below toward integer and half-integer points of the plane z = 0 (vertices,
/// edges, interiors), axis-parallel ones, random ones and ones from far away (1e29).
std::vector<RayRecord> leaf_rays(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> grid(-10, 10);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<RayRecord> out;
    for (std::size_t i = 0; i < n; ++i) {
        float tx = float(grid(rng)) / 2, ty = float(grid(rng)) / 2;
        float ox = u(rng) * 6, oy = u(rng) * 6, oz = (i % 2 ? 1 : -1) * (1 + 5 * (u(rng) + 1));
        if (i % 5 == 3) ox = tx, oy = ty;                                // parallel to z
        if (i % 5 == 4) ox *= 1e29f, oy *= 1e29f, oz *= 1e29f;           // from far away
        RayRecord r{ox, oy, oz, 0, tx - ox, ty - oy, -oz, inf};
        if (i % 7 == 6) r.dx = u(rng), r.dy = u(rng), r.dz = u(rng);   // random
        if (i % 11 == 10) r.tmax = 0.5f + float(i % 3) * 0.5f;         // ends before or at a hit
        out.push_back(r);
    }
    return out;
}

/// Rays up through huge_and_small's triangles, z their largest component (so that the huge
/// triangle's re-scaled test is exact enough for its box: a ray along x would lose its z), some
/// ending between the small triangles and the huge one.
std::vector<RayRecord> upward_rays(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<RayRecord> out;
    for (std::size_t i = 0; i < n; ++i) {
        RayRecord r{u(rng) * 3, u(rng) * 3, -2 + u(rng), 0, u(rng) * 0.5f, u(rng) * 0.5f, 1, inf};
        if (i % 3 == 1) r.tmax = 4 + u(rng);
        out.push_back(r);
    }
    return out;
}

/// The BVH walk (leaves up to `leaf` triangles) against brute force on closest, any and count.
void check_leaves(const MeshData& mesh, const std::vector<RayRecord>& rays, int leaf)
{
    Scene scene;
    scene.add_mesh(mesh);
    RenderOptions o;
    o.bvh.max_leaf_size = leaf;
    test::check_scene(scene, rays, false, o);
}

} // namespace

TEST_CASE("ray queries through leaves of 1 to 8 triangles equal brute force", "[device][rays]")
{
    SECTION("leaves of 1 to 8 triangles, rays through their vertices and edges")
    {
        for (int n = 1; n <= 8; ++n)
            for (int leaf : {4, 8}) check_leaves(fan(n, n % 3), leaf_rays(1500, unsigned(n)), leaf);
    }
    SECTION("a triangle re-scaled near 1e30 in leaves with small ones")
    {
        for (int leaf : {1, 4}) check_leaves(huge_and_small(), upward_rays(3000, 9), leaf);
    }
}
