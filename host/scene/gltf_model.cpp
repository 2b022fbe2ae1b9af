// tinygltf behind one call for host/scene/scene_gltf.cpp: the JSON's depth is bounded first
// (tinygltf's extras parser recurses), file access goes through callbacks of ours (no path expansion, no
// writes, image files never read, nothing at all for the fuzz targets), images are not decoded,
// and a node's matrix or T R S becomes a clvis Mat4 (row by row, double).
#ifdef CLVIS_HAVE_TINYGLTF

#include "scene/gltf_model.hpp"
#include "scene/scene_parsers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include <nlohmann/json.hpp>

namespace clvis::detail {

namespace {

bool is_glb(std::string_view bytes) { return bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0; }

/// The JSON chunk of a GLB as far as the file holds it (tinygltf checks the container itself).
std::string_view glb_json(std::string_view bytes)
{
    if (bytes.size() < 20) return {};
    std::uint32_t length;
    std::memcpy(&length, bytes.data() + 12, 4);
    return bytes.substr(20, std::min<std::size_t>(length, bytes.size() - 20));
}

void check_depth(std::string_view json, const std::string& name)
{
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < json.size(); ++i) {
        char c = json[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > CLVIS_GLTF_MAX_DEPTH)
                fail(name, "JSON nested deeper than " + std::to_string(CLVIS_GLTF_MAX_DEPTH) + " levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

/// Texture files play no part in visibility: refusing them makes tinygltf skip them with a warning.
bool is_image_file(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    for (const char* image : {".png", ".jpg", ".jpeg", ".ktx", ".ktx2", ".webp", ".dds", ".bmp", ".gif", ".basis"})
        if (ext == image) return true;
    return false;
}

bool file_exists(const std::string& path, void* read_files)
{
    std::error_code ec;
    return *static_cast<bool*>(read_files) && !is_image_file(path) && std::filesystem::is_regular_file(path, ec);
}

std::string expand_path(const std::string& path, void*) { return path; }

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* read_files)
{
    if (!*static_cast<bool*>(read_files)) return false;
    try {
        std::string bytes = read_file(path);
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        return false;
    }
}

bool refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*)
{
    if (err) *err += "clvis never writes glTF files";
    return false;
}

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*)
{
    return true;
}

/// tinygltf's messages end in newlines and may repeat; one line each, joined by "; ".
std::string one_line(const std::string& text)
{
    std::string out;
    for (char c : text) out += (c == '\n' || c == '\r') ? ' ' : c;
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out;
}

/// Required extensions that change neither positions nor indices nor the node tree are safe to
/// ignore for visibility; every other one is refused by name (the spec says a loader must).
void check_extensions(const std::vector<std::string>& required, const std::string& name)
{
    static const char* harmless[] = {"KHR_materials_", "KHR_texture_", "EXT_texture_", "KHR_lights_punctual",
                                     "KHR_xmp", "MSFT_texture_dds"};
    for (const std::string& ext : required)
        if (std::none_of(std::begin(harmless), std::end(harmless),
                         [&](const char* h) { return ext.rfind(h, 0) == 0; }))
            fail(name, "extensionsRequired: " + ext + " is not supported (it may change the geometry)");
}

/// `why` ("asset.version \"1.0\"") shows a glTF 1.0 file.
[[noreturn]] void refuse_version_1(const std::string& why, const std::string& name)
{
    fail(name, why + ": glTF 1.0, clvis reads glTF 2.0 only (convert the file, e.g. with gltf-pipeline or Blender)");
}

/// An asset.version other than 2.x.
void check_version(const std::string& version, const std::string& name)
{
    if (version.rfind("2.", 0) == 0) return;
    std::string why = "asset.version \"" + version + "\"";
    if (version.rfind("1.", 0) == 0) refuse_version_1(why, name);
    fail(name, why + ": clvis reads glTF 2.0 only");
}

/// The GLB container's header and JSON chunk, each fault named (tinygltf says "Invalid glTF
/// binary." for all of them): version 1 is glTF 1.0's binary extension (KHR_binary_glTF).
void check_glb(std::string_view bytes, const std::string& name)
{
    auto u32 = [&](std::size_t at) {
        std::uint32_t v;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    const std::string size = std::to_string(bytes.size());
    if (bytes.size() < 20) fail(name, "invalid GLB: " + size + " bytes, shorter than its 20-byte headers");
    std::uint32_t version = u32(4), length = u32(8), json = u32(12), type = u32(16);
    if (version == 1) refuse_version_1("GLB version 1 (KHR_binary_glTF)", name);
    if (version != 2) fail(name, "GLB version " + std::to_string(version) + ": clvis reads GLB version 2 (glTF 2.0)");
    if (length > bytes.size())
        fail(name, "invalid GLB: the header says " + std::to_string(length) + " bytes, the file holds " + size +
                       " (truncated?)");
    if (type != 0x4E4F534A) fail(name, "invalid GLB: the first chunk is not JSON (its type is not \"JSON\")");
    if (json < 1 || 20ull + json > length)
        fail(name, "invalid GLB: the JSON chunk of " + std::to_string(json) + " bytes does not fit in the " +
                       std::to_string(length) + " bytes the header gives");
}

/// Why tinygltf refused the JSON, where its own message would name a symptom: a glTF 1.0 file
/// (asset.version "1.x", or no asset and 1.0's objects in place of arrays) or a required extension
/// clvis lacks (Draco's accessors have no bufferView). Returns when neither applies.
void explain_refusal(std::string_view json, const std::string& name)
{
    nlohmann::json doc = nlohmann::json::parse(json.begin(), json.end(), nullptr, false);
    if (!doc.is_object()) return;
    auto asset = doc.find("asset");
    if (asset != doc.end() && asset->is_object()) {
        auto version = asset->find("version");
        if (version != asset->end() && version->is_string()) check_version(version->get<std::string>(), name);
    } else {
        for (const char* key : {"scenes", "meshes", "nodes", "accessors"}) {
            auto it = doc.find(key);
            if (it != doc.end() && it->is_object())
                refuse_version_1(std::string("no asset, and \"") + key + "\" is an object, not an array", name);
        }
    }
    auto required = doc.find("extensionsRequired");
    if (required == doc.end() || !required->is_array()) return;
    std::vector<std::string> names;
    for (const auto& e : *required)
        if (e.is_string()) names.push_back(e.get<std::string>());
    check_extensions(names, name);
}

double finite(double v, const std::string& where, const std::string& name)
{
    if (!std::isfinite(v)) fail(name, where + ": not a finite number");
    return v;
}

const std::vector<double>& sized(const std::vector<double>& v, std::size_t n, const std::string& where,
                                 const std::string& name)
{
    if (!v.empty() && v.size() != n) fail(name, where + ": expected " + std::to_string(n) + " numbers");
    for (std::size_t i = 0; i < v.size(); ++i) finite(v[i], where + "[" + std::to_string(i) + "]", name);
    return v;
}

} // namespace

tinygltf::Model load_gltf_model(std::string_view bytes, const std::string& name, bool read_files)
{
    if (bytes.size() > std::numeric_limits<unsigned int>::max()) fail(name, "larger than 4 GiB");
    bool glb = is_glb(bytes);
    if (glb) check_glb(bytes, name);
    std::string_view json = glb ? glb_json(bytes) : bytes;
    check_depth(json, name);
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(skip_image, nullptr);
    loader.SetFsCallbacks({file_exists, expand_path, read_whole_file, refuse_write, &read_files});
    tinygltf::Model model;
    std::string err, warn, base = std::filesystem::path(name).parent_path().string();
    bool ok = false;
    try {
        auto size = static_cast<unsigned int>(bytes.size());
        ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                               size, base)
                 : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base);
    } catch (const std::exception& e) {
        fail(name, std::string("invalid glTF: ") + e.what());
    }
    if (!ok) {
        explain_refusal(json, name);
        std::string why = one_line(err.empty() ? warn : err);
        fail(name, "invalid " + std::string(glb ? "GLB" : "glTF") + ": " + (why.empty() ? "tinygltf gave no reason" : why));
    }
    check_version(model.asset.version, name);
    check_extensions(model.extensionsRequired, name);
    return model;
}

Mat4 gltf_node_transform(const tinygltf::Node& node, const std::string& at, const std::string& name)
{
    Mat4 m;
    const auto& matrix = sized(node.matrix, 16, at + ".matrix", name);
    if (!matrix.empty()) {
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) m(r, c) = matrix[std::size_t(c * 4 + r)]; // glTF is column-major
        if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1)
            fail(name, at + ".matrix: the last row must be 0 0 0 1 (glTF matrices are affine)");
        return m;
    }
    const auto& t = sized(node.translation, 3, at + ".translation", name);
    const auto& q = sized(node.rotation, 4, at + ".rotation", name);
    const auto& s = sized(node.scale, 3, at + ".scale", name);
    if (!q.empty()) {
        double x = q[0], y = q[1], z = q[2], w = q[3];
        double rotation[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                                 {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                                 {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m(r, c) = rotation[r][c];
    }
    if (!s.empty())
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m(r, c) *= s[std::size_t(c)];
    if (!t.empty())
        for (int r = 0; r < 3; ++r) m(r, 3) = t[std::size_t(r)];
    return m;
}

} // namespace clvis::detail

#endif // CLVIS_HAVE_TINYGLTF
