// Mesh and scene files: the bundled meshes with their triangle counts and fan ids, the OBJ
// index forms, PLY in all three encodings, STL both ways, the JSON scene file, and named errors
// (file, line or byte) for malformed input, including every assimp test model.
#include "catch.hpp"

#include "scene/scene_parsers.hpp"

#include <clvis/clvis.hpp>
#include <clvis/views_file.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

using namespace clvis;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir()
{
    fs::path dir = fs::temp_directory_path() / "clvis-scene-io-test";
    fs::create_directories(dir);
    return dir;
}

std::string write_file(const std::string& name, const std::string& bytes)
{
    fs::path p = temp_dir() / name;
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return p.string();
}

std::string scene_path(const std::string& name) { return std::string(CLVIS_SOURCE_DIR) + "/scenes/" + name; }

/// The message of the Error that loading `path` throws, after checking its kind; "" if none.
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

std::vector<std::uint32_t> triangle(const MeshData& m, std::size_t t)
{
    return {m.indices[t * 3], m.indices[t * 3 + 1], m.indices[t * 3 + 2]};
}

void append_le(std::string& s, const void* p, std::size_t n)
{
    s.append(static_cast<const char*>(p), n);
}
void append_be(std::string& s, const void* p, std::size_t n)
{
    const char* c = static_cast<const char*>(p);
    for (std::size_t i = n; i-- > 0;) s.push_back(c[i]);
}

} // namespace

TEST_CASE("every bundled mesh loads with its documented triangle count", "[io]")
{
    struct Expect {
        const char* file;
        std::size_t triangles;
    } expected[] = {{"stanford-bunny.obj", 69451}, {"teapot.obj", 6320}, {"spot.obj", 5856}, {"suzanne.obj", 968}};
    for (const Expect& e : expected) {
        INFO(e.file);
        MeshData m = load_mesh(scene_path(e.file));
        CHECK(m.triangle_count() == e.triangles);
        Scene s;
        CHECK_NOTHROW(s.add_mesh(std::move(m)));
    }
}

TEST_CASE("suzanne's quads become fans (v0, vk, vk+1) in file order", "[io]")
{
    MeshData m = load_mesh(scene_path("suzanne.obj"));
    REQUIRE(m.triangle_count() == 968);
    // f 1//1 3//3 45//45 47//47: the first quad.
    CHECK(triangle(m, 0) == std::vector<std::uint32_t>{0, 2, 44});
    CHECK(triangle(m, 1) == std::vector<std::uint32_t>{0, 44, 46});
    // SOURCES.md: fans 269 and 270 are one triangle wound both ways (1-based 71, 139, 138).
    CHECK(triangle(m, 269) == std::vector<std::uint32_t>{70, 138, 137});
    CHECK(triangle(m, 270) == std::vector<std::uint32_t>{70, 137, 138});
    CHECK(triangle(m, 967) == std::vector<std::uint32_t>{322, 390, 504});
    // Its faces name one normal per position (v//vn with equal indices): the normals are kept.
    CHECK(m.normals.size() == m.positions.size());
}

TEST_CASE("OBJ negative indices count back from the last vertex so far", "[io]")
{
    MeshData m = load_mesh(write_file("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
                                                      "v 0 0 1\nf -4 -1 -2\nvt 0 0\nf -1/-1 -2/-1 -3/-1\n"));
    REQUIRE(m.triangle_count() == 3);
    CHECK(triangle(m, 0) == std::vector<std::uint32_t>{0, 1, 2});
    CHECK(triangle(m, 1) == std::vector<std::uint32_t>{0, 3, 2});
    CHECK(triangle(m, 2) == std::vector<std::uint32_t>{3, 2, 1});
    // A relative texture coordinate index before any vt reaches before the first one.
    std::string msg = load_error(write_file("negative_vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/-1 2 3\n"));
    CHECK(msg.find("negative_vt.obj:4: relative texture coordinate index -1") != std::string::npos);
}

