// Wavefront OBJ from memory into one MeshData: every `v` in order, every `f` fanned
// (v0, vk, vk+1) in file order whatever group it is in, `l`/`p` and other statements skipped.
// Attributes (CONVENTIONS.md "Vertex attributes"): "uv" from `vt u [v [w]]` through each corner's
// own texture index (`f v/vt/vn`), so seams keep their two values; "color" from the `v x y z r g b`
// extension (alpha 1). Corners without a texture index, and vertices without a colour in a file
// that gives them elsewhere, are NaN.
// Called by load_mesh (host/scene/scene_io.cpp) and by the fuzz target fuzz_obj.
#include "scene/corner_attributes.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/text_parse.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace clvis::detail {

namespace {

using namespace std::string_view_literals;

constexpr std::uint32_t CLVIS_OBJ_NO_NORMAL = 0xFFFFFFFFu;
constexpr std::uint32_t CLVIS_OBJ_NO_TEXCOORD = 0xFFFFFFFFu;
constexpr float CLVIS_OBJ_NAN = std::numeric_limits<float>::quiet_NaN();

/// An index that names an element not yet defined when its face was read: checked at the end,
/// since an absolute index may refer forward.
struct ForwardRef {
    std::size_t line;
    std::int64_t index; ///< 1-based, as written
    int kind;           ///< 0 position, 1 texture coordinate, 2 normal
};

const char* kind_name(int kind)
{
    return kind == 0 ? "vertex" : kind == 1 ? "texture coordinate" : "normal";
}

class ObjParser {
public:
    ObjParser(std::string_view text, const std::string& name) : c_(text), name_(name)
    {
        mesh_.name = name;
        if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) c_.p += 3; // UTF-8 BOM
    }

    MeshData parse()
    {
        while (!c_.at_end()) {
            c_.skip_blanks(true);
            if (c_.at_line_end()) {
                c_.next_line(true);
                continue;
            }
            std::string_view keyword = c_.token();
            if (keyword == "v") vertex();
            else if (keyword == "f") face();
            else if (keyword == "vn") normal();
            else if (keyword == "vt") texcoord();
            c_.next_line(true); // the rest of the line: w, names, other statements
        }
        return finish();
    }

private:
    [[noreturn]] void fail(const std::string& what) const { fail_at_line(name_, c_.line, what); }

    float coordinate(const char* statement, int i)
    {
        c_.skip_blanks(true);
        if (c_.at_line_end())
            fail(std::string("'") + statement + "' needs 3 coordinates, found " + std::to_string(i));
        float v;
        if (!parse_float(c_, v, "#"sv))
            fail("malformed or out-of-range number '" + std::string(token_preview(c_)) + "'");
        if (!std::isfinite(v)) fail("non-finite coordinate in '" + std::string(statement) + "'");
        return v;
    }

    void vertex()
    {
        if (mesh_.positions.size() / 3 >= 0xFFFFFFFFull) fail("more vertices than 32-bit indices allow");
        for (int i = 0; i < 3; ++i) mesh_.positions.push_back(coordinate("v", i));
        vertex_colour();
    }

    /// The colour extension `v x y z r g b`: exactly three more numbers on the line (one more is
    /// OBJ's w; anything else is skipped as before). Colours are kept as written, alpha 1.
    void vertex_colour()
    {
        float extra[4];
        int n = 0;
        for (; n < 4; ++n) {
            c_.skip_blanks(true);
            if (c_.at_line_end() || !parse_float(c_, extra[n], "#"sv)) break;
        }
        c_.skip_blanks(true);
        bool colour = n == 3 && c_.at_line_end();
        if (colour && colors_.empty()) // the first colour: the vertices before it have none
            colors_.assign((mesh_.positions.size() / 3 - 1) * 4, CLVIS_OBJ_NAN);
        if (colour) colors_.insert(colors_.end(), {extra[0], extra[1], extra[2], 1.0f});
        else if (!colors_.empty()) colors_.insert(colors_.end(), 4, CLVIS_OBJ_NAN);
    }

