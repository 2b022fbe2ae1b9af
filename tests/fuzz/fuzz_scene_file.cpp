// libFuzzer target: parse_scene_file (host/scene/scene_file.cpp) on arbitrary text. Mesh files are not
// read: a mesh named "bad..." fails as a file would, any other is one triangle, so the fuzzer
// explores the JSON fields. It must return a scene or throw clvis::Error. Seeds: corpus/scene/.
#include "fuzz_check.hpp"
#include "scene/scene_parsers.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    std::string_view text(reinterpret_cast<const char*>(data), size);
    auto load = [](const std::string& path) {
        if (path.find("bad") != std::string::npos) clvis::detail::fail(path, "a mesh file that does not load");
        clvis::MeshData m;
        m.name = path;
        m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        m.indices = {0, 1, 2};
        return m;
    };
    clvis::SceneFile f;
    try {
        f = clvis::detail::parse_scene_file(text, "fuzz/scene.json", load);
    } catch (const clvis::Error&) {
        return 0;
    }
    if (f.scene.meshes().empty()) clvis::fuzz::broken("a scene file without meshes");
    if (f.width < 0 || f.height < 0) clvis::fuzz::broken("a negative image size");
    try {
        if (f.camera) f.camera->validate();
    } catch (const clvis::Error&) {
        clvis::fuzz::broken("a camera that does not validate");
    }
    return 0;
}