TEST_CASE("OBJ faces in every index form give the same positions and triangles", "[io]")
{
    const char* vertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n";
    const char* faces[] = {"f 1 2 3 4\n", "f 1/1 2/2 3/3 4/1\n", "f 1//1 2//1 3//1 4//1\n", "f 1/1/1 2/2/1 3/3/1 4/3/1\n"};
    for (const char* f : faces) {
        INFO(f);
        MeshData m = load_mesh(write_file("forms.obj", std::string(vertices) + f));
        REQUIRE(m.triangle_count() == 2);
        CHECK(triangle(m, 0) == std::vector<std::uint32_t>{0, 1, 2});
        CHECK(triangle(m, 1) == std::vector<std::uint32_t>{0, 2, 3});
        CHECK(m.positions == std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    }
}

TEST_CASE("OBJ groups go into one mesh in order, lines, points and the rest skipped", "[io]")
{
    std::string text = "# comment\nmtllib x.mtl\no first\nv 0 0 0\nv 1 0 0\nv 0 1 0 1.0 0.5 0.5 0.5\n"
                       "usemtl red\ns 1\nf 1 2 3\nl 1 2\np 3\ng second\nv 0 0 1\ncstype bezier\n"
                       "f 1 3 4 # trailing comment\n\n   \t\n";
    MeshData m = load_mesh(write_file("groups.obj", text));
    REQUIRE(m.triangle_count() == 2);
    CHECK(m.vertex_count() == 4);
    CHECK(triangle(m, 1) == std::vector<std::uint32_t>{0, 2, 3});
    CHECK(m.normals.empty());
}

TEST_CASE("OBJ line continuations, CRLF, a BOM and a last line without newline are read", "[io]")
{
    std::string text = "\xEF\xBB\xBFv 0 0 0\r\nv 1 \\\r\n 0 0\r\nv 0 1 0\nf 1 2 \\\n 3";
    MeshData m = load_mesh(write_file("continued.obj", text));
    REQUIRE(m.triangle_count() == 1);
    CHECK(m.positions == std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
    // A later error still names the physical line.
    std::string msg = load_error(write_file("continued_bad.obj", "v 0 0 \\\n0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"));
    CHECK(msg.find("continued_bad.obj:5:") != std::string::npos);
}

TEST_CASE("OBJ polygons fan in order and degenerate faces keep their ids", "[io]")
{
    std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 1 0\n"
                       "f 1 1 1\nf 1 2 3 4 5\nf 2 2 3\n";
    MeshData m = load_mesh(write_file("fan.obj", text));
    REQUIRE(m.triangle_count() == 5);
    CHECK(triangle(m, 0) == std::vector<std::uint32_t>{0, 0, 0});
    CHECK(triangle(m, 1) == std::vector<std::uint32_t>{0, 1, 2});
    CHECK(triangle(m, 2) == std::vector<std::uint32_t>{0, 2, 3});
    CHECK(triangle(m, 3) == std::vector<std::uint32_t>{0, 3, 4});
    CHECK(triangle(m, 4) == std::vector<std::uint32_t>{1, 1, 2});
}

TEST_CASE("OBJ normals are kept only when each position has one normal", "[io]")
{
    std::string base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 0 -1\nvn 0 0 1\n";
    MeshData same = load_mesh(write_file("n1.obj", base + "f 1//1 2//1 3//1\nf 2//3 4//3 3//3\n"));
    REQUIRE(same.normals.size() == 12);
    CHECK(same.normals[3 * 3 + 2] == 1.0f);
    MeshData conflict = load_mesh(write_file("n2.obj", base + "f 1//1 2//1 3//1\nf 2//2 4//2 3//2\n"));
    CHECK(conflict.normals.empty());
    MeshData partial = load_mesh(write_file("n3.obj", base + "f 1//1 2//1 3//1\nf 2 4 3\n"));
    CHECK(partial.normals.empty());
    MeshData forward = load_mesh(write_file("n4.obj", "f 1//1 2//1 3//1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1 0\n"));
    CHECK(forward.normals == std::vector<float>{0, 1, 0, 0, 1, 0, 0, 1, 0});
}

TEST_CASE("malformed OBJ files throw Error(Io) naming the file and the line", "[io]")
{
    struct Case {
        const char* text;
        int line;
        const char* says;
    } cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", 4, "before the first"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n", 4, "out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", 4, "at least 3"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", 4, "malformed"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/5 2 3\n", 4, "texture coordinate index 5"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//2 3//2\nvn 0 0 1\n", 4, "normal index 2"},
        {"# header\nv 0 0 zero\n", 2, "malformed"},
        {"v 0 0 0\nv 1 0\n", 2, "needs 3 coordinates"},
        {"v 0 0 0\nv 1 nan 0\n", 2, "non-finite"},
        {"v 0 0 0\nv 1 1e39 0\n", 2, "non-finite"},
        {"v 0 0 0\n\n\nv 1 0 inf\n", 4, "non-finite"},
        {"v 1 2 3.1+e2\n", 1, "malformed"},
        {"v 1 2 ++3\n", 1, "malformed"},
        {"vn 0 0 x\n", 1, "malformed"},
    };
    for (const Case& c : cases) {
        INFO(c.text);
        std::string msg = load_error(write_file("bad_case.obj", c.text));
        CHECK(msg.find("bad_case.obj:" + std::to_string(c.line) + ":") != std::string::npos);
        CHECK(msg.find(c.says) != std::string::npos);
    }
}

TEST_CASE("files without triangles, empty and missing files are errors that name the file", "[io]")
{
    CHECK(load_error(write_file("empty.obj", "")).find("empty.obj: contains no triangles") != std::string::npos);
    CHECK(load_error(write_file("points.obj", "v 0 0 0\nv 1 0 0\np 1 2\nl 1 2\n")).find("no triangles") !=
          std::string::npos);
    CHECK(load_error(write_file("empty.ply", "")).find("empty.ply") != std::string::npos);
    CHECK(load_error(write_file("empty.stl", "")).find("empty.stl") != std::string::npos);
    CHECK(load_error(write_file("empty.mesh", "")).find("empty.mesh: empty file") != std::string::npos);
    std::string missing = (temp_dir() / "does-not-exist.obj").string();
    CHECK(load_error(missing).find(missing + ": cannot read") != std::string::npos);
    CHECK(load_error(temp_dir().string()).find("not a regular file") != std::string::npos);
}

namespace {

/// A small mesh in PLY, with properties to skip: a double-precision vertex with an extra
/// property, an int list of indices named vertex_index, a second list before it, and an
/// "edge" element with a list of its own.
std::string ply_file(const char* format)
{
    std::string h = std::string("ply\nformat ") + format + " 1.0\ncomment made by the test\n"
                    "element vertex 5\nproperty double x\nproperty uchar tag\nproperty double y\nproperty float z\n"
                    "element edge 1\nproperty list uchar int ends\n"
                    "element face 3\nproperty list uchar float uv\nproperty list ushort int vertex_index\n"
                    "property short flags\nend_header\n";
    const double xy[5][2] = {{0, 0}, {1.5, 0}, {1, 1}, {0, 1}, {-0.25, 2e-3}};
    const float z[5] = {0.5f, 0.1f, -3, 1e-7f, 1e8f};
    const std::vector<std::vector<std::int32_t>> faces = {{0, 1, 2}, {0, 2, 3, 4}, {4, 4, 1}};
    bool ascii = std::strcmp(format, "ascii") == 0, big = std::strcmp(format, "binary_big_endian") == 0;
    auto put = [&](const void* p, std::size_t n) { big ? append_be(h, p, n) : append_le(h, p, n); };
    for (int v = 0; v < 5; ++v) {
        unsigned char tag = std::uint8_t(200 + v);
        if (ascii) {
            char line[128];
            std::snprintf(line, sizeof line, "%.17g %d %.17g %.9g\n", xy[v][0], tag, xy[v][1], double(z[v]));
            h += line;
        } else {
            put(&xy[v][0], 8);
            put(&tag, 1);
            put(&xy[v][1], 8);
            put(&z[v], 4);
        }
    }
    if (ascii) {
        h += "2 0 1\n";
    } else {
        unsigned char two = 2;
        std::int32_t ends[2] = {0, 1};
        put(&two, 1);
        put(&ends[0], 4);
        put(&ends[1], 4);
    }
    for (const auto& f : faces) {
        std::uint16_t n = std::uint16_t(f.size());
        std::int16_t flags = -7;
        unsigned char uvs = 2;
        float uv[2] = {0.25f, 0.75f};
        if (ascii) {
            h += "2 0.25 0.75 " + std::to_string(n);
            for (std::int32_t i : f) h += " " + std::to_string(i);
            h += " -7\n";
        } else {
            put(&uvs, 1);
            put(&uv[0], 4);
            put(&uv[1], 4);
            put(&n, 2);
            for (std::int32_t i : f) put(&i, 4);
            put(&flags, 2);
        }
    }
    return h;
}

} // namespace

TEST_CASE("PLY ascii, binary little and big endian give the same mesh", "[io]")
{
    MeshData a = load_mesh(write_file("a.ply", ply_file("ascii")));
    MeshData le = load_mesh(write_file("le.ply", ply_file("binary_little_endian")));
    MeshData be = load_mesh(write_file("be.ply", ply_file("binary_big_endian")));
    REQUIRE(a.triangle_count() == 4);
    CHECK(a.indices == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4, 4, 4, 1});
    CHECK(a.positions == std::vector<float>{0, 0, 0.5f, 1.5f, 0, 0.1f, 1, 1, -3, 0, 1, 1e-7f, -0.25f, 2e-3f, 1e8f});
    CHECK(le.indices == a.indices);
    CHECK(be.indices == a.indices);
    CHECK(le.positions == a.positions);
    CHECK(be.positions == a.positions);
}

