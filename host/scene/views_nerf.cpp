// NeRF / instant-ngp transforms.json as views (CONVENTIONS.md "Cameras from other tools"), and
// the dispatch of JSON views files among clvis's, NeRF's and glTF's. Each frame becomes the
// CameraSpec a clvis views file would hold ("pose": transform_matrix, "intrinsics": [fx, fy, cx,
// cy]) resolved as that file's reader resolves it, so the camera is the same bit for bit.
#include "scene/scene_parsers.hpp"
#include "scene/views_import.hpp"

#include <clvis/camera_spec.hpp>

#include <cmath>
#include <optional>

#ifdef CLVIS_HAVE_JSON
#include <nlohmann/json.hpp>
#endif

namespace clvis::detail {

#ifdef CLVIS_HAVE_JSON

namespace {

using Json = nlohmann::json;

constexpr int max_depth = 32;
constexpr double max_side = 65536;

Json parse(std::string_view text, const std::string& path)
{
    Json::parser_callback_t limit = [&path](int depth, Json::parse_event_t, Json&) {
        if (depth > max_depth) fail(path, "JSON nested deeper than " + std::to_string(max_depth) + " levels");
        return true;
    };
    try {
        return Json::parse(text.begin(), text.end(), limit);
    } catch (const Json::exception& e) {
        fail(path, std::string("invalid JSON: ") + e.what());
    }
}

class NerfReader {
public:
    NerfReader(const Json& root, const std::string& path) : root_(root), path_(path) {}

    ViewsFile read(const GivenSize& given)
    {
        const Json& frames = root_["frames"];
        if (!frames.is_array() || frames.empty()) bad("frames", "expected a non-empty array of frames");
        ViewsFile out;
        out.format = ViewsFormat::Nerf;
        std::vector<CameraSpec> specs;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const Json& f = frames[i];
            std::string at = "frames[" + std::to_string(i) + "]";
            if (!f.is_object()) bad(at, "expected an object with transform_matrix");
            int w = side(f, at, "w", given.width, "width"), h = side(f, at, "h", given.height, "height");
            if (i == 0) {
                out.width = w;
                out.height = h;
            } else if (w != out.width || h != out.height) {
                bad(at, "is " + std::to_string(w) + "x" + std::to_string(h) + ", frames[0] " +
                            std::to_string(out.width) + "x" + std::to_string(out.height) +
                            ": views share one image size");
            }
            refuse_distortion(f, at);
            CameraSpec spec;
            spec.intrinsics = intrinsics(f, at, w, h);
            spec.pose = pose(f, at);
            try {
                out.views.push_back(spec.resolve(Bounds{}, w, h, [&](const std::string& field) {
                    return at + (field == "pose" ? ".transform_matrix" : "." + field);
                }));
            } catch (const Error& e) {
                fail(path_, e.what());
            }
        }
        return out;
    }

private:
    [[noreturn]] void bad(const std::string& where, const std::string& what) const { fail(path_, where + ": " + what); }

    /// `key` of the frame, else of the file; a value that is not a finite number is an error.
    std::optional<double> value(const Json& frame, const std::string& at, const char* key) const
    {
        const Json* j = frame.contains(key) ? &frame[key] : root_.contains(key) ? &root_[key] : nullptr;
        if (!j) return std::nullopt;
        std::string where = frame.contains(key) ? at + "." + key : key;
        if (!j->is_number() || !std::isfinite(j->get<double>())) bad(where, "expected a finite number");
        return j->get<double>();
    }

    int side(const Json& f, const std::string& at, const char* key, std::optional<int> given, const char* what) const
    {
        std::optional<double> v = value(f, at, key);
        if (!v) {
            if (given) return *given;
            bad(key, std::string("missing: the image ") + what + " (give it in the file, or --" + what +
                         " on the command line, " + what + "= in Python)");
        }
        if (!(*v >= 1 && *v <= max_side && std::floor(*v) == *v))
            bad(f.contains(key) ? at + "." + key : key, "expected an integer from 1 to 65536, got " + shortest(*v));
        return int(*v);
    }

