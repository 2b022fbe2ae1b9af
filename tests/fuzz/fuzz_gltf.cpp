// libFuzzer target: parse_gltf (host/scene/scene_gltf.cpp, through tinygltf compiled here with the
// same instrumentation) on arbitrary bytes, as a .gltf or, with the "glTF" magic, a .glb. No file
// is read (buffers must be data URIs or the GLB's own chunk). It must return items whose meshes are
// valid and whose transforms are affine and finite, or throw clvis::Error. Seeds: corpus/gltf/.
#include "fuzz_check.hpp"
#include "scene/scene_parsers.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    clvis::GltfScene g;
    try {
        g = clvis::detail::parse_gltf(bytes, "fuzz/scene.gltf", false);
    } catch (const clvis::Error&) {
        return 0;
    }
    if (g.items.empty()) clvis::fuzz::broken("a glTF scene without items");
    for (const clvis::MeshData& m : g.meshes) clvis::fuzz::check_mesh(m);
    for (const clvis::GltfScene::Item& item : g.items) {
        if (item.mesh >= g.meshes.size()) clvis::fuzz::broken("an item naming a mesh that does not exist");
        for (double v : item.transform.m)
            if (!std::isfinite(v)) clvis::fuzz::broken("a non-finite transform");
        if (item.transform(3, 0) != 0 || item.transform(3, 1) != 0 || item.transform(3, 2) != 0 ||
            item.transform(3, 3) != 1)
            clvis::fuzz::broken("a transform that is not affine");
    }
    return 0;
}
