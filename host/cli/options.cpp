// Parsing of the flags shared by render, compare and info (CONVENTIONS.md "Command line"). The
// camera flags come from camera_fields(), so that they and scene files take the same fields.
#include "options.hpp"

#include <cstdlib>

#include <algorithm>
#include <cctype>
#include <chrono>

namespace clvis::cli {

namespace {

[[noreturn]] void bad(const std::string& where, const std::string& what)
{
    throw Error(Error::Kind::InvalidArgument, where + ": " + what);
}

} // namespace

std::string flag_of(const std::string& field)
{
    std::string flag = "--" + field;
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
}

void CameraOptions::add_to(CLI::App& app)
{
    std::map<std::string, CLI::Option*> options;
    for (const CameraField& f : camera_fields()) {
        std::string name = f.name;
        auto* option = app.add_option_function<std::vector<std::string>>(
            flag_of(name), [this, name](const std::vector<std::string>& v) { given[name] = v.empty() ? "" : v.front(); },
            f.help);
        option->type_name(f.form)->expected(f.bare ? 0 : 1, 1);
        options[name] = option;
    }
    options["fov"]->excludes(options["ortho"]);
    options["focal_length"]->excludes(options["fov"])->excludes(options["ortho"]);
    app.add_option("--width", width, "image width in pixels (default: the scene file's, else 1920)");
    app.add_option("--height", height, "image height in pixels (default: the scene file's, else 1080)");
}

CameraSpec CameraOptions::spec() const
{
    CameraSpec spec;
    for (const auto& [name, text] : given) set_camera_field(spec, name, text, flag_of(name));
    return spec;
}

View resolve_view(const CameraOptions& flags, const SceneFile& file, const std::string& scene_name,
                  const std::optional<std::pair<int, int>>& fixed)
{
    View view;
    for (auto [flag, given, from_file, size, out] :
         {std::tuple{"--width", flags.width, file.width, fixed ? fixed->first : 0, &view.width},
          std::tuple{"--height", flags.height, file.height, fixed ? fixed->second : 0, &view.height}}) {
        const char* key = flag + 2;
        if (given && *given <= 0) bad(flag, "must be positive, got " + std::to_string(*given));
        if (fixed && given && *given != size)
            bad(flag, std::to_string(*given) + " does not match the buffers (" + std::to_string(fixed->first) + "x" +
                          std::to_string(fixed->second) + ")");
        if (fixed && !given && from_file && from_file != size)
            bad(scene_name + ": " + key, std::to_string(from_file) + " does not match the buffers (" +
                                             std::to_string(fixed->first) + "x" + std::to_string(fixed->second) +
                                             "); --" + key + " overrides it");
        *out = fixed ? size : given ? *given : from_file ? from_file : *out;
    }
    CameraSpec spec = file.camera_spec.overridden_by(flags.spec());
    // A field the flags did not give comes from the scene file: name it as the file does.
    auto name = [&](const std::string& field) {
        return flags.given.count(field) || scene_name.empty() ? flag_of(field) : scene_name + ": camera." + field;
    };
    view.camera = spec.resolve(file.scene.bounds(), view.width, view.height, name);
    view.framed = spec.framing();
    return view;
}

void DeviceOptions::add_to(CLI::App& app)
{
    app.add_option("--device", spec, "OpenCL device: index, cpu, gpu, or part of its name (env CLVIS_DEVICE)");
}

Device DeviceOptions::open() const { return Device::open(spec); }

bool is_scene_file(const std::string& path)
{
    std::string ext = path.size() >= 5 ? path.substr(path.size() - 5) : "";
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".json";
}

void SceneInput::add_to(CLI::App& app, const std::string& description)
{
    app.add_option("meshes", files, description)->required();
}

std::string SceneInput::scene_file() const
{
    return files.size() == 1 && is_scene_file(files[0]) ? files[0] : std::string();
}

SceneFile SceneInput::load(double* load_ms) const
{
    auto t0 = std::chrono::steady_clock::now();
    SceneFile out;
    if (!scene_file().empty()) out = load_scene_file(files[0]);
    else out.scene = load_scene(files);
    if (load_ms)
        *load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

void add_verbose_flag(CLI::App& app)
{
    app.add_flag_callback(
        "--verbose", [] { ::setenv("CLVIS_BUILD_LOG", "1", 1); },
        "also print the kernels' build logs (compiler warnings) on standard error as they are built");
}

} // namespace clvis::cli
