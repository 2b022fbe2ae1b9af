// Run under mpirun (tests/CMakeLists.txt: 2 and 3 ranks): every distribution mode, on the bundled
// meshes and a procedural scene, by both paths, must give the keys of one process rendering
// everything, bit for bit: screen and scene on rank 0; frames on the rank of each view, every view
// rendered by exactly one rank. Exits non-zero naming the first case that differs.
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>
#include <clvis/dist.hpp>
#include <clvis/procedural.hpp>
#include <clvis/scene_io.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

using namespace clvis;

namespace {

using test::Case;

std::vector<Case> cases()
{
    std::vector<Case> out;
    for (const char* name : {"spot", "suzanne", "teapot"}) {
        Scene s;
        s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + name + ".obj"));
        Camera c = Camera::framing(s.bounds());
        out.push_back({name, s, c, 157, 93});
    }
    Scene soup;
    soup.add_mesh(make_soup(5000, 3));
    soup.add_mesh(make_uv_sphere(1200));
    soup.add_mesh(make_grid(2000, 5));
    out.push_back({"procedural", soup, Camera::framing(soup.bounds()), 101, 67});
    return out;
}

/// Compares on rank 0; returns the number of differing keys (0 elsewhere).
std::size_t differing(const std::vector<std::uint64_t>& got, const std::vector<std::uint64_t>& want)
{
    if (got.size() != want.size()) return want.size() + 1;
    std::size_t n = 0;
    for (std::size_t i = 0; i < got.size(); ++i) n += got[i] != want[i];
    return n;
}

/// Views around the case's camera: its own, orbits of its eye about the target, and one from above.
std::vector<Camera> views_of(const Camera& c, int count)
{
    std::vector<Camera> out;
    Vec3 d = c.eye - c.target;
    for (int k = 0; k < count; ++k) {
        double a = 2.399963 * k; // the golden angle: no two views alike
        Camera v = c;
        v.eye = c.target + Vec3{d.x * std::cos(a) + d.z * std::sin(a), d.y + 0.1 * k, d.z * std::cos(a) - d.x * std::sin(a)};
        out.push_back(v);
    }
    return out;
}

/// Frames on `ranks` ranks: each view on its rank against this process rendering it alone, and
/// every view rendered by exactly one rank. Returns the number of failures (on every rank).
int check_frames(MPI_Comm comm, Renderer& whole, const Case& c, Path path)
{
    std::vector<Camera> views = views_of(c.camera, 7);
    std::vector<int> seen(views.size(), 0), seen_all(views.size(), 0);
    std::vector<std::uint64_t> got;
    int failures = 0;
    dist::render_frames(comm, whole, views, c.width, c.height, path, [&](int v, const VisibilityBuffer& vis) {
        ++seen[std::size_t(v)];
        vis.read_keys(got);
        std::size_t bad = differing(got, whole.render(views[std::size_t(v)], c.width, c.height, path).read_keys());
        if (bad) {
            ++failures;
            std::fprintf(stderr, "dist_check: %s, %s path, frames mode, view %d: %zu keys differ\n", c.name.c_str(),
                         to_string(path), v, bad);
        }
    });
    MPI_Allreduce(seen.data(), seen_all.data(), int(seen.size()), MPI_INT, MPI_SUM, comm);
    for (std::size_t v = 0; v < views.size(); ++v)
        if (seen_all[v] != 1) {
            ++failures;
            std::fprintf(stderr, "dist_check: %s, frames mode: view %zu rendered by %d ranks\n", c.name.c_str(), v,
                         seen_all[v]);
        }
    return failures;
}

int run(MPI_Comm comm)
{
    int rank = 0, ranks = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &ranks);
    Device device = Device::open();
    int failures = 0, checked = 0;
    for (const Case& c : cases()) {
        Renderer whole(device, c.scene);
        dist::Share share = dist::share_of(c.scene.triangle_count(), rank, ranks);
        std::unique_ptr<Renderer> part;
        if (share.size() > 0) part = std::make_unique<Renderer>(device, dist::scene_part(c.scene, share));
        for (Path path : {Path::Raster, Path::Ray}) {
            std::vector<std::uint64_t> want;
            if (rank == 0) want = whole.render(c.camera, c.width, c.height, path).read_keys();
            auto screen = dist::render_screen(comm, whole, c.camera, c.width, c.height, path);
            auto scene = dist::render_scene(comm, part.get(), std::uint32_t(share.first), c.camera, c.width, c.height,
                                            path);
            failures += check_frames(comm, whole, c, path);
            ++checked;
            if (rank != 0) continue;
            for (auto [mode, got] : {std::pair{"screen", &screen}, std::pair{"scene", &scene}}) {
                std::size_t bad = differing(*got, want);
                ++checked;
                if (bad) {
                    ++failures;
                    std::fprintf(stderr, "dist_check: %s, %s path, %s mode on %d ranks: %zu keys differ\n",
                                 c.name.c_str(), to_string(path), mode, ranks, bad);
                }
            }
        }
    }
    if (rank == 0) std::printf("dist_check: %d ranks, %d cases, %d differ\n", ranks, checked, failures);
    return failures;
}

} // namespace

int main(int argc, char** argv)
{
    MPI_Init(&argc, &argv);
    int failures = 1;
    try {
        failures = run(MPI_COMM_WORLD);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dist_check: %s\n", e.what());
        MPI_Abort(MPI_COMM_WORLD, 2);
    }
    int any = 0;
    MPI_Allreduce(&failures, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return any ? 1 : 0;
}
