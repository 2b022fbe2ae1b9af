// The raster fine stage's two mappings (RasterMapping): a work-item per square of pixels
// (raster_fine) and a work-group per square with a work-item per pixel (raster_fine_pixel, the
// bin walked in batches through local memory). Both must give the same keys bit for bit, ids and
// depth bits, whatever the scene, image size, tile size, depth test, samples or region, and
// when a device's loop cap splits the bins into launches.
#include "catch.hpp"
#include "test_meshes.hpp"

#include "runtime/cl_runtime.hpp"

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

std::vector<std::uint64_t> keys_of(Device& d, const Scene& s, const Camera& c, int w, int h, RenderOptions o,
                                   RasterMapping mapping)
{
    o.raster_mapping = mapping;
    Renderer r(d, s, o);
    return r.render(c, w, h, Path::Raster).read_keys();
}

/// The depth tests the device offers: tile ownership always, atomics where it has 64-bit atomics.
std::vector<RasterAtomics> depth_tests(const Device& d)
{
    if (d.info().int64_atomics) return {RasterAtomics::Off, RasterAtomics::On};
    return {RasterAtomics::Off};
}

/// Renders with both mappings under `o` (each depth test) and checks the keys are the same, and
/// that the frame draws something (`min_covered` keys not background).
void check_same(Device& d, const Scene& s, const Camera& c, int w, int h, RenderOptions o, std::size_t min_covered)
{
    for (RasterAtomics mode : depth_tests(d)) {
        o.raster_atomics = mode;
        std::vector<std::uint64_t> square = keys_of(d, s, c, w, h, o, RasterMapping::Square);
        std::vector<std::uint64_t> pixel = keys_of(d, s, c, w, h, o, RasterMapping::Pixel);
        INFO(w << "x" << h << " tile " << o.tile_size << " samples " << o.samples << " atomics "
               << to_string(mode) << " region " << o.region.x << "," << o.region.y);
        std::size_t drawn = 0;
        for (std::uint64_t k : square) drawn += std::uint32_t(k) != background_id;
        CHECK(drawn >= min_covered);
        CHECK(pixel == square);
    }
}

} // namespace

TEST_CASE("the pixel mapping gives the square mapping's keys on meshes", "[device][raster]")
{
    Scene bunny = test::scene_file("stanford-bunny.obj");
    Scene spot = test::scene_file("spot.obj");
    Camera on_bunny = test::look({-0.02, 0.11, 0.25}, {-0.02, 0.1, 0}, 45, 0.01, 10);
    Camera on_spot = test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20);
    RenderOptions o;
    for (int tile : {0, 8, 32}) {
        o.tile_size = tile;
        check_same(device(), bunny, on_bunny, 97, 61, o, 500);
        check_same(device(), spot, on_spot, 160, 90, o, 1000);
    }
    o.tile_size = 0;
    check_same(device(), bunny, on_bunny, 1, 1, o, 0);
    check_same(device(), spot, on_spot, 33, 200, o, 500);
}

TEST_CASE("the pixel mapping gives the square mapping's keys per sample and region", "[device][raster]")
{
    Scene spot = test::scene_file("spot.obj");
    Camera c = test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20);
    RenderOptions o;
    o.samples = 4;
    check_same(device(), spot, c, 75, 50, o, 4 * 300);
    o.samples = 1;
    o.region = Region{37, 11, 61, 53};
    check_same(device(), spot, c, 160, 90, o, 300);
    o.tile_size = 4;
    o.region = Region{3, 70, 100, 20};
    check_same(device(), spot, c, 160, 90, o, 50);
}

TEST_CASE("the pixel mapping draws long bins in chunks within a loop cap", "[device][raster]")
{
    // A cap forced on a device of its own: 2000 passes give raster_fine_pixel 332 bin entries
    // per launch, so the 1500 triangles over every tile take 5 launches, each merging with the last.
    Device capped = Device::open();
    detail::DeviceAccess::of(capped, "test").measured_loop_limit = 2000;
    MeshData m;
    for (int k = 0; k < 1500; ++k) {
        float z = -50.0f + 0.02f * float(k), x0 = -20.25f + 0.003f * float(k % 7);
        m.positions.insert(m.positions.end(), {x0, -18.5f, z, 19.75f, -18.5f, z, 19.75f, 21.5f, z});
        std::uint32_t b = std::uint32_t(3 * k);
        m.indices.insert(m.indices.end(), {b, b + 1, b + 2});
    }
    Scene s;
    s.add_mesh(m);
    Camera c = Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 64, 0.5, 100);
    RenderOptions o;
    o.tile_size = 16;
    std::vector<std::uint64_t> want = keys_of(device(), s, c, 48, 40, o, RasterMapping::Square);
    std::size_t last = 0;
    for (std::uint64_t k : want) last += std::uint32_t(k) == 1499u;
    CHECK(last > 200); // the nearest triangle, over a third of the image
    for (RasterAtomics mode : depth_tests(capped)) {
        o.raster_atomics = mode;
        CHECK(keys_of(capped, s, c, 48, 40, o, RasterMapping::Pixel) == want);
    }
}

TEST_CASE("raster mappings are named auto, square and pixel, others refused")
{
    CHECK(raster_mapping_from_string("auto") == RasterMapping::Auto);
    CHECK(raster_mapping_from_string("square") == RasterMapping::Square);
    CHECK(raster_mapping_from_string("pixel") == RasterMapping::Pixel);
    CHECK(std::string(to_string(RasterMapping::Pixel)) == "pixel");
    CHECK_THROWS_WITH(raster_mapping_from_string("tiles"), Catch::Contains("auto, square, pixel"));
    CHECK(RenderOptions{}.raster_mapping == RasterMapping::Auto);
}
