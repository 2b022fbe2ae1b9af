// The minimal clvis program: load a mesh, frame it, render it by rasterization and by ray
// casting, check that both see the same thing, and write a PNG of each.
//
//   minimal MESH [OUT_PREFIX]
#include <clvis/clvis.hpp>

#include <cstdio>

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s MESH [OUT_PREFIX]\n", argv[0]);
        return 2;
    }
    std::string prefix = argc > 2 ? argv[2] : "minimal";
    try {
        clvis::Scene scene;
        scene.add_mesh(clvis::load_mesh(argv[1]));
        clvis::Camera camera = clvis::Camera::framing(scene.bounds());
        const int width = 640, height = 480;

        clvis::Device device = clvis::Device::open(); // CLVIS_DEVICE, else first GPU, else CPU
        clvis::Renderer renderer(device, scene);
        clvis::VisibilityBuffer raster = renderer.render(camera, width, height, clvis::Path::Raster);
        clvis::VisibilityBuffer ray = renderer.render(camera, width, height, clvis::Path::Ray);

        clvis::Referee referee(scene, camera, width, height);
        clvis::CompareReport report = referee.compare(raster.read(), ray.read());
        std::printf("%zu triangles on %s: %zu pixels equal, %zu explained, %zu errors\n", scene.triangle_count(),
                    device.info().name.c_str(), report.equal, report.explained, report.errors);
#if CLVIS_WITH_IMAGE_IO
        clvis::write_image(prefix + "-raster.png", clvis::shade(renderer, raster, camera));
        clvis::write_image(prefix + "-ray.png", clvis::shade(renderer, ray, camera));
#endif
        return report.errors == 0 ? 0 : 1;
    } catch (const clvis::Error& e) {
        std::fprintf(stderr, "minimal: %s\n", e.what());
        return 1;
    }
}
