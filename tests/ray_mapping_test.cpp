// The ray path's two mappings (RayMapping): a work-item per 4x4 packet of rays in 16-wide vectors
// (ray_trace.cl) and a work-item per ray with a work-group per tile (ray_trace_single.cl). Both
// must give the same keys bit for bit, ids and depth bits, in both coverage modes, with culling,
// several samples per pixel, regions, every kind of camera, instances, batches of views and the
// exact edge fallback (CTest's device_exact_float entry runs the last case with the float-only
// form).
#include "catch.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>

#include <string>
#include <vector>

using namespace clvis;

namespace {

Device& device()
{
    static Device d = Device::open();
    return d;
}

std::vector<std::uint64_t> keys_of(const Scene& s, const Camera& c, int w, int h, RenderOptions o, RayMapping mapping,
                                   Path path = Path::Ray)
{
    o.ray_mapping = mapping;
    Renderer r(device(), s, o);
    return r.render(c, w, h, path).read_keys();
}

/// Renders the ray path with both mappings under `o`, in both coverage modes and every cull mode,
/// and checks the keys are the same, and that the frame without culling draws something
/// (`min_covered` keys not background).
void check_same(const Scene& s, const Camera& c, int w, int h, RenderOptions o, std::size_t min_covered)
{
    for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
        for (Cull cull : {Cull::None, Cull::Back, Cull::Front}) {
            o.coverage = coverage;
            o.cull = cull;
            std::vector<std::uint64_t> packet = keys_of(s, c, w, h, o, RayMapping::Packet);
            std::vector<std::uint64_t> single = keys_of(s, c, w, h, o, RayMapping::Single);
            INFO(w << "x" << h << " " << to_string(coverage) << " cull " << int(cull) << " samples " << o.samples
                   << " region " << o.region.x << "," << o.region.y << " " << c.to_flags());
            std::size_t drawn = 0;
            for (std::uint64_t k : packet) drawn += std::uint32_t(k) != background_id;
            if (cull == Cull::None) CHECK(drawn >= min_covered);
            CHECK(single == packet);
        }
    }
}

/// A soup as a plain mesh, beside a 2 x 2 array of instances of a sphere, one mirrored in x and
/// one squashed in y: the two-level walk, boxes and vertices transformed on the fly.
Scene instanced_scene()
{
    Scene s;
    s.add_mesh(make_soup(300, 5));
    std::size_t sphere = s.add_prototype(make_uv_sphere(600));
    for (int k = 0; k < 4; ++k) {
        Mat4 t;
        t(0, 0) = k == 1 ? -0.45 : 0.45;
        t(1, 1) = k == 2 ? 0.2 : 0.45;
        t(2, 2) = 0.45;
        t(0, 3) = k % 2 ? 1.0 : 0.0;
        t(1, 3) = k / 2 ? 1.0 : 0.0;
        t(2, 3) = -0.1 * k;
        s.add_instance(sphere, t);
    }
    return s;
}

} // namespace

TEST_CASE("the single mapping gives the packet mapping's keys on meshes", "[device][ray]")
{
    // The bunny from its side, spot from behind (the back faces of its hidden side culled or kept).
    Scene bunny = test::scene_file("stanford-bunny.obj"), spot = test::scene_file("spot.obj");
    RenderOptions o;
    check_same(bunny, test::look({0.22, 0.14, 0.08}, {-0.02, 0.1, 0}, 45, 0.01, 10), 97, 61, o, 800);
    Camera on_spot = test::look({-1.4, 1.1, -2.0}, {0, 0.3, 0}, 40, 0.1, 20);
    check_same(spot, on_spot, 160, 90, o, 2200);
    check_same(spot, on_spot, 1, 1, o, 0);
    // Orthographic and off-centre intrinsics, and the near plane cutting the mesh.
    check_same(spot, Camera::framing(spot.bounds(), Projection::Orthographic), 64, 48, o, 350);
    Camera off = Camera::framing(spot.bounds());
    off.intrinsics = Intrinsics{70, 64, 20.5, 31};
    check_same(spot, off, 57, 43, o, 300);
    check_same(bunny, test::look({-0.02, 0.1, 0.02}, {-0.02, 0.1, -1}, 60, 0.01, 10), 40, 30, o, 300);
}

TEST_CASE("the single mapping gives the packet mapping's keys on procedural scenes", "[device][ray]")
{
    Scene sphere;
    sphere.add_mesh(make_uv_sphere(5000));
    check_same(sphere, Camera::framing(sphere.bounds()), 50, 37, RenderOptions{}, 250);
    Scene soup;
    soup.add_mesh(make_soup(3000, 7));
    check_same(soup, test::look({0.5, 0.5, 2.2}, {0.5, 0.5, 0.5}, 45, 0.1, 10), 45, 45, RenderOptions{}, 240);
    Scene terrain;
    terrain.add_mesh(make_grid(4000, 3));
    check_same(terrain, test::look({0, 1.2, 1.6}, {0, 0, 0}, 50, 0.05, 10), 64, 40, RenderOptions{}, 1000);
}

