// The JSON scene file (meshes, transforms or instances, camera, image size) and the JSON views file
// (one size, many cameras): parse_scene_file and parse_views_file read them from memory through one
// reader whose camera fields go through the one table of camera_spec.cpp; load_scene_file and
// load_views_file (host/scene/views_import.cpp, which reads other tools' cameras too) read them
// from disk. Format dispatch for meshes is host/scene/scene_io.cpp.
#include "scene/scene_parsers.hpp"

#include <clvis/scene_io.hpp>
#include <clvis/views_file.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#ifdef CLVIS_HAVE_JSON
#include <nlohmann/json.hpp>
#endif

namespace clvis {

namespace detail {

#ifdef CLVIS_HAVE_JSON

namespace {

using Json = nlohmann::json;

/// Scene files are shallow; a deeper document is refused before it can exhaust the stack.
constexpr int CLVIS_SCENE_MAX_DEPTH = 32;
/// Largest image side a scene file may ask for, in pixels.
constexpr std::int64_t CLVIS_SCENE_MAX_SIDE = 65536;

class SceneReader {
public:
    SceneReader(const std::string& path, const std::function<MeshData(const std::string&)>& load)
        : path_(path), load_(load)
    {
    }

    SceneFile read(std::string_view text)
    {
        Json root = parse(text);
        if (!root.is_object()) fail(path_, "expected a JSON object at the top level");
        for (auto it = root.begin(); it != root.end(); ++it)
            if (it.key() != "meshes" && it.key() != "camera" && it.key() != "width" && it.key() != "height")
                bad(it.key(), "unknown field");
        SceneFile out;
        meshes(root, out.scene);
        if (root.contains("camera")) out.camera_spec = camera(root["camera"]);
        out.width = side(root, "width");
        out.height = side(root, "height");
        if (!out.camera_spec.empty()) out.camera = resolve(out);
        return out;
    }

    ViewsFile read_views(std::string_view text)
    {
        Json root = parse(text);
        if (!root.is_object()) fail(path_, "expected a JSON object at the top level");
        for (auto it = root.begin(); it != root.end(); ++it)
            if (it.key() != "views" && it.key() != "width" && it.key() != "height") bad(it.key(), "unknown field");
        ViewsFile out;
        out.width = side(root, "width");
        out.height = side(root, "height");
        if (out.width == 0) bad("width", "missing");
        if (out.height == 0) bad("height", "missing");
        if (!root.contains("views") || !root["views"].is_array() || root["views"].empty())
            bad("views", "expected a non-empty array of cameras");
        const Json& views = root["views"];
        for (std::size_t i = 0; i < views.size(); ++i) {
            std::string where = "views[" + std::to_string(i) + "]";
            CameraSpec spec;
            ItemTransforms moved; // "items": the view's item transforms (flow between views)
            Json fields = views[i];
            if (fields.is_object() && fields.contains("items")) {
                moved = items(fields["items"], where + ".items");
                fields.erase("items");
            }
            out.items.push_back(std::move(moved));
            try {
                spec = camera(fields);
            } catch (const Error& e) {
                // camera() names its fields "camera.*": here they are "views[i].*".
                std::string msg = e.what(), prefix = path_ + ": camera";
                if (msg.rfind(prefix, 0) != 0) throw;
                fail(path_, where + msg.substr(prefix.size()));
            }
            // A views file has no scene to frame: each view places its camera itself.
            if (spec.framing()) bad(where, "eye and target, or pose, are needed");
            try {
                out.views.push_back(spec.resolve(Bounds{}, out.width, out.height,
                                                 [&](const std::string& field) { return where + "." + field; }));
            } catch (const Error& e) {
                fail(path_, e.what());
            }
        }
        return out;
    }

private:
    [[noreturn]] void bad(const std::string& where, const std::string& what) const { fail(path_, where + ": " + what); }

    Json parse(std::string_view text) const
    {
        Json::parser_callback_t limit = [this](int depth, Json::parse_event_t, Json&) {
            if (depth > CLVIS_SCENE_MAX_DEPTH)
                fail(path_, "JSON nested deeper than " + std::to_string(CLVIS_SCENE_MAX_DEPTH) + " levels");
            return true;
        };
        try {
            return Json::parse(text.begin(), text.end(), limit);
        } catch (const Json::exception& e) {
            fail(path_, std::string("invalid JSON: ") + e.what());
        }
    }

