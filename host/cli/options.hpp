// Flags shared by render, compare and info: the scene (mesh files or a scene file), the camera
// of CONVENTIONS.md's "Command line" (one flag per field of camera_fields(), the same table that
// scene files use) and the device. Errors name the flag.
#pragma once

#include <clvis/clvis.hpp>

#include <CLI/CLI.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace clvis::cli {

/// "--film-gate" for the camera field "film_gate".
std::string flag_of(const std::string& field);

/// --eye --target --up | --pose M, --fov | --ortho [HEIGHT] | --focal-length --film-gate --fit |
/// --intrinsics FX,FY,CX,CY, --near --far, and --width --height.
struct CameraOptions {
    std::map<std::string, std::string> given; ///< camera field -> its flag's text ("" when bare)
    std::optional<int> width, height;

    void add_to(CLI::App& app);
    /// The camera flags given, as a description (Error(InvalidArgument) naming a bad flag).
    CameraSpec spec() const;
};

/// The camera and image size of a run: the scene file's, overridden field by field by the flags.
struct View {
    Camera camera;
    int width = default_width, height = default_height;
    bool framed = false; ///< the framing camera: the caller prints the flags that reproduce it
};

/// Resolves the view of `file` (its camera, width and height) under the flags. With `fixed`
/// (compare: the buffers' size), a --width/--height or a scene file's size that differs is an
/// error. Throws Error(InvalidArgument) naming the flag or the scene file's field.
View resolve_view(const CameraOptions& flags, const SceneFile& file, const std::string& scene_name,
                  const std::optional<std::pair<int, int>>& fixed = {});

/// --device SPEC (else CLVIS_DEVICE, else the default of Device::open).
struct DeviceOptions {
    std::string spec;
    void add_to(CLI::App& app);
    Device open() const;
};

/// Every mesh format load_mesh reads (by extension), as the help says it.
constexpr const char* mesh_files_help = "mesh files (OBJ, PLY, STL, glTF 2.0: .gltf, .glb)";

/// Positional mesh files (or one .json scene file), loaded in order.
struct SceneInput {
    std::vector<std::string> files;
    void add_to(CLI::App& app, const std::string& description = std::string(mesh_files_help) +
                                                                 " or one scene file (.json), in scene order");
    /// Loads the files; `load_ms` receives the time spent reading them.
    SceneFile load(double* load_ms = nullptr) const;
    /// The scene file's name for messages, or "" when meshes were given.
    std::string scene_file() const;
};

/// --verbose: also print each kernel program's build log (compiler warnings included) on standard
/// error as it is built (CLVIS_BUILD_LOG=1 for the library); without it builds say nothing.
void add_verbose_flag(CLI::App& app);

/// True when `path` names a scene file (.json, any case).
bool is_scene_file(const std::string& path);

/// `flag` taking a name of the option enum E (option_names<E>(), the library's one table) into
/// `value`; CLI11 refuses any other name, naming the flag and the names.
template <class E>
CLI::Option* add_choice(CLI::App& app, const std::string& flag, E& value, const std::string& help)
{
    return app
        .add_option_function<std::string>(
            flag, [&value](const std::string& name) { value = option_from_string<E>(name); }, help)
        ->check(CLI::IsMember(option_names<E>()));
}

} // namespace clvis::cli
