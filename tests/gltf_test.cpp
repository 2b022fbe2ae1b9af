// glTF 2.0 files: small ones written here (JSON with base64 buffers, .bin files beside them, GLB
// containers) check the ids of CONVENTIONS.md's "Instances" section (pre-order walk, primitive
// and index order), node transforms (matrix and T R S), strips, fans and sparse accessors; malformed
// ones name the file and what is wrong; every glTF2 file of assimp-testmodels loads or fails cleanly.
#include "catch.hpp"

#include "scene/scene_parsers.hpp"
#include "test_files.hpp"

#include <clvis/clvis.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace clvis;
namespace fs = std::filesystem;

namespace {

std::string write_file(const std::string& name, const std::string& bytes)
{
    return test::write_temp_file("clvis-gltf-test", name, bytes);
}

using test::base64;

/// Builds one glTF: a single buffer of views and accessors, then meshes, nodes and scenes as JSON
/// text given by the test.
struct Gltf {
    std::string bin;
    std::vector<std::string> views, accessors;

    int view(const void* data, std::size_t bytes)
    {
        while (bin.size() % 4) bin += '\0';
        views.push_back("{\"buffer\":0,\"byteOffset\":" + std::to_string(bin.size()) +
                        ",\"byteLength\":" + std::to_string(bytes) + "}");
        bin.append(static_cast<const char*>(data), bytes);
        return int(views.size()) - 1;
    }
    int accessor(const std::string& json)
    {
        accessors.push_back(json);
        return int(accessors.size()) - 1;
    }
    /// A FLOAT VEC3 accessor (POSITION).
    int positions(const std::vector<float>& xyz, const std::string& sparse = "")
    {
        int v = view(xyz.data(), xyz.size() * 4);
        return accessor("{\"bufferView\":" + std::to_string(v) + ",\"componentType\":5126,\"type\":\"VEC3\",\"count\":" +
                        std::to_string(xyz.size() / 3) + sparse + "}");
    }
    /// An UNSIGNED_SHORT SCALAR accessor (indices).
    int indices(const std::vector<std::uint16_t>& ids, const std::string& sparse = "")
    {
        int v = view(ids.data(), ids.size() * 2);
        return accessor("{\"bufferView\":" + std::to_string(v) + ",\"componentType\":5123,\"type\":\"SCALAR\",\"count\":" +
                        std::to_string(ids.size()) + sparse + "}");
    }
    static std::string list(const std::vector<std::string>& items)
    {
        std::string s = "[";
        for (std::size_t i = 0; i < items.size(); ++i) s += (i ? "," : "") + items[i];
        return s + "]";
    }
    /// The whole file; `buffer` is the buffer's uri ("" for a GLB's own chunk).
    std::string json(const std::string& rest, const std::string& buffer) const
    {
        std::string uri = buffer.empty() ? "" : ",\"uri\":\"" + buffer + "\"";
        return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) + uri +
               "}],\"bufferViews\":" + list(views) + ",\"accessors\":" + list(accessors) + "," + rest + "}";
    }
    std::string embedded(const std::string& rest) const
    {
        return json(rest, "data:application/octet-stream;base64," + base64(bin));
    }
    std::string glb(const std::string& rest) const
    {
        std::string j = json(rest, ""), b = bin;
        while (j.size() % 4) j += ' ';
        while (b.size() % 4) b += '\0';
        std::string out = "glTF";
        auto u32 = [&out](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
        u32(2);
        u32(std::uint32_t(12 + 8 + j.size() + 8 + b.size()));
        u32(std::uint32_t(j.size()));
        u32(0x4E4F534A); // "JSON"
        out += j;
        u32(std::uint32_t(b.size()));
        u32(0x004E4942); // "BIN\0"
        return out + b;
    }
};

/// A triangle in the plane z = `z`, so that each primitive is told by its depth.
std::vector<float> triangle_at(float z) { return {0, 0, z, 1, 0, z, 0, 1, z}; }

std::string mesh(const std::vector<int>& position_accessors)
{
    std::vector<std::string> prims;
    for (int a : position_accessors) prims.push_back("{\"attributes\":{\"POSITION\":" + std::to_string(a) + "}}");
    return "{\"primitives\":" + Gltf::list(prims) + "}";
}

/// The message of the Error that loading `path` throws, after checking its kind and that it
/// starts with the path; "" if none.
std::string load_error(const std::string& path)
{
    try {
        load_gltf(path);
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find(path) == 0);
        return e.what();
    }
    return "";
}

} // namespace

