// RasterMapping::Auto on the test device: it draws the keys of both fixed mappings, measures once
// per key (device, depth test, tile size) and then reads the cache, measures again after a damaged
// cache file, and can be forced or bypassed. Each case points the cache at a fresh folder of its own.
#include "catch.hpp"
#include "test_files.hpp"
#include "test_meshes.hpp"

#include "render/raster_tune.hpp"

#include <clvis/clvis.hpp>

#include <fstream>
#include <string>
#include <vector>

using namespace clvis;

namespace {

Device& device()
{
    static Device d = Device::open();
    return d;
}

Scene spot_scene()
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"));
    return s;
}

/// The mapping a Renderer under `o` runs, resolved by its first raster frame.
RasterMappingChoice resolved(const Scene& s, RenderOptions o)
{
    Renderer r(device(), s, o);
    r.render(test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20), 32, 24, Path::Raster);
    return r.raster_mapping();
}

/// What tests check of a measured choice: a real mapping and both times.
void check_measured(const RasterMappingChoice& c)
{
    CHECK(c.source == "measured");
    CHECK((c.mapping == RasterMapping::Square || c.mapping == RasterMapping::Pixel));
    CHECK(c.square_ms > 0);
    CHECK(c.pixel_ms > 0);
    CHECK(c.mapping == (c.pixel_ms < c.square_ms ? RasterMapping::Pixel : RasterMapping::Square));
}

} // namespace

TEST_CASE("the auto raster mapping draws the keys of both fixed mappings", "[device][raster]")
{
    test::ScopedEnv dir("CLVIS_CACHE_DIR", test::fresh_temp_dir("clvis-raster-tune-keys").c_str());
    Scene s = spot_scene();
    Camera c = test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20);
    RenderOptions o;
    REQUIRE(o.raster_mapping == RasterMapping::Auto);
    for (int tile : {0, 8}) {
        o.tile_size = tile;
        std::vector<std::vector<std::uint64_t>> keys;
        for (RasterMapping m : {RasterMapping::Auto, RasterMapping::Square, RasterMapping::Pixel}) {
            o.raster_mapping = m;
            Renderer r(device(), s, o);
            keys.push_back(r.render(c, 97, 61, Path::Raster).read_keys());
            CHECK(r.raster_mapping().mapping != RasterMapping::Auto);
        }
        std::size_t drawn = 0;
        for (std::uint64_t k : keys[0]) drawn += std::uint32_t(k) != background_id;
        CHECK(drawn > 1000);
        CHECK(keys[0] == keys[1]);
        CHECK(keys[0] == keys[2]);
    }
}

TEST_CASE("the auto raster mapping is measured once per key, then read from the cache", "[device][raster]")
{
    auto folder = test::fresh_temp_dir("clvis-raster-tune-cache");
    test::ScopedEnv dir("CLVIS_CACHE_DIR", folder.c_str()), cache("CLVIS_TUNE_CACHE", nullptr),
        force("CLVIS_TUNE_RASTER_MAPPING", nullptr);
    Scene s = spot_scene();
    RenderOptions o;
    o.tile_size = 16;
    RasterMappingChoice first = resolved(s, o);
    check_measured(first);
    RasterMappingChoice again = resolved(s, o);
    CHECK(again.source == "cache");
    CHECK(again.mapping == first.mapping);
    CHECK(again.square_ms == first.square_ms);
    CHECK(again.pixel_ms == first.pixel_ms);
    o.tile_size = 32; // another key
    check_measured(resolved(s, o));
    CHECK(resolved(s, o).source == "cache");

    // The stored file names the choice; damaged, it is measured again and rewritten.
    std::filesystem::path file =
        detail::tune_file(folder, "raster_mapping", detail::raster_mapping_request(device(), o).key);
    REQUIRE(std::filesystem::exists(file));
    std::ofstream(file, std::ios::trunc) << "clvis-tune 1\nname raster_mapping\nchoice";
    check_measured(resolved(s, o));
    CHECK(resolved(s, o).source == "cache");
    bool listed = false;
    for (const TunedChoice& t : tuned_choices(device().info()))
        listed |= t.name == "raster_mapping" && t.times_ms.size() == 2;
    CHECK(listed);

    test::ScopedEnv off("CLVIS_TUNE_CACHE", "0");
    check_measured(resolved(s, o));
}

TEST_CASE("the auto raster mapping can be forced, and a named mapping is kept", "[device][raster]")
{
    test::ScopedEnv dir("CLVIS_CACHE_DIR", test::fresh_temp_dir("clvis-raster-tune-force").c_str());
    Scene s = spot_scene();
    RenderOptions o;
    {
        test::ScopedEnv force("CLVIS_TUNE_RASTER_MAPPING", "pixel");
        RasterMappingChoice c = resolved(s, o);
        CHECK(c.mapping == RasterMapping::Pixel);
        CHECK(c.source == "forced");
        CHECK(c.square_ms == -1);
        o.raster_mapping = RasterMapping::Square; // the option wins over the variable
        c = resolved(s, o);
        CHECK(c.mapping == RasterMapping::Square);
        CHECK(c.source == "option");
        o.raster_mapping = RasterMapping::Auto;
    }
    {
        test::ScopedEnv force("CLVIS_TUNE_RASTER_MAPPING", "square");
        CHECK(resolved(s, o).mapping == RasterMapping::Square);
    }
    test::ScopedEnv junk("CLVIS_TUNE_RASTER_MAPPING", "tiles");
    Renderer r(device(), s, o);
    CHECK_THROWS_WITH(r.raster_mapping(), Catch::Contains("CLVIS_TUNE_RASTER_MAPPING") && Catch::Contains("tiles"));
}
