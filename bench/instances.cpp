// Times a scene of many instances of one mesh (issue #20): COUNT copies of MESH on a square grid,
// each turned and scaled, rendered at SIZE x SIZE from above the grid. Prints the ray path's BVH
// build (prototype trees and top level), its device bytes, frame times, and the top level's
// rebuild after moving one instance; with --raster also the raster path's frames (drawn without
// the expansion, in chunks of instances) and its device bytes. Peak memory: run under
// /usr/bin/time -v.
// Usage: clvis_instances [COUNT [MESH [SIZE [FRAMES]]]] [--raster]
//        (defaults: 10000 scenes/stanford-bunny.obj 512 5).
#include "render/renderer_probe.hpp"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace clvis;

namespace {

double ms_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// Instance i of a side x side grid of cells `cell` wide: turned about y, scaled 0.8..1.
Mat4 placement(int i, int side, double cell, double turn)
{
    double a = 2.399963 * i + turn, s = 0.8 + 0.2 * ((i * 7919) % 101) / 100.0;
    double c = s * std::cos(a), n = s * std::sin(a);
    Mat4 m;
    m.m = {c, 0, n, cell * (i % side), 0, s, 0, 0, -n, 0, c, cell * (i / side), 0, 0, 0, 1};
    return m;
}

void frames(Renderer& r, const Camera& cam, int size, int count, Path path)
{
    std::vector<double> ms;
    for (int f = 0; f < count; ++f) {
        r.render(cam, size, size, path);
        ms.push_back(r.last_frame().frame_ms);
    }
    std::sort(ms.begin(), ms.end());
    std::printf("%s frames: median %.1f ms, min %.1f ms (%d frames, %dx%d)\n", to_string(path), ms[ms.size() / 2],
                ms.front(), count, size, size);
}

} // namespace

int main(int argc, char** argv)
{
    std::vector<std::string> args;
    bool raster = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--raster") == 0) raster = true;
        else args.push_back(argv[i]);
    }
    int count = args.size() > 0 ? std::atoi(args[0].c_str()) : 10000;
    std::string mesh = args.size() > 1 ? args[1] : std::string(CLVIS_BENCH_SOURCE_DIR) + "/scenes/stanford-bunny.obj";
    int size = args.size() > 2 ? std::atoi(args[2].c_str()) : 512;
    int frame_count = args.size() > 3 ? std::atoi(args[3].c_str()) : 5;
    try {
        MeshData m = load_mesh(mesh);
        Bounds b;
        for (std::size_t i = 0; i < m.positions.size(); i += 3) b.add({m.positions[i], m.positions[i + 1], m.positions[i + 2]});
        Vec3 ext = b.hi - b.lo;
        double cell = 1.5 * std::max(ext.x, ext.z);
        int side = int(std::ceil(std::sqrt(double(count))));
        Scene scene;
        std::size_t p = scene.add_prototype(m);
        for (int i = 0; i < count; ++i) scene.add_instance(p, placement(i, side, cell, 0));
        std::printf("%d instances of %s: %zu triangles as an expansion\n", count, mesh.c_str(), scene.triangle_count());
        double w = cell * side;
        Vec3 centre{w / 2, 0, w / 2};
        Camera cam = Camera::perspective({w / 2, w * 0.6, w * 1.2}, centre, {0, 1, 0}, 50, w * 0.01, w * 4);
        Device device = Device::open();
        auto t0 = std::chrono::steady_clock::now();
        Renderer r(device, scene);
        r.prepare(Path::Ray);
        const BvhStats& s = r.bvh_stats();
        std::printf("ray path ready in %.0f ms: BVH build %.1f ms (top level %.1f ms, %zu prototype trees), "
                    "%zu nodes, device bytes %llu\n",
                    ms_since(t0), s.build_ms, s.top_build_ms, s.prototype_builds, s.nodes,
                    (unsigned long long)s.device_bytes);
        frames(r, cam, size, frame_count, Path::Ray);
        for (int k = 1; k <= 3; ++k) {
            scene.set_transform(0, placement(0, side, cell, 0.5 * k));
            t0 = std::chrono::steady_clock::now();
            r.update(scene);
            std::printf("move one instance: update %.1f ms (top level %.1f ms, prototype trees built so far %zu)\n",
                        ms_since(t0), r.bvh_stats().top_build_ms, r.bvh_stats().prototype_builds);
        }
        frames(r, cam, size, frame_count, Path::Ray);
        if (raster) {
            frames(r, cam, size, frame_count, Path::Raster);
            std::printf("raster path: device bytes of the meshes and instance records %llu, expansion uploaded: %s\n",
                        (unsigned long long)detail::item_device_bytes(r), detail::expansion_uploaded(r) ? "yes" : "no");
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "clvis_instances: %s\n", e.what());
        return 1;
    }
    return 0;
}