    /// `vt u [v [w]]`: u and v kept (v 0 when absent, as OBJ says), w skipped.
    void texcoord()
    {
        float uv[2] = {0, 0};
        for (int i = 0; i < 2; ++i) {
            c_.skip_blanks(true);
            if (c_.at_line_end()) {
                if (i == 0) fail("'vt' needs at least 1 coordinate, found 0");
                break;
            }
            if (!parse_float(c_, uv[i], "#"sv))
                fail("malformed or out-of-range number '" + std::string(token_preview(c_)) + "'");
        }
        texcoords_.insert(texcoords_.end(), {uv[0], uv[1]});
    }

    void normal()
    {
        for (int i = 0; i < 3; ++i) normals_.push_back(coordinate("vn", i));
    }

    /// One index of a face corner, resolved to 0-based; `count` elements of `kind` so far.
    std::uint32_t index(int kind, std::size_t count, std::string_view stops)
    {
        std::int64_t i;
        if (!parse_int(c_, i, stops))
            fail("malformed " + std::string(kind_name(kind)) + " index '" + std::string(token_preview(c_)) + "'");
        if (i == 0) fail(std::string(kind_name(kind)) + " index 0 (OBJ indices start at 1)");
        if (i < 0) {
            if (std::uint64_t(-(i + 1)) >= count)
                fail("relative " + std::string(kind_name(kind)) + " index " + std::to_string(i) + " reaches before the first one (" +
                     std::to_string(count) + " defined so far)");
            return std::uint32_t(std::int64_t(count) + i);
        }
        if (i > 0xFFFFFFFFll) fail(std::string(kind_name(kind)) + " index " + std::to_string(i) + " is out of range");
        if (std::uint64_t(i) > count) forward_.push_back({c_.line, i, kind});
        return std::uint32_t(i - 1);
    }

    void face()
    {
        corners_.clear();
        corner_normals_.clear();
        corner_texcoords_.clear();
        bool all_normals = true, any_texcoord = false;
        for (;;) {
            c_.skip_blanks(true);
            if (c_.at_line_end()) break;
            corners_.push_back(index(0, mesh_.positions.size() / 3, "/#"sv));
            std::uint32_t n = CLVIS_OBJ_NO_NORMAL, t = CLVIS_OBJ_NO_TEXCOORD;
            if (!c_.at_end() && *c_.p == '/') {
                ++c_.p;
                if (!c_.at_end() && *c_.p != '/') {
                    t = index(1, texcoords_.size() / 2, "/#"sv);
                    any_texcoord = true;
                }
                if (!c_.at_end() && *c_.p == '/') {
                    ++c_.p;
                    n = index(2, normals_.size() / 3, "#"sv);
                }
            }
            if (n == CLVIS_OBJ_NO_NORMAL) all_normals = false;
            corner_normals_.push_back(n);
            corner_texcoords_.push_back(t);
        }
        if (corners_.size() < 3)
            fail("a face needs at least 3 vertices, this one has " + std::to_string(corners_.size()));
        if (!all_normals && faces_have_normals_) {
            faces_have_normals_ = false;
            std::vector<std::uint32_t>().swap(face_normals_);
        }
        if (any_texcoord && !faces_have_texcoords_) { // the first: the corners before it have none
            faces_have_texcoords_ = true;
            face_texcoords_.assign(mesh_.indices.size(), CLVIS_OBJ_NO_TEXCOORD);
        }
        for (std::size_t k = 1; k + 1 < corners_.size(); ++k) {
            mesh_.indices.insert(mesh_.indices.end(), {corners_[0], corners_[k], corners_[k + 1]});
            if (faces_have_normals_)
                face_normals_.insert(face_normals_.end(), {corner_normals_[0], corner_normals_[k], corner_normals_[k + 1]});
            if (faces_have_texcoords_)
                face_texcoords_.insert(face_texcoords_.end(),
                                       {corner_texcoords_[0], corner_texcoords_[k], corner_texcoords_[k + 1]});
        }
    }