TEST_CASE("PLY with CRLF, a stray header line, integer coordinates, vertex_indices loads", "[io]")
{
    std::string text = "ply\r\nformat ascii 1.0\r\nCreated by an exporter\r\nelement vertex 3\r\nproperty int x\r\nproperty int y\r\n"
                       "property int z\r\nelement face 1\r\nproperty list uchar uint vertex_indices\r\nend_header\r\n"
                       "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
    MeshData m = load_mesh(write_file("crlf.ply", text));
    CHECK(m.indices == std::vector<std::uint32_t>{0, 1, 2});
    CHECK(m.positions == std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
}

TEST_CASE("malformed PLY files throw Error(Io) naming the file and the line or byte", "[io]")
{
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    struct Case {
        std::string text;
        const char* says;
    } cases[] = {
        {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "face 0 refers to vertex 3"},
        {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", "bad_case.ply:13: face 0"},
        {head + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "at least 3"},
        {head + "0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", "bad_case.ply:11: vertex 1: malformed"},
        {head + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "bad_case.ply:11: vertex 1: non-finite"},
        {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "ends before"},
        {head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n", "unexpected data"},
        {"ply\nformat ascii 1.0\nelement vertex 999999999\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n0 0 0\n", "more than the rest of the file can hold"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float y\nproperty float z\nend_header\n", "no property 'x'"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "no end_header"},
        {"ply\nformat text 1.0\nend_header\n", "bad_case.ply:2: unknown format"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float128 x\nend_header\n", "bad_case.ply:4:"},
        {"ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "bad_case.ply:3: malformed element count"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n", "no triangles"},
        {"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n" + std::string(20, '\0'), "more than the rest of the file can hold"},
        {"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n" +
             std::string(12, '\0') + std::string("\xff\xff\xff\x7f", 4) + std::string(12, '\0'),
         "truncated"},
    };
    for (const Case& c : cases) {
        INFO(c.text);
        std::string msg = load_error(write_file("bad_case.ply", c.text));
        CHECK(msg.find("bad_case.ply") != std::string::npos);
        CHECK(msg.find(c.says) != std::string::npos);
    }
}

TEST_CASE("PLY binary errors name the byte offset and the element", "[io]")
{
    std::string text = "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                       "property float z\nend_header\n";
    std::size_t body = text.size();
    float v[6] = {0, 0, 0, 1, std::numeric_limits<float>::infinity(), 0};
    for (float f : v) append_be(text, &f, 4);
    std::string msg = load_error(write_file("inf.ply", text));
    CHECK(msg.find("inf.ply: byte " + std::to_string(body + 16) + " (vertex 1): non-finite") != std::string::npos);
}

namespace {

std::string stl_binary(const std::vector<float>& triangles, const std::string& header)
{
    std::string s = header;
    s.resize(80, ' ');
    std::uint32_t n = std::uint32_t(triangles.size() / 9);
    append_le(s, &n, 4);
    for (std::uint32_t t = 0; t < n; ++t) {
        float normal[3] = {0, 0, 1};
        append_le(s, normal, 12);
        append_le(s, &triangles[t * 9], 36);
        s.append(2, '\0');
    }
    return s;
}

const std::vector<float> stl_triangles = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0.5f, -2.25f, 1e-3f};

} // namespace

TEST_CASE("STL ascii and binary give the same triangles, facet by facet", "[io]")
{
    // The facet normal is not used: "nan" there (exporters write it for degenerate facets) loads.
    std::string ascii = "solid test\n"
                        "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
                        "      vertex 0 1 0\n    endloop\n  endfacet\nendsolid test\n"
                        "solid second\n facet normal nan nan nan\n outer loop\n vertex 0 0 1\n vertex 1 0 1\n"
                        " vertex 0.5 -2.25 1e-3\n endloop\n endfacet\nendsolid\n";
    MeshData a = load_mesh(write_file("a.stl", ascii));
    MeshData b = load_mesh(write_file("b.stl", stl_binary(stl_triangles, "binary")));
    // A binary file whose header starts with "solid": its size says binary.
    MeshData c = load_mesh(write_file("c.stl", stl_binary(stl_triangles, "solid but binary")));
    for (const MeshData* m : {&a, &b, &c}) {
        CHECK(m->positions == stl_triangles);
        CHECK(m->indices == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5});
    }
}

TEST_CASE("malformed STL files throw Error(Io) naming the file and the line or byte", "[io]")
{
    std::string truncated = stl_binary(stl_triangles, "binary");
    truncated.resize(truncated.size() - 10);
    CHECK(load_error(write_file("t.stl", truncated)).find("t.stl: truncated binary STL") != std::string::npos);
    std::string lying = stl_binary(stl_triangles, "binary");
    lying[80] = '\xff';
    lying[83] = '\x7f';
    CHECK(load_error(write_file("l.stl", lying)).find("l.stl: truncated binary STL: byte 80") != std::string::npos);
    std::vector<float> nan = stl_triangles;
    nan[9] = std::numeric_limits<float>::quiet_NaN();
    CHECK(load_error(write_file("n.stl", stl_binary(nan, "x"))).find("n.stl: byte 146 (triangle 1): non-finite") !=
          std::string::npos);
    std::string text = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n";
    CHECK(load_error(write_file("a.stl", text)).find("a.stl:6: expected 'vertex', found 'endloop'") != std::string::npos);
    CHECK(load_error(write_file("b.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 q\n"))
              .find("b.stl:4: malformed") != std::string::npos);
    CHECK(load_error(write_file("c.stl", "solid x\nendsolid x\n")).find("c.stl: contains no triangles") !=
          std::string::npos);
}

TEST_CASE("without a known extension the format comes from the content", "[io]")
{
    CHECK(load_mesh(write_file("obj.mesh", "# c\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).triangle_count() == 1);
    CHECK(load_mesh(write_file("ply.mesh", ply_file("binary_little_endian"))).triangle_count() == 4);
    CHECK(load_mesh(write_file("stl.mesh", stl_binary(stl_triangles, "anything"))).triangle_count() == 2);
    CHECK(load_mesh(write_file("upper.STL", stl_binary(stl_triangles, "anything"))).triangle_count() == 2);
    CHECK(load_error(write_file("what.mesh", "hello world\n")).find("what.mesh: unknown mesh format") !=
          std::string::npos);
}

#if __has_include(<nlohmann/json.hpp>)

TEST_CASE("a JSON scene file gives meshes with transforms, a camera and an image size", "[io]")
{
    fs::path dir = temp_dir() / "scene";
    fs::create_directories(dir / "sub");
    write_file("scene/sub/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::string json = R"({
      "meshes": [
        {"file": "sub/tri.obj"},
        {"file": ")" + (dir / "sub" / "tri.obj").string() + R"(",
         "transform": [2, 0, 0, 10,  0, 1, 0, 20,  0, 0, 1, 30,  0, 0, 0, 1]}
      ],
      "camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 30, "near": 0.5, "far": 50},
      "width": 640, "height": 480
    })";
    std::string path = write_file("scene/scene.json", json);
    SceneFile f = load_scene_file(path);
    REQUIRE(f.scene.meshes().size() == 2);
    CHECK(f.scene.triangle_count() == 2);
    CHECK(f.scene.meshes()[0].transform.is_identity());
    CHECK(f.scene.meshes()[1].transform(0, 0) == 2);
    CHECK(f.scene.meshes()[1].transform(2, 3) == 30);
    CHECK(f.scene.world_positions()[3 * 4] == 12.0f); // mesh 1's vertex 1: (1,0,0) -> (12,20,30)
    REQUIRE(f.camera.has_value());
    CHECK(f.camera->eye.z == 5);
    CHECK(f.camera->fov_y == 30);
    CHECK(f.camera->near == 0.5);
    CHECK(f.camera->far == 50);
    CHECK(f.camera->projection == Projection::Perspective);
    CHECK(f.width == 640);
    CHECK(f.height == 480);

    std::string ortho = write_file("scene/ortho.json", R"({"meshes": [{"file": "sub/tri.obj"}],
        "camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "ortho": 3, "near": 1, "far": 9}})");
    SceneFile o = load_scene_file(ortho);
    REQUIRE(o.camera.has_value());
    CHECK(o.camera->projection == Projection::Orthographic);
    CHECK(o.camera->ortho_height == 3);
    CHECK(o.width == 0);
    CHECK(load_scene({path}).triangle_count() == 2);

    // A pose (camera-to-world, row by row) and intrinsics in pixels: the camera at (1, 2, 3)
    // looking down world -x with y up.
    std::string posed = write_file("scene/posed.json", R"({"meshes": [{"file": "sub/tri.obj"}],
        "camera": {"pose": [0, 0, 1, 1,  0, 1, 0, 2,  -1, 0, 0, 3,  0, 0, 0, 1],
                   "intrinsics": [500, 400, 320.5, 240.25], "near": 0.5, "far": 50}})");
    SceneFile q = load_scene_file(posed);
    REQUIRE(q.camera.has_value());
    REQUIRE(q.camera->intrinsics.has_value());
    CHECK(q.camera->intrinsics->cx == 320.5);
    CHECK(q.camera->intrinsics->fy == 400);
    CHECK(q.camera->eye.x == 1);
    CHECK(q.camera->frame().f.x == -1);
    CHECK(q.camera->frame().r.z == -1);
    CHECK(q.camera->near == 0.5);
}

TEST_CASE("a views file gives cameras of one size; {view} names are zero-padded", "[io]")
{
    fs::create_directories(temp_dir() / "scene");
    std::string path = write_file("scene/views.json", R"({"width": 64, "height": 48, "views": [
        {"eye": [0, 0, 5], "target": [0, 0, 0], "fov": 30},
        {"pose": [1,0,0,0, 0,1,0,0, 0,0,1,7, 0,0,0,1], "intrinsics": [50, 50, 32, 24], "near": 1, "far": 20}]})");
    ViewsFile f = load_views_file(path);
    CHECK(f.width == 64);
    CHECK(f.height == 48);
    REQUIRE(f.views.size() == 2);
    CHECK(f.views[0].fov_y == 30);
    CHECK(f.views[1].eye.z == 7);
    REQUIRE(f.views[1].intrinsics.has_value());
    CHECK(f.views[1].intrinsics->fx == 50);
    std::string bad = write_file("scene/bad-views.json", R"({"width": 64, "height": 48, "views": [
        {"eye": [0, 0, 5], "target": [0, 0, 0]}, {"target": [0, 0, 0]}]})");
    std::string msg;
    try {
        load_views_file(bad);
    } catch (const Error& e) {
        msg = e.what();
    }
    CHECK(msg == bad + ": views[1].eye: is needed with views[1].target");
    std::string none = write_file("scene/no-views.json", R"({"width": 64, "height": 48, "views": []})");
    CHECK_THROWS_AS(load_views_file(none), Error);
    CHECK(view_file_name("out/ids-{view}.tif", 7, 63) == "out/ids-07.tif");
    CHECK(view_file_name("{view}/{view}.exr", 3, 9) == "3/3.exr");
    CHECK(view_file_name("ids.tif", 3, 9) == "ids.tif");
    CHECK(view_file_name("v{view}", 120, 1000) == "v0120");
}

TEST_CASE("a scene file describes every camera the flags can, physical included", "[io]")
{
    fs::create_directories(temp_dir() / "scene");
    write_file("scene/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    auto camera_of = [](const std::string& camera, const std::string& size = "") {
        std::string json = R"({"meshes": [{"file": "tri.obj"}], "camera": )" + camera + size + "}";
        SceneFile f = load_scene_file(write_file("scene/camera.json", json));
        REQUIRE(f.camera.has_value());
        return *f.camera;
    };
    const Vec3 eye{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
    const std::string look = R"("eye": [0, 0, 5], "target": [0, 0, 0], )";
    // The physical camera at the file's own aspect (100x50 = 2), and at the default 1920x1080.
    Camera physical = camera_of("{" + look + R"("focal_length": 50, "film_gate": [36, 24], "fit": "overscan", )"
                                R"("near": 1, "far": 9})", R"(, "width": 100, "height": 50)");
    Camera expected = Camera::physical(eye, target, up, 50, 36, 24, FilmFit::Overscan, 2.0, 1, 9);
    CHECK(physical.fov_y == Approx(expected.fov_y).epsilon(1e-12));
    Camera fill = camera_of("{" + look + R"("focal_length": 50, "film_gate": [36, 24], "near": 1, "far": 9})");
    CHECK(fill.fov_y == Approx(Camera::physical(eye, target, up, 50, 36, 24, FilmFit::Fill, 1920.0 / 1080, 1, 9).fov_y));
    // No eye and target: the framing camera, orthographic with "ortho": true, with given fields.
    Scene tri;
    tri.add_mesh(load_mesh((temp_dir() / "scene" / "tri.obj").string()));
    Camera framing_ortho = Camera::framing(tri.bounds(), Projection::Orthographic);
    Camera ortho = camera_of(R"({"ortho": true})");
    CHECK(ortho.projection == Projection::Orthographic);
    CHECK(ortho.ortho_height == framing_ortho.ortho_height);
    CHECK(ortho.eye.z == framing_ortho.eye.z);
    Camera narrow = camera_of(R"({"fov": 20, "near": 0.25})");
    CHECK(narrow.fov_y == 20);
    CHECK(narrow.near == 0.25);
    CHECK(narrow.eye.x == Camera::framing(tri.bounds()).eye.x);
    // Every camera field that the tool's flags take, a scene file takes under the same name.
    for (const CameraField& field : camera_fields()) {
        INFO(field.name);
        std::string value = field.numbers == 0 ? "\"overscan\"" : field.numbers == 1 ? "2" : "[";
        for (int i = 0; field.numbers > 1 && i < field.numbers; ++i) value += (i ? ", " : "") + std::string("3");
        if (field.numbers > 1) value += "]";
        std::string json = std::string(R"({"meshes": [{"file": "tri.obj"}], "camera": {")") + field.name + "\": " +
                           value + "}}";
        std::string msg;
        try {
            load_scene_file(write_file("scene/field.json", json));
        } catch (const Error& e) {
            msg = e.what();
        }
        CHECK(msg.find("not a camera field") == std::string::npos);
        CHECK(msg.find("expected") == std::string::npos);
    }
}

TEST_CASE("bad scene files name the file and the JSON path of the bad field", "[io]")
{
    fs::create_directories(temp_dir() / "scene");
    write_file("scene/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_file("scene/bad.obj", "v 0 0 0\nf 1 2 3\n");
    struct Case {
        const char* json;
        const char* says;
    } cases[] = {
        {R"({"meshes": [{"file": "tri.obj"}, {"file": "tri.obj", "transform": [1, 2, 3]}]})",
         "meshes[1].transform: expected 16 numbers"},
        {R"({"meshes": [{"file": "tri.obj", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]}]})",
         "meshes[0].transform: the last row must be 0 0 0 1"},
        {R"({"meshes": [{"file": "tri.obj", "transform": [1,0,0,0, 0,"a",0,0, 0,0,1,0, 0,0,0,1]}]})",
         "meshes[0].transform[5]: expected a number"},
        {R"({"meshes": [{"file": "missing.obj"}]})", "meshes[0].file: "},
        {R"({"meshes": [{"file": "bad.obj"}]})", "bad.obj:2: vertex index 2 is out of range"},
        {R"({"meshes": [{"file": 7}]})", "meshes[0].file: expected a file name"},
        {R"({"meshes": [{"flie": "tri.obj"}]})", "meshes[0].flie: unknown field"},
        {R"({"meshes": []})", "meshes: expected a non-empty array"},
        {R"({"mesh": []})", "mesh: unknown field"},
        {R"({})", "meshes: missing"},
        {R"([1, 2])", "expected a JSON object"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0, 0], "target": [0, 0, 0]}})",
         "camera.eye: expected 3 numbers"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0, 0, 1], "target": [0, 0, 0], "fov": 30, "ortho": 2}})",
         "camera.fov: give one projection"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0, 0, 1], "target": [0, 0, 0], "near": -1}})",
         "camera.near: "},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"target": [0, 0, 0]}})", "camera.eye: is needed with"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"fob": 30}})", "camera.fob: not a camera field"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"ortho": 0}})", "camera.ortho: the view height must be > 0"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"ortho": false}})", "camera.ortho: expected a number"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"fit": "wide"}})", "camera.fit: expected fill or overscan"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"fit": "fill"}})", "camera.fit: applies to the physical"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"focal_length": 35}})",
         "camera.film_gate: is needed with camera.focal_length"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"film_gate": [36, 0], "focal_length": 35}})",
         "camera.film_gate: the gate's height must be > 0"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov": [30, 40]}})", "camera.fov: expected 1 number"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "eye": [0, 0, 1]}})",
         "camera.pose: replaces camera.eye"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"pose": [2,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}})",
         "camera.pose: pose: the 3x3 part is not orthonormal"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0, 0, 1], "target": [0, 0, 0], "intrinsics": [1, 1, 0]}})",
         "camera.intrinsics: expected 4 numbers"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0, 0, 1], "target": [0, 0, 0], "intrinsics": [1, 1, 0, 0], "fov": 3}})",
         "camera.intrinsics: replaces camera.fov"},
        {R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0, 0, 1], "target": [0, 0, 0], "intrinsics": [-1, 1, 0, 0]}})",
         "camera.intrinsics: fx must be > 0"},
        {R"({"meshes": [{"file": "tri.obj"}], "width": 640.5})", "width: expected an integer"},
        {R"({"meshes": [{"file": "tri.obj"}], "height": 0})", "height: expected an integer"},
        {R"({"meshes": [{"file": "tri.obj"}],)", "invalid JSON"},
    };
    for (const Case& c : cases) {
        INFO(c.json);
        std::string path = write_file("scene/bad.json", c.json);
        std::string msg;
        try {
            load_scene_file(path);
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::Io);
            msg = e.what();
        }
        CHECK(msg.find(path + ": ") == 0);
        CHECK(msg.find(c.says) != std::string::npos);
    }
    std::string deep = "{\"meshes\": " + std::string(10000, '[') + std::string(10000, ']') + "}";
    CHECK_THROWS_AS(load_scene_file(write_file("scene/deep.json", deep)), Error);
}

