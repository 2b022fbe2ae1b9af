// Vertex attributes as the loaders fill them (CONVENTIONS.md "Vertex attributes"): OBJ `vt` through
// each corner's own index (a seam keeps both values, negative and forward indices, fans) and the
// `v x y z r g b` colours; PLY ascii and binary (both byte orders) colours of integer and float
// types, texture coordinates and custom properties; glTF TEXCOORD_0/1 and COLOR_0 (normalised
// integers, RGB given alpha 1, strips) once per shared mesh; scene files' instances sharing their
// prototype's; files without attributes carrying none; malformed input named by file and line.
#include "catch.hpp"

#include "test_files.hpp"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

using namespace clvis;

namespace {

std::string write_file(const std::string& name, const std::string& bytes)
{
    return test::write_temp_file("clvis-attributes-load-test", name, bytes);
}

const CornerAttribute* find(const MeshData& m, const std::string& name)
{
    for (const CornerAttribute& a : m.attributes)
        if (a.name == name) return &a;
    return nullptr;
}

/// The value of corner `corner` (3 per triangle, in index order).
std::vector<float> corner(const CornerAttribute& a, std::size_t corner)
{
    auto c = std::size_t(a.components);
    return std::vector<float>(a.values.begin() + std::ptrdiff_t(corner * c),
                              a.values.begin() + std::ptrdiff_t((corner + 1) * c));
}

bool all_nan(const std::vector<float>& v)
{
    for (float f : v)
        if (!std::isnan(f)) return false;
    return true;
}

/// The message of the Error that loading `path` throws; "" if none.
std::string load_error(const std::string& path)
{
    try {
        load_mesh(path);
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Io);
        return e.what();
    }
    return "";
}

template <class T> void put(std::string& s, T v, bool big)
{
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    s.append(reinterpret_cast<const char*>(b), sizeof(T));
}

} // namespace

TEST_CASE("OBJ vt: each corner its own texture index, seams keep both values, fans follow positions",
          "[attributes_load][io]")
{
    // Position 1 is met with vt 1 by the first face and with vt 4 by the second (a seam); the
    // second face names its texture coordinates relatively; the quad fans (1,2,3), (1,3,4).
    std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                       "vt 0 0\nvt 1 0\nvt 1 1 0.5\nvt 0.25\n"
                       "f 1/1 2/2 3/3\n"
                       "f 1/-1/1 3/-2/1 4/-1/1\n"
                       "f 1/1 2/2 3/3 4/4\n"
                       "vn 0 0 1\n";
    MeshData m = load_mesh(write_file("seam.obj", text));
    REQUIRE(m.triangle_count() == 4);
    REQUIRE(m.attributes.size() == 1);
    const CornerAttribute& uv = m.attributes[0];
    CHECK(uv.name == "uv");
    CHECK(uv.components == 2);
    REQUIRE(uv.values.size() == 12 * 2);
    CHECK(m.indices[0] == m.indices[3]); // one position ...
    CHECK(corner(uv, 0) == std::vector<float>{0, 0}); // ... two texture coordinates
    CHECK(corner(uv, 3) == std::vector<float>{0.25f, 0}); // vt 4: v absent is 0
    CHECK(corner(uv, 4) == std::vector<float>{1, 1});     // w skipped
    CHECK(corner(uv, 5) == std::vector<float>{0.25f, 0});
    // The quad's fans: (v1, v2, v3) then (v1, v3, v4), corners as positions.
    std::vector<std::vector<float>> fans = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0.25f, 0}};
    for (std::size_t k = 0; k < 6; ++k) CHECK(corner(uv, 6 + k) == fans[k]);
    CHECK(std::vector<std::uint32_t>(m.indices.begin() + 6, m.indices.end()) ==
          std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
    // Taken by a Scene as it is.
    Scene s;
    s.add_mesh(m);
    CHECK(s.meshes()[0].data.attributes.size() == 1);
}