#ifdef CLVIS_HAVE_TINYGLTF

TEST_CASE("glTF ids follow the pre-order walk: roots, children, primitives in order", "[io][gltf]")
{
    Gltf g;
    int a0 = g.positions(triangle_at(1)), a1 = g.positions(triangle_at(2)), b = g.positions(triangle_at(3)),
        c = g.positions(triangle_at(4));
    // Scene 1 is the default: roots 2 then 0; node 2 holds mesh 0 (two primitives) and child 1.
    std::string rest = "\"meshes\":[" + mesh({a0, a1}) + "," + mesh({b}) + "," + mesh({c}) +
                       "],\"nodes\":[{\"mesh\":2},{\"mesh\":1},{\"mesh\":0,\"children\":[1]},{\"mesh\":1}],"
                       "\"scenes\":[{\"nodes\":[3]},{\"nodes\":[2,0]}],\"scene\":1";
    std::string path = write_file("walk.gltf", g.embedded(rest));
    GltfScene s = load_gltf(path);
    REQUIRE(s.items.size() == 4);
    std::vector<float> depths;
    for (const auto& item : s.items) depths.push_back(s.meshes[item.mesh].positions[2]);
    CHECK(depths == std::vector<float>{1, 2, 3, 4});
    CHECK(s.items[0].node == 2);
    CHECK(s.items[2].node == 1);
    CHECK(s.items[3].node == 0);
    Scene scene = load_scene({path});
    REQUIRE(scene.meshes().size() == 4);
    for (std::uint32_t id = 0; id < 4; ++id) {
        float t[9];
        scene.triangle(id, t);
        CHECK(t[2] == float(id + 1));
    }
    // Without "scene", scene 0: node 3 alone.
    std::string first = rest.substr(0, rest.find(",\"scene\":1"));
    GltfScene s0 = load_gltf(write_file("scene0.gltf", g.embedded(first)));
    REQUIRE(s0.items.size() == 1);
    CHECK(s0.items[0].node == 3);
}

TEST_CASE("glTF node transforms multiply along the path, matrix and T R S alike", "[io][gltf]")
{
    Gltf g;
    int a = g.positions({1, 0, 0, 0, 1, 0, 0, 0, 1});
    char h[32];
    std::snprintf(h, sizeof h, "%.17g", std::sqrt(0.5));
    // Root: translation (0, 0, 5), rotation 90 degrees about z, scale 2. Child: a column-major
    // matrix that moves by (1, 0, 0) and scales y by 3.
    std::string rest = "\"meshes\":[" + mesh({a}) +
                       "],\"nodes\":[{\"translation\":[0,0,5],\"rotation\":[0,0," + h + "," + h + "],\"scale\":[2,2,2],\"children\":[1]},"
                       "{\"mesh\":0,\"matrix\":[1,0,0,0, 0,3,0,0, 0,0,1,0, 1,0,0,1]}],\"scenes\":[{\"nodes\":[0]}]";
    MeshData m = load_mesh(write_file("transforms.gltf", g.embedded(rest)));
    REQUIRE(m.vertex_count() == 3);
    // p -> child (x + 1, 3 y, z) -> scale 2 -> rotate (x, y) to (-y, x) -> translate z + 5.
    const float expected[9] = {0, 4, 5, -6, 2, 5, 0, 2, 7};
    for (int i = 0; i < 9; ++i) CHECK(m.positions[std::size_t(i)] == Approx(expected[i]).margin(1e-5));
    // The same items as meshes with transforms give the same bits as the flattened mesh.
    Scene scene = load_scene({write_file("transforms.gltf", g.embedded(rest))});
    CHECK(scene.world_positions() == m.positions);
    CHECK(scene.meshes()[0].transform(1, 0) == Approx(2).margin(1e-12)); // the rotated x axis
}

