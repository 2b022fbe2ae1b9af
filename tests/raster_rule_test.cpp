// The ray paths' raster-rule coverage (RenderOptions::coverage): ids and depths bit-identical to
// the raster path's on unseen random soups under random perspective, orthographic and intrinsics
// cameras (near clipping, guard band, odd sizes, culling), on a grid whose samples lie on shared
// edges, and the default watertight test shown to differ there (so the equality is not vacuous).
// The agreement suite (agree_harness.cpp) checks the same equality on every agreement case.
#include "catch.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>

#include <cstdio>
#include <random>
#include <set>
#include <vector>
#include <string>

using namespace clvis;

namespace {

/// Deterministic on every standard library: mt19937_64's bits turned into doubles by hand.
struct Rng {
    std::mt19937_64 bits;
    explicit Rng(std::uint64_t seed) : bits(seed) {}
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(bits() >> 11) * 0x1p-53; }
    Vec3 point(double r) { return {uniform(-r, r), uniform(-r, r), uniform(-r, r)}; }
};

/// A soup of `n` triangles in a cube of half side 1: most small, some long slivers, a few huge
/// ones reaching far outside the view (guard band) and behind the eye (near).
MeshData random_soup(Rng& rng, int n)
{
    MeshData m;
    m.name = "soup";
    for (int t = 0; t < n; ++t) {
        double size = t % 151 == 0 ? 40 : (t % 5 == 0 ? 0.6 : 0.15);
        Vec3 c = rng.point(1);
        Vec3 a = c + rng.point(size), b = c + rng.point(size), d = c + rng.point(t % 7 == 0 ? 0.002 : size);
        for (Vec3 v : {a, b, d}) m.positions.insert(m.positions.end(), {float(v.x), float(v.y), float(v.z)});
        for (int k = 0; k < 3; ++k) m.indices.push_back(std::uint32_t(3 * t + k));
    }
    return m;
}

Scene soup_scene(Rng& rng)
{
    Scene s;
    s.add_mesh(random_soup(rng, 500));
    return s;
}

RenderOptions rule_options()
{
    RenderOptions o;
    o.coverage = Coverage::RasterRule;
    return o;
}

/// A random camera of kind k (0: perspective outside, 1: orthographic, 2: intrinsics with an
/// off-centre principal point, 3: perspective inside the soup, so that triangles cross near).
Camera random_camera(Rng& rng, int kind, int w, int h)
{
    Vec3 eye = kind == 3 ? rng.point(0.5) : normalize(rng.point(1)) * rng.uniform(2.5, 5);
    Vec3 target = rng.point(0.4);
    if (kind == 3) target = eye + rng.point(1);
    double near = kind == 3 ? rng.uniform(0.01, 0.2) : 0.5;
    Camera c = test::look(eye, target, rng.uniform(30, 100), near, 20);
    if (kind == 1) c = Camera::orthographic(eye, target, c.up, rng.uniform(1, 4), near, 20);
    if (kind == 2) {
        Intrinsics k;
        k.fx = rng.uniform(0.5, 1.5) * w;
        k.fy = k.fx * rng.uniform(0.9, 1.1);
        k.cx = rng.uniform(-0.2, 1.2) * w;
        k.cy = rng.uniform(-0.2, 1.2) * h;
        c = Camera::from_intrinsics(eye, target, c.up, k, near, 20);
    }
    return c;
}

/// Renders raster, then ray and brute with the raster rule; requires bit-identical buffers and
/// returns the covered pixels.
std::size_t check_identical(Renderer& raster, Renderer& rule, const Camera& cam, int w, int h, bool brute,
                            const std::string& name)
{
    INFO("case " << name << " " << w << "x" << h << ": " << cam.to_flags());
    HostVisibility r = raster.render(cam, w, h, Path::Raster).read();
    std::size_t ray = test::differing_bits(r, rule.render(cam, w, h, Path::Ray).read());
    std::size_t br = brute ? test::differing_bits(r, rule.render(cam, w, h, Path::Brute).read()) : 0;
    std::set<std::uint32_t> seen(r.ids.begin(), r.ids.end());
    std::printf("raster-rule %-28s %4dx%-4d covered %6zu, %5zu ids | ray %zu differ | brute %zu differ\n",
                name.c_str(), w, h, test::covered(r), seen.size(), ray, br);
    CHECK(ray == 0);
    CHECK(br == 0);
    return test::covered(r);
}

} // namespace

TEST_CASE("coverage modes have names and unknown names are refused")
{
    CHECK(std::string(to_string(Coverage::Watertight)) == "watertight");
    CHECK(std::string(to_string(Coverage::RasterRule)) == "raster-rule");
    CHECK(coverage_from_string("raster-rule") == Coverage::RasterRule);
    CHECK(coverage_from_string("watertight") == Coverage::Watertight);
    CHECK(RenderOptions{}.coverage == Coverage::Watertight);
    CHECK_THROWS_WITH(coverage_from_string("raster"), Catch::Contains("coverage: expected one of watertight, raster-rule, got 'raster'"));
}

