// Files of rays and answers for `clvis rays` and outside tools: a strict .npy reader and writer
// (NumPy's format: magic, version, a little-endian header length, a Python dict literal with
// 'descr', 'fortran_order' and 'shape', then the data in C order) and raw little-endian records.
#include <clvis/error.hpp>
#include <clvis/ray_io.hpp>

#include <cctype>
#include <cstring>
#include <fstream>
#include <iterator>

namespace clvis {

namespace {

const char npy_magic[] = "\x93NUMPY";
constexpr std::size_t npy_magic_size = 6;
/// NumPy pads magic + length + header to a multiple of this (bytes).
constexpr std::size_t npy_align = 64;
const char* hit_descr = "[('t', '<f4'), ('id', '<u4'), ('u', '<f4'), ('v', '<f4')]";

[[noreturn]] void fail(const std::string& path, const std::string& what)
{
    throw Error(Error::Kind::Io, path + ": " + what);
}

std::vector<char> read_all(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open for reading");
    return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_all(const std::string& path, const std::string& head, const void* data, std::size_t bytes)
{
    std::ofstream out(path, std::ios::binary);
    if (!out) fail(path, "cannot open for writing");
    out.write(head.data(), std::streamsize(head.size()));
    out.write(static_cast<const char*>(data), std::streamsize(bytes));
    if (!out) fail(path, "write failed");
}

bool is_npy(const std::string& path)
{
    return path.size() >= 4 && path.compare(path.size() - 4, 4, ".npy") == 0;
}

/// A reader of the header's dict literal, as NumPy writes it: {'key': value, ...}.
struct HeaderParser {
    const std::string& text;
    const std::string& path;
    std::size_t pos = 0;

    void skip() { while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos; }
    bool accept(char c)
    {
        skip();
        if (pos < text.size() && text[pos] == c) {
            ++pos;
            return true;
        }
        return false;
    }
    void expect(char c)
    {
        if (!accept(c)) fail(path, std::string("malformed .npy header: expected '") + c + "' at offset " + std::to_string(pos) + " of \"" + text + "\"");
    }
    std::string quoted()
    {
        skip();
        if (pos >= text.size() || (text[pos] != '\'' && text[pos] != '"')) fail(path, "malformed .npy header: expected a string in \"" + text + "\"");
        char q = text[pos++];
        std::size_t end = text.find(q, pos);
        if (end == std::string::npos) fail(path, "malformed .npy header: unterminated string");
        std::string s = text.substr(pos, end - pos);
        pos = end + 1;
        return s;
    }
    /// A list value's text, brackets included (a structured dtype).
    std::string bracketed()
    {
        std::size_t start = pos, depth = 0;
        for (; pos < text.size(); ++pos) {
            if (text[pos] == '[') ++depth;
            if (text[pos] == ']' && --depth == 0) return text.substr(start, ++pos - start);
        }
        fail(path, "malformed .npy header: unterminated list");
    }
    std::vector<std::size_t> shape()
    {
        expect('(');
        std::vector<std::size_t> dims;
        while (!accept(')')) {
            skip();
            std::size_t start = pos;
            while (pos < text.size() && std::isdigit(static_cast<unsigned char>(text[pos]))) ++pos;
            if (start == pos) fail(path, "malformed .npy header: the shape holds a non-integer in \"" + text + "\"");
            dims.push_back(std::stoull(text.substr(start, pos - start)));
            if (!accept(',')) {
                expect(')');
                break;
            }
        }
        return dims;
    }
};

/// The header of an .npy file in `bytes`: fills `a` (but its data) and returns the data offset.
std::size_t parse_npy_header(const std::vector<char>& bytes, const std::string& path, NpyArray& a)
{
    if (bytes.size() < npy_magic_size + 4 || std::memcmp(bytes.data(), npy_magic, npy_magic_size) != 0)
        fail(path, "not an .npy file (no \\x93NUMPY magic)");
    int major = static_cast<unsigned char>(bytes[6]);
    std::size_t len_size = major == 1 ? 2 : (major == 2 || major == 3) ? 4 : 0;
    if (!len_size) fail(path, "unsupported .npy format version " + std::to_string(major));
    std::size_t header_len = 0;
    for (std::size_t k = 0; k < len_size; ++k)
        header_len |= std::size_t(static_cast<unsigned char>(bytes[8 + k])) << (8 * k);
    std::size_t start = 8 + len_size;
    if (bytes.size() < start + header_len) fail(path, "truncated .npy header");
    std::string text(bytes.data() + start, header_len);
    HeaderParser p{text, path};
    bool have_descr = false, have_order = false, have_shape = false;
    p.expect('{');
    while (!p.accept('}')) {
        std::string key = p.quoted();
        p.expect(':');
        p.skip();
        if (key == "descr") {
            a.descr = p.pos < text.size() && text[p.pos] == '[' ? p.bracketed() : p.quoted();
            have_descr = true;
        } else if (key == "fortran_order") {
            if (text.compare(p.pos, 5, "False") == 0) p.pos += 5;
            else if (text.compare(p.pos, 4, "True") == 0) fail(path, "Fortran-ordered .npy arrays are not supported (save with C order)");
            else fail(path, "malformed .npy header: fortran_order is neither True nor False");
            have_order = true;
        } else if (key == "shape") {
            a.shape = p.shape();
            have_shape = true;
        } else {
            fail(path, "malformed .npy header: unknown key '" + key + "'");
        }
        if (!p.accept(',')) {
            p.expect('}');
            break;
        }
    }
    if (!have_descr || !have_order || !have_shape) fail(path, "malformed .npy header: it needs descr, fortran_order and shape");
    return start + header_len;
}

std::string shape_text(const std::vector<std::size_t>& shape)
{
    if (shape.size() == 1) return "(" + std::to_string(shape[0]) + ",)";
    std::string s = "(";
    for (std::size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + std::to_string(shape[k]);
    return s + ")";
}

/// Checks the dtype and shape of `a` against (`descr`, (N,) or (N, inner)); returns N.
std::size_t check_array(const NpyArray& a, const std::string& path, const std::string& descr, std::size_t inner)
{
    if (a.descr != descr) fail(path, "dtype '" + a.descr + "', expected '" + descr + "'");
    bool ok = inner == 1 ? a.shape.size() == 1 : a.shape.size() == 2 && a.shape[1] == inner;
    if (!ok)
        fail(path, "shape " + shape_text(a.shape) + ", expected " + (inner == 1 ? std::string("(N,)") : "(N, " + std::to_string(inner) + ")"));
    return a.shape[0];
}

template <class T>
std::vector<T> raw_records(const std::string& path)
{
    std::vector<char> bytes = read_all(path);
    if (bytes.size() % sizeof(T) != 0)
        fail(path, std::to_string(bytes.size()) + " bytes is not a whole number of " + std::to_string(sizeof(T)) + "-byte records");
    std::vector<T> out(bytes.size() / sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

template <class T>
void write_records(const std::string& path, const std::string& descr, const std::vector<T>& v)
{
    if (is_npy(path)) write_npy(path, descr, {v.size()}, v.data(), v.size() * sizeof(T));
    else write_all(path, std::string(), v.data(), v.size() * sizeof(T));
}

} // namespace

NpyArray read_npy(const std::string& path)
{
    std::vector<char> bytes = read_all(path);
    NpyArray a;
    std::size_t offset = parse_npy_header(bytes, path, a);
    a.data.assign(bytes.begin() + std::ptrdiff_t(offset), bytes.end());
    return a;
}

void write_npy(const std::string& path, const std::string& descr, const std::vector<std::size_t>& shape,
               const void* data, std::size_t bytes)
{
    std::string header = "{'descr': " + descr + ", 'fortran_order': False, 'shape': " + shape_text(shape) + ", }";
    std::size_t total = npy_magic_size + 4 + header.size() + 1;
    header.append((npy_align - total % npy_align) % npy_align, ' ');
    header += '\n';
    std::string head(npy_magic, npy_magic_size);
    head += '\x01';
    head += '\x00';
    head += char(header.size() & 0xFF);
    head += char(header.size() >> 8);
    write_all(path, head + header, data, bytes);
}

std::vector<RayRecord> read_rays(const std::string& path)
{
    if (!is_npy(path)) return raw_records<RayRecord>(path);
    NpyArray a = read_npy(path);
    std::size_t n = check_array(a, path, "<f4", 8);
    if (a.data.size() != n * sizeof(RayRecord))
        fail(path, "holds " + std::to_string(a.data.size()) + " data bytes, the shape needs " + std::to_string(n * sizeof(RayRecord)));
    std::vector<RayRecord> rays(n);
    if (n) std::memcpy(rays.data(), a.data.data(), a.data.size());
    return rays;
}

void write_rays(const std::string& path, const std::vector<RayRecord>& rays)
{
    if (is_npy(path)) write_npy(path, "'<f4'", {rays.size(), 8}, rays.data(), rays.size() * sizeof(RayRecord));
    else write_records(path, std::string(), rays);
}

std::vector<HitRecord> read_hits(const std::string& path)
{
    if (!is_npy(path)) return raw_records<HitRecord>(path);
    NpyArray a = read_npy(path);
    std::size_t n = check_array(a, path, hit_descr, 1);
    if (a.data.size() != n * sizeof(HitRecord))
        fail(path, "holds " + std::to_string(a.data.size()) + " data bytes, the shape needs " + std::to_string(n * sizeof(HitRecord)));
    std::vector<HitRecord> hits(n);
    if (n) std::memcpy(hits.data(), a.data.data(), a.data.size());
    return hits;
}

void write_hits(const std::string& path, const std::vector<HitRecord>& hits) { write_records(path, hit_descr, hits); }
void write_hit_lists(const std::string& path, const std::vector<HitRecord>& hits, std::size_t per_ray)
{
    if (per_ray == 0 || hits.size() % per_ray != 0)
        fail(path, std::to_string(hits.size()) + " hits are not lists of " + std::to_string(per_ray));
    if (is_npy(path)) write_npy(path, hit_descr, {hits.size() / per_ray, per_ray}, hits.data(), hits.size() * sizeof(HitRecord));
    else write_records(path, std::string(), hits);
}

void write_flags(const std::string& path, const std::vector<std::uint8_t>& flags) { write_records(path, "'|u1'", flags); }
void write_counts(const std::string& path, const std::vector<std::uint32_t>& counts) { write_records(path, "'<u4'", counts); }

} // namespace clvis
