// The raster path's two depth tests: 64-bit atomic min (RasterAtomics::On) and tile ownership
// (Off), chosen by Auto from the device's extensions. Tile ownership builds with no 64-bit atomic
// in its kernels, runs where a device has none, and gives the atomic test's keys bit for bit
// (raster_test.cpp and the agreement suite, agree_harness.cpp, compare the two modes on every
// frame they draw).
#include "catch.hpp"
#include "test_meshes.hpp"

#include "runtime/cl_runtime.hpp"
#include "runtime/embedded_kernels.hpp"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace clvis;

namespace {

/// The lines of `source` that a build with `macro` defined may compile: conditional blocks on
/// `macro` resolved, every other conditional kept whole (both branches), so nothing is missed.
std::string compiled_with(const std::string& source, const std::string& macro)
{
    std::istringstream in(source);
    std::string line, out;
    std::vector<int> stack; // per open conditional: 1 keep, 0 drop, -1 unknown (kept)
    auto keeping = [&] { return std::find(stack.begin(), stack.end(), 0) == stack.end(); };
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string directive, name;
        words >> directive >> name;
        if (directive == "#ifdef" || directive == "#ifndef") {
            stack.push_back(name != macro ? -1 : (directive == "#ifdef") ? 1 : 0);
        } else if (directive == "#if") {
            stack.push_back(-1);
        } else if (directive == "#else" && !stack.empty()) {
            stack.back() = stack.back() == -1 ? -1 : 1 - stack.back();
        } else if (directive == "#endif" && !stack.empty()) {
            stack.pop_back();
        } else if (keeping()) {
            out += line + "\n";
        }
    }
    return out;
}

Scene spot()
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"));
    return s;
}

std::vector<std::uint64_t> raster_keys(const Device& d, const Scene& s, const Camera& c, int w, int h,
                                       RasterAtomics mode)
{
    RenderOptions o;
    o.raster_atomics = mode;
    return Renderer(d, s, o).render(c, w, h, Path::Raster).read_keys();
}

} // namespace

TEST_CASE("raster atomics modes are named for flags, and an unknown one is refused")
{
    for (RasterAtomics m : {RasterAtomics::Auto, RasterAtomics::On, RasterAtomics::Off})
        CHECK(raster_atomics_from_string(to_string(m)) == m);
    CHECK(RenderOptions{}.raster_atomics == RasterAtomics::Auto);
    try {
        raster_atomics_from_string("sometimes");
        FAIL("an unknown raster atomics mode was accepted");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::InvalidArgument);
        CHECK(std::string(e.what()).find("sometimes") != std::string::npos);
    }
}

TEST_CASE("the tile-ownership raster kernels name no 64-bit atomic and enable none", "[device][raster][rusticl]")
{
    // OpenCL C 1.2 spells its 64-bit atomics atom_* (32-bit ones also atomic_*), enabled by the
    // cl_khr_int64_* pragmas: none may remain in what a tile-ownership build compiles. The
    // atomic depth test's setup does use them (the scan can fail), and both variants build here.
    Device d = Device::open();
    for (const char* name : {"raster_setup", "raster_bin", "raster_fine"}) {
        INFO("kernels/" << name << ".cl");
        std::string owned = compiled_with(detail::embedded_kernel(name), "CLVIS_RASTER_OWNED");
        CHECK(owned.find("atom_") == std::string::npos);
        CHECK(owned.find("cl_khr_int64") == std::string::npos);
        CHECK(owned.find("__kernel") != std::string::npos);
        const char* owned_option = std::string(name) == "raster_setup" ? "-DCLVIS_RASTER_OWNED" : "";
        CHECK_NOTHROW(detail::DeviceAccess::of(d, "test").program(name, owned_option));
    }
    std::string atomic = compiled_with(detail::embedded_kernel("raster_setup"), "CLVIS_RASTER_ATOMIC_TEST_UNDEFINED");
    CHECK(atomic.find("atom_min") != std::string::npos);
    CHECK(atomic.find("cl_khr_int64_extended_atomics") != std::string::npos);
}

TEST_CASE("without 64-bit atomics the raster path owns tiles, with the same keys", "[device][raster][rusticl]")
{
    // A device of its own whose reported extensions lack the atomics.
    Device plain = Device::open();
    Device lacking = Device::open();
    detail::DeviceAccess::of(lacking, "test").info.int64_atomics = false;
    Scene s = spot();
    Bounds b = s.bounds();
    const int w = 203, h = 117; // odd sizes: squares and spans cut by the image's edges
    for (const Camera& c : {Camera::framing(b), Camera::framing(b, Projection::Orthographic),
                            test::look(b.center() + Vec3{0.05, 0.1, 0.3}, b.center() + Vec3{0, 0, -1}, 90, 0.01, 10)}) {
        INFO(c.to_flags());
        std::vector<std::uint64_t> reference = raster_keys(plain, s, c, w, h, RasterAtomics::Auto);
        CHECK(test::covered(split_keys(reference.data(), w, h)) > 0);
        CHECK(raster_keys(lacking, s, c, w, h, RasterAtomics::Auto) == reference);
        CHECK(raster_keys(lacking, s, c, w, h, RasterAtomics::Off) == reference);
        CHECK(raster_keys(plain, s, c, w, h, RasterAtomics::Off) == reference);
    }
    try {
        raster_keys(lacking, s, Camera::framing(b), 8, 8, RasterAtomics::On);
        FAIL("rasterized with 64-bit atomics on a device without them");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Device);
        CHECK(std::string(e.what()).find("64-bit atomics") != std::string::npos);
        CHECK(std::string(e.what()).find("off") != std::string::npos);
    }
}

