// PLY from memory into one MeshData: the header's elements in order, `vertex` x, y, z (any
// numeric type), `face` vertex_indices / vertex_index lists fanned (v0, vk, vk+1) in file order,
// every other element and property skipped by its declared size. Vertex properties other than
// x, y, z, nx, ny, nz become attributes (plan_ply_attributes, host/scene/corner_attributes.cpp),
// expanded to corners through the faces. Called by load_mesh (host/scene/scene_io.cpp) and by the
// fuzz target fuzz_ply.
#include "scene/corner_attributes.hpp"
#include "scene/scene_parsers.hpp"
#include "scene/text_parse.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace clvis::detail {

namespace {

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

struct Property {
    std::string name;
    bool list = false;
    PlyType count_type = PlyType::U8; ///< lists only
    PlyType type = PlyType::F32;      ///< the scalar, or each item of a list
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

std::size_t size_of(PlyType t)
{
    switch (t) {
    case PlyType::I8: case PlyType::U8: return 1;
    case PlyType::I16: case PlyType::U16: return 2;
    case PlyType::I32: case PlyType::U32: case PlyType::F32: return 4;
    case PlyType::F64: return 8;
    }
    return 1;
}

/// A value as the file would write it: 3, -1, 2.5, 1e+20.
std::string number_text(double v)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

bool is_integer(PlyType t) { return t != PlyType::F32 && t != PlyType::F64; }

/// The largest value of an integer type (what a colour of that type is divided by), 0 for floats.
double integer_max(PlyType t)
{
    switch (t) {
    case PlyType::I8: return 127;
    case PlyType::U8: return 255;
    case PlyType::I16: return 32767;
    case PlyType::U16: return 65535;
    case PlyType::I32: return 2147483647.0;
    case PlyType::U32: return 4294967295.0;
    default: return 0;
    }
}

bool type_from_name(std::string_view s, PlyType& t)
{
    static const struct { const char* name; PlyType type; } names[] = {
        {"char", PlyType::I8},    {"int8", PlyType::I8},     {"uchar", PlyType::U8},   {"uint8", PlyType::U8},
        {"short", PlyType::I16},  {"int16", PlyType::I16},   {"ushort", PlyType::U16}, {"uint16", PlyType::U16},
        {"int", PlyType::I32},    {"int32", PlyType::I32},   {"uint", PlyType::U32},   {"uint32", PlyType::U32},
        {"float", PlyType::F32},  {"float32", PlyType::F32}, {"double", PlyType::F64}, {"float64", PlyType::F64},
    };
    for (const auto& n : names)
        if (s == n.name) {
            t = n.type;
            return true;
        }
    return false;
}

/// Which element a value belongs to ("vertex 12"), spelled out only for a message.
struct Where {
    const std::string* element;
    std::uint64_t index;
    std::string str() const { return *element + " " + std::to_string(index); }
};

/// Values of the body in binary, either byte order; positions in messages are byte offsets.
class BinaryReader {
public:
    BinaryReader(std::string_view bytes, std::size_t offset, bool big_endian, const std::string& name)
        : begin_(reinterpret_cast<const unsigned char*>(bytes.data())), p_(begin_ + offset),
          end_(begin_ + bytes.size()), big_(big_endian), name_(name)
    {
    }

    [[noreturn]] void fail(const Where& where, const std::string& what) const
    {
        clvis::detail::fail(name_, "byte " + std::to_string(value_at_) + " (" + where.str() + "): " + what);
    }

    /// The most elements of `min_bytes` each that the rest of the body can hold.
    std::uint64_t room_for(std::uint64_t min_bytes) const
    {
        return min_bytes == 0 ? std::numeric_limits<std::uint64_t>::max() : std::uint64_t(end_ - p_) / min_bytes;
    }

    double scalar(PlyType t, const Where& where)
    {
        std::size_t n = size_of(t);
        value_at_ = std::size_t(p_ - begin_);
        if (std::size_t(end_ - p_) < n) fail(where, "truncated data: the file ends inside a value");
        unsigned char b[8];
        if (big_) {
            for (std::size_t i = 0; i < n; ++i) b[i] = p_[n - 1 - i];
        } else {
            std::memcpy(b, p_, n);
        }
        p_ += n;
        switch (t) {
        case PlyType::I8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
        case PlyType::U8: return b[0];
        case PlyType::I16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
        case PlyType::U16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
        case PlyType::I32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
        case PlyType::U32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
        case PlyType::F32: { float v; std::memcpy(&v, b, 4); return v; }
        case PlyType::F64: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0;
    }

    void skip(PlyType t, std::uint64_t count, const Where& where)
    {
        value_at_ = std::size_t(p_ - begin_);
        if (count > std::uint64_t(end_ - p_) / size_of(t))
            fail(where, "truncated data: a list of " + std::to_string(count) + " items runs past the end of the file");
        p_ += count * size_of(t);
    }

    void finish() const {}

private:
    const unsigned char* begin_;
    const unsigned char* p_;
    const unsigned char* end_;
    bool big_;
    const std::string& name_;
    std::size_t value_at_ = 0; ///< byte offset of the value being read, for messages
};

/// Values of the body in ASCII, separated by any white space; positions in messages are lines.
class AsciiReader {
public:
    AsciiReader(std::string_view bytes, std::size_t offset, std::size_t line, const std::string& name)
        : c_(bytes.substr(offset)), name_(name)
    {
        c_.line = line;
    }

