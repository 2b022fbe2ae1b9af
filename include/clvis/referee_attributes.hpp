// The referee of the attributes resolved from a visibility buffer (CONVENTIONS.md
// "Barycentrics"): from the scene's float32 vertices in double precision, the point P that (u, v)
// name on the answered triangle must project to within bary_px_tolerance px of the sample, and
// its view depth must equal the depth buffer's within the depth tolerance. Independent of the
// kernels that computed them.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/referee.hpp>
#include <clvis/scene.hpp>
#include <clvis/visibility.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace clvis {

/// Pixels between the projection of P and the sample, at most.
constexpr double bary_px_tolerance = 0.01;
/// The depth tolerance: depth_tolerance_rel d, plus the change of depth over
/// depth_tolerance_px px along the triangle's screen-space depth gradient.
constexpr double depth_tolerance_rel = 1e-5;
constexpr double depth_tolerance_px = referee_depth_judge_px; // the raster path's snapping step

struct BaryVerdict {
    bool ok = true;
    double px_error = 0;      ///< distance of P's projection from the sample, px
    double depth_error = 0;   ///< |view depth of P - the buffer's depth|
    double depth_allowed = 0; ///< the tolerance it was held to
    std::string describe(int x, int y) const;
};

struct BaryReport {
    std::size_t pixels = 0, covered = 0, errors = 0;
    double max_px_error = 0;               ///< over covered pixels
    double max_depth_error_share = 0;      ///< depth_error / depth_allowed, largest
    std::vector<std::string> first_errors; ///< up to 10
};

class BarycentricReferee {
public:
    /// Copies the scene (its items, not their expansion); Error(InvalidArgument) for an invalid camera or size.
    BarycentricReferee(const Scene& scene, const Camera& camera, int width, int height);

    /// Judges (u, v) answered with triangle `id` (or background_id) and the buffer's `depth` at
    /// pixel (x, y)'s sample at raster (sx, sy) (the pixel's centre by default).
    BaryVerdict judge(int x, int y, std::uint32_t id, double u, double v, double depth) const;
    BaryVerdict judge_at(double sx, double sy, std::uint32_t id, double u, double v, double depth) const;
    /// Judges every pixel: `uv` holds 2 floats per pixel, row 0 on top.
    BaryReport check(const HostVisibility& vis, const std::vector<float>& uv) const;

    /// View depth of the plane of triangle `id` along the primary ray through raster (sx, sy).
    double plane_depth(std::uint32_t id, double sx, double sy) const;
    /// The triangle's vertices in double (from the float32 world positions).
    void vertices(std::uint32_t id, Vec3 out[3]) const;

private:
    Camera camera_;
    int width_, height_;
    Scene scene_; ///< items and prototypes, never the expansion
};

/// Named corner attributes (CONVENTIONS.md "Vertex attributes"): a value is right within
/// corner_tolerance_rel of the largest magnitude among the triangle's three corner values (plus
/// corner_tolerance_abs) of the value computed in double from the sample's exact barycentrics (the
/// double-precision primary ray meeting the plane of the triangle's float32 world vertices); NaN
/// where the item lacks the attribute and on the background.
constexpr double corner_tolerance_rel = 1e-5;
constexpr double corner_tolerance_abs = 1e-6;

struct CornerReport {
    std::size_t pixels = 0, covered = 0, errors = 0;
    double max_error_share = 0;            ///< |error| / allowed, largest over covered pixels
    std::vector<std::string> first_errors; ///< up to 10
};

class CornerReferee {
public:
    /// Copies the scene; Error(InvalidArgument) for an invalid camera or size.
    CornerReferee(const Scene& scene, const Camera& camera, int width, int height);
    /// The exact value of attribute `name` (`components` doubles into `out`) at the sample at raster
    /// (sx, sy) of triangle `id`, and into `allowed` the tolerance of each component; false (and
    /// nothing written) where the answer must be NaN: the background, or an item without it.
    bool expected(double sx, double sy, std::uint32_t id, const std::string& name, double* out,
                  double* allowed) const;
    /// Judges every pixel's value of `name` (its components adjacent, row 0 on top) against `vis`'s
    /// ids. Error(InvalidArgument) for a name the scene lacks or sizes that differ.
    CornerReport check(const HostVisibility& vis, const std::string& name, const std::vector<float>& values) const;
    /// Judges object ids: each pixel's item (Scene::mesh_of of its id), background_id on the
    /// background. Returns the number of wrong pixels; `first` gets up to 10 descriptions.
    std::size_t check_objects(const HostVisibility& vis, const std::vector<std::uint32_t>& objects,
                              std::vector<std::string>* first = nullptr) const;

private:
    Camera camera_;
    int width_, height_;
    Scene scene_;
};

} // namespace clvis