TEST_CASE("glTF strips and fans follow the specification's vertex order", "[io][gltf]")
{
    Gltf g;
    std::vector<float> five;
    for (int i = 0; i < 5; ++i) five.insert(five.end(), {float(i), float(i % 2), 0});
    int p = g.positions(five);
    int reversed = g.indices({4, 3, 2, 1, 0});
    auto prim = [&](int mode, int indices) {
        std::string ind = indices < 0 ? "" : ",\"indices\":" + std::to_string(indices);
        return "{\"attributes\":{\"POSITION\":" + std::to_string(p) + "},\"mode\":" + std::to_string(mode) + ind + "}";
    };
    std::string rest = "\"meshes\":[{\"primitives\":[" + prim(5, -1) + "," + prim(6, -1) + "," + prim(5, reversed) +
                       "," + prim(6, reversed) +
                       "]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    GltfScene s = load_gltf(write_file("strips.gltf", g.embedded(rest)));
    REQUIRE(s.items.size() == 4);
    // glTF 2.0, 3.7.2.1: strip p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}, fan p_i = {v_{i+1}, v_{i+2}, v_0}
    // (not OpenGL's odd-triangle order v_{i+1}, v_i, v_{i+2}: the same winding, other first vertex).
    using V = std::vector<std::uint32_t>;
    CHECK(s.meshes[s.items[0].mesh].indices == V{0, 1, 2, 1, 3, 2, 2, 3, 4});
    CHECK(s.meshes[s.items[1].mesh].indices == V{1, 2, 0, 2, 3, 0, 3, 4, 0});
    CHECK(s.meshes[s.items[2].mesh].indices == V{4, 3, 2, 3, 1, 2, 2, 1, 0});
    CHECK(s.meshes[s.items[3].mesh].indices == V{3, 2, 4, 2, 1, 4, 1, 0, 4});
}

TEST_CASE("glTF sparse accessors replace the listed positions and indices", "[io][gltf]")
{
    Gltf g;
    std::vector<std::uint16_t> which = {1};
    std::vector<float> moved = {5, 0, 0};
    int wv = g.view(which.data(), 2), mv = g.view(moved.data(), 12);
    std::string sparse_pos = ",\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":" + std::to_string(wv) +
                             ",\"componentType\":5123},\"values\":{\"bufferView\":" + std::to_string(mv) + "}}";
    int dense = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, sparse_pos);
    // No bufferView: zeros, then the sparse values.
    int bufferless = g.accessor("{\"componentType\":5126,\"type\":\"VEC3\",\"count\":3" + sparse_pos + "}");
    std::vector<std::uint16_t> three = {3};
    int tv = g.view(three.data(), 2);
    std::string sparse_ind = ",\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":" + std::to_string(wv) +
                             ",\"componentType\":5123},\"values\":{\"bufferView\":" + std::to_string(tv) + "}}";
    int ind = g.indices({0, 1, 2}, sparse_ind);
    std::string rest = "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(dense) +
                       "},\"indices\":" + std::to_string(ind) + "},{\"attributes\":{\"POSITION\":" +
                       std::to_string(bufferless) + "}}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    GltfScene s = load_gltf(write_file("sparse.gltf", g.embedded(rest)));
    REQUIRE(s.items.size() == 2);
    const MeshData& a = s.meshes[s.items[0].mesh];
    CHECK(a.positions == std::vector<float>{0, 0, 0, 5, 0, 0, 0, 1, 0, 1, 1, 0});
    CHECK(a.indices == std::vector<std::uint32_t>{0, 3, 2});
    CHECK(s.meshes[s.items[1].mesh].positions == std::vector<float>{0, 0, 0, 5, 0, 0, 0, 0, 0});
}

TEST_CASE("glTF points and lines are skipped with a note; no triangle at all is an error", "[io][gltf]")
{
    Gltf g;
    int a = g.positions(triangle_at(0));
    std::string lines = "{\"attributes\":{\"POSITION\":" + std::to_string(a) + "},\"mode\":1}";
    std::string tris = "{\"attributes\":{\"POSITION\":" + std::to_string(a) + "}}";
    std::string tail = "],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    GltfScene s = load_gltf(write_file("lines.gltf", g.embedded("\"meshes\":[{\"primitives\":[" + lines + "," + tris +
                                                                "]}" + tail)));
    CHECK(s.items.size() == 1);
    REQUIRE(s.notes.size() == 1);
    CHECK(s.notes[0].find("meshes[0].primitives[0]: mode LINES skipped") == 0);
    std::string only = write_file("only_lines.gltf", g.embedded("\"meshes\":[{\"primitives\":[" + lines + "]}" + tail));
    CHECK(load_error(only).find("contains no triangles") != std::string::npos);
}