    double number(const Json& j, const std::string& where) const
    {
        if (!j.is_number()) bad(where, "expected a number");
        double v = j.get<double>();
        if (!std::isfinite(v)) bad(where, "expected a finite number");
        return v;
    }

    std::vector<double> numbers(const Json& j, std::size_t count, const std::string& where) const
    {
        if (!j.is_array() || j.size() != count) bad(where, "expected " + std::to_string(count) + " numbers");
        std::vector<double> v;
        for (std::size_t i = 0; i < count; ++i) v.push_back(number(j[i], where + "[" + std::to_string(i) + "]"));
        return v;
    }

    Vec3 vec3(const Json& j, const std::string& where) const
    {
        std::vector<double> v = numbers(j, 3, where);
        return {v[0], v[1], v[2]};
    }

    void meshes(const Json& root, Scene& scene) const
    {
        if (!root.contains("meshes")) bad("meshes", "missing (a scene file names at least one mesh)");
        const Json& list = root["meshes"];
        if (!list.is_array() || list.empty()) bad("meshes", "expected a non-empty array of {\"file\": ...}");
        std::filesystem::path folder = std::filesystem::path(path_).parent_path();
        for (std::size_t i = 0; i < list.size(); ++i) {
            std::string at = "meshes[" + std::to_string(i) + "]";
            const Json& m = list[i];
            if (!m.is_object()) bad(at, "expected an object {\"file\": ..., \"transform\": [16 numbers]}");
            for (auto it = m.begin(); it != m.end(); ++it)
                if (it.key() != "file" && it.key() != "transform" && it.key() != "instances")
                    bad(at + "." + it.key(), "unknown field");
            if (m.contains("transform") && m.contains("instances"))
                bad(at, "give either transform or instances, not both");
            if (!m.contains("file") || !m["file"].is_string() || m["file"].get_ref<const std::string&>().empty())
                bad(at + ".file", "expected a file name");
            Mat4 transform;
            if (m.contains("transform")) transform = matrix(m["transform"], at + ".transform");
            std::filesystem::path file = m["file"].get<std::string>();
            if (file.is_relative()) file = folder / file;
            MeshData mesh;
            try {
                mesh = load_(file.string());
            } catch (const Error& e) {
                throw Error(e.kind(), path_ + ": " + at + ".file: " + e.what());
            }
            if (!m.contains("instances")) {
                scene.add_mesh(std::move(mesh), transform);
                continue;
            }
            const Json& list = m["instances"];
            if (!list.is_array() || list.empty()) bad(at + ".instances", "expected a non-empty array of 16-number matrices");
            std::vector<Mat4> transforms;
            for (std::size_t k = 0; k < list.size(); ++k)
                transforms.push_back(matrix(list[k], at + ".instances[" + std::to_string(k) + "]"));
            std::size_t prototype = scene.add_prototype(std::move(mesh));
            for (const Mat4& t : transforms) scene.add_instance(prototype, t);
        }
    }

    /// A view's "items": {"K": M, ...}, K an item index in decimal, M an affine 4x4 row by row.
    ItemTransforms items(const Json& j, const std::string& where) const
    {
        if (!j.is_object()) bad(where, "expected an object {\"ITEM\": [16 numbers], ...}");
        ItemTransforms out;
        for (auto it = j.begin(); it != j.end(); ++it) {
            const std::string& key = it.key();
            std::string at = where + "." + key;
            if (key.empty() || key.size() > 9 || key.find_first_not_of("0123456789") != std::string::npos)
                bad(at, "an item index (a non-negative integer) is expected as the key");
            out[std::size_t(std::stoul(key))] = matrix(it.value(), at);
        }
        return out;
    }

