// Ray queries whose rays start on the surface (ambient-occlusion and shadow rays): the triangle a
// ray starts on and its neighbours fail the float test's trust check (clvis_ray_trusted), so leaves
// mix triangles of the float test and of the wide one, and rays start on vertices and edges shared
// by several triangles. Leaves of 4, 5 (one more than a group of four), 16 and 64 triangles; every
// answer of the BVH walk equals brute force bit for bit (a leaf test that skips the wide path's
// triangles fails here: checked with a four-lane leaf test that dropped them).
#include "catch.hpp"
#include "ray_query_check.hpp"

#include <clvis/clvis.hpp>
#include <clvis/procedural.hpp>
#include <clvis/ray_query.hpp>

#include <limits>
#include <random>

using namespace clvis;

namespace {

/// Rays from points of the mesh's triangles (interiors, vertices, edge midpoints, all in float32),
/// random directions, tmin 0 or a little more, tmax short, long or infinite.
std::vector<RayRecord> surface_rays(const MeshData& m, std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0, 1), s(-1, 1);
    std::uniform_int_distribution<std::size_t> tri(0, m.indices.size() / 3 - 1);
    std::vector<RayRecord> out;
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t t = tri(rng);
        const float* a = &m.positions[3 * m.indices[3 * t]];
        const float* b = &m.positions[3 * m.indices[3 * t + 1]];
        const float* c = &m.positions[3 * m.indices[3 * t + 2]];
        float wb = u(rng), wc = u(rng);
        if (wb + wc > 1) wb = 1 - wb, wc = 1 - wc;
        if (i % 6 == 4) wb = 0, wc = 0;       // a vertex
        if (i % 6 == 5) wb = 0.5f, wc = 0.5f; // an edge's midpoint
        float p[3];
        for (int k = 0; k < 3; ++k) p[k] = a[k] + (b[k] - a[k]) * wb + (c[k] - a[k]) * wc;
        RayRecord r{p[0], p[1], p[2], i % 4 == 1 ? 1e-4f : 0.0f, s(rng), s(rng), s(rng),
                    i % 3 == 0 ? std::numeric_limits<float>::infinity() : (i % 3 == 1 ? 0.3f : 2.0f)};
        out.push_back(r);
    }
    return out;
}

void check_surface(const MeshData& mesh, int leaf, unsigned seed)
{
    Scene scene;
    scene.add_mesh(mesh);
    RenderOptions o;
    o.bvh.max_leaf_size = leaf;
    test::check_scene(scene, surface_rays(mesh, 2500, seed), false, o);
}

} // namespace

TEST_CASE("rays from the surface, through leaves of 4 to 64 triangles, equal brute force", "[device][rays]")
{
    SECTION("a closed sphere")
    {
        MeshData sphere = make_uv_sphere(1200);
        for (int leaf : {4, 5, 16, 64}) check_surface(sphere, leaf, unsigned(leaf));
    }
    SECTION("a soup")
    {
        MeshData soup = make_soup(1500, 7);
        for (int leaf : {4, 5, 64}) check_surface(soup, leaf, 100u + unsigned(leaf));
    }
}
