// Files into scenes: load_mesh reads a whole file and picks a parser (host/scene/scene_obj.cpp,
// scene_ply.cpp, scene_stl.cpp, scene_gltf.cpp) by extension, else by content; load_scene puts
// paths into one Scene (a glTF file's items each as a mesh with its transform, a JSON scene file
// through load_scene_file, host/scene/scene_file.cpp).
#include "lower_case.hpp"
#include "scene/scene_parsers.hpp"

#include <clvis/scene_io.hpp>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace clvis {

namespace detail {

std::string read_file(const std::string& path)
{
    std::error_code ec;
    auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
        fail(path, "cannot read: " + (ec ? ec.message() : std::string("no such file")));
    if (!std::filesystem::is_regular_file(status)) fail(path, "cannot read: not a regular file");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) fail(path, std::string("cannot open: ") + std::strerror(errno));
    std::string data;
    std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec) data.resize(std::size_t(size));
    std::size_t got = data.empty() ? 0 : std::fread(data.data(), 1, data.size(), f.get());
    data.resize(got);
    char buffer[65536]; // the file may have grown since it was measured
    while (std::size_t n = std::fread(buffer, 1, sizeof buffer, f.get())) data.append(buffer, n);
    if (std::ferror(f.get())) fail(path, std::string("read error: ") + std::strerror(errno));
    return data;
}

MeshFormat format_from_extension(const std::string& path)
{
    std::string ext = lower_extension(path);
    if (ext == ".obj") return MeshFormat::Obj;
    if (ext == ".ply") return MeshFormat::Ply;
    if (ext == ".stl") return MeshFormat::Stl;
    if (ext == ".gltf" || ext == ".glb") return MeshFormat::Gltf;
    return MeshFormat::Unknown;
}

namespace {

bool starts_with_word(std::string_view s, std::string_view word)
{
    return s.compare(0, word.size(), word) == 0 &&
           (s.size() == word.size() || std::isspace(static_cast<unsigned char>(s[word.size()])));
}

/// The first statement of an OBJ file is one of its keywords (after blank and comment lines).
bool looks_like_obj(std::string_view s)
{
    static const char* keywords[] = {"v", "vt", "vn", "vp", "f", "o", "g", "s", "l", "p", "mtllib", "usemtl"};
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        if (i < s.size() && s[i] == '#') {
            while (i < s.size() && s[i] != '\n') ++i;
            continue;
        }
        for (const char* k : keywords)
            if (starts_with_word(s.substr(i), k)) return true;
        return false;
    }
    return false;
}

} // namespace

MeshFormat format_from_content(std::string_view bytes)
{
    if (bytes.compare(0, 4, "ply\n") == 0 || bytes.compare(0, 5, "ply\r\n") == 0) return MeshFormat::Ply;
    if (bytes.compare(0, 4, "glTF") == 0) return MeshFormat::Gltf;
    if (bytes.size() >= 84) {
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + 80;
        std::uint64_t n = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
        if (bytes.size() == 84 + 50 * n) return MeshFormat::Stl;
    }
    std::size_t i = 0;
    while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
    if (starts_with_word(bytes.substr(i), "solid")) return MeshFormat::Stl;
    if (looks_like_obj(bytes)) return MeshFormat::Obj;
    return MeshFormat::Unknown;
}

MeshData parse_mesh(std::string_view bytes, const std::string& path)
{
    MeshFormat format = format_from_extension(path);
    if (format == MeshFormat::Unknown) format = format_from_content(bytes);
    switch (format) {
    case MeshFormat::Obj: return parse_obj(bytes, path);
    case MeshFormat::Ply: return parse_ply(bytes, path);
    case MeshFormat::Stl: return parse_stl(bytes, path);
    case MeshFormat::Gltf: return flatten_gltf(parse_gltf(bytes, path, true), path);
    case MeshFormat::Unknown: break;
    }
    if (bytes.empty()) fail(path, "empty file, contains no triangles");
    fail(path, "unknown mesh format: not .obj, .ply, .stl, .gltf or .glb, and the content is none of them");
}

} // namespace detail

MeshData load_mesh(const std::string& path)
{
    std::string bytes = detail::read_file(path);
    return detail::parse_mesh(bytes, path);
}

void add_gltf(Scene& scene, GltfScene gltf)
{
    // A glTF mesh that several nodes use becomes a prototype with one instance per node.
    std::vector<std::size_t> uses(gltf.meshes.size(), 0), prototype(gltf.meshes.size(), Scene::no_prototype);
    for (const GltfScene::Item& item : gltf.items) ++uses[item.mesh];
    for (const GltfScene::Item& item : gltf.items) {
        if (uses[item.mesh] == 1) {
            scene.add_mesh(std::move(gltf.meshes[item.mesh]), item.transform);
            continue;
        }
        if (prototype[item.mesh] == Scene::no_prototype)
            prototype[item.mesh] = scene.add_prototype(std::move(gltf.meshes[item.mesh]));
        scene.add_instance(prototype[item.mesh], item.transform);
    }
}

Scene load_scene(const std::vector<std::string>& paths)
{
    if (paths.empty()) throw Error(Error::Kind::InvalidArgument, "load_scene: no files given");
    Scene scene;
    for (const std::string& path : paths) {
        if (detail::lower_extension(path) == ".json") {
            if (paths.size() != 1)
                throw Error(Error::Kind::InvalidArgument,
                            "load_scene: the scene file " + path + " must be the only path (got " +
                                std::to_string(paths.size()) + ")");
            return load_scene_file(path).scene;
        }
        if (detail::format_from_extension(path) == detail::MeshFormat::Gltf) {
            add_gltf(scene, load_gltf(path));
            continue;
        }
        scene.add_mesh(load_mesh(path));
    }
    return scene;
}

} // namespace clvis