TEST_CASE("OBJ vt: corners without a texture index are NaN, forward indices resolve, none kept when unused",
          "[attributes_load][io]")
{
    // The first face names no vt (NaN corners, filled in when a later face names one); the second
    // names vt 2 before it is defined; the third leaves out one corner's.
    std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\n"
                       "f 1 2 3\n"
                       "f 1/2 2/2 3/2\n"
                       "vt 0.5 0.5\nvt 0.75 0.25\n"
                       "f 1/1 2 3/1\n";
    MeshData m = load_mesh(write_file("partial.obj", text));
    const CornerAttribute* uv = find(m, "uv");
    REQUIRE(uv);
    REQUIRE(uv->values.size() == 9 * 2);
    for (std::size_t k = 0; k < 3; ++k) CHECK(all_nan(corner(*uv, k)));
    for (std::size_t k = 3; k < 6; ++k) CHECK(corner(*uv, k) == std::vector<float>{0.75f, 0.25f});
    CHECK(corner(*uv, 6) == std::vector<float>{0.5f, 0.5f});
    CHECK(all_nan(corner(*uv, 7)));
    CHECK(corner(*uv, 8) == std::vector<float>{0.5f, 0.5f});

    // vt lines that no face names give no attribute; neither does a file with neither.
    CHECK(load_mesh(write_file("unused.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2 3\n")).attributes.empty());
    CHECK(load_mesh(write_file("plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).attributes.empty());
}

TEST_CASE("OBJ colours: v x y z r g b is color with alpha 1, other vertices NaN, w is no colour",
          "[attributes_load][io]")
{
    // Vertex 1 has w (no colour), the others colours; vertex 5 (unused) has none.
    std::string text = "v 0 0 0 1\nv 1 0 0 1 0 0\nv 1 1 0 0 1 0 # green\nv 0 1 0 0.25 0.5 0.75\nv 9 9 9\n"
                       "f 2 3 4 1\n";
    MeshData m = load_mesh(write_file("colours.obj", text));
    REQUIRE(m.attributes.size() == 1);
    const CornerAttribute& color = m.attributes[0];
    CHECK(color.name == "color");
    CHECK(color.components == 4);
    REQUIRE(color.values.size() == 6 * 4);
    CHECK(corner(color, 0) == std::vector<float>{1, 0, 0, 1});
    CHECK(corner(color, 1) == std::vector<float>{0, 1, 0, 1});
    CHECK(corner(color, 2) == std::vector<float>{0.25f, 0.5f, 0.75f, 1});
    CHECK(corner(color, 3) == std::vector<float>{1, 0, 0, 1});
    CHECK(corner(color, 4) == std::vector<float>{0.25f, 0.5f, 0.75f, 1});
    CHECK(all_nan(corner(color, 5))); // vertex 1: "v 0 0 0 1" is x y z w
    CHECK(m.vertex_count() == 5);
}

TEST_CASE("OBJ texture coordinates: bad indices and values name the file and line", "[attributes_load][io]")
{
    const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    struct Case {
        std::string text, expected;
    } cases[] = {
        {v + "vt 0 0\nvt 1 0\nf 1/1 2/9 3/2\n", "bad.obj:6: texture coordinate index 9 is out of range (the file defines 2)"},
        {v + "vt 0 0\nf 1/1 2/-2 3/1\n", "bad.obj:5: relative texture coordinate index -2 reaches before the first one"},
        {v + "f 1/0 2/1 3/1\nvt 0 0\n", "bad.obj:4: texture coordinate index 0"},
        {v + "vt 0 0\nvt 0.5 abc\nf 1/1 2/1 3/1\n", "bad.obj:5: malformed or out-of-range number 'abc'"},
        {v + "vt\nf 1/1 2/1 3/1\n", "bad.obj:4: 'vt' needs at least 1 coordinate"},
    };
    for (const Case& c : cases) {
        std::string path = write_file("bad.obj", c.text);
        std::string message = load_error(path);
        INFO(c.text);
        CHECK(message.rfind(path + ":", 0) == 0);
        CHECK(message.find(c.expected) != std::string::npos);
    }
}

TEST_CASE("PLY ascii: uchar colours, texture coordinates and custom properties by name", "[attributes_load][io]")
{
    // nx (a normal) and a list are no attributes; temp-C is named temp_C.
    std::string text = "ply\nformat ascii 1.0\nelement vertex 4\n"
                       "property float x\nproperty float y\nproperty float z\nproperty float nx\n"
                       "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                       "property float temperature\nproperty float u\nproperty float v\n"
                       "property list uchar float weights\nproperty short temp-C\n"
                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                       "0 0 0 0 255 0 0 20.5 0 0 2 1 2 -3\n"
                       "1 0 0 0 0 255 0 21.5 1 0 0 7\n"
                       "1 1 0 0 0 0 255 22.5 1 1 1 9 100\n"
                       "0 1 0 0 51 102 153 23.5 0 1 0 -32768\n"
                       "4 0 1 2 3\n";
    MeshData m = load_mesh(write_file("colours.ply", text));
    REQUIRE(m.triangle_count() == 2);
    std::vector<std::string> names;
    for (const CornerAttribute& a : m.attributes) names.push_back(a.name);
    CHECK(names == std::vector<std::string>{"uv", "color", "temperature", "temp_C"});
    const CornerAttribute* color = find(m, "color");
    const CornerAttribute* t = find(m, "temperature");
    const CornerAttribute* uv = find(m, "uv");
    const CornerAttribute* tc = find(m, "temp_C");
    REQUIRE((color && t && uv && tc));
    CHECK(color->components == 4);
    CHECK(t->components == 1);
    CHECK(tc->components == 1);
    REQUIRE(color->values.size() == 6 * 4);
    // Fan (0,1,2), (0,2,3).
    CHECK(corner(*color, 0) == std::vector<float>{1, 0, 0, 1});
    CHECK(corner(*color, 1) == std::vector<float>{0, 1, 0, 1});
    CHECK(corner(*color, 5) == std::vector<float>{float(51.0 / 255), float(102.0 / 255), float(153.0 / 255), 1});
    std::vector<float> temperatures(t->values.begin(), t->values.end());
    CHECK(temperatures == std::vector<float>{20.5f, 21.5f, 22.5f, 20.5f, 22.5f, 23.5f});
    CHECK(corner(*uv, 2) == std::vector<float>{1, 1});
    CHECK(corner(*uv, 5) == std::vector<float>{0, 1});
    CHECK(corner(*tc, 5) == std::vector<float>{-32768}); // not a colour: as stored
}

TEST_CASE("PLY binary, both byte orders: float colours with alpha, ushort colours, s and t", "[attributes_load][io]")
{
    for (bool big : {false, true}) {
        INFO((big ? "big endian" : "little endian"));
        std::string text = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                           " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "property float red\nproperty float green\nproperty float blue\nproperty float alpha\n"
                           "property double s\nproperty double t\nproperty ushort temperature\n"
                           "element face 1\nproperty list uchar uint vertex_indices\nend_header\n";
        for (int i = 0; i < 3; ++i) {
            put<float>(text, float(i == 1), big);
            put<float>(text, float(i == 2), big);
            put<float>(text, 0, big);
            for (float c : {0.5f * float(i), 0.25f, 2.0f, 0.75f}) put<float>(text, c, big); // floats as they are
            put<double>(text, 0.125 * i, big);
            put<double>(text, 1.0 - 0.125 * i, big);
            put<std::uint16_t>(text, std::uint16_t(1000 + i), big);
        }
        text += char(3);
        for (std::uint32_t v : {2u, 0u, 1u}) put<std::uint32_t>(text, v, big);
        MeshData m = load_mesh(write_file(big ? "big.ply" : "little.ply", text));
        const CornerAttribute* color = find(m, "color");
        const CornerAttribute* uv = find(m, "uv");
        const CornerAttribute* t = find(m, "temperature");
        REQUIRE((color && uv && t));
        REQUIRE(m.attributes.size() == 3);
        CHECK(corner(*color, 0) == std::vector<float>{1.0f, 0.25f, 2.0f, 0.75f}); // vertex 2
        CHECK(corner(*color, 1) == std::vector<float>{0.0f, 0.25f, 2.0f, 0.75f});
        CHECK(corner(*uv, 0) == std::vector<float>{0.25f, 0.75f});
        CHECK(corner(*uv, 2) == std::vector<float>{0.125f, 0.875f});
        CHECK(std::vector<float>(t->values.begin(), t->values.end()) == std::vector<float>{1002, 1000, 1001});
    }
    // Integer colours are divided by their type's maximum; alpha absent is 1.
    std::string text = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nproperty ushort red\nproperty ushort green\nproperty ushort blue\n"
                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i < 3; ++i) {
        for (float p : {float(i == 1), float(i == 2), 0.0f}) put<float>(text, p, false);
        for (std::uint16_t c : {std::uint16_t(65535), std::uint16_t(0), std::uint16_t(13107 * i)})
            put<std::uint16_t>(text, c, false);
    }
    text += char(3);
    for (std::int32_t v : {0, 1, 2}) put<std::int32_t>(text, v, false);
    MeshData m = load_mesh(write_file("ushort.ply", text));
    REQUIRE(m.attributes.size() == 1);
    CHECK(corner(m.attributes[0], 2) == std::vector<float>{1, 0, 0.4f, 1});
}

TEST_CASE("PLY: two properties that give one attribute name are refused by name", "[attributes_load][io]")
{
    std::string text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                       "property float a_b\nproperty float a-b\n"
                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                       "0 0 0 1 2\n1 0 0 1 2\n0 1 0 1 2\n3 0 1 2\n";
    std::string message = load_error(write_file("clash.ply", text));
    CHECK(message.find("clash.ply: vertex property 'a-b' would be the attribute 'a_b', which vertex property "
                       "'a_b' already gives") != std::string::npos);
    // Without attributes: none kept (and STL has none).
    std::string plain = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                        "property float nx\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                        "0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n";
    CHECK(load_mesh(write_file("plain.ply", plain)).attributes.empty());
    std::string stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                      "endfacet\nendsolid t\n";
    CHECK(load_mesh(write_file("plain.stl", stl)).attributes.empty());
}

TEST_CASE("scene files' instances share their prototype's attributes; the bundled spot has its uv",
          "[attributes_load][io][instances]")
{
    std::string obj = write_file("prototype.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25\nf 1/1 2/1 3/1\n");
    std::string json = "{\"meshes\": [{\"file\": \"prototype.obj\", \"instances\": [[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],"
                       " [1,0,0,2, 0,1,0,0, 0,0,1,0, 0,0,0,1]]}, {\"file\": \"prototype.obj\"}]}";
    Scene scene = load_scene_file(write_file("instances.json", json)).scene;
    REQUIRE(scene.prototypes().size() == 1);
    REQUIRE(scene.meshes().size() == 3);
    REQUIRE(scene.prototypes()[0].attributes.size() == 1);
    CHECK(scene.meshes()[0].data.attributes.empty()); // nothing copied per instance
    CHECK(&scene.data_of(0).attributes == &scene.prototypes()[0].attributes);
    CHECK(&scene.data_of(1).attributes == &scene.prototypes()[0].attributes);
    CHECK(corner(scene.data_of(2).attributes[0], 2) == std::vector<float>{0.5f, 0.25f});

    MeshData spot = load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj");
    REQUIRE(spot.attributes.size() == 1);
    CHECK(spot.attributes[0].name == "uv");
    REQUIRE(spot.attributes[0].values.size() == spot.indices.size() * 2);
    std::size_t outside = 0; // a few of spot's vt lie just outside [0, 1]
    for (float f : spot.attributes[0].values) outside += !(f >= -0.1f && f <= 1.1f);
    CHECK(outside == 0);
    CHECK(corner(spot.attributes[0], 0) == std::vector<float>{0.800375f, 0.667457f}); // "f 739/1 735/2 736/3"
    // Its seams: positions whose corners carry different texture coordinates (277 of them).
    std::vector<std::vector<float>> first(spot.vertex_count());
    std::vector<char> seam(spot.vertex_count(), 0);
    for (std::size_t k = 0; k < spot.indices.size(); ++k) {
        std::vector<float> value = corner(spot.attributes[0], k);
        std::vector<float>& f = first[spot.indices[k]];
        if (f.empty()) f = value;
        else if (f != value) seam[spot.indices[k]] = 1;
    }
    CHECK(std::count(seam.begin(), seam.end(), 1) == 277);
}

#ifdef CLVIS_HAVE_TINYGLTF

namespace {

using test::base64;

/// One embedded buffer of views and accessors; the rest of the JSON given by the test.
struct Gltf {
    std::string bin;
    std::vector<std::string> views, accessors;

    /// An accessor over `data`: componentType, type ("VEC2"), count and extra JSON (normalized).
    template <class T>
    int accessor(const std::vector<T>& data, int component_type, const std::string& type, std::size_t count,
                 const std::string& extra = "")
    {
        while (bin.size() % 4) bin += '\0';
        views.push_back("{\"buffer\":0,\"byteOffset\":" + std::to_string(bin.size()) +
                        ",\"byteLength\":" + std::to_string(data.size() * sizeof(T)) + "}");
        bin.append(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(T));
        accessors.push_back("{\"bufferView\":" + std::to_string(views.size() - 1) + ",\"componentType\":" +
                            std::to_string(component_type) + ",\"type\":\"" + type + "\",\"count\":" +
                            std::to_string(count) + extra + "}");
        return int(accessors.size()) - 1;
    }
    static std::string list(const std::vector<std::string>& items)
    {
        std::string s = "[";
        for (std::size_t i = 0; i < items.size(); ++i) s += (i ? "," : "") + items[i];
        return s + "]";
    }
    std::string file(const std::string& rest) const
    {
        return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) +
               ",\"uri\":\"data:application/octet-stream;base64," + base64(bin) + "\"}],\"bufferViews\":" +
               list(views) + ",\"accessors\":" + list(accessors) + "," + rest + "}";
    }
};

constexpr int k_ubyte = 5121, k_ushort = 5123, k_float = 5126;

/// The gltf's attribute `a` of mesh `m`, corner by corner, against `per_vertex` values through m's indices.
void check_corners(const MeshData& m, const CornerAttribute& a, const std::vector<float>& per_vertex)
{
    REQUIRE(a.values.size() == m.indices.size() * std::size_t(a.components));
    for (std::size_t k = 0; k < m.indices.size(); ++k) {
        auto c = std::size_t(a.components);
        std::vector<float> expected(per_vertex.begin() + std::ptrdiff_t(m.indices[k] * c),
                                    per_vertex.begin() + std::ptrdiff_t((m.indices[k] + 1) * c));
        CHECK(corner(a, k) == expected);
    }
}

} // namespace

TEST_CASE("glTF TEXCOORD_0/1 and COLOR_0: normalised as glTF says, per corner, once per shared mesh",
          "[attributes_load][io][gltf]")
{
    Gltf g;
    std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    int pos = g.accessor(quad, k_float, "VEC3", 4);
    int ind = g.accessor(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}, k_ushort, "SCALAR", 6);
    std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 0.5f};
    int tex0 = g.accessor(uv, k_float, "VEC2", 4);
    int tex1 = g.accessor(std::vector<std::uint16_t>{0, 65535, 13107, 0, 65535, 65535, 0, 0}, k_ushort, "VEC2", 4,
                          ",\"normalized\":true");
    int col = g.accessor(std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 51, 102, 153}, k_ubyte, "VEC3", 4,
                         ",\"normalized\":true");
    // A strip of 4 vertices, not indexed, with float RGBA colours; and a primitive without attributes.
    std::vector<float> strip_uv = {0, 0, 0.25f, 0, 0.5f, 0, 0.75f, 0};
    std::vector<float> strip_rgba = {0.1f, 0.2f, 0.3f, 0.4f, 1, 1, 1, 1, 0, 0, 0, 0, 2, 3, 4, 5};
    int spos = g.accessor(quad, k_float, "VEC3", 4);
    int stex = g.accessor(strip_uv, k_float, "VEC2", 4);
    int scol = g.accessor(strip_rgba, k_float, "VEC4", 4);
    int ppos = g.accessor(std::vector<float>{0, 0, 1, 1, 0, 1, 0, 1, 1}, k_float, "VEC3", 3);
    auto n = [](int i) { return std::to_string(i); };
    std::string rest =
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + n(pos) + ",\"TEXCOORD_0\":" + n(tex0) +
        ",\"TEXCOORD_1\":" + n(tex1) + ",\"COLOR_0\":" + n(col) + "},\"indices\":" + n(ind) + "}]},"
        "{\"primitives\":[{\"attributes\":{\"POSITION\":" + n(spos) + ",\"TEXCOORD_0\":" + n(stex) + ",\"COLOR_0\":" +
        n(scol) + "},\"mode\":5}]},{\"primitives\":[{\"attributes\":{\"POSITION\":" + n(ppos) + "}}]}],"
        "\"nodes\":[{\"mesh\":0},{\"mesh\":0,\"translation\":[3,0,0]},{\"mesh\":1},{\"mesh\":2}],"
        "\"scenes\":[{\"nodes\":[0,1,2,3]}]";
    std::string path = write_file("attributes.gltf", g.file(rest));

    GltfScene s = load_gltf(path);
    REQUIRE(s.meshes.size() == 3);
    REQUIRE(s.items.size() == 4);
    const MeshData& m0 = s.meshes[0];
    REQUIRE(m0.attributes.size() == 3);
    CHECK(m0.attributes[0].name == "uv");
    CHECK(m0.attributes[1].name == "uv1");
    CHECK(m0.attributes[2].name == "color");
    check_corners(m0, m0.attributes[0], uv);
    check_corners(m0, m0.attributes[1], {0, 1, 0.2f, 0, 1, 1, 0, 0});
    check_corners(m0, m0.attributes[2], {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 0.2f, 0.4f, 0.6f, 1});
    // The strip's triangles (0,1,2), (1,3,2): corners follow them.
    const MeshData& m1 = s.meshes[1];
    CHECK(m1.indices == std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2});
    REQUIRE(m1.attributes.size() == 2);
    check_corners(m1, m1.attributes[0], strip_uv);
    check_corners(m1, m1.attributes[1], strip_rgba);
    CHECK(s.meshes[2].attributes.empty());

    // As a scene: mesh 0's two nodes are instances of one prototype, which holds its attributes once.
    Scene scene = load_scene({path});
    REQUIRE(scene.prototypes().size() == 1);
    CHECK(scene.prototypes()[0].attributes.size() == 3);
    CHECK(&scene.data_of(0).attributes == &scene.prototypes()[0].attributes);
    CHECK(&scene.data_of(1).attributes == &scene.prototypes()[0].attributes);
    CHECK(scene.data_of(2).attributes.size() == 2);

    // Flattened: every item's corners in id order, NaN where an item lacks the attribute.
    MeshData flat = load_mesh(path);
    REQUIRE(flat.attributes.size() == 3);
    REQUIRE(flat.triangle_count() == 7);
    const CornerAttribute& uv1 = flat.attributes[1];
    CHECK(uv1.name == "uv1");
    for (std::size_t k = 0; k < 12; ++k) CHECK(corner(uv1, k) == corner(m0.attributes[1], k % 6));
    for (std::size_t k = 12; k < 21; ++k) CHECK(all_nan(corner(uv1, k)));
    CHECK(corner(flat.attributes[2], 12) == corner(m1.attributes[1], 0));
    CHECK(all_nan(corner(flat.attributes[0], 20)));
    Scene flat_scene;
    flat_scene.add_mesh(flat); // the attributes are well formed
}

