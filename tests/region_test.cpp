// Region rendering: a rectangle of the image rendered alone holds the same keys, bit for bit, as
// those pixels of the whole image's render, on every path and tile size; bad regions are refused.
#include "catch.hpp"

#include <clvis/clvis.hpp>
#include <clvis/procedural.hpp>
#include <clvis/scene_io.hpp>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

using namespace clvis;

namespace {

Scene bundled(const std::string& name)
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + name + ".obj"));
    return s;
}

Scene procedural_soup()
{
    Scene s;
    s.add_mesh(make_soup(3000, 7));
    s.add_mesh(make_uv_sphere(800));
    return s;
}

/// The keys of `region` cut out of a whole image's keys.
std::vector<std::uint64_t> crop(const std::vector<std::uint64_t>& whole, int width, const Region& r)
{
    std::vector<std::uint64_t> out;
    out.reserve(std::size_t(r.width) * std::size_t(r.height));
    for (int j = r.y; j < r.y + r.height; ++j)
        for (int i = r.x; i < r.x + r.width; ++i) out.push_back(whole[std::size_t(j) * std::size_t(width) + std::size_t(i)]);
    return out;
}

/// Regions of every kind: random, odd sizes, on the borders, single pixels, whole rows and columns.
std::vector<Region> regions_of(int width, int height, std::uint64_t seed)
{
    std::vector<Region> out = {{0, 0, 1, 1},
                               {width - 1, height - 1, 1, 1},
                               {0, 0, width, height},
                               {0, height / 2, width, 1},
                               {width / 3, 0, 1, height},
                               {width - 7, 0, 7, height},
                               {0, height - 5, width, 5}};
    std::mt19937_64 rng(seed);
    for (int k = 0; k < 12; ++k) {
        int w = 1 + int(rng() % std::uint64_t(width)), h = 1 + int(rng() % std::uint64_t(height));
        int x = int(rng() % std::uint64_t(width - w + 1)), y = int(rng() % std::uint64_t(height - h + 1));
        out.push_back({x, y, w, h});
    }
    return out;
}

void check_regions(Device& device, const Scene& scene, const Camera& camera, int width, int height, int tile)
{
    RenderOptions options;
    options.tile_size = tile;
    Renderer renderer(device, scene, options);
    for (Path path : {Path::Raster, Path::Ray, Path::Brute}) {
        if (path == Path::Brute && scene.triangle_count() > 4000) continue;
        auto whole = renderer.render(camera, width, height, path).read_keys();
        std::size_t drawn = 0;
        for (auto key : whole) drawn += (key & 0xFFFFFFFFu) != background_id;
        REQUIRE(drawn > 0);
        for (const Region& r : regions_of(width, height, std::uint64_t(width) * 31 + std::uint64_t(tile))) {
            VisibilityBuffer part(device, r.width, r.height);
            renderer.render(camera, width, height, r, path, part);
            INFO(to_string(path) << " tile " << tile << " region " << r.width << "x" << r.height << " at " << r.x
                                 << "," << r.y << " of " << width << "x" << height);
            CHECK(part.read_keys() == crop(whole, width, r));
        }
    }
}

} // namespace

TEST_CASE("a region holds the bits of the whole render's pixels, bundled meshes", "[device][region]")
{
    Device device = Device::open();
    for (const char* name : {"spot", "suzanne"}) {
        Scene scene = bundled(name);
        Camera camera = Camera::framing(scene.bounds());
        for (int tile : {4, 16, 64}) check_regions(device, scene, camera, 97, 61, tile);
        check_regions(device, scene, Camera::framing(scene.bounds(), Projection::Orthographic), 64, 50, 8);
    }
}

TEST_CASE("a region holds the bits of the whole render's pixels, procedural scenes", "[device][region]")
{
    Device device = Device::open();
    Scene scene = procedural_soup();
    Camera camera = Camera::framing(scene.bounds());
    for (int tile : {8, 32}) check_regions(device, scene, camera, 83, 77, tile);
    // Close enough that triangles cross near and the guard band: the clipper's output is binned too.
    Camera close = Camera::perspective({0.1, 0.2, 0.3}, {0, 0, -1}, {0, 1, 0}, 100, 0.01, 100);
    check_regions(device, scene, close, 71, 45, 16);
}

TEST_CASE("the region of render options picks the pixels of a plain render", "[device][region]")
{
    Device device = Device::open();
    Scene scene = bundled("spot");
    Camera camera = Camera::framing(scene.bounds());
    auto whole = Renderer(device, scene).render(camera, 40, 30, Path::Raster).read_keys();
    RenderOptions options;
    options.region = {5, 7, 13, 11};
    Renderer renderer(device, scene, options);
    VisibilityBuffer part = renderer.render(camera, 40, 30, Path::Raster);
    CHECK(part.width() == 13);
    CHECK(part.height() == 11);
    CHECK(part.read_keys() == crop(whole, 40, options.region));
    VisibilityBuffer target(device, 13, 11);
    CHECK_THROWS_WITH(renderer.render(camera, Path::Raster, target), Catch::Contains("region"));
}

TEST_CASE("regions outside the image or of the wrong size are refused with the values named", "[device][region]")
{
    Device device = Device::open();
    Scene scene = bundled("spot");
    Camera camera = Camera::framing(scene.bounds());
    Renderer renderer(device, scene);
    VisibilityBuffer target(device, 8, 8);
    CHECK_THROWS_WITH(renderer.render(camera, 40, 30, Region{35, 0, 8, 8}, Path::Ray, target),
                      Catch::Contains("8x8 at (35, 0)") && Catch::Contains("40x30"));
    CHECK_THROWS_WITH(renderer.render(camera, 40, 30, Region{-1, 0, 8, 8}, Path::Raster, target),
                      Catch::Contains("(-1, 0)"));
    CHECK_THROWS_WITH(renderer.render(camera, 40, 30, Region{0, 0, 0, 8}, Path::Raster, target),
                      Catch::Contains("0x8"));
    CHECK_THROWS_WITH(renderer.render(camera, 40, 30, Region{0, 0, 8, 4}, Path::Raster, target),
                      Catch::Contains("the target is 8x8"));
}