    [[noreturn]] void fail(const Where& where, const std::string& what) const
    {
        fail_at_line(name_, c_.line, where.str() + ": " + what);
    }

    /// Each value takes at least two characters (a digit and a separator).
    std::uint64_t room_for(std::uint64_t min_values) const
    {
        return min_values == 0 ? std::numeric_limits<std::uint64_t>::max()
                               : (std::uint64_t(c_.end - c_.p) + 1) / (2 * min_values);
    }

    double scalar(PlyType t, const Where& where)
    {
        c_.skip_space();
        if (c_.at_end()) fail(where, "the file ends before the last value");
        if (is_integer(t)) {
            std::int64_t v;
            if (!parse_int(c_, v)) fail(where, "malformed integer '" + std::string(token_preview(c_)) + "'");
            return double(v);
        }
        if (t == PlyType::F32) {
            float v; // read as float directly: no double rounding
            if (!parse_float(c_, v)) fail(where, "malformed or out-of-range number '" + std::string(token_preview(c_)) + "'");
            return v;
        }
        double v;
        if (!parse_double(c_, v)) fail(where, "malformed or out-of-range number '" + std::string(token_preview(c_)) + "'");
        return v;
    }

    void skip(PlyType t, std::uint64_t count, const Where& where)
    {
        for (std::uint64_t i = 0; i < count; ++i) scalar(t, where);
    }

    void finish()
    {
        c_.skip_space();
        if (!c_.at_end())
            fail_at_line(name_, c_.line, "unexpected data after the last element: '" + std::string(token_preview(c_)) + "'");
    }

private:
    TextCursor c_;
    const std::string& name_;
};

class PlyParser {
public:
    PlyParser(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) { mesh_.name = name; }

