// load_views_file: a views file of any format told by content (CONVENTIONS.md "Many views" and
// "Cameras from other tools"), the COLMAP text model's reader, and views_file_text, which writes
// cameras back as the clvis views file that reads as the same bits. NeRF's transforms.json is
// read in views_nerf.cpp, glTF's cameras in views_gltf.cpp.
#include "scene/scene_parsers.hpp"
#include "scene/views_import.hpp"

#include <clvis/camera_spec.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

namespace clvis {

const char* to_string(ViewsFormat format) noexcept
{
    switch (format) {
    case ViewsFormat::Nerf: return "nerf";
    case ViewsFormat::Colmap: return "colmap";
    case ViewsFormat::Gltf: return "gltf";
    case ViewsFormat::Clvis: break;
    }
    return "clvis";
}

namespace detail {

std::string shortest(double v)
{
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

namespace {

/// One line of a COLMAP text file, split at blanks, with its 1-based number.
struct Line {
    std::size_t number = 0;
    std::vector<std::string_view> tokens;
    std::string_view text; ///< the line without its end
};

/// Every line of `text` except '#' comments; blank lines are kept (images.txt's second line of an
/// image may be empty). The empty piece after a final newline is not a line.
std::vector<Line> lines_of(std::string_view text)
{
    std::vector<Line> out;
    std::size_t start = 0, number = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        std::string_view s = text.substr(start, end - start);
        if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
        ++number;
        start = end + 1;
        std::size_t first = s.find_first_not_of(" \t");
        if (first != std::string_view::npos && s[first] == '#') continue;
        Line l;
        l.number = number;
        l.text = s;
        std::size_t p = 0;
        while (p < s.size()) {
            std::size_t a = s.find_first_not_of(" \t", p);
            if (a == std::string_view::npos) break;
            std::size_t b = s.find_first_of(" \t", a);
            if (b == std::string_view::npos) b = s.size();
            l.tokens.push_back(s.substr(a, b - a));
            p = b;
        }
        out.push_back(l);
    }
    return out;
}

double number_at(const Line& l, std::size_t i, const char* what, const std::string& name)
{
    double v = 0;
    std::string_view t = l.tokens[i];
    auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v))
        fail_at_line(name, l.number, std::string(what) + ": '" + std::string(t) + "' is not a finite number");
    return v;
}

long long integer_at(const Line& l, std::size_t i, const char* what, const std::string& name)
{
    long long v = 0;
    std::string_view t = l.tokens[i];
    auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size())
        fail_at_line(name, l.number, std::string(what) + ": '" + std::string(t) + "' is not an integer");
    return v;
}

struct ColmapCamera {
    int width = 0, height = 0;
    Intrinsics k;
    std::size_t line = 0;
};

