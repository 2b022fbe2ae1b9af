// The Renderer's contract beside the paths themselves: arguments refused with the value named,
// buffers of the caller, updates, threads, and many frames without growth.
#include "catch.hpp"
#include "test_meshes.hpp"

#include "runtime/cl_runtime.hpp"

#include <clvis/clvis.hpp>

#include <fstream>
#include <thread>

using namespace clvis;

namespace {

using test::covered;

Scene quad_scene()
{
    Scene s;
    MeshData m;
    m.name = "quad";
    m.positions = {-1, -1, -3, 1, -1, -3, 1, 1, -3, -1, 1, -3};
    m.indices = {0, 1, 2, 0, 2, 3};
    s.add_mesh(m);
    return s;
}

Camera front() { return Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.1, 10); }

/// Resident set size in KiB (Linux), for the growth check.
long rss_kib()
{
    std::ifstream status("/proc/self/status");
    std::string key;
    long value = 0;
    while (status >> key) {
        if (key == "VmRSS:") {
            status >> value;
            return value;
        }
        status.ignore(1 << 16, '\n');
    }
    return 0;
}

} // namespace

TEST_CASE("render options and requests are checked with the value named", "[device][renderer]")
{
    Device d = Device::open();
    Scene s = quad_scene();
    RenderOptions bad;
    bad.tile_size = 12;
    CHECK_THROWS_WITH(Renderer(d, s, bad), Catch::Contains("tile size") && Catch::Contains("12"));
    bad = {};
    bad.bvh.max_leaf_size = 0;
    CHECK_THROWS_WITH(Renderer(d, s, bad), Catch::Contains("leaf size"));
    CHECK_THROWS_AS(Renderer(Device(), s), Error);

    Renderer r(d, s);
    Camera cam = front();
    cam.near = -1;
    CHECK_THROWS_WITH(r.render(cam, 8, 8, Path::Raster), Catch::Contains("near"));
    CHECK_THROWS_WITH(r.render(front(), 0, 8, Path::Ray), Catch::Contains("image size"));
    CHECK_THROWS_AS(r.render(front(), 100000, 100000, Path::Raster), Error);
    CHECK_THROWS_WITH(path_from_string("zbuffer"), Catch::Contains("zbuffer"));
}

TEST_CASE("samples per pixel other than 1, 2, 4, 8, 16 are refused, the value named", "[device][renderer][samples]")
{
    Device d = Device::open();
    Scene s = quad_scene();
    for (int n : {0, -4, 3, 6, 32}) {
        RenderOptions bad;
        bad.samples = n;
        CHECK_THROWS_WITH(Renderer(d, s, bad), Catch::Contains("samples") && Catch::Contains(std::to_string(n)));
        CHECK_THROWS_AS(VisibilityBuffer(d, 4, 4, n), Error);
    }
    RenderOptions four;
    four.samples = 4;
    Renderer r(d, s, four);
    VisibilityBuffer vis = r.render(front(), 8, 8, Path::Raster);
    CHECK(vis.samples() == 4);
    CHECK(vis.key_count() == 8 * 8 * 4);
    CHECK(vis.read().ids.size() == 8 * 8 * 4);
    VisibilityBuffer one(d, 8, 8);
    CHECK_THROWS_WITH(r.render(front(), Path::Ray, one), Catch::Contains("sample"));
    CHECK_THROWS_WITH(resolve(r, vis, front(), AttributeRequest{}), Catch::Contains("sample"));
}

TEST_CASE("both paths render into a buffer the caller owns", "[device][renderer]")
{
    Device d = Device::open();
    Scene s = quad_scene();
    Renderer r(d, s);
    cl_int err = 0;
    cl_mem mine = clCreateBuffer(d.context(), CL_MEM_READ_WRITE, 32 * 32 * 8, nullptr, &err);
    REQUIRE(err == CL_SUCCESS);
    VisibilityBuffer target = VisibilityBuffer::wrap(d, mine, 32, 32);
    clReleaseMemObject(mine); // the wrapper keeps its own reference
    for (Path p : {Path::Raster, Path::Ray, Path::Brute}) {
        r.render(front(), p, target);
        HostVisibility v = target.read();
        CHECK(covered(v) > 100);
        CHECK(v.depth_at(16, 16) == Approx(3.0f));
    }
    CHECK_THROWS_AS(VisibilityBuffer::wrap(d, target.keys(), 64, 64), Error); // too small
}

TEST_CASE("update re-uploads moved meshes for both paths", "[device][renderer]")
{
    Device d = Device::open();
    Scene s = quad_scene();
    for (BvhUpdate mode : {BvhUpdate::Refit, BvhUpdate::Rebuild}) {
        RenderOptions o;
        o.bvh.update = mode;
        Renderer r(d, s, o);
        r.render(front(), 16, 16, Path::Ray);
        Scene moved = s;
        Mat4 m;
        m(0, 3) = 5; // slide the quad out of view
        moved.set_transform(0, m);
        r.update(moved);
        CHECK(covered(r.render(front(), 16, 16, Path::Ray).read()) == 0);
        CHECK(covered(r.render(front(), 16, 16, Path::Raster).read()) == 0);
        CHECK(r.bvh_stats().refitted == (mode == BvhUpdate::Refit));
        r.update(s);
        CHECK(covered(r.render(front(), 16, 16, Path::Ray).read()) > 0);
    }
    Scene other;
    CHECK_THROWS_WITH(Renderer(d, s).update(other), Catch::Contains("meshes"));
}

TEST_CASE("two renderers on two threads both give the right buffers", "[device][renderer]")
{
    Device d = Device::open();
    Scene sphere;
    sphere.add_mesh(make_uv_sphere(5000));
    Camera cam = Camera::framing(sphere.bounds());
    Renderer reference(d, sphere);
    auto expected_raster = reference.render(cam, 96, 64, Path::Raster).read_keys();
    auto expected_ray = reference.render(cam, 96, 64, Path::Ray).read_keys();
    std::vector<std::uint64_t> got[2][2];
    auto work = [&](int t) {
        Renderer r(d, sphere);
        for (int i = 0; i < 10; ++i) {
            got[t][0] = r.render(cam, 96, 64, Path::Raster).read_keys();
            got[t][1] = r.render(cam, 96, 64, Path::Ray).read_keys();
        }
    };
    std::thread a(work, 0), b(work, 1);
    a.join();
    b.join();
    for (int t = 0; t < 2; ++t) {
        CHECK(got[t][0] == expected_raster);
        CHECK(got[t][1] == expected_ray);
    }
}

TEST_CASE("a renderer reused for a thousand frames with changing cameras does not grow", "[device][renderer][slow]")
{
    Device d = Device::open();
    Scene s;
    s.add_mesh(make_uv_sphere(2000));
    Renderer r(d, s);
    Camera cam = Camera::framing(s.bounds());
    VisibilityBuffer target(d, 64, 48);
    auto frame = [&](int i) {
        Camera c = cam;
        c.eye.x += 0.01 * (i % 50);
        r.render(c, i % 2 ? Path::Ray : Path::Raster, target);
        if (i % 100 == 0) r.update(s);
    };
    for (int i = 0; i < 200; ++i) frame(i); // reach the steady state (caches, pools)
    long before = rss_kib();
    for (int i = 0; i < 1000; ++i) frame(i);
    long after = rss_kib();
    INFO("resident set " << before << " KiB before, " << after << " KiB after 1000 frames");
    CHECK(after - before < 8 * 1024);
}