TEST_CASE("a .glb, a .gltf with a base64 buffer and one with a .bin file load alike", "[io][gltf]")
{
    Gltf g;
    int a = g.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    int i = g.indices({0, 1, 2, 2, 1, 3});
    std::string rest = "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(a) +
                       "},\"indices\":" + std::to_string(i) + "}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    write_file("quad.bin", g.bin);
    MeshData embedded = load_mesh(write_file("quad_embedded.gltf", g.embedded(rest)));
    MeshData glb = load_mesh(write_file("quad.glb", g.glb(rest)));
    MeshData external = load_mesh(write_file("quad_external.gltf", g.json(rest, "quad.bin")));
    MeshData no_extension = load_mesh(write_file("quad_glb.mesh", g.glb(rest))); // told by its magic
    for (const MeshData* m : {&glb, &external, &no_extension}) {
        CHECK(m->positions == embedded.positions);
        CHECK(m->indices == embedded.indices);
    }
    CHECK(embedded.indices == std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3});
}

TEST_CASE("glTF nodes that share a mesh share one prototype, each with its transform", "[io][gltf]")
{
    Gltf g;
    int a = g.positions(triangle_at(0));
    std::string rest = "\"meshes\":[" + mesh({a}) +
                       "],\"nodes\":[{\"mesh\":0},{\"mesh\":0,\"translation\":[0,0,-2]},{\"mesh\":0,\"scale\":[1,1,3]}],"
                       "\"scenes\":[{\"nodes\":[0,1,2]}]";
    GltfScene s = load_gltf(write_file("shared.gltf", g.embedded(rest)));
    REQUIRE(s.meshes.size() == 1);
    REQUIRE(s.items.size() == 3);
    CHECK(s.triangle_count() == 3);
    CHECK(s.items[1].transform(2, 3) == -2);
    CHECK(s.items[2].transform(2, 2) == 3);
    // load_scene makes the shared mesh a prototype with one instance per node: the bits of the
    // flattened mesh, the triangles stored once.
    std::string path = write_file("shared.gltf", g.embedded(rest));
    Scene scene = load_scene({path});
    REQUIRE(scene.meshes().size() == 3);
    CHECK(scene.prototypes().size() == 1);
    for (const auto& m : scene.meshes()) CHECK(m.prototype == 0);
    CHECK(scene.world_positions() == load_mesh(path).positions);
}

TEST_CASE("malformed glTF files throw Error(Io) naming the file and what is wrong", "[io][gltf]")
{
    Gltf g;
    int a = g.positions(triangle_at(0));
    int far_index = g.indices({0, 1, 7});
    auto file = [&](const std::string& meshes, const std::string& nodes, const std::string& scenes) {
        return g.embedded("\"meshes\":[" + meshes + "],\"nodes\":[" + nodes + "],\"scenes\":[" + scenes + "]");
    };
    std::string ok_mesh = mesh({a});
    std::string with_index = "{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(a) +
                             "},\"indices\":" + std::to_string(far_index) + "}]}";
    struct Case {
        const char* file;
        std::string bytes;
        const char* message;
    } cases[] = {
        {"index.gltf", file(with_index, "{\"mesh\":0}", "{\"nodes\":[0]}"), "index 2 is 7, past the 3 vertices"},
        {"cycle.gltf", file(ok_mesh, "{\"mesh\":0,\"children\":[0]}", "{\"nodes\":[0]}"), "nodes[0] is reached twice"},
        {"twice.gltf", file(ok_mesh, "{\"mesh\":0}", "{\"nodes\":[0,0]}"), "nodes[0] is reached twice"},
        {"no_node.gltf", file(ok_mesh, "{\"mesh\":0}", "{\"nodes\":[3]}"), "nodes[3] does not exist"},
        {"no_mesh.gltf", file(ok_mesh, "{\"mesh\":4}", "{\"nodes\":[0]}"), "nodes[0].mesh: 4 does not exist"},
        {"matrix.gltf", file(ok_mesh, "{\"mesh\":0,\"matrix\":[1,0,0,1, 0,1,0,0, 0,0,1,0, 0,0,0,1]}", "{\"nodes\":[0]}"),
         "nodes[0].matrix: the last row must be 0 0 0 1"},
        {"trs.gltf", file(ok_mesh, "{\"mesh\":0,\"scale\":[1,1]}", "{\"nodes\":[0]}"), "nodes[0].scale: expected 3"},
        {"mode.gltf", file("{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"mode\":9}]}", "{\"mesh\":0}", "{\"nodes\":[0]}"),
         "meshes[0].primitives[0].mode: 9 is not a glTF primitive mode"},
        {"accessor.gltf", file(mesh({17}), "{\"mesh\":0}", "{\"nodes\":[0]}"), "accessors[17] does not exist"},
        {"no_scene.gltf", g.embedded("\"meshes\":[" + ok_mesh + "],\"nodes\":[{\"mesh\":0}]"), "contains no scene"},
        {"draco.gltf", file(ok_mesh, "{\"mesh\":0}", "{\"nodes\":[0]}").insert(1, "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],"),
         "extensionsRequired: KHR_draco_mesh_compression is not supported"},
        {"deep.gltf", std::string(100, '[') + std::string(100, ']'), "JSON nested deeper than 64 levels"},
        {"not_json.gltf", "{\"asset\": oops", "invalid glTF"},
        {"truncated.glb", g.glb("\"meshes\":[" + ok_mesh + "]").substr(0, 40), "invalid GLB"},
        {"missing_bin.gltf", g.json("\"meshes\":[" + ok_mesh + "],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]", "nowhere.bin"),
         "nowhere.bin"},
    };
    for (const Case& c : cases) {
        INFO(c.file);
        std::string message = load_error(write_file(c.file, c.bytes));
        CHECK(message.find(c.message) != std::string::npos);
        INFO(message);
        CHECK_FALSE(message.empty());
    }
    // A view that runs past its buffer, and an accessor past its view.
    Gltf h;
    int p = h.positions(triangle_at(0));
    h.views[0] = "{\"buffer\":0,\"byteLength\":400}";
    std::string rest = "\"meshes\":[" + mesh({p}) + "],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    CHECK(load_error(write_file("view.gltf", h.embedded(rest))).find("bufferViews[0]: bytes 0 + 400 lie outside") !=
          std::string::npos);
    h.views[0] = "{\"buffer\":0,\"byteLength\":20}";
    CHECK(load_error(write_file("past.gltf", h.embedded(rest))).find("accessors[0]: 3 elements of 12 bytes") !=
          std::string::npos);
}

