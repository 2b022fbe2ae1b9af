// clvis info: what a mesh file holds (triangles, vertices, bounds, load time; for glTF also its
// items, shared meshes and what was skipped), or why it is bad.
#include "commands.hpp"

#include <clvis/clvis.hpp>

#include <cctype>
#include <chrono>
#include <filesystem>
#include <optional>
#include <cstdio>
#include <string>
#include <vector>

namespace clvis::cli {

namespace {

bool is_gltf(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".gltf" || ext == ".glb";
}

} // namespace

void add_info_command(CLI::App& app)
{
    auto* cmd = app.add_subcommand("info", "Load mesh files and report what each holds.\n"
                                           "Example: clvis info scenes/stanford-bunny.obj scenes/spot.obj");
    auto files = std::make_shared<std::vector<std::string>>();
    cmd->add_option("files", *files, "mesh files (OBJ, PLY, STL, glTF 2.0: .gltf, .glb)")->required();
    cmd->callback([files] {
        for (const auto& path : *files) {
            auto t0 = std::chrono::steady_clock::now();
            std::optional<GltfScene> gltf;
            Scene scene;
            if (is_gltf(path)) {
                gltf = load_gltf(path);
                add_gltf(scene, *gltf);
            } else {
                scene.add_mesh(load_mesh(path));
            }
            double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            bool normals = !gltf && !scene.meshes().front().data.normals.empty();
            Bounds b = scene.bounds();
            std::printf("%s\n", path.c_str());
            std::printf("    triangles  %zu\n", scene.triangle_count());
            std::printf("    vertices   %zu%s\n", scene.vertex_count(), normals ? " (with normals)" : "");
            if (gltf) {
                std::printf("    glTF       %zu items of %zu meshes\n", gltf->items.size(), gltf->meshes.size());
                for (const std::string& note : gltf->notes) std::printf("    note       %s\n", note.c_str());
            }
            std::printf("    bounds     [%g, %g, %g] .. [%g, %g, %g]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
            std::printf("    load       %.1f ms\n", ms);
        }
    });
}

} // namespace clvis::cli