    void refuse_distortion(const Json& f, const std::string& at) const
    {
        for (const char* key : {"k1", "k2", "k3", "k4", "p1", "p2"}) {
            std::optional<double> v = value(f, at, key);
            if (v && *v != 0)
                bad(f.contains(key) ? at + "." + key : key,
                    shortest(*v) + ": lens distortion is not drawn (clvis's camera is a pinhole; undistort the images "
                                   "and set it to 0)");
        }
        if (const Json* j = field(f, "camera_model")) { // nerfstudio's
            std::string model = j->is_string() ? j->get<std::string>() : std::string();
            if (model != "PINHOLE" && model != "SIMPLE_PINHOLE" && model != "OPENCV")
                bad(where(f, at, "camera_model"),
                    "'" + model + "' is not read (clvis reads pinhole cameras: PINHOLE, or OPENCV without distortion)");
        }
        if (const Json* j = field(f, "is_fisheye"); j && j->is_boolean() && j->get<bool>())
            bad(where(f, at, "is_fisheye"), "a fisheye lens is not drawn");
    }

    /// `key` of the frame, else of the file, else null.
    const Json* field(const Json& frame, const char* key) const
    {
        return frame.contains(key) ? &frame[key] : root_.contains(key) ? &root_[key] : nullptr;
    }

    /// Where `key` was read from: the frame's path, or the file's key.
    static std::string where(const Json& frame, const std::string& at, const char* key)
    {
        return frame.contains(key) ? at + "." + key : std::string(key);
    }

    /// fl_x (fl_y: fl_x when absent), else camera_angle_x (fx = fy = w / 2 / tan(angle / 2),
    /// NeRF's focal); cx, cy where given, else the image's centre.
    Intrinsics intrinsics(const Json& f, const std::string& at, int w, int h) const
    {
        std::optional<double> flx = value(f, at, "fl_x"), fly = value(f, at, "fl_y");
        std::optional<double> angle = value(f, at, "camera_angle_x");
        Intrinsics k;
        if (flx) {
            k.fx = *flx;
            k.fy = fly ? *fly : *flx;
        } else if (angle) {
            if (!(*angle > 0 && *angle < 3.14159265358979323846))
                bad(f.contains("camera_angle_x") ? at + ".camera_angle_x" : "camera_angle_x",
                    "expected a horizontal field of view in radians in (0, pi), got " + shortest(*angle));
            k.fx = 0.5 * w / std::tan(0.5 * *angle);
            k.fy = k.fx;
        } else {
            bad(at, "no focal length: give fl_x (and fl_y) or camera_angle_x");
        }
        std::optional<double> cx = value(f, at, "cx"), cy = value(f, at, "cy");
        k.cx = cx ? *cx : w / 2.0;
        k.cy = cy ? *cy : h / 2.0;
        return k;
    }

    Mat4 pose(const Json& f, const std::string& at) const
    {
        std::string where = at + ".transform_matrix";
        if (!f.contains("transform_matrix")) bad(where, "missing");
        const Json& m = f["transform_matrix"];
        if (!m.is_array() || m.size() != 4) bad(where, "expected 4 rows of 4 numbers");
        Mat4 out;
        for (std::size_t r = 0; r < 4; ++r) {
            if (!m[r].is_array() || m[r].size() != 4) bad(where, "expected 4 rows of 4 numbers");
            for (std::size_t c = 0; c < 4; ++c) {
                const Json& v = m[r][c];
                if (!v.is_number() || !std::isfinite(v.get<double>()))
                    bad(where + "[" + std::to_string(r) + "][" + std::to_string(c) + "]", "expected a finite number");
                out(int(r), int(c)) = v.get<double>();
            }
        }
        return out;
    }

    const Json& root_;
    const std::string& path_;
};

} // namespace

ViewsFile parse_nerf_views(std::string_view text, const std::string& path, const GivenSize& size)
{
    Json root = parse(text, path);
    if (!root.is_object() || !root.contains("frames")) fail(path, "expected a JSON object with \"frames\"");
    return NerfReader(root, path).read(size);
}

ViewsFile parse_json_views(std::string_view text, const std::string& path, const GivenSize& size)
{
    Json root = parse(text, path);
    if (root.is_object() && !root.contains("views")) {
        if (root.contains("frames")) return NerfReader(root, path).read(size);
        if (root.contains("asset")) return parse_gltf_views(text, path, size, true);
    }
    return parse_views_file(text, path);
}

#else

ViewsFile parse_nerf_views(std::string_view, const std::string& path, const GivenSize&)
{
    fail(path, "cannot read transforms.json: this build of clvis was made without nlohmann::json");
}

ViewsFile parse_json_views(std::string_view, const std::string& path, const GivenSize&)
{
    fail(path, "cannot read views files: this build of clvis was made without nlohmann::json");
}

#endif

} // namespace clvis::detail