TEST_CASE("glTF attributes of the wrong type or count are refused by name", "[attributes_load][io][gltf]")
{
    struct Case {
        std::string attribute, expected;
        int component_type;
        std::string type, extra;
        std::size_t count;
    } cases[] = {
        {"COLOR_0", "componentType 5120 (normalized) is not FLOAT, or UNSIGNED_BYTE or UNSIGNED_SHORT normalized",
         5120, "VEC3", ",\"normalized\":true", 4},
        {"TEXCOORD_0", "componentType 5121 is not FLOAT, or UNSIGNED_BYTE", k_ubyte, "VEC2", "", 4},
        {"TEXCOORD_0", "type is VEC3, expected VEC2", k_float, "VEC3", "", 4},
        {"TEXCOORD_1", "meshes[0].primitives[0].attributes.TEXCOORD_1: 3 elements, POSITION has 4", k_float, "VEC2", "", 3},
    };
    for (const Case& c : cases) {
        Gltf g;
        int pos = g.accessor(std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, k_float, "VEC3", 4);
        int a = g.accessor(std::vector<float>(16, 0.5f), c.component_type, c.type, c.count, c.extra);
        std::string rest = "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(pos) + ",\"" +
                           c.attribute + "\":" + std::to_string(a) + "},\"mode\":6}]}],\"nodes\":[{\"mesh\":0}],"
                           "\"scenes\":[{\"nodes\":[0]}]";
        std::string path = write_file("bad.gltf", g.file(rest));
        std::string message = load_error(path);
        INFO(c.expected);
        CHECK(message.rfind(path + ":", 0) == 0);
        CHECK(message.find(c.expected) != std::string::npos);
    }
}

#endif // CLVIS_HAVE_TINYGLTF
