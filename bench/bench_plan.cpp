// The benchmark's sweep and its close-up camera (see bench_plan.hpp).
#include "bench_plan.hpp"

#include <clvis/error.hpp>
#include <clvis/procedural.hpp>
#include <clvis/scene_io.hpp>

#include <algorithm>
#include <filesystem>
#include <optional>

namespace clvis::bench {

namespace {

namespace fs = std::filesystem;

/// Folders that may hold the bundled meshes: ./scenes, then the source tree's.
std::vector<fs::path> scene_dirs()
{
    std::vector<fs::path> dirs{fs::path("scenes")};
#ifdef CLVIS_BENCH_SOURCE_DIR
    dirs.push_back(fs::path(CLVIS_BENCH_SOURCE_DIR) / "scenes");
#endif
    return dirs;
}

std::optional<fs::path> find_scene_dir()
{
    for (const auto& d : scene_dirs()) {
        std::error_code ec;
        if (fs::is_regular_file(d / "stanford-bunny.obj", ec)) return d;
    }
    return std::nullopt;
}

Scene scene_of(MeshData mesh)
{
    Scene s;
    s.add_mesh(std::move(mesh));
    return s;
}

/// The mesh named `file` from the scenes folder, or a scene whose loading throws that it is missing.
std::function<Scene()> mesh_file(const std::optional<fs::path>& dir, const std::string& file)
{
    return [dir, file] {
        if (!dir)
            throw Error(Error::Kind::Io, file + ": no scenes folder found (looked in ./scenes and the source tree)");
        return scene_of(load_mesh((*dir / file).string()));
    };
}

std::string count_label(std::size_t n)
{
    if (n >= (1u << 20) && n % (1u << 20) == 0) return std::to_string(n >> 20) + "M";
    if (n >= 1024 && n % 1024 == 0) return std::to_string(n >> 10) + "k";
    return std::to_string(n);
}

} // namespace

std::vector<Workload> plan(bool quick)
{
    std::optional<fs::path> dir = find_scene_dir();
    std::vector<Workload> w;
    const ViewSpec hd_triangles{false, 1920, 1080, {"triangles"}};
    std::vector<std::size_t> sphere_counts = quick ? std::vector<std::size_t>{1u << 10, 1u << 16}
                                                   : std::vector<std::size_t>{1u << 10, 1u << 12, 1u << 14, 1u << 16,
                                                                              1u << 18, 1u << 20, 1u << 22};
    for (std::size_t n : sphere_counts)
        w.push_back({"sphere-" + count_label(n), [n] { return scene_of(make_uv_sphere(n)); }, {hd_triangles}});
    if (!quick)
        for (std::size_t n : {std::size_t(1) << 16, std::size_t(1) << 20}) {
            w.push_back({"grid-" + count_label(n), [n] { return scene_of(make_grid(n, 7)); }, {hd_triangles}});
            w.push_back({"soup-" + count_label(n), [n] { return scene_of(make_soup(n, 7)); }, {hd_triangles}});
        }

    Workload bunny{"stanford-bunny", mesh_file(dir, "stanford-bunny.obj"), {}};
    bunny.views.push_back({false, 1920, 1080, {"mesh", "resolution"}});
    bunny.views.push_back({true, 1920, 1080, {"mesh"}});
    std::vector<std::pair<int, int>> sizes = quick ? std::vector<std::pair<int, int>>{{640, 480}}
                                                   : std::vector<std::pair<int, int>>{{256, 256},
                                                                                      {640, 480},
                                                                                      {1280, 720},
                                                                                      {2560, 1440},
                                                                                      {3840, 2160}};
    for (auto [width, height] : sizes) bunny.views.push_back({false, width, height, {"resolution"}});
    w.push_back(bunny);

    std::vector<std::string> others;
    if (dir) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(*dir, ec)) {
            std::string ext = entry.path().extension().string();
            std::string name = entry.path().filename().string();
            if ((ext == ".obj" || ext == ".ply" || ext == ".stl") && name != "stanford-bunny.obj") others.push_back(name);
        }
        std::sort(others.begin(), others.end());
    }
    if (quick) others.erase(std::remove_if(others.begin(), others.end(),
                                           [](const std::string& n) { return n != "suzanne.obj"; }),
                            others.end());
    for (const auto& name : others) {
        Workload m{fs::path(name).stem().string(), mesh_file(dir, name), {}};
        m.views.push_back({false, 1920, 1080, {"mesh"}});
        if (!quick) m.views.push_back({true, 1920, 1080, {"mesh"}});
        if (name == "suzanne.obj") m.views.push_back({false, quick ? 192 : 256, quick ? 108 : 144, {"brute"}});
        w.push_back(m);
    }
    if (!quick) w[0].views.push_back({false, 256, 144, {"brute"}}); // the 1k sphere
    return w;
}

Camera closeup_of(const Camera& framing, const Bounds& bounds)
{
    Camera c = framing;
    double dist = length(framing.eye - framing.target) * closeup_fraction;
    double radius = length(bounds.extent()) / 2;
    c.eye = framing.target + normalize(framing.eye - framing.target) * dist;
    c.near = closeup_near_fraction * dist;
    c.far = 1.1 * (dist + radius);
    return c;
}

} // namespace clvis::bench
