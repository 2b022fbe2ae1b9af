// The mapping tuners on Oclgrind's simulated device (issue 34): with an empty tune cache and no
// CLVIS_TUNE_*_MAPPING forcing, a Renderer's first raster frame measures RasterMapping::Auto (a
// Renderer per candidate: square, then pixel) and its first ray frame RayMapping::Auto (packet,
// then single), each on the tuning workload, then draws the frame with the chosen mapping; the
// keys must equal PoCL's under that mapping. Run by its own CTest entry ("oclgrind_tune", with
// CLVIS_TUNE_WORKLOAD=small and tests/oclgrind/keep_buffers.c preloaded), which fails on any report.
#include "catch.hpp"
#include "test_files.hpp"

#include <clvis/clvis.hpp>

#include <string>

using namespace clvis;

TEST_CASE("both mapping tuners measure on Oclgrind from an empty cache and run clean", "[.oclgrind_tune]")
{
    auto folder = test::fresh_temp_dir("clvis-oclgrind-tune-cache");
    test::ScopedEnv dir("CLVIS_CACHE_DIR", folder.c_str()), cache("CLVIS_TUNE_CACHE", nullptr),
        raster("CLVIS_TUNE_RASTER_MAPPING", nullptr), ray("CLVIS_TUNE_RAY_MAPPING", nullptr);
    Device grind = Device::open("oclgrind"), pocl = Device::open("portable computing language");
    REQUIRE(grind.info().name.find("Oclgrind") != std::string::npos);
    Scene s;
    s.add_mesh(make_uv_sphere(240));
    Camera cam = Camera::framing(s.bounds());
    const int w = 41, h = 29;

    {
        // A Renderer that lived and died first, as in a program that drew a preview, or in the
        // tuner itself (a Renderer per candidate): the tuners' buffers take the indices Oclgrind
        // hands out again (keep_buffers.c says why that matters there).
        RenderOptions named;
        named.raster_mapping = RasterMapping::Square;
        named.ray_mapping = RayMapping::Packet;
        Renderer preview(grind, s, named);
        CHECK(preview.render(cam, 13, 9, Path::Raster).read_keys().size() == 13 * 9);
        CHECK(preview.render(cam, 13, 9, Path::Ray).read_keys().size() == 13 * 9);
    }
    Renderer on_grind(grind, s); // RenderOptions' defaults: both mappings Auto
    auto raster_keys = on_grind.render(cam, w, h, Path::Raster).read_keys();
    RasterMappingChoice rm = on_grind.raster_mapping();
    CHECK(rm.source == "measured");
    CHECK((rm.square_ms > 0 && rm.pixel_ms > 0));
    auto ray_keys = on_grind.render(cam, w, h, Path::Ray).read_keys();
    RayMappingChoice ym = on_grind.ray_mapping();
    CHECK(ym.source == "measured");
    CHECK((ym.packet_ms > 0 && ym.single_ms > 0));
    INFO("raster " << to_string(rm.mapping) << ", ray " << to_string(ym.mapping));

    RenderOptions chosen;
    chosen.raster_mapping = rm.mapping;
    chosen.ray_mapping = ym.mapping;
    Renderer on_pocl(pocl, s, chosen);
    CHECK(raster_keys == on_pocl.render(cam, w, h, Path::Raster).read_keys());
    CHECK(ray_keys == on_pocl.render(cam, w, h, Path::Ray).read_keys());
}