std::map<long long, ColmapCamera> colmap_cameras(std::string_view text, const std::string& name)
{
    std::map<long long, ColmapCamera> out;
    const ColmapCamera* first = nullptr;
    for (const Line& l : lines_of(text)) {
        if (l.tokens.empty()) continue;
        if (l.tokens.size() < 4)
            fail_at_line(name, l.number, "expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
        long long id = integer_at(l, 0, "CAMERA_ID", name);
        std::string model(l.tokens[1]);
        ColmapCamera c;
        c.line = l.number;
        long long w = integer_at(l, 2, "WIDTH", name), h = integer_at(l, 3, "HEIGHT", name);
        if (w < 1 || h < 1 || w > 65536 || h > 65536)
            fail_at_line(name, l.number, "camera " + std::to_string(id) + ": size " + std::to_string(w) + "x" +
                                             std::to_string(h) + " is not from 1x1 to 65536x65536");
        c.width = int(w);
        c.height = int(h);
        std::size_t params = l.tokens.size() - 4;
        auto need = [&](std::size_t n, const char* form) {
            if (params != n)
                fail_at_line(name, l.number, "camera " + std::to_string(id) + ": " + model + " takes " +
                                                 std::to_string(n) + " parameters (" + form + "), got " +
                                                 std::to_string(params));
        };
        if (model == "PINHOLE") {
            need(4, "fx fy cx cy");
            c.k = {number_at(l, 4, "fx", name), number_at(l, 5, "fy", name), number_at(l, 6, "cx", name),
                   number_at(l, 7, "cy", name)};
        } else if (model == "SIMPLE_PINHOLE") {
            need(3, "f cx cy");
            double f = number_at(l, 4, "f", name);
            c.k = {f, f, number_at(l, 5, "cx", name), number_at(l, 6, "cy", name)};
        } else {
            fail_at_line(name, l.number, "camera " + std::to_string(id) + ": model " + model +
                                             " is not read (clvis reads PINHOLE and SIMPLE_PINHOLE; undistort "
                                             "the images first, e.g. colmap image_undistorter)");
        }
        if (!out.emplace(id, c).second)
            fail_at_line(name, l.number, "camera " + std::to_string(id) + " is given twice");
        const ColmapCamera& here = out[id];
        if (!first) first = &here;
        else if (here.width != first->width || here.height != first->height)
            fail_at_line(name, l.number, "camera " + std::to_string(id) + " is " + std::to_string(here.width) + "x" +
                                             std::to_string(here.height) + ", the camera of line " +
                                             std::to_string(first->line) + " " + std::to_string(first->width) +
                                             "x" + std::to_string(first->height) + ": views share one image size");
    }
    if (out.empty()) fail(name, "holds no camera");
    return out;
}

/// COLMAP's world-to-camera rotation of the unit quaternion (qw, qx, qy, qz) (its
/// QuaternionToRotationMatrix), and the clvis pose of the camera [R | t] in OpenCV's axes (x
/// right, y down, z forward), which are this frame's (x, -y, -z): columns R's rows 0, -1, -2 and
/// the eye -R^T t (Camera::from_opencv's pose), zeros +0.
Mat4 colmap_pose(double qw, double qx, double qy, double qz, double tx, double ty, double tz)
{
    double R[3][3] = {{1 - 2 * qy * qy - 2 * qz * qz, 2 * qx * qy - 2 * qw * qz, 2 * qz * qx + 2 * qw * qy},
                      {2 * qx * qy + 2 * qw * qz, 1 - 2 * qx * qx - 2 * qz * qz, 2 * qy * qz - 2 * qw * qx},
                      {2 * qz * qx - 2 * qw * qy, 2 * qy * qz + 2 * qw * qx, 1 - 2 * qx * qx - 2 * qy * qy}};
    Mat4 pose;
    for (int i = 0; i < 3; ++i) { // + 0.0: a negated zero is +0, as the same pose typed in a views file
        pose(i, 0) = R[0][i] + 0.0;
        pose(i, 1) = -R[1][i] + 0.0;
        pose(i, 2) = -R[2][i] + 0.0;
        pose(i, 3) = -(R[0][i] * tx + R[1][i] * ty + R[2][i] * tz) + 0.0;
    }
    return pose;
}

} // namespace