TEST_CASE("the single mapping gives the packet mapping's keys per sample and region", "[device][ray]")
{
    Scene spot = test::scene_file("spot.obj");
    Camera c = test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20);
    RenderOptions o;
    o.samples = 4;
    check_same(spot, c, 75, 50, o, 4 * 300);
    o.samples = 1;
    o.region = Region{37, 11, 61, 53};
    check_same(spot, c, 160, 90, o, 300);
    o.region = Region{3, 70, 100, 20};
    check_same(spot, c, 160, 90, o, 50);
}

TEST_CASE("the single mapping gives the packet mapping's keys with instances", "[device][ray][instances]")
{
    Scene s = instanced_scene();
    check_same(s, Camera::framing(s.bounds()), 61, 45, RenderOptions{}, 300);
    check_same(s, Camera::framing(s.bounds(), Projection::Orthographic), 40, 40, RenderOptions{}, 280);
}

TEST_CASE("the single mapping gives the brute path's keys", "[device][ray]")
{
    Scene soup;
    soup.add_mesh(make_soup(400, 11));
    Camera c = test::look({0.5, 0.4, 2}, {0.5, 0.5, 0.5}, 40, 0.1, 10);
    for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
        RenderOptions o;
        o.coverage = coverage;
        INFO(to_string(coverage));
        CHECK(keys_of(soup, c, 40, 33, o, RayMapping::Single) == keys_of(soup, c, 40, 33, o, RayMapping::Single, Path::Brute));
    }
}

TEST_CASE("the single mapping gives the packet mapping's keys in a batch of views", "[device][ray]")
{
    Scene spot = test::scene_file("spot.obj");
    std::vector<Camera> cams = {test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20),
                                Camera::framing(spot.bounds(), Projection::Orthographic),
                                test::look({-2, 0.5, -1}, {0, 0.3, 0}, 30, 0.1, 20)};
    std::vector<std::vector<std::uint64_t>> keys;
    for (RayMapping mapping : {RayMapping::Packet, RayMapping::Single}) {
        RenderOptions o;
        o.ray_mapping = mapping;
        Renderer r(device(), spot, o);
        VisibilityBatch batch(device(), int(cams.size()), 37, 29);
        render_views(r, cams, Path::Ray, batch);
        keys.emplace_back();
        for (int v = 0; v < batch.views(); ++v) {
            std::vector<std::uint64_t> k = batch.view(v).read_keys();
            CHECK(k == keys_of(spot, cams[std::size_t(v)], 37, 29, RenderOptions{}, RayMapping::Packet));
            keys.back().insert(keys.back().end(), k.begin(), k.end());
        }
    }
    CHECK(keys[0] == keys[1]);
}

TEST_CASE("the single mapping gives the packet mapping's keys where the exact fallback runs", "[device][ray]")
{
    // Pixel centres on every vertex and edge of a plane grid (orthographic, 1 px per unit: edge
    // functions round to zero on shared edges), and a tilted grid behind planes seen edge-on.
    MeshData flat;
    const int n = 40;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            flat.positions.insert(flat.positions.end(), {float(i) - 20.5f, float(j) - 15.5f, -0.125f * float(i % 3)});
    test::add_grid_triangles(flat, n);
    Scene grid;
    grid.add_mesh(flat);
    check_same(grid, Camera::orthographic({0, 0, 40}, {0, 0, 0}, {0, 1, 0}, 32, 0.5, 100), 40, 32, RenderOptions{}, 1000);
    Scene edge_on;
    edge_on.add_mesh(flat);
    for (int k = -8; k <= 8; ++k) {
        float x = 0.25f * float(k);
        edge_on.add_mesh(test::triangle(x, -3, 1, x, 3, 1, x, 0, 2.5f));
    }
    check_same(edge_on, Camera::perspective({0, 0.3, 30}, {0, 0, 0}, {0, 1, 0}, 20, 0.01, 100), 41, 31, RenderOptions{},
               800);
}

TEST_CASE("ray mappings are named auto, packet and single, others refused")
{
    CHECK(ray_mapping_from_string("auto") == RayMapping::Auto);
    CHECK(ray_mapping_from_string("packet") == RayMapping::Packet);
    CHECK(ray_mapping_from_string("single") == RayMapping::Single);
    CHECK(std::string(to_string(RayMapping::Single)) == "single");
    CHECK_THROWS_WITH(ray_mapping_from_string("pixel"), Catch::Contains("auto, packet, single"));
    CHECK(RenderOptions{}.ray_mapping == RayMapping::Auto);
}
