// clvis info: what a mesh file holds (triangles, vertices, bounds, load time; for glTF also its
// items, shared meshes and what was skipped), or what a scene file describes (its meshes, the
// camera and image size that render would use), or why it is bad.
#include "commands.hpp"
#include "options.hpp"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <optional>
#include <cstdio>
#include <string>
#include <vector>

namespace clvis::cli {

namespace {

void print_bounds(const Bounds& b, const char* label)
{
    std::printf("    %-10s [%g, %g, %g] .. [%g, %g, %g]\n", label, b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
}

/// "uv (2), color (4)": a mesh's attributes, names and components.
std::string attribute_list(const MeshData& m)
{
    std::string s;
    for (const CornerAttribute& a : m.attributes)
        s += (s.empty() ? "" : ", ") + a.name + " (" + std::to_string(a.components) + ")";
    return s;
}

bool is_gltf(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".gltf" || ext == ".glb";
}

void mesh_info(const std::string& path)
{
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
    std::printf("%s\n", path.c_str());
    std::printf("    triangles  %zu\n", scene.triangle_count());
    std::printf("    vertices   %zu%s\n", scene.vertex_count(), normals ? " (with normals)" : "");
    if (gltf) {
        std::printf("    glTF       %zu items of %zu meshes\n", gltf->items.size(), gltf->meshes.size());
        for (const std::string& note : gltf->notes) std::printf("    note       %s\n", note.c_str());
        for (const MeshData& m : gltf->meshes)
            if (!m.attributes.empty()) // "<file> meshes[0].primitives[1]": the glTF path after the file
                std::printf("    attributes %s: %s\n", m.name.substr(std::min(m.name.size(), path.size() + 1)).c_str(),
                            attribute_list(m).c_str());
    } else if (!scene.meshes().front().data.attributes.empty()) {
        std::printf("    attributes %s\n", attribute_list(scene.meshes().front().data).c_str());
    }
    print_bounds(scene.bounds(), "bounds");
    std::printf("    load       %.1f ms\n", ms);
}

/// A scene file as render reads it: with no flags, this size and this camera.
void scene_file_info(const std::string& path)
{
    auto t0 = std::chrono::steady_clock::now();
    SceneFile file = load_scene_file(path);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    View view = resolve_view(CameraOptions{}, file, path);
    std::printf("%s (scene file)\n", path.c_str());
    for (std::size_t k = 0; k < file.scene.meshes().size(); ++k) {
        const auto& m = file.scene.meshes()[k];
        std::string attributes = attribute_list(file.scene.data_of(k));
        std::printf("    mesh       %s: %zu triangles%s%s%s\n", m.data.name.c_str(), m.data.triangle_count(),
                    m.transform.is_identity() ? "" : ", transformed", attributes.empty() ? "" : ", attributes ",
                    attributes.c_str());
    }
    std::printf("    triangles  %zu\n", file.scene.triangle_count());
    std::printf("    vertices   %zu\n", file.scene.vertex_count());
    print_bounds(file.scene.bounds(), "bounds");
    std::printf("    size       %dx%d%s\n", view.width, view.height,
                file.width || file.height ? "" : " (not given: the default)");
    std::printf("    camera     %s%s\n", view.framed ? "framing: " : "", view.camera.to_flags().c_str());
    std::printf("    load       %.1f ms\n", ms);
}

} // namespace

void add_info_command(CLI::App& app)
{
    auto* cmd = app.add_subcommand("info", "Load mesh files or scene files and report what each holds.\n"
                                           "Example: clvis info scenes/stanford-bunny.obj scenes/spot.obj");
    auto files = std::make_shared<std::vector<std::string>>();
    cmd->add_option("files", *files, std::string(mesh_files_help) + " or scene files (.json)")->required();
    cmd->callback([files] {
        for (const auto& path : *files) {
            if (is_scene_file(path)) scene_file_info(path);
            else mesh_info(path);
        }
    });
}

} // namespace clvis::cli
