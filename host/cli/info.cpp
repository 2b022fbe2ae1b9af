// clvis info: what a mesh file holds (triangles, vertices, bounds, load time), or why it is bad.
#include "commands.hpp"

#include <clvis/clvis.hpp>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace clvis::cli {

void add_info_command(CLI::App& app)
{
    auto* cmd = app.add_subcommand("info", "Load mesh files and report what each holds.\n"
                                           "Example: clvis info scenes/stanford-bunny.obj scenes/spot.obj");
    auto files = std::make_shared<std::vector<std::string>>();
    cmd->add_option("files", *files, "mesh files (OBJ, PLY, STL)")->required();
    cmd->callback([files] {
        for (const auto& path : *files) {
            auto t0 = std::chrono::steady_clock::now();
            MeshData mesh = load_mesh(path);
            double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            Scene scene;
            scene.add_mesh(std::move(mesh));
            const auto& data = scene.meshes().front().data;
            Bounds b = scene.bounds();
            std::printf("%s\n", path.c_str());
            std::printf("    triangles  %zu\n", data.triangle_count());
            std::printf("    vertices   %zu%s\n", data.vertex_count(), data.normals.empty() ? "" : " (with normals)");
            std::printf("    bounds     [%g, %g, %g] .. [%g, %g, %g]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
            std::printf("    load       %.1f ms\n", ms);
        }
    });
}

} // namespace clvis::cli
