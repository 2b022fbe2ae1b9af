// Flags shared by render, compare and bench: the scene (mesh files or a scene file), the camera
// of CONVENTIONS.md's "Command line" and the device. Parsing errors name the flag.
#pragma once

#include <clvis/clvis.hpp>

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace clvis::cli {

/// --eye --target --up | --pose M, --fov | --ortho [HEIGHT] | --focal-length --film-gate --fit |
/// --intrinsics FX,FY,CX,CY, --near --far --width --height. With no camera flag, the framing
/// camera of the scene.
struct CameraOptions {
    std::string eye, target, up;      ///< "X,Y,Z" as given
    std::optional<double> fov;
    std::optional<double> ortho;      ///< height; set to 0 by a bare --ortho (framing height)
    bool ortho_flag = false;
    std::optional<double> focal_length;
    std::string film_gate;            ///< "W,H" in mm
    std::string fit = "fill";
    std::string intrinsics;           ///< "FX,FY,CX,CY" in pixels
    std::string pose;                 ///< 16 numbers, camera-to-world, row by row
    std::optional<double> near, far;
    int width = 1920, height = 1080;

    void add_to(CLI::App& app);
    /// The camera for `scene` (framing when no camera flag is given; `from_file` when the scene
    /// file gave one and no flag overrides it). Throws Error(InvalidArgument) naming the flag.
    Camera resolve(const Scene& scene, const std::optional<Camera>& from_file = {}) const;
    /// True when the camera was framed automatically (the caller prints its flags).
    bool framed(const std::optional<Camera>& from_file = {}) const;
};

/// --device SPEC (else CLVIS_DEVICE, else the default of Device::open).
struct DeviceOptions {
    std::string spec;
    void add_to(CLI::App& app);
    Device open() const;
};

/// Positional mesh files (or one .json scene file), loaded in order; width/height from a scene
/// file apply unless given on the command line.
struct SceneInput {
    std::vector<std::string> files;
    void add_to(CLI::App& app, const std::string& description = "mesh files (OBJ, PLY, STL) or one scene file (.json), in scene order");
    /// Loads the files; `load_ms` receives the time spent reading them.
    SceneFile load(double* load_ms = nullptr) const;
};

/// Parses "X,Y,Z" (plain decimal or scientific numbers, no spaces); names `flag` on error.
Vec3 parse_vec3(const std::string& text, const std::string& flag);
/// Parses `count` comma-separated numbers; `form` describes them for the error ("W,H").
std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& flag,
                                  const std::string& form);

} // namespace clvis::cli
