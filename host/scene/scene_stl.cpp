// STL from memory into one MeshData, ASCII or binary. Every facet becomes one triangle with
// three vertices of its own (positions are not welded, so vertex 3i..3i+2 is facet i); ids are
// facet order, solid after solid. Called by load_mesh (host/scene/scene_io.cpp) and by fuzz_stl.
#include "scene/scene_parsers.hpp"
#include "scene/text_parse.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace clvis::detail {

namespace {

constexpr std::size_t CLVIS_STL_HEADER = 84; ///< bytes: 80 of header text, a uint32 count
constexpr std::size_t CLVIS_STL_FACET = 50;  ///< bytes: normal, 3 vertices (float32), uint16

bool starts_with_solid(std::string_view bytes)
{
    std::size_t i = 0;
    while (i < bytes.size() && TextCursor::is_blank(bytes[i])) ++i;
    return bytes.compare(i, 5, "solid") == 0 && (i + 5 == bytes.size() || TextCursor::is_blank(bytes[i + 5]));
}

std::uint32_t read_u32_le(const unsigned char* p)
{
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

float read_f32_le(const unsigned char* p)
{
    std::uint32_t u = read_u32_le(p);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

MeshData parse_binary(std::string_view bytes, const std::string& name)
{
    if (bytes.size() < CLVIS_STL_HEADER)
        fail(name, "truncated binary STL: " + std::to_string(bytes.size()) + " bytes, the header alone takes 84");
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    std::uint64_t count = read_u32_le(data + 80);
    std::uint64_t room = (bytes.size() - CLVIS_STL_HEADER) / CLVIS_STL_FACET;
    if (count > room)
        fail(name, "truncated binary STL: byte 80 declares " + std::to_string(count) + " triangles, the file holds " +
                       std::to_string(room) + " (" + std::to_string(bytes.size()) + " bytes)");
    if (count == 0) fail(name, "contains no triangles (binary STL with a count of 0)");
    MeshData mesh;
    mesh.name = name;
    mesh.positions.resize(count * 9);
    mesh.indices.resize(count * 3);
    for (std::uint64_t t = 0; t < count; ++t) {
        const unsigned char* facet = data + CLVIS_STL_HEADER + t * CLVIS_STL_FACET;
        for (int k = 0; k < 9; ++k) {
            float v = read_f32_le(facet + 12 + 4 * k);
            if (!std::isfinite(v))
                fail(name, "byte " + std::to_string(CLVIS_STL_HEADER + t * CLVIS_STL_FACET + 12 + 4 * k) + " (triangle " +
                               std::to_string(t) + "): non-finite coordinate");
            mesh.positions[t * 9 + k] = v;
        }
        for (int k = 0; k < 3; ++k) mesh.indices[t * 3 + k] = std::uint32_t(t * 3 + k);
    }
    return mesh;
}

class AsciiStlParser {
public:
    AsciiStlParser(std::string_view text, const std::string& name) : c_(text), name_(name) { mesh_.name = name; }

    MeshData parse()
    {
        for (;;) {
            c_.skip_space();
            if (c_.at_end()) break;
            std::string_view word = c_.token();
            if (word == "solid" || word == "endsolid") c_.next_line(); // the rest is the solid's name
            else if (word == "facet") facet();
            else fail("expected 'solid', 'facet' or 'endsolid', found '" + std::string(word.substr(0, 32)) + "'");
        }
        if (mesh_.indices.empty()) clvis::detail::fail(name_, "contains no triangles (no facets)");
        return std::move(mesh_);
    }

private:
    [[noreturn]] void fail(const std::string& what) const { fail_at_line(name_, c_.line, what); }

    void expect(std::string_view word)
    {
        c_.skip_space();
        std::string_view got = c_.token();
        if (got != word) fail("expected '" + std::string(word) + "', found '" + std::string(got.substr(0, 32)) + "'");
    }

    float number(const char* what)
    {
        c_.skip_space();
        float v;
        if (!parse_float(c_, v))
            fail("malformed or out-of-range number '" + std::string(token_preview(c_)) + "' in " + what);
        return v;
    }

    float coordinate()
    {
        float v = number("a vertex");
        if (!std::isfinite(v)) fail("non-finite coordinate in a vertex");
        return v;
    }

    void facet()
    {
        // The normal is not used: exporters write "nan" for degenerate facets, and that is fine.
        expect("normal");
        for (int k = 0; k < 3; ++k) number("the facet normal");
        expect("outer");
        expect("loop");
        if (mesh_.positions.size() / 3 + 3 > 0xFFFFFFFFull) fail("more vertices than 32-bit indices allow");
        std::uint32_t first = std::uint32_t(mesh_.positions.size() / 3);
        for (int v = 0; v < 3; ++v) {
            expect("vertex");
            for (int k = 0; k < 3; ++k) mesh_.positions.push_back(coordinate());
        }
        expect("endloop");
        expect("endfacet");
        mesh_.indices.insert(mesh_.indices.end(), {first, first + 1, first + 2});
    }

    TextCursor c_;
    const std::string& name_;
    MeshData mesh_;
};

} // namespace

MeshData parse_stl(std::string_view bytes, const std::string& name)
{
    bool exact_binary_size = bytes.size() >= CLVIS_STL_HEADER &&
                             bytes.size() == CLVIS_STL_HEADER + CLVIS_STL_FACET * std::uint64_t(read_u32_le(
                                                 reinterpret_cast<const unsigned char*>(bytes.data()) + 80));
    if (exact_binary_size || !starts_with_solid(bytes)) return parse_binary(bytes, name);
    return AsciiStlParser(bytes, name).parse();
}

} // namespace clvis::detail
