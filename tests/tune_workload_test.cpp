// The mapping tuners' workload scale (render/tune_workload.hpp): CLVIS_TUNE_WORKLOAD=small gives
// both tuners a key of their own (a choice measured on one workload is never read as the other's),
// measures through the same candidates' Renderers, and any other value is refused, naming it.
#include "catch.hpp"
#include "test_files.hpp"

#include "render/raster_tune.hpp"
#include "render/ray_tune.hpp"
#include "render/tune_workload.hpp"

#include <clvis/clvis.hpp>

#include <filesystem>
#include <string>

using namespace clvis;

namespace {

Device& device()
{
    static Device d = Device::open();
    return d;
}

} // namespace

TEST_CASE("CLVIS_TUNE_WORKLOAD=small keys and measures both tuners apart from the full workload", "[device][raster]")
{
    auto folder = test::fresh_temp_dir("clvis-tune-workload-cache");
    test::ScopedEnv dir("CLVIS_CACHE_DIR", folder.c_str()), cache("CLVIS_TUNE_CACHE", nullptr),
        raster("CLVIS_TUNE_RASTER_MAPPING", nullptr), ray("CLVIS_TUNE_RAY_MAPPING", nullptr);
    RenderOptions o;
    std::string full_name, small_name;
    detail::TuneKey full_raster, full_ray;
    {
        test::ScopedEnv workload("CLVIS_TUNE_WORKLOAD", nullptr);
        full_name = detail::tune_workload_name();
        full_raster = detail::raster_mapping_request(device(), o).key;
        full_ray = detail::ray_mapping_request(device(), o).key;
        test::ScopedEnv named("CLVIS_TUNE_WORKLOAD", "full");
        CHECK(detail::tune_workload_name() == full_name);
        CHECK(detail::raster_mapping_request(device(), o).key == full_raster);
    }
    // The full workload's name is the one every cache written before the variable holds.
    CHECK(full_name == "sphere6000+grid6000@640x480 min(3 frames, 500 ms) frame_ms v3");
    test::ScopedEnv workload("CLVIS_TUNE_WORKLOAD", "small");
    small_name = detail::tune_workload_name();
    CHECK(small_name != full_name);
    CHECK(small_name.find("160x120") != std::string::npos);
    CHECK(detail::raster_mapping_request(device(), o).key != full_raster);
    CHECK(detail::ray_mapping_request(device(), o).key != full_ray);

    // Measured on the small workload (square then pixel, packet then single), then from the cache.
    Scene s;
    s.add_mesh(make_uv_sphere(200));
    Camera cam = Camera::framing(s.bounds());
    for (int round = 0; round < 2; ++round) {
        Renderer r(device(), s);
        r.render(cam, 24, 16, Path::Raster);
        r.render(cam, 24, 16, Path::Ray);
        RasterMappingChoice rm = r.raster_mapping();
        RayMappingChoice ym = r.ray_mapping();
        INFO("round " << round);
        CHECK(rm.source == (round == 0 ? "measured" : "cache"));
        CHECK(ym.source == (round == 0 ? "measured" : "cache"));
        CHECK((rm.square_ms > 0 && rm.pixel_ms > 0));
        CHECK((ym.packet_ms > 0 && ym.single_ms > 0));
    }
    // Nothing of the full workload was measured or written: its key reads as absent.
    CHECK(!std::filesystem::exists(detail::tune_file(folder, "raster_mapping", full_raster)));
    CHECK(!std::filesystem::exists(detail::tune_file(folder, "ray_mapping", full_ray)));

    test::ScopedEnv junk("CLVIS_TUNE_WORKLOAD", "tiny");
    Renderer r(device(), s);
    CHECK_THROWS_WITH(r.render(cam, 8, 8, Path::Raster),
                      Catch::Contains("CLVIS_TUNE_WORKLOAD") && Catch::Contains("tiny"));
}