    MeshData parse()
    {
        header();
        if (format_ == PlyFormat::Ascii) {
            AsciiReader r(bytes_, body_, body_line_, name_);
            body(r);
        } else {
            BinaryReader r(bytes_, body_, format_ == PlyFormat::BinaryBig, name_);
            body(r);
        }
        if (mesh_.indices.empty()) fail(name_, "contains no triangles (no faces)");
        if (max_index_ >= mesh_.vertex_count())
            fail(name_, "face " + std::to_string(max_index_face_) + " refers to vertex " + std::to_string(max_index_) +
                            ", the file has " + std::to_string(mesh_.vertex_count()) + " vertices");
        for (VertexAttribute& a : attributes_) {
            mesh_.attributes.push_back(corners_of(a, mesh_.indices));
            std::vector<float>().swap(a.values);
        }
        return std::move(mesh_);
    }

private:
    // ---- header ------------------------------------------------------------------------------
    void header()
    {
        TextCursor c(bytes_);
        bool have_format = false;
        for (;;) {
            if (c.at_end()) fail(name_, "the header has no end_header line");
            std::size_t line = c.line;
            const char* b = c.p;
            while (c.p != c.end && *c.p != '\n') ++c.p;
            std::string_view text(b, std::size_t(c.p - b));
            if (c.p != c.end) { ++c.p; ++c.line; }
            std::vector<std::string_view> words = split(text);
            if (line == 1) {
                if (words.size() != 1 || words[0] != "ply") fail_at_line(name_, 1, "not a PLY file (the first line must be 'ply')");
                continue;
            }
            // Comments, and lines no reader knows (some exporters write a bare "Created by ..."):
            // only format, element and property lines shape the body.
            if (words.empty() || (words[0] != "end_header" && words[0] != "format" && words[0] != "element" &&
                                  words[0] != "property"))
                continue;
            if (words[0] == "end_header") {
                if (!have_format) fail_at_line(name_, line, "the header has no format line");
                body_ = std::size_t(c.p - bytes_.data());
                body_line_ = c.line;
                return;
            }
            if (words[0] == "format") {
                if (words.size() != 3) fail_at_line(name_, line, "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
                if (words[1] == "ascii") format_ = PlyFormat::Ascii;
                else if (words[1] == "binary_little_endian") format_ = PlyFormat::BinaryLittle;
                else if (words[1] == "binary_big_endian") format_ = PlyFormat::BinaryBig;
                else fail_at_line(name_, line, "unknown format '" + std::string(words[1].substr(0, 32)) + "'");
                have_format = true;
            } else if (words[0] == "element") {
                if (words.size() != 3) fail_at_line(name_, line, "expected 'element <name> <count>'");
                Element e;
                e.name = std::string(words[1]);
                auto [q, ec] = std::from_chars(words[2].data(), words[2].data() + words[2].size(), e.count);
                if (ec != std::errc() || q != words[2].data() + words[2].size())
                    fail_at_line(name_, line, "malformed element count '" + std::string(words[2].substr(0, 32)) + "'");
                elements_.push_back(std::move(e));
            } else {
                if (elements_.empty()) fail_at_line(name_, line, "a property before any element");
                Property p;
                bool ok;
                if (words.size() >= 2 && words[1] == "list") {
                    ok = words.size() == 5 && type_from_name(words[2], p.count_type) && type_from_name(words[3], p.type) &&
                         is_integer(p.count_type);
                    p.list = true;
                    if (ok) p.name = std::string(words[4]);
                } else {
                    ok = words.size() == 3 && type_from_name(words[1], p.type);
                    if (ok) p.name = std::string(words[2]);
                }
                if (!ok)
                    fail_at_line(name_, line, "expected 'property <type> <name>' or 'property list <integer type> <type> <name>'");
                elements_.back().properties.push_back(std::move(p));
            }
        }
    }

    static std::vector<std::string_view> split(std::string_view s)
    {
        std::vector<std::string_view> words;
        std::size_t i = 0;
        while (i < s.size()) {
            while (i < s.size() && TextCursor::is_blank(s[i])) ++i;
            std::size_t b = i;
            while (i < s.size() && !TextCursor::is_blank(s[i])) ++i;
            if (i > b) words.push_back(s.substr(b, i - b));
        }
        return words;
    }

    // ---- body --------------------------------------------------------------------------------
    template <class Reader>
    void body(Reader& r)
    {
        bool seen_vertex = false, seen_face = false;
        for (const Element& e : elements_) {
            if (e.name == "vertex" && !seen_vertex) {
                seen_vertex = true;
                vertices(r, e);
            } else if (e.name == "face" && !seen_face) {
                seen_face = true;
                faces(r, e);
            } else {
                skip_element(r, e);
            }
        }
        if (!seen_vertex) fail(name_, "no 'vertex' element");
        r.finish();
    }

    /// Refuses a count that the rest of the file cannot hold, before anything is reserved. A list
    /// takes its length, and the list at `face_list` three items more (a face has 3 vertices).
    template <class Reader>
    void check_room(const Reader& r, const Element& e, int face_list = -1)
    {
        std::uint64_t min_size = 0;
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            const Property& p = e.properties[k];
            bool ascii = format_ == PlyFormat::Ascii;
            min_size += ascii ? 1 : size_of(p.list ? p.count_type : p.type);
            if (int(k) == face_list) min_size += ascii ? 3 : 3 * size_of(p.type);
        }
        if (e.count > r.room_for(min_size))
            fail(name_, "the header declares " + std::to_string(e.count) + " '" + e.name +
                            "' elements, more than the rest of the file can hold");
    }

    static Where where(const Element& e, std::uint64_t i) { return {&e.name, i}; }

    template <class Reader>
    std::uint64_t list_length(Reader& r, const Property& p, const Where& at)
    {
        double n = r.scalar(p.count_type, at);
        if (n < 0) r.fail(at, "negative list length in '" + p.name + "'");
        return std::uint64_t(n);
    }

    template <class Reader>
    void skip_property(Reader& r, const Property& p, const Where& at)
    {
        if (p.list) r.skip(p.type, list_length(r, p, at), at);
        else r.skip(p.type, 1, at);
    }

    template <class Reader>
    void skip_element(Reader& r, const Element& e)
    {
        if (e.properties.empty()) return; // holds no bytes, however many it declares
        check_room(r, e);
        for (std::uint64_t i = 0; i < e.count; ++i)
            for (const Property& p : e.properties) skip_property(r, p, where(e, i));
    }