TEST_CASE("glTF 1.0, required extensions clvis lacks and broken GLBs are refused for their cause", "[io][gltf]")
{
    // glTF 1.0: named by asset.version, by 1.0's objects in place of arrays when there is no
    // asset, and by a GLB of version 1 (KHR_binary_glTF).
    std::string v1 = "\"scenes\":{\"s\":{\"nodes\":[\"n\"]}},\"scene\":\"s\",\"nodes\":{\"n\":{\"meshes\":[\"m\"]}},"
                     "\"meshes\":{\"m\":{\"primitives\":[]}}";
    CHECK(load_error(write_file("v1.gltf", "{\"asset\":{\"version\":\"1.0\"}," + v1 + "}"))
              .find("asset.version \"1.0\": glTF 1.0, clvis reads glTF 2.0 only") != std::string::npos);
    CHECK(load_error(write_file("v1_no_asset.gltf", "{" + v1 + "}"))
              .find("no asset, and \"scenes\" is an object, not an array: glTF 1.0") != std::string::npos);
    Gltf g;
    int a = g.positions(triangle_at(0));
    std::string rest = "\"meshes\":[" + mesh({a}) + "],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
    std::string glb = g.glb(rest), v1_glb = glb;
    v1_glb[4] = 1;
    CHECK(load_error(write_file("v1.glb", v1_glb)).find("GLB version 1 (KHR_binary_glTF)") != std::string::npos);
    for (const char* dir : {"BoxTextured-glTF-Binary", "TwoBoxes", "IncorrectVertexArrays"})
        for (const auto& e : fs::directory_iterator(fs::path("/usr/share/assimp/models/glTF") / dir)) {
            std::string ext = e.path().extension().string();
            if (ext != ".gltf" && ext != ".glb") continue;
            INFO(e.path().string());
            CHECK(load_error(e.path().string()).find("glTF 1.0, clvis reads glTF 2.0 only") != std::string::npos);
        }
    // A required extension is named even where tinygltf would first trip over what it changes:
    // Draco's accessors have no bufferView, meshopt's buffer no uri.
    std::string draco = "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
                        "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],\"buffers\":[{\"byteLength\":4,"
                        "\"uri\":\"data:application/octet-stream;base64,AAAAAA==\"}],\"bufferViews\":[{\"buffer\":0,"
                        "\"byteLength\":4}],\"accessors\":[{\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"},"
                        "{\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"meshes\":[{\"primitives\":[{"
                        "\"attributes\":{\"POSITION\":1},\"indices\":0,\"extensions\":{\"KHR_draco_mesh_compression\":"
                        "{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}}}]}],\"nodes\":[{\"mesh\":0}],"
                        "\"scenes\":[{\"nodes\":[0]}]}";
    CHECK(load_error(write_file("draco_indices.gltf", draco))
              .find("extensionsRequired: KHR_draco_mesh_compression is not supported") != std::string::npos);
    std::string meshopt = "{\"asset\":{\"version\":\"2.0\"},\"extensionsRequired\":[\"EXT_meshopt_compression\"],"
                          "\"buffers\":[{\"byteLength\":36,\"extensions\":{\"EXT_meshopt_compression\":{\"fallback\":true}}}]," +
                          rest + "}";
    CHECK(load_error(write_file("meshopt.gltf", meshopt)).find("extensionsRequired: EXT_meshopt_compression is not supported") !=
          std::string::npos);
    const std::string engine = "/usr/share/assimp/models/glTF2/draco/2CylinderEngine.gltf";
    CHECK(load_error(engine).find("KHR_draco_mesh_compression is not supported") != std::string::npos);
    // A GLB names what is wrong with its container (tinygltf says "Invalid glTF binary." to all).
    std::string longer = glb, not_json = glb;
    std::uint32_t claimed = std::uint32_t(glb.size() + 100);
    std::memcpy(&longer[8], &claimed, 4);
    not_json[16] = 'X';
    CHECK(load_error(write_file("short.glb", glb.substr(0, 16))).find("16 bytes, shorter than its 20-byte headers") !=
          std::string::npos);
    CHECK(load_error(write_file("truncated.glb", glb.substr(0, 40))).find("the file holds 40 (truncated?)") !=
          std::string::npos);
    CHECK(load_error(write_file("longer.glb", longer)).find("the header says " + std::to_string(claimed) + " bytes") !=
          std::string::npos);
    CHECK(load_error(write_file("not_json.glb", not_json)).find("the first chunk is not JSON") != std::string::npos);
}

