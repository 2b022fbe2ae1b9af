// The on-disk program cache (host/runtime/program_cache.hpp) on the test device: PoCL caches
// programs itself, so a program's binary is kept only once it has been built from source twice;
// later devices load it and render the same keys; a damaged binary is rebuilt from source.
#include "catch.hpp"
#include "test_files.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace clvis;

namespace {

/// Files in `dir` whose names end with `suffix`.
std::vector<std::filesystem::path> files_ending(const std::filesystem::path& dir, const std::string& suffix)
{
    std::vector<std::filesystem::path> out;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        std::string name = e.path().filename().string();
        if (name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
            out.push_back(e.path());
    }
    return out;
}

/// Both paths' buffers of spot from a device opened now (a new program cache in memory each time).
std::vector<HostVisibility> render_both()
{
    Device device = Device::open();
    Renderer r(device, test::scene_file("spot.obj"), RenderOptions{});
    Camera cam = test::look({1.6, 0.9, 2.2}, {0, 0.3, 0}, 40, 0.1, 20);
    return {r.render(cam, 48, 32, Path::Raster).read(), r.render(cam, 48, 32, Path::Ray).read()};
}

void check_same(const std::vector<HostVisibility>& a, const std::vector<HostVisibility>& b)
{
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        CHECK(a[k].ids == b[k].ids);
        CHECK(std::memcmp(a[k].depth.data(), b[k].depth.data(), a[k].depth.size() * sizeof(float)) == 0);
    }
}

} // namespace

TEST_CASE("programs built from source twice are kept and loaded; a damaged binary is rebuilt",
          "[device][pocl]")
{
    std::filesystem::path dir = test::fresh_temp_dir("clvis-program-cache");
    test::ScopedEnv env("CLVIS_CACHE_DIR", dir.string().c_str());

    auto first = render_both();
    CHECK(files_ending(dir, ".bin").empty()); // PoCL's own cache serves a first build
    CHECK_FALSE(files_ending(dir, ".seen").empty());

    auto second = render_both();
    auto binaries = files_ending(dir, ".bin");
    CHECK(binaries.size() >= 5); // the raster path's four programs and ray_trace at least
    for (auto b : binaries) CHECK(std::filesystem::exists(b.replace_extension(".seen")));
    check_same(first, second);

    // Loaded from the binaries: the same keys.
    check_same(first, render_both());

    // Damaged binaries: the driver refuses them and the programs are built from source again.
    for (const auto& b : binaries) std::ofstream(b, std::ios::binary | std::ios::trunc) << "not a program";
    check_same(first, render_both());
}
