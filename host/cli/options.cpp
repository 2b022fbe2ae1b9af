// Parsing of the flags shared by render, compare and bench (CONVENTIONS.md "Command line").
#include "options.hpp"

#include <charconv>
#include <chrono>
#include <cmath>

namespace clvis::cli {

namespace {

[[noreturn]] void bad(const std::string& flag, const std::string& what)
{
    throw Error(Error::Kind::InvalidArgument, flag + ": " + what);
}

double parse_number(const std::string& text, const std::string& flag)
{
    double v = 0;
    const char* end = text.data() + text.size();
    auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end)
        bad(flag, "'" + text + "' is not a number");
    if (!std::isfinite(v)) bad(flag, "'" + text + "' is not finite");
    return v;
}

} // namespace

std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& flag,
                                  const std::string& form)
{
    std::vector<double> out;
    std::size_t start = 0;
    while (true) {
        std::size_t comma = text.find(',', start);
        out.push_back(parse_number(text.substr(start, comma - start), flag));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (out.size() != count) bad(flag, "expected " + form + ", got '" + text + "'");
    return out;
}

Vec3 parse_vec3(const std::string& text, const std::string& flag)
{
    auto v = parse_numbers(text, 3, flag, "X,Y,Z");
    return {v[0], v[1], v[2]};
}

void CameraOptions::add_to(CLI::App& app)
{
    app.add_option("--eye", eye, "camera position X,Y,Z (world units)");
    app.add_option("--target", target, "point looked at X,Y,Z");
    app.add_option("--up", up, "up vector X,Y,Z (default 0,1,0)");
    auto* fov_opt = app.add_option("--fov", fov, "vertical field of view in degrees (perspective)");
    auto* ortho_opt = app.add_option_function<std::vector<double>>(
                            "--ortho",
                            [this](const std::vector<double>& v) {
                                ortho_flag = true;
                                ortho = v.empty() ? 0.0 : v.front();
                            },
                            "orthographic camera of this view height (world units); bare: framed")
                          ->expected(0, 1);
    auto* focal = app.add_option("--focal-length", focal_length, "physical camera: focal length in mm");
    app.add_option("--film-gate", film_gate, "physical camera: film gate W,H in mm (e.g. 36,24)");
    app.add_option("--fit", fit, "physical camera: fill or overscan (default fill)")
        ->check(CLI::IsMember({"fill", "overscan"}));
    auto* intr = app.add_option("--intrinsics", intrinsics,
                                "focal lengths and principal point FX,FY,CX,CY in pixels (pixel i's centre at i+0.5)");
    auto* pose_opt = app.add_option("--pose", pose, "camera-to-world 4x4 matrix, 16 numbers row by row (replaces --eye/--target/--up)");
    fov_opt->excludes(ortho_opt);
    focal->excludes(fov_opt)->excludes(ortho_opt);
    intr->excludes(fov_opt)->excludes(ortho_opt)->excludes(focal);
    for (const char* name : {"--eye", "--target", "--up"}) pose_opt->excludes(app.get_option(name));
    app.add_option("--near", near, "near view depth (> 0)");
    app.add_option("--far", far, "far view depth (> near)");
    app.add_option("--width", width, "image width in pixels")->default_val(1920);
    app.add_option("--height", height, "image height in pixels")->default_val(1080);
}

bool CameraOptions::framed(const std::optional<Camera>& from_file) const
{
    return eye.empty() && target.empty() && pose.empty() && !from_file;
}

Camera CameraOptions::resolve(const Scene& scene, const std::optional<Camera>& from_file) const
{
    if (width <= 0) bad("--width", "must be positive, got " + std::to_string(width));
    if (height <= 0) bad("--height", "must be positive, got " + std::to_string(height));
    if (focal_length && film_gate.empty()) bad("--film-gate", "is needed with --focal-length");
    if (!film_gate.empty() && !focal_length) bad("--focal-length", "is needed with --film-gate");

    Projection projection = ortho_flag ? Projection::Orthographic : Projection::Perspective;
    Camera cam;
    if (framed(from_file)) {
        cam = Camera::framing(scene.bounds(), projection);
    } else if (from_file && eye.empty() && target.empty() && pose.empty()) {
        cam = *from_file;
    } else {
        if (!pose.empty()) {
            auto v = parse_numbers(pose, 16, "--pose", "16 numbers");
            Mat4 m;
            std::copy(v.begin(), v.end(), m.m.begin());
            try {
                cam = Camera::from_pose(m);
            } catch (const Error& e) {
                bad("--pose", std::string(e.what()).substr(8));
            }
        } else {
            if (eye.empty()) bad("--eye", "is needed with --target");
            if (target.empty()) bad("--target", "is needed with --eye");
            cam.eye = parse_vec3(eye, "--eye");
            cam.target = parse_vec3(target, "--target");
            cam.up = {0, 1, 0};
        }
        cam.projection = projection;
        // Depth range of the framing camera unless --near/--far say otherwise.
        Bounds b = scene.bounds();
        double dist = length(b.center() - cam.eye), radius = length(b.extent()) / 2;
        cam.near = std::fmax(0.9 * (dist - radius), 1e-4 * std::fmax(dist + radius, 1e-30));
        cam.far = 1.1 * (dist + radius);
        if (!(cam.far > cam.near)) cam.far = cam.near * 2;
    }
    if (!up.empty()) cam.up = parse_vec3(up, "--up");
    if (fov) {
        cam.projection = Projection::Perspective;
        cam.fov_y = *fov;
    }
    if (ortho_flag) {
        cam.projection = Projection::Orthographic;
        if (*ortho > 0) cam.ortho_height = *ortho;
        else if (*ortho < 0) bad("--ortho", "height must be > 0");
        else if (!framed(from_file)) cam.ortho_height = length(scene.bounds().extent());
    }
    if (focal_length) {
        auto gate = parse_numbers(film_gate, 2, "--film-gate", "W,H");
        cam = Camera::physical(cam.eye, cam.target, cam.up, *focal_length, gate[0], gate[1],
                               fit == "overscan" ? FilmFit::Overscan : FilmFit::Fill, double(width) / height,
                               cam.near, cam.far);
    }
    if (!intrinsics.empty()) {
        auto k = parse_numbers(intrinsics, 4, "--intrinsics", "FX,FY,CX,CY");
        cam.projection = Projection::Perspective;
        cam.intrinsics = Intrinsics{k[0], k[1], k[2], k[3]};
    }
    if (near) cam.near = *near;
    if (far) cam.far = *far;
    try {
        cam.validate();
    } catch (const Error& e) {
        std::string msg = e.what();
        for (auto [word, flag] : {std::pair{"eye", "--eye"}, {"target", "--target"}, {"up", "--up"},
                                  {"near", "--near"}, {"far", "--far"}, {"fov", "--fov"}, {"ortho", "--ortho"},
                                  {"intrinsics", "--intrinsics"}})
            if (msg.rfind(std::string("camera: ") + word, 0) == 0) bad(flag, msg.substr(8));
        throw;
    }
    return cam;
}

void DeviceOptions::add_to(CLI::App& app)
{
    app.add_option("--device", spec, "OpenCL device: index, cpu, gpu, or part of its name (env CLVIS_DEVICE)");
}

Device DeviceOptions::open() const { return Device::open(spec); }

void SceneInput::add_to(CLI::App& app, const std::string& description)
{
    app.add_option("meshes", files, description)->required();
}

SceneFile SceneInput::load(double* load_ms) const
{
    auto t0 = std::chrono::steady_clock::now();
    SceneFile out;
    if (files.size() == 1 && files[0].size() > 5 && files[0].substr(files[0].size() - 5) == ".json")
        out = load_scene_file(files[0]);
    else
        out.scene = load_scene(files);
    if (load_ms)
        *load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

} // namespace clvis::cli