TEST_CASE("raster-rule rays equal the raster path on unseen soups and cameras", "[device][rule]")
{
    Device device = Device::open();
    Rng rng(20261201);
    const int sizes[][2] = {{97, 61}, {64, 64}, {33, 130}, {5, 3}};
    for (int s = 0; s < 3; ++s) {
        Scene scene;
        scene.add_mesh(random_soup(rng, 400 + 300 * s));
        RenderOptions o;
        o.cull = s == 2 ? Cull::Back : Cull::None;
        o.bvh.max_leaf_size = 1 + 3 * s;
        Renderer raster(device, scene, o);
        o.coverage = Coverage::RasterRule;
        Renderer rule(device, scene, o);
        std::size_t covered = 0;
        for (int k = 0; k < 8; ++k) {
            const int* wh = sizes[k % 4];
            Camera cam = random_camera(rng, k % 4, wh[0], wh[1]);
            covered += check_identical(raster, rule, cam, wh[0], wh[1], true,
                                       "soup " + std::to_string(s) + " camera " + std::to_string(k));
        }
        CHECK(covered > 1000); // the cases draw something
    }
}

TEST_CASE("a batch of views traced with the raster rule equals the raster path view by view",
          "[device][rule]")
{
    Device device = Device::open();
    Rng rng(7);
    Scene scene = soup_scene(rng);
    Renderer raster(device, scene), rule(device, scene, rule_options());
    std::vector<Camera> cams;
    for (int k = 0; k < 4; ++k) cams.push_back(random_camera(rng, k, 45, 37));
    VisibilityBatch batch(device, 4, 45, 37);
    render_views(rule, cams, Path::Ray, batch);
    for (int k = 0; k < 4; ++k) {
        INFO("view " << k << ": " << cams[k].to_flags());
        HostVisibility r = raster.render(cams[k], 45, 37, Path::Raster).read();
        CHECK(test::differing_bits(r, batch.view(k).read()) == 0);
    }
}

TEST_CASE("a region traced with the raster rule equals the raster path's full image there",
          "[device][rule]")
{
    Device device = Device::open();
    Rng rng(11);
    Scene scene = soup_scene(rng);
    Camera cam = random_camera(rng, 0, 61, 43);
    HostVisibility full = Renderer(device, scene).render(cam, 61, 43, Path::Raster).read();
    RenderOptions o = rule_options();
    o.region = {13, 6, 37, 29}; // packets from an unaligned corner, cut at both ends
    Renderer rule(device, scene, o);
    for (Path p : {Path::Ray, Path::Brute}) {
        HostVisibility part = rule.render(cam, 61, 43, p).read();
        REQUIRE(part.width == 37);
        HostVisibility crop;
        crop.width = 37;
        crop.height = 29;
        for (int y = 6; y < 35; ++y)
            for (int x = 13; x < 50; ++x) {
                crop.ids.push_back(full.id(x, y));
                crop.depth.push_back(full.depth_at(x, y));
            }
        INFO(to_string(p) << " path");
        CHECK(test::covered(crop) > 0);
        CHECK(test::differing_bits(crop, part) == 0);
    }
}

TEST_CASE("raster-rule rays take the raster's tie rule on shared edges; watertight ones need not",
          "[device][rule]")
{
    // A 16 x 16 grid of unit quads, tilted so that the ray's hit distance and the raster's
    // interpolated depth differ in bits; the orthographic view puts pixel centres (32 px over 16
    // units) on every vertex and on the shared edges.
    MeshData grid;
    for (int j = 0; j <= 16; ++j)
        for (int i = 0; i <= 16; ++i) grid.positions.insert(grid.positions.end(), {float(i), float(j), float(0.3 * i)});
    test::add_grid_triangles(grid, 16);
    Scene scene;
    scene.add_mesh(grid);
    Device device = Device::open();
    Renderer raster(device, scene);
    RenderOptions o;
    o.coverage = Coverage::RasterRule;
    Renderer rule(device, scene, o);
    Camera ortho = Camera::orthographic({7.75, 8.25, 20}, {7.75, 8.25, 0}, {0, 1, 0}, 16, 1, 100);
    Camera persp = Camera::perspective({5, 9, 30}, {8, 8, 2}, {0, 1, 0}, 40, 1, 100);
    std::size_t watertight_differ = 0;
    for (const Camera& cam : {ortho, persp}) {
        check_identical(raster, rule, cam, 32, 32, true, "tilted grid");
        watertight_differ += test::differing_bits(raster.render(cam, 32, 32, Path::Raster).read(),
                                                  raster.render(cam, 32, 32, Path::Ray).read());
    }
    std::printf("raster-rule tilted grid: the watertight ray path differs from raster on %zu pixels\n",
                watertight_differ);
    CHECK(watertight_differ > 0);
}