TEST_CASE("glTF camera nodes of the scene are listed in one note", "[io][gltf]")
{
    Gltf g;
    int a = g.positions(triangle_at(0));
    std::string rest = "\"meshes\":[" + mesh({a}) + "],\"cameras\":[{\"name\":\"Main\",\"type\":\"perspective\","
                       "\"perspective\":{\"yfov\":0.8,\"znear\":0.1}},{\"type\":\"orthographic\",\"orthographic\":"
                       "{\"xmag\":1,\"ymag\":1,\"znear\":0.1,\"zfar\":9}}],\"nodes\":[{\"mesh\":0,\"children\":[2]},"
                       "{\"camera\":1},{\"camera\":0}],\"scenes\":[{\"nodes\":[0]}]";
    GltfScene s = load_gltf(write_file("cameras.gltf", g.embedded(rest)));
    REQUIRE(s.notes.size() == 1); // nodes[1] is outside the scene
    CHECK(s.notes[0] == "cameras ignored (clvis places its own camera): nodes[2] (cameras[0] \"Main\", perspective)");
    s = load_gltf(write_file("cameras2.gltf", g.embedded(rest.replace(rest.find("[0]}]"), 5, "[0,1]}]"))));
    REQUIRE(s.notes.size() == 1);
    CHECK(s.notes[0].find("nodes[2] (cameras[0] \"Main\", perspective), nodes[1] (cameras[1], orthographic)") !=
          std::string::npos);
}

TEST_CASE("every glTF2 file of assimp-testmodels loads or throws clvis::Error", "[io][gltf]")
{
    // The set-up installs assimp-testmodels: a missing folder is a broken install, not a skip.
    const fs::path root = "/usr/share/assimp/models/glTF2";
    REQUIRE(fs::is_directory(root));
    std::size_t files = 0, loaded = 0;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        std::string ext = e.path().extension().string();
        if (!e.is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
        ++files;
        INFO(e.path().string());
        try {
            Scene s = load_scene({e.path().string()});
            CHECK(s.triangle_count() > 0);
            ++loaded;
        } catch (const Error& err) {
            CHECK(std::string(err.what()).find(e.path().string()) == 0);
        }
    }
    CHECK(files >= 46);
    CHECK(loaded >= 25);
}

#else

TEST_CASE("without tinygltf a glTF file is refused with a clear error", "[io][gltf]")
{
    std::string path = write_file("refused.gltf", "{\"asset\":{\"version\":\"2.0\"}}");
    CHECK(load_error(path).find("made without tinygltf") != std::string::npos);
}

#endif
