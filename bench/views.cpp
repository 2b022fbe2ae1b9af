// Times many views per call against the sum of the batch's kernel times and against a loop of
// single renders: VIEWS views of the bunny around it at SIZE x SIZE, on each path.
// Usage: clvis_views [MESH [VIEWS [SIZE [REPEAT]]]] (defaults: scenes/stanford-bunny.obj 64 256 5).
#include <clvis/clvis.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace clvis;

int main(int argc, char** argv)
{
    std::string mesh = argc > 1 ? argv[1] : std::string(CLVIS_BENCH_SOURCE_DIR) + "/scenes/stanford-bunny.obj";
    int views = argc > 2 ? std::atoi(argv[2]) : 64, size = argc > 3 ? std::atoi(argv[3]) : 256;
    int repeat = argc > 4 ? std::atoi(argv[4]) : 5;
    try {
        Scene scene;
        scene.add_mesh(load_mesh(mesh));
        Device device = Device::open();
        Renderer renderer(device, scene);
        Camera framing = Camera::framing(scene.bounds());
        Vec3 c = scene.bounds().center(), d = framing.eye - c;
        std::vector<Camera> cams;
        for (int i = 0; i < views; ++i) {
            double a = 2 * 3.14159265358979323846 * i / views;
            Camera cam = framing;
            cam.eye = c + Vec3{d.x * std::cos(a) - d.z * std::sin(a), d.y, d.x * std::sin(a) + d.z * std::cos(a)};
            cams.push_back(cam);
        }
        VisibilityBatch batch(device, views, size, size);
        VisibilityBuffer single(device, size, size);
        std::printf("%s, %zu triangles, %d views at %dx%d, best of %d:\n", device.info().name.c_str(),
                    scene.triangle_count(), views, size, size, repeat);
        for (Path p : {Path::Ray, Path::Raster}) {
            render_views(renderer, cams, p, batch); // warm-up: first launches compile
            renderer.render(cams[0], p, single);
            double batch_ms = 1e300, kernels_ms = 0, loop_ms = 1e300, loop_kernels_ms = 0;
            for (int r = 0; r < repeat; ++r) {
                render_views(renderer, cams, p, batch);
                if (renderer.last_frame().frame_ms < batch_ms) {
                    batch_ms = renderer.last_frame().frame_ms;
                    kernels_ms = 0;
                    for (const auto& s : renderer.last_frame().stages) kernels_ms += s.ms;
                }
                auto t0 = std::chrono::steady_clock::now();
                double k = 0;
                for (const Camera& cam : cams) {
                    renderer.render(cam, p, single);
                    for (const auto& s : renderer.last_frame().stages) k += s.ms;
                }
                double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                if (ms < loop_ms) {
                    loop_ms = ms;
                    loop_kernels_ms = k;
                }
            }
            std::printf("  %-6s batch %8.2f ms (%7.1f views/s), its kernels %8.2f ms: batch / kernels %.2fx\n",
                        to_string(p), batch_ms, views * 1000 / batch_ms, kernels_ms, batch_ms / kernels_ms);
            std::printf("  %-6s loop  %8.2f ms (%7.1f views/s), its kernels %8.2f ms: loop / batch %.2fx\n",
                        to_string(p), loop_ms, views * 1000 / loop_ms, loop_kernels_ms, loop_ms / batch_ms);
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "clvis_views: %s\n", e.what());
        return 1;
    }
    return 0;
}