    Mat4 matrix(const Json& j, const std::string& where) const
    {
        std::vector<double> v = numbers(j, 16, where);
        Mat4 t;
        std::copy(v.begin(), v.end(), t.m.begin());
        if (t(3, 0) != 0 || t(3, 1) != 0 || t(3, 2) != 0 || t(3, 3) != 1)
            bad(where, "the last row must be 0 0 0 1 (an affine transform, row by row)");
        return t;
    }

    /// The "camera" object, field by field through the one table of camera fields.
    CameraSpec camera(const Json& j) const
    {
        if (!j.is_object()) bad("camera", "expected an object");
        CameraSpec spec;
        for (auto it = j.begin(); it != j.end(); ++it) {
            std::string where = "camera." + it.key();
            const Json& v = it.value();
            CameraValue value;
            if (v.is_number()) {
                value.numbers.push_back(number(v, where));
            } else if (v.is_array()) {
                for (std::size_t i = 0; i < v.size(); ++i)
                    value.numbers.push_back(number(v[i], where + "[" + std::to_string(i) + "]"));
            } else if (v.is_string()) {
                value.word = v.get<std::string>();
            } else if (v.is_boolean() && v.get<bool>()) {
                value.bare = true;
            } else {
                bad(where, "expected a number, an array of numbers or a word");
            }
            try {
                set_camera_field(spec, it.key(), value, where);
            } catch (const Error& e) {
                fail(path_, e.what());
            }
        }
        return spec;
    }

    Camera resolve(const SceneFile& f) const
    {
        try {
            return f.camera_spec.resolve(f.scene.bounds(), f.width ? f.width : default_width,
                                         f.height ? f.height : default_height,
                                         [](const std::string& field) { return "camera." + field; });
        } catch (const Error& e) {
            fail(path_, e.what());
        }
    }

    int side(const Json& root, const char* key) const
    {
        if (!root.contains(key)) return 0;
        const Json& j = root[key];
        if (!j.is_number_integer() || j.get<std::int64_t>() < 1 || j.get<std::int64_t>() > CLVIS_SCENE_MAX_SIDE)
            bad(key, "expected an integer from 1 to " + std::to_string(CLVIS_SCENE_MAX_SIDE));
        return int(j.get<std::int64_t>());
    }

    const std::string& path_;
    const std::function<MeshData(const std::string&)>& load_;
};

} // namespace

SceneFile parse_scene_file(std::string_view text, const std::string& path,
                           const std::function<MeshData(const std::string&)>& load)
{
    return SceneReader(path, load).read(text);
}

ViewsFile parse_views_file(std::string_view text, const std::string& path)
{
    static const std::function<MeshData(const std::string&)> no_meshes;
    return SceneReader(path, no_meshes).read_views(text);
}

#else

ViewsFile parse_views_file(std::string_view, const std::string& path)
{
    fail(path, "cannot read views files: this build of clvis was made without nlohmann::json");
}

SceneFile parse_scene_file(std::string_view, const std::string& path, const std::function<MeshData(const std::string&)>&)
{
    fail(path, "cannot read scene files: this build of clvis was made without nlohmann::json");
}

#endif

} // namespace detail

SceneFile load_scene_file(const std::string& path)
{
    std::string text = detail::read_file(path);
    return detail::parse_scene_file(text, path, load_mesh);
}

bool ViewsFile::moves() const
{
    for (const ItemTransforms& t : items)
        if (!t.empty()) return true;
    return false;
}

void check_view_items(const ViewsFile& views, const Scene& scene)
{
    for (std::size_t v = 0; v < views.items.size(); ++v)
        for (const auto& [item, transform] : views.items[v])
            if (item >= scene.meshes().size())
                throw Error(Error::Kind::InvalidArgument,
                            views.path + ": views[" + std::to_string(v) + "].items." + std::to_string(item) +
                                ": no such item (the scene has " + std::to_string(scene.meshes().size()) + ")");
}

std::string view_file_name(const std::string& pattern, int view, int last)
{
    const std::string key = "{view}";
    auto at = pattern.find(key);
    if (at == std::string::npos) return pattern;
    std::string digits = std::to_string(view);
    std::size_t width = std::to_string(std::max(last, 0)).size();
    if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
    return pattern.substr(0, at) + digits + view_file_name(pattern.substr(at + key.size()), view, last);
}

} // namespace clvis
