// A camera as people describe it, on the command line (--film-gate 36,24) or in a scene file
// ("film_gate": [36, 24]): every field optional, one table of fields for both, resolved against
// the scene's bounds and the image's size into a Camera. A new kind of camera is a new field
// here, and both the tool's flags and scene files take it.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/math.hpp>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace clvis {

/// The image size when neither the command line nor a scene file gives one.
constexpr int default_width = 1920, default_height = 1080;

/// What a description gives; anything absent takes the default of CONVENTIONS.md's command line.
struct CameraSpec {
    std::optional<Vec3> eye, target, up;
    std::optional<double> fov;                   ///< vertical field of view, degrees
    bool ortho = false;                          ///< orthographic
    std::optional<double> ortho_height;          ///< world units; absent: from the scene's bounds
    std::optional<double> focal_length;          ///< physical camera: mm
    std::optional<std::array<double, 2>> film_gate; ///< physical camera: aperture W, H in mm
    std::optional<FilmFit> fit;                  ///< physical camera: default Fill
    std::optional<double> near, far;             ///< view depths
    std::optional<Intrinsics> intrinsics;        ///< fx, fy, cx, cy in pixels; replaces fov
    std::optional<Mat4> pose;                    ///< camera-to-world; replaces eye, target, up

    bool empty() const;
    /// True when neither eye, target nor pose is given: the framing camera of the scene.
    bool framing() const { return !eye && !target && !pose; }

    /// This description with each field that `over` gives replaced by it. A projection given in
    /// `over` (fov, ortho, intrinsics, or any physical field) replaces this one's other
    /// projections; a pose replaces eye, target and up, and eye or target a pose.
    CameraSpec overridden_by(const CameraSpec& over) const;

    /// The camera for a scene with `scene_bounds`, rendered at width x height:
    ///  - no eye and no target: Camera::framing (orthographic when `ortho`), then the given fields;
    ///  - else a pose, or eye and target (both needed), up (default 0,1,0), and near and far, unless given,
    ///    those of the framing camera at this eye's distance from the bounds' centre;
    ///  - fov, ortho (height absent: the bounds' diagonal; framing: 2R), or the physical camera
    ///    (focal_length and film_gate both needed; fit only with them) at the image's aspect, or
    ///    intrinsics (CONVENTIONS.md "Cameras from intrinsics").
    /// Throws Error(InvalidArgument) naming the field by `name(field)` (e.g. "--film-gate" or
    /// "camera.film_gate"; the field's own name when `name` is empty): conflicting projections,
    /// a field needed with another, and whatever Camera::validate refuses.
    Camera resolve(const Bounds& scene_bounds, int width, int height,
                   const std::function<std::string(const std::string& field)>& name = {}) const;
};

/// One field of a description: `name` is its scene-file key, and `--name` with '_' as '-' its
/// command-line flag.
struct CameraField {
    const char* name;   ///< "eye", "film_gate", ...
    const char* form;   ///< its value for people: "X,Y,Z", "DEGREES", "fill|overscan"
    const char* help;   ///< one line
    int numbers;        ///< how many numbers its value holds; 0: a word
    bool bare;          ///< may be given without a value (--ortho; "ortho": true in a file)
};

/// Every field, in the order help lists them.
const std::vector<CameraField>& camera_fields();

/// A field's value: numbers, a word (for `fit`), or nothing at all (bare).
struct CameraValue {
    std::vector<double> numbers;
    std::string word;
    bool bare = false;
};

/// Sets field `name` of `spec`. Throws Error(InvalidArgument) beginning with `where` (the flag
/// or the file's JSON path) for an unknown field, a value of the wrong form, a non-finite
/// number, or a value out of the field's domain (sizes and heights > 0, fit fill or overscan).
void set_camera_field(CameraSpec& spec, const std::string& name, const CameraValue& value,
                      const std::string& where);
/// The same from the command line's text: comma-separated numbers ("1,2.5,-3e-2", no spaces),
/// a word, or "" for a bare flag.
void set_camera_field(CameraSpec& spec, const std::string& name, const std::string& text,
                      const std::string& where);

} // namespace clvis
