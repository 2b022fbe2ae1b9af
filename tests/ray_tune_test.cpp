// RayMapping::Auto on the test device: it traces the keys of both fixed mappings (frames, views,
// a tree built first for ray queries), measures once per key (device, coverage mode) and then
// reads the cache, measures nothing for the brute path, and can be forced or bypassed. Each case
// points the cache at a fresh folder of its own.
#include "catch.hpp"
#include "test_files.hpp"
#include "test_meshes.hpp"

#include "render/ray_tune.hpp"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

using namespace clvis;

namespace {

Device& device()
{
    static Device d = Device::open();
    return d;
}

Camera spot_camera() { return test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20); }

/// The mapping a Renderer under `o` runs, resolved by its first ray frame. When `measured`, checks
/// that it was measured now: both times known, the faster mapping chosen.
RayMappingChoice resolved(const Scene& s, RenderOptions o, bool measured = false)
{
    Renderer r(device(), s, o);
    r.render(spot_camera(), 32, 24, Path::Ray);
    RayMappingChoice c = r.ray_mapping();
    if (measured) {
        CHECK(c.source == "measured");
        CHECK((c.packet_ms > 0 && c.single_ms > 0));
        CHECK(c.mapping == (c.single_ms < c.packet_ms ? RayMapping::Single : RayMapping::Packet));
    }
    return c;
}

} // namespace

TEST_CASE("the auto ray mapping traces the keys of both fixed mappings", "[device][ray]")
{
    test::ScopedEnv dir("CLVIS_CACHE_DIR", test::fresh_temp_dir("clvis-ray-tune-keys").c_str());
    Scene s = test::scene_file("spot.obj");
    RenderOptions o;
    REQUIRE(o.ray_mapping == RayMapping::Auto);
    for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
        o.coverage = coverage;
        std::vector<std::uint64_t> want; // the packets', then the same from the others
        for (RayMapping m : {RayMapping::Packet, RayMapping::Single, RayMapping::Auto}) {
            o.ray_mapping = m;
            Renderer r(device(), s, o);
            std::vector<std::uint64_t> keys = r.render(spot_camera(), 97, 61, Path::Ray).read_keys();
            if (want.empty()) want = keys;
            CHECK(keys == want);
            CHECK(r.ray_mapping().mapping != RayMapping::Auto);
        }
        CHECK(std::count_if(want.begin(), want.end(), [](std::uint64_t k) { return std::uint32_t(k) != background_id; }) >
              1000);
    }
}

TEST_CASE("the auto ray mapping applies to views and to a tree built for queries", "[device][ray]")
{
    test::ScopedEnv dir("CLVIS_CACHE_DIR", test::fresh_temp_dir("clvis-ray-tune-late").c_str());
    Scene s = test::scene_file("spot.obj");
    RenderOptions packet;
    packet.ray_mapping = RayMapping::Packet;
    std::vector<std::uint64_t> want = Renderer(device(), s, packet).render(spot_camera(), 45, 33, Path::Ray).read_keys();
    for (const char* forced : {"packet", "single"}) {
        test::ScopedEnv force("CLVIS_TUNE_RAY_MAPPING", forced);
        Renderer r(device(), s);
        RayQuery query(r); // builds the tree, and the packet kernel, before any mapping is chosen
        CHECK(r.render(spot_camera(), 45, 33, Path::Ray).read_keys() == want);
        CHECK(to_string(r.ray_mapping().mapping) == std::string(forced));
        Renderer views(device(), s);
        VisibilityBatch batch(device(), 2, 45, 33);
        render_views(views, {spot_camera(), spot_camera()}, Path::Ray, batch);
        CHECK(batch.view(1).read_keys() == want);
        CHECK(views.ray_mapping().source == "forced");
    }
}

TEST_CASE("the auto ray mapping is measured once per key, then read from the cache", "[device][ray]")
{
    auto folder = test::fresh_temp_dir("clvis-ray-tune-cache");
    test::ScopedEnv dir("CLVIS_CACHE_DIR", folder.c_str()), cache("CLVIS_TUNE_CACHE", nullptr),
        force("CLVIS_TUNE_RAY_MAPPING", nullptr);
    Scene s = test::scene_file("spot.obj");
    RenderOptions o;
    std::filesystem::path file =
        detail::tune_file(folder, "ray_mapping", detail::ray_mapping_request(device(), o).key);
    Renderer(device(), s, o).render(spot_camera(), 32, 24, Path::Brute); // the brute path needs no mapping
    CHECK_FALSE(std::filesystem::exists(file));

    RayMappingChoice first = resolved(s, o, true);
    CHECK(std::filesystem::exists(file));
    RayMappingChoice again = resolved(s, o);
    CHECK(again.source == "cache");
    CHECK(again.mapping == first.mapping);
    CHECK(again.packet_ms == first.packet_ms);
    CHECK(again.single_ms == first.single_ms);
    o.coverage = Coverage::RasterRule; // another key
    resolved(s, o, true);
    CHECK(resolved(s, o).source == "cache");
    std::vector<TunedChoice> tuned = tuned_choices(device().info());
    CHECK(std::count_if(tuned.begin(), tuned.end(), [](const TunedChoice& t) {
              return t.name == "ray_mapping" && t.times_ms.size() == 2;
          }) == 2); // one per coverage mode

    test::ScopedEnv off("CLVIS_TUNE_CACHE", "0");
    resolved(s, o, true);
}

TEST_CASE("the auto ray mapping can be forced, and a named mapping is kept", "[device][ray]")
{
    test::ScopedEnv dir("CLVIS_CACHE_DIR", test::fresh_temp_dir("clvis-ray-tune-force").c_str());
    Scene s = test::scene_file("spot.obj");
    struct Case {
        const char* variable;
        RayMapping option, runs;
        const char* source;
    };
    for (const Case& k : {Case{"single", RayMapping::Auto, RayMapping::Single, "forced"},
                          Case{"packet", RayMapping::Auto, RayMapping::Packet, "forced"},
                          Case{"single", RayMapping::Packet, RayMapping::Packet, "option"}}) {
        test::ScopedEnv force("CLVIS_TUNE_RAY_MAPPING", k.variable);
        RenderOptions o;
        o.ray_mapping = k.option;
        RayMappingChoice c = resolved(s, o);
        CHECK(c.mapping == k.runs);
        CHECK(c.source == k.source);
        CHECK((c.packet_ms == -1 && c.single_ms == -1));
    }
    test::ScopedEnv junk("CLVIS_TUNE_RAY_MAPPING", "rays");
    Renderer r(device(), s);
    CHECK_THROWS_WITH(r.ray_mapping(), Catch::Contains("CLVIS_TUNE_RAY_MAPPING") && Catch::Contains("rays"));
    CHECK_THROWS_WITH(r.render(spot_camera(), 8, 8, Path::Ray), Catch::Contains("CLVIS_TUNE_RAY_MAPPING"));
}