#else

TEST_CASE("without nlohmann::json a scene file is refused with a clear error", "[io]")
{
    std::string path = write_file("nojson.json", "{}");
    try {
        load_scene_file(path);
        FAIL("load_scene_file read a scene file without JSON support");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Io);
        CHECK(std::string(e.what()).find("nlohmann::json") != std::string::npos);
    }
}

#endif

TEST_CASE("load_scene concatenates mesh files in order and takes a scene file only alone", "[io]")
{
    std::string a = write_file("one.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::string b = write_file("two.stl", stl_binary(stl_triangles, "x"));
    Scene s = load_scene({a, b, a});
    CHECK(s.triangle_count() == 4);
    CHECK(s.meshes()[1].first_triangle == 1);
    CHECK(s.meshes()[2].first_triangle == 3);
    CHECK_THROWS_AS(load_scene({}), Error);
    CHECK_THROWS_AS(load_scene({a, write_file("s.json", "{}")}), Error);
}

TEST_CASE("every assimp test model either loads or throws clvis::Error", "[io]")
{
    // The set-up installs assimp-testmodels: a missing folder is a broken install, not a skip.
    const fs::path root = "/usr/share/assimp/models";
    REQUIRE(fs::is_directory(root / "invalid"));
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(root / "invalid"))
        if (e.is_regular_file()) files.push_back(e.path());
    for (const char* sub : {"OBJ", "PLY", "STL"})
        for (const auto& e : fs::directory_iterator(root / sub)) {
            detail::MeshFormat f = detail::format_from_extension(e.path().string());
            if (e.is_regular_file() && f != detail::MeshFormat::Unknown) files.push_back(e.path());
        }
    REQUIRE(files.size() > 40);
    std::size_t loaded = 0;
    for (const fs::path& p : files) {
        INFO(p.string());
        try {
            MeshData m = load_mesh(p.string());
            Scene s;
            s.add_mesh(std::move(m)); // what loads is a valid mesh
            ++loaded;
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find(p.string()) == 0);
        }
    }
    CHECK(loaded > 20);
}
