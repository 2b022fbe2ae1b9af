// A second OpenCL implementation against the first: the bundled meshes drawn by both paths (and,
// on a device with 64-bit atomics, both raster depth tests) on the pinned device (CLVIS_DEVICE)
// and on a reference device (CLVIS_REFERENCE_DEVICE, PoCL in the rusticl CTest). Every pixel of
// the pinned device's buffers is judged by the referee (0 errors, ids and depths); its keys equal
// the reference's bit for bit where both devices round single-precision division and square root
// correctly, and the keys that differ are counted and printed otherwise (OpenCL allows 2.5 ulp).
// Hidden ([.reference]): run by the rusticl CTest, which names the two devices.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace clvis;

namespace {

struct Drawn {
    std::string frame; ///< mesh, camera and path
    std::string mode;  ///< the raster depth test as the device resolved it ("atomics", "tiles"), or "bvh"
    std::vector<std::uint64_t> keys;
};

/// Every frame of the comparison on `device`: bundled meshes, framing and a close camera that cuts
/// near, at an odd size, by each path and each raster depth test the device offers.
std::vector<Drawn> draw_all(const Device& device, const std::vector<Scene>& scenes, const std::vector<std::string>& names,
                            int w, int h, bool judge)
{
    std::vector<Drawn> out;
    for (std::size_t m = 0; m < scenes.size(); ++m) {
        const Scene& s = scenes[m];
        Bounds b = s.bounds();
        double r = length(b.extent()) / 2;
        Camera close = Camera::perspective(b.center() + Vec3{0.3, 0.2, 1} * (0.8 * r), b.center(), {0, 1, 0}, 70,
                                           0.3 * r, 4 * r);
        std::vector<std::pair<std::string, Camera>> cams = {{"framing", Camera::framing(b)},
                                                            {"ortho", Camera::framing(b, Projection::Orthographic)},
                                                            {"close", close}};
        RenderOptions off;
        off.raster_atomics = RasterAtomics::Off;
        std::vector<std::pair<std::string, RenderOptions>> modes = {
            {device.info().int64_atomics ? "atomics" : "tiles", RenderOptions{}}};
        if (device.info().int64_atomics) modes.push_back({"tiles", off});
        for (std::size_t k = 0; k < modes.size(); ++k) {
            Renderer renderer(device, s, modes[k].second);
            for (auto& [cam_name, cam] : cams) {
                std::vector<Path> paths = {Path::Raster};
                if (k == 0) paths.push_back(Path::Ray);
                for (Path p : paths) {
                    std::string frame = names[m] + " " + cam_name + " " + to_string(p);
                    std::string mode = p == Path::Ray ? "bvh" : modes[k].first;
                    std::string what = frame + " (" + mode + ")";
                    VisibilityBuffer vis = renderer.render(cam, w, h, p);
                    out.push_back({frame, mode, vis.read_keys()});
                    if (!judge) continue;
                    CompareReport r = Referee(s, cam, w, h).check(vis.read());
                    INFO(what << " on " << device.info().name << ": " << r.errors << " errors, " << r.depth_errors
                              << " depth errors" << (r.first_errors.empty() ? "" : "; " + r.first_errors[0].describe()));
                    CHECK(r.errors == 0);
                    CHECK(r.depths_judged);
                    CHECK(r.depth_errors == 0);
                }
            }
        }
    }
    return out;
}

} // namespace

TEST_CASE("a second device passes the referee and gives the reference device's keys", "[.reference]")
{
    const char* spec = std::getenv("CLVIS_REFERENCE_DEVICE");
    REQUIRE(spec != nullptr); // the CTest that runs this names the reference
    Device pinned = Device::open();
    Device reference = Device::open(spec);
    REQUIRE(pinned.info().name + pinned.info().platform != reference.info().name + reference.info().platform);
    std::vector<std::string> names = {"spot", "suzanne", "teapot"};
    std::vector<Scene> scenes;
    for (const auto& n : names) {
        scenes.emplace_back();
        scenes.back().add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + n + ".obj"));
    }
    const int w = 123, h = 77;
    std::vector<Drawn> got = draw_all(pinned, scenes, names, w, h, true);
    std::vector<Drawn> want = draw_all(reference, scenes, names, w, h, false);
    bool exact = pinned.info().correctly_rounded_divide_sqrt && reference.info().correctly_rounded_divide_sqrt;
    std::printf("reference: %s (%s) against %s (%s); division and square root correctly rounded on both: %s\n",
                pinned.info().name.c_str(), pinned.info().platform.c_str(), reference.info().name.c_str(),
                reference.info().platform.c_str(), exact ? "yes" : "no");
    std::size_t compared = 0;
    for (const Drawn& g : got)
        for (const Drawn& r : want) {
            // Every raster depth test of either device gives the same keys: compare each with each.
            if (g.frame != r.frame) continue;
            std::size_t differ = 0, ids_differ = 0;
            for (std::size_t i = 0; i < g.keys.size(); ++i) {
                differ += g.keys[i] != r.keys[i];
                ids_differ += std::uint32_t(g.keys[i]) != std::uint32_t(r.keys[i]);
            }
            std::printf("reference %-24s %-7s against %-7s %zu keys differ (%zu ids) of %zu\n", g.frame.c_str(),
                        g.mode.c_str(), r.mode.c_str(), differ, ids_differ, g.keys.size());
            INFO(g.frame << " (" << g.mode << ") against the reference's (" << r.mode << ")");
            if (exact) CHECK(differ == 0);
            ++compared;
        }
    CHECK(compared >= got.size());
}

TEST_CASE("the devices of the platform CLVIS_COUNT_PLATFORM names are counted", "[.count_devices]")
{
    // The rusticl CTest's probe: it skips, saying why, where the count is 0.
    const char* platform = std::getenv("CLVIS_COUNT_PLATFORM");
    REQUIRE(platform != nullptr);
    std::string wanted = platform;
    std::size_t n = 0;
    for (const DeviceInfo& d : list_devices()) n += d.platform.find(wanted) != std::string::npos;
    std::printf("clvis devices on platform '%s': %zu\n", platform, n);
}