    MeshData finish()
    {
        std::size_t counts[3] = {mesh_.positions.size() / 3, texcoords_.size() / 2, normals_.size() / 3};
        for (const ForwardRef& r : forward_)
            if (std::uint64_t(r.index) > counts[r.kind])
                fail_at_line(name_, r.line,
                             std::string(kind_name(r.kind)) + " index " + std::to_string(r.index) +
                                 " is out of range (the file defines " + std::to_string(counts[r.kind]) + ")");
        if (mesh_.indices.empty()) fail_no_triangles();
        if (faces_have_normals_) keep_normals();
        keep_attributes();
        return std::move(mesh_);
    }

    /// "uv" when some face names texture coordinates, "color" when some vertex has a colour.
    void keep_attributes()
    {
        if (faces_have_texcoords_) {
            CornerAttribute uv{"uv", 2, {}};
            uv.values.resize(face_texcoords_.size() * 2);
            for (std::size_t i = 0; i < face_texcoords_.size(); ++i) {
                std::uint32_t t = face_texcoords_[i];
                bool has = t != CLVIS_OBJ_NO_TEXCOORD;
                uv.values[i * 2] = has ? texcoords_[std::size_t(t) * 2] : CLVIS_OBJ_NAN;
                uv.values[i * 2 + 1] = has ? texcoords_[std::size_t(t) * 2 + 1] : CLVIS_OBJ_NAN;
            }
            std::vector<std::uint32_t>().swap(face_texcoords_);
            mesh_.attributes.push_back(std::move(uv));
        }
        if (!colors_.empty())
            mesh_.attributes.push_back(corners_of(VertexAttribute{"color", 4, std::move(colors_)}, mesh_.indices));
    }

    [[noreturn]] void fail_no_triangles() const
    {
        clvis::detail::fail(name_, "contains no triangles (a mesh file must have at least one face)");
    }

    /// One normal per position when every corner that uses a position names the same normal
    /// (by index or by value); otherwise the mesh keeps no normals. Unused positions get (0,0,0).
    void keep_normals()
    {
        std::vector<std::uint32_t> of_vertex(mesh_.vertex_count(), CLVIS_OBJ_NO_NORMAL);
        for (std::size_t i = 0; i < mesh_.indices.size(); ++i) {
            std::uint32_t& n = of_vertex[mesh_.indices[i]];
            std::uint32_t m = face_normals_[i];
            if (n == CLVIS_OBJ_NO_NORMAL) n = m;
            else if (n != m && !same_normal(n, m)) return;
        }
        mesh_.normals.assign(mesh_.positions.size(), 0.0f);
        for (std::size_t v = 0; v < of_vertex.size(); ++v)
            if (of_vertex[v] != CLVIS_OBJ_NO_NORMAL)
                for (int k = 0; k < 3; ++k) mesh_.normals[v * 3 + k] = normals_[std::size_t(of_vertex[v]) * 3 + k];
    }

    bool same_normal(std::uint32_t a, std::uint32_t b) const
    {
        for (int k = 0; k < 3; ++k)
            if (normals_[std::size_t(a) * 3 + k] != normals_[std::size_t(b) * 3 + k]) return false;
        return true;
    }

    TextCursor c_;
    const std::string& name_;
    MeshData mesh_;
    std::vector<float> normals_;
    std::vector<float> texcoords_; ///< u, v per `vt`
    std::vector<float> colors_;    ///< r, g, b, 1 per vertex once one vertex has a colour, else empty
    std::vector<std::uint32_t> corners_, corner_normals_, corner_texcoords_;
    std::vector<std::uint32_t> face_normals_; ///< normal index per entry of mesh_.indices
    std::vector<std::uint32_t> face_texcoords_; ///< texture index per entry of mesh_.indices once one face has one
    bool faces_have_normals_ = true;
    bool faces_have_texcoords_ = false; ///< some face names a texture coordinate
    std::vector<ForwardRef> forward_;
};

} // namespace

MeshData parse_obj(std::string_view text, const std::string& name) { return ObjParser(text, name).parse(); }

} // namespace clvis::detail