    template <class Reader>
    void vertices(Reader& r, const Element& e)
    {
        int slot[3] = {-1, -1, -1};
        for (std::size_t k = 0; k < e.properties.size(); ++k)
            for (int axis = 0; axis < 3; ++axis)
                if (e.properties[k].name == std::string(1, char('x' + axis))) {
                    if (e.properties[k].list) fail(name_, "vertex property '" + e.properties[k].name + "' is a list");
                    slot[axis] = int(k);
                }
        for (int axis = 0; axis < 3; ++axis)
            if (slot[axis] < 0) fail(name_, std::string("the vertex element has no property '") + char('x' + axis) + "'");
        if (e.count > 0xFFFFFFFFull) fail(name_, "more vertices than 32-bit indices allow");
        check_room(r, e);
        std::vector<PlyVertexProperty> described;
        for (const Property& p : e.properties) described.push_back({p.name, p.list, p.list ? 0 : integer_max(p.type)});
        // Without faces the file is refused as "no triangles": no attribute is kept for it.
        bool faces = false;
        for (const Element& f : elements_) faces = faces || (f.name == "face" && f.count > 0);
        PlyAttributePlan plan;
        if (faces) plan = plan_ply_attributes(described, e.count, name_);
        else plan.slots.resize(e.properties.size());
        attributes_ = std::move(plan.attributes);
        mesh_.positions.resize(e.count * 3);
        float* out = mesh_.positions.data();
        for (std::uint64_t i = 0; i < e.count; ++i) {
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const Property& p = e.properties[k];
                int axis = int(k) == slot[0] ? 0 : int(k) == slot[1] ? 1 : int(k) == slot[2] ? 2 : -1;
                if (axis < 0 && plan.slots[k].attribute >= 0) { // kept as stored, NaN included
                    const PlyAttributePlan::Slot& s = plan.slots[k];
                    VertexAttribute& a = attributes_[std::size_t(s.attribute)];
                    double v = r.scalar(p.type, where(e, i)) / s.divisor;
                    a.values[std::size_t(i) * std::size_t(a.components) + std::size_t(s.component)] = float(v);
                    continue;
                }
                if (axis < 0) {
                    skip_property(r, p, where(e, i));
                    continue;
                }
                double v = r.scalar(p.type, where(e, i));
                float f = float(v);
                if (!std::isfinite(f))
                    r.fail(where(e, i), std::string("non-finite coordinate ") + char('x' + axis));
                out[i * 3 + std::size_t(axis)] = f;
            }
        }
    }

    template <class Reader>
    void faces(Reader& r, const Element& e)
    {
        int slot = -1;
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            const Property& p = e.properties[k];
            if (p.name == "vertex_indices" || p.name == "vertex_index") {
                if (!p.list) fail(name_, "face property '" + p.name + "' is not a list");
                slot = int(k);
                break;
            }
        }
        if (slot < 0) fail(name_, "the face element has no vertex_indices (or vertex_index) list");
        check_room(r, e, slot);
        mesh_.indices.reserve(std::size_t(e.count) * 3);
        std::vector<std::uint32_t> poly;
        for (std::uint64_t i = 0; i < e.count; ++i) {
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const Property& p = e.properties[k];
                if (int(k) != slot) {
                    skip_property(r, p, where(e, i));
                    continue;
                }
                Where at = where(e, i);
                std::uint64_t n = list_length(r, p, at);
                if (n < 3) r.fail(at, "a face needs at least 3 vertices, this one has " + std::to_string(n));
                poly.clear();
                for (std::uint64_t j = 0; j < n; ++j) {
                    double v = r.scalar(p.type, at);
                    if (!(v >= 0 && v <= double(0xFFFFFFFEu) && v == std::floor(v)))
                        r.fail(at, "vertex index " + number_text(v) + " is not a valid index");
                    std::uint32_t index = std::uint32_t(v);
                    if (index > max_index_) { // the first face naming the largest index
                        max_index_ = index;
                        max_index_face_ = i;
                    }
                    poly.push_back(index);
                }
                for (std::size_t j = 1; j + 1 < poly.size(); ++j)
                    mesh_.indices.insert(mesh_.indices.end(), {poly[0], poly[j], poly[j + 1]});
            }
        }
    }

    std::string_view bytes_;
    const std::string& name_;
    MeshData mesh_;
    std::vector<VertexAttribute> attributes_; ///< per vertex until the faces are read
    PlyFormat format_ = PlyFormat::Ascii;
    std::vector<Element> elements_;
    std::size_t body_ = 0;       ///< byte offset of the first value
    std::size_t body_line_ = 1;  ///< its line (ASCII)
    std::uint64_t max_index_ = 0;
    std::uint64_t max_index_face_ = 0;
};

} // namespace

MeshData parse_ply(std::string_view bytes, const std::string& name) { return PlyParser(bytes, name).parse(); }

} // namespace clvis::detail