TEST_CASE("tile ownership draws nothing as the background, and grows its list of triangles",
          "[device][raster][rusticl]")
{
    Device d = Device::open();
    // Nothing listed: the frame is only the clear.
    Scene behind;
    behind.add_mesh(test::triangle(-1, -1, 1, 1, -1, 1, 0, 1, 1));
    Camera front = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.1, 10);
    for (std::uint64_t k : raster_keys(d, behind, front, 19, 5, RasterAtomics::Off)) CHECK(k == background_key);
    // More small triangles than the first list holds (every one is listed under tile ownership).
    MeshData m;
    const int n = 100; // 2 n^2 = 20000 triangles, each about a pixel, far above the first capacity
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            m.positions.insert(m.positions.end(), {float(i) / n - 0.5f, float(j) / n - 0.5f, -1.0f});
    test::add_grid_triangles(m, n);
    Scene grid;
    grid.add_mesh(m);
    Camera c = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.1, 10);
    std::vector<std::uint64_t> off = raster_keys(d, grid, c, 160, 160, RasterAtomics::Off);
    CHECK(test::covered(split_keys(off.data(), 160, 160)) > 100 * 100);
    if (d.info().int64_atomics) CHECK(off == raster_keys(d, grid, c, 160, 160, RasterAtomics::On));
}

TEST_CASE("a device's loop cap is measured, and long bins are drawn in chunks within it",
          "[device][raster][rusticl]")
{
    Device d = Device::open();
    std::uint32_t limit = detail::DeviceAccess::of(d, "test").loop_limit();
    CHECK(limit == detail::DeviceAccess::of(d, "test").loop_limit());
    CHECK(limit > 1000u);
    INFO("loop limit " << limit);
    // A cap forced on a device of its own: 4000 passes give raster_fine.cl 28 bin entries per
    // launch, so the 6000-entry bins below take 215 launches, each merging with the last.
    Device capped = Device::open();
    detail::DeviceAccess::of(capped, "test").measured_loop_limit = 4000;
    MeshData m;
    for (int k = 0; k < 3000; ++k) {
        float z = -50.0f + 0.01f * float(k), x0 = -20.25f + 0.003f * float(k % 7);
        m.positions.insert(m.positions.end(), {x0, -18.5f, z, 19.75f, -18.5f, z, 19.75f, 21.5f, z, x0, 21.5f, z});
        std::uint32_t b = std::uint32_t(4 * k);
        m.indices.insert(m.indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
    }
    Scene s;
    s.add_mesh(m);
    Camera c = Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 64, 0.5, 100);
    std::vector<std::uint64_t> want = raster_keys(d, s, c, 64, 64, RasterAtomics::Auto);
    std::set<std::uint32_t> ids;
    for (std::uint64_t k : want) ids.insert(std::uint32_t(k));
    CHECK(ids == std::set<std::uint32_t>{5998u, 5999u, background_id});
    CHECK(raster_keys(capped, s, c, 64, 64, RasterAtomics::Off) == want);
    if (capped.info().int64_atomics) CHECK(raster_keys(capped, s, c, 64, 64, RasterAtomics::On) == want);
    // A cap the raster path cannot keep is refused by name, not drawn wrong.
    detail::DeviceAccess::of(capped, "test").measured_loop_limit = 200;
    try {
        raster_keys(capped, s, c, 64, 64, RasterAtomics::Off);
        FAIL("rendered under a loop cap the raster path cannot keep");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("after 200 iterations") != std::string::npos);
    }
}

TEST_CASE("a frame reports the depth test Auto drew it with", "[device][raster][pocl]")
{
    Device d = Device::open(); // ctest pins CLVIS_DEVICE=cpu: PoCL's CPU device, 64-bit atomics
    REQUIRE(d.info().int64_atomics);
    Scene s = spot(); // about 5.9k triangles: tile ownership from 16 keys a triangle (94k keys)
    Camera c = Camera::framing(s.bounds());
    auto drawn = [&](RasterAtomics mode, int w, int h, Path path = Path::Raster) {
        RenderOptions o;
        o.raster_atomics = mode;
        Renderer r(d, s, o);
        r.render(c, w, h, path);
        return r.last_frame().raster_atomics;
    };
    CHECK(drawn(RasterAtomics::Auto, 400, 300) == RasterAtomics::Off); // few triangles a key: owned
    CHECK(drawn(RasterAtomics::Auto, 64, 64) == RasterAtomics::On);    // many: atomics
    CHECK(drawn(RasterAtomics::On, 400, 300) == RasterAtomics::On);
    CHECK(drawn(RasterAtomics::Off, 64, 64) == RasterAtomics::Off);
    CHECK(drawn(RasterAtomics::Auto, 400, 300, Path::Ray) == RasterAtomics::Auto);
}