ViewsFile parse_colmap_views(std::string_view cameras_text, const std::string& cameras_name,
                             std::string_view images_text, const std::string& name)
{
    std::map<long long, ColmapCamera> cameras = colmap_cameras(cameras_text, cameras_name);
    struct Image {
        long long id;
        CameraSpec spec;
        std::size_t line;
    };
    std::vector<Image> images;
    std::vector<Line> lines = lines_of(images_text);
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const Line& l = lines[i];
        if (l.tokens.empty()) continue; // no image line is blank: a blank line here is spacing
        if (l.tokens.size() < 10)
            fail_at_line(name, l.number, "expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
        ++i; // the image's 2D points, one line (perhaps empty), skipped
        long long id = integer_at(l, 0, "IMAGE_ID", name);
        double q[4], t[3];
        for (int k = 0; k < 4; ++k) q[k] = number_at(l, std::size_t(1 + k), "the quaternion", name);
        for (int k = 0; k < 3; ++k) t[k] = number_at(l, std::size_t(5 + k), "the translation", name);
        long long camera = integer_at(l, 8, "CAMERA_ID", name);
        auto found = cameras.find(camera);
        if (found == cameras.end())
            fail_at_line(name, l.number, "image " + std::to_string(id) + ": camera " + std::to_string(camera) +
                                             " is not in " + cameras_name);
        double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(norm > 0) || !std::isfinite(norm))
            fail_at_line(name, l.number, "image " + std::to_string(id) + ": the quaternion has no direction");
        Image im{id, {}, l.number};
        im.spec.pose = colmap_pose(q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm, t[0], t[1], t[2]);
        im.spec.intrinsics = found->second.k;
        images.push_back(im);
    }
    if (images.empty()) fail(name, "holds no image");
    std::stable_sort(images.begin(), images.end(), [](const Image& a, const Image& b) { return a.id < b.id; });
    for (std::size_t i = 1; i < images.size(); ++i)
        if (images[i].id == images[i - 1].id)
            fail_at_line(name, images[i].line, "image " + std::to_string(images[i].id) + " is given twice");
    ViewsFile out;
    out.format = ViewsFormat::Colmap;
    out.width = cameras.begin()->second.width;
    out.height = cameras.begin()->second.height;
    for (const Image& im : images) {
        try {
            out.views.push_back(im.spec.resolve(Bounds{}, out.width, out.height, [&](const std::string& field) {
                return "image " + std::to_string(im.id) + " (" + field + ")";
            }));
        } catch (const Error& e) {
            fail_at_line(name, im.line, e.what());
        }
    }
    return out;
}

} // namespace detail

namespace {

ViewsFile read_views_any(const std::string& path, std::optional<int> width, std::optional<int> height)
{
    namespace fs = std::filesystem;
    detail::GivenSize size{width, height};
    fs::path p(path);
    std::error_code ec;
    std::string leaf = p.filename().string();
    if (fs::is_directory(p, ec) || leaf == "cameras.txt" || leaf == "images.txt") {
        fs::path folder = fs::is_directory(p, ec) ? p : p.parent_path();
        fs::path cams = folder / "cameras.txt", imgs = folder / "images.txt";
        if (!fs::exists(cams, ec) && fs::exists(folder / "cameras.bin", ec))
            detail::fail(path, "a COLMAP binary model: clvis reads the text model (colmap model_converter "
                               "--output_type TXT)");
        std::string cameras = detail::read_file(cams.string()), images = detail::read_file(imgs.string());
        return detail::parse_colmap_views(cameras, cams.string(), images, imgs.string());
    }
    std::string bytes = detail::read_file(path);
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".gltf" || ext == ".glb" || bytes.compare(0, 4, "glTF") == 0)
        return detail::parse_gltf_views(bytes, path, size, true);
    return detail::parse_json_views(bytes, path, size);
}

} // namespace

ViewsFile load_views_file(const std::string& path, std::optional<int> width, std::optional<int> height)
{
    ViewsFile out = read_views_any(path, width, height);
    out.path = path;
    out.items.resize(out.views.size()); // other tools' cameras move no items
    return out;
}

std::string views_file_text(const ViewsFile& f)
{
    using detail::shortest;
    auto vec = [](Vec3 v) { return "[" + shortest(v.x) + ", " + shortest(v.y) + ", " + shortest(v.z) + "]"; };
    std::string s = "{\"width\": " + std::to_string(f.width) + ", \"height\": " + std::to_string(f.height) +
                    ", \"views\": [";
    for (std::size_t i = 0; i < f.views.size(); ++i) {
        const Camera& c = f.views[i];
        s += i ? ",\n  " : "\n  ";
        s += "{\"eye\": " + vec(c.eye) + ", \"target\": " + vec(c.target) + ", \"up\": " + vec(c.up) + ", ";
        if (c.intrinsics)
            s += "\"intrinsics\": [" + shortest(c.intrinsics->fx) + ", " + shortest(c.intrinsics->fy) + ", " +
                 shortest(c.intrinsics->cx) + ", " + shortest(c.intrinsics->cy) + "]";
        else if (c.projection == Projection::Orthographic) s += "\"ortho\": " + shortest(c.ortho_height);
        else s += "\"fov\": " + shortest(c.fov_y);
        s += ", \"near\": " + shortest(c.near) + ", \"far\": " + shortest(c.far) + "}";
    }
    return s + "\n]}\n";
}

} // namespace clvis
