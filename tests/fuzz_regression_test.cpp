// Replays what the fuzzers keep: every input under tests/fuzz/regressions/<format>/ (inputs that
// once crashed a parser, or hostile ones made by hand) and every seed under tests/fuzz/corpus/
// goes through its parser and either gives a valid mesh or scene, or throws clvis::Error.
#include "catch.hpp"

#include "scene/scene_parsers.hpp"

#include <clvis/clvis.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace clvis;
namespace fs = std::filesystem;

namespace {

std::string read_bytes(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The fuzz target's stand-in for mesh files: "bad..." fails, anything else is one triangle.
MeshData fake_mesh(const std::string& path)
{
    if (path.find("bad") != std::string::npos) detail::fail(path, "a mesh file that does not load");
    MeshData m;
    m.name = path;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    m.indices = {0, 1, 2};
    return m;
}

/// Parses one input as its folder says; true when it loaded, false when it threw clvis::Error.
bool replay(const std::string& format, const std::string& bytes, const std::string& name)
{
    try {
        if (format == "scene") {
            SceneFile f = detail::parse_scene_file(bytes, name, fake_mesh);
            CHECK_FALSE(f.scene.empty());
            return true;
        }
        if (format == "gltf") {
            GltfScene g = detail::parse_gltf(bytes, name, false);
            CHECK(g.triangle_count() > 0);
            Scene s;
            for (const GltfScene::Item& item : g.items) s.add_mesh(g.meshes[item.mesh], item.transform);
            return true;
        }
        MeshData m = format == "obj" ? detail::parse_obj(bytes, name)
                     : format == "ply" ? detail::parse_ply(bytes, name)
                                       : detail::parse_stl(bytes, name);
        CHECK(m.triangle_count() > 0);
        Scene s;
        s.add_mesh(std::move(m)); // valid indices, finite positions, consistent sizes
        return true;
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Io);
        CHECK(std::string(e.what()).find(name) == 0);
        return false;
    }
}

std::size_t replay_folder(const fs::path& root)
{
    REQUIRE(fs::is_directory(root));
    std::size_t count = 0;
    for (const char* format : {"obj", "ply", "stl", "gltf", "scene"}) {
        fs::path dir = root / format;
        REQUIRE(fs::is_directory(dir));
        for (const auto& e : fs::directory_iterator(dir)) {
            if (!e.is_regular_file()) continue;
            INFO(e.path().string());
            replay(format, read_bytes(e.path()), e.path().filename().string());
            ++count;
        }
    }
    return count;
}

} // namespace

TEST_CASE("every kept fuzz regression either loads or throws clvis::Error", "[io][fuzz]")
{
    CHECK(replay_folder(fs::path(CLVIS_SOURCE_DIR) / "tests" / "fuzz" / "regressions") > 0);
}

TEST_CASE("every fuzz seed loads or throws clvis::Error, the well-formed ones load", "[io][fuzz]")
{
    fs::path corpus = fs::path(CLVIS_SOURCE_DIR) / "tests" / "fuzz" / "corpus";
    CHECK(replay_folder(corpus) >= 20);
    std::vector<const char*> seeds = {"obj/suzanne.obj", "ply/suzanne_le.ply", "ply/quad_be.ply",
                                      "stl/suzanne_binary.stl", "stl/solid_but_binary.stl", "scene/full.json",
                                      "obj/attributes.obj", "ply/attributes_ascii.ply", "ply/attributes_be.ply"};
#ifdef CLVIS_HAVE_TINYGLTF
    seeds.insert(seeds.end(), {"gltf/walk.gltf", "gltf/sparse.gltf", "gltf/strips.gltf", "gltf/quad.glb",
                               "gltf/attributes.gltf"});
#endif
    for (const char* seed : seeds) {
        INFO(seed);
        std::string format = std::string(seed).substr(0, std::string(seed).find('/'));
        CHECK(replay(format, read_bytes(corpus / seed), seed));
    }
}
