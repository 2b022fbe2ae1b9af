// The camera of CONVENTIONS.md: a look-at frame or a camera-to-world pose (the camera looks down
// -z), perspective with a vertical field of view or with intrinsics in pixels, or orthographic
// with a view height; near and far view depths, and raster space with row 0 on top, sampled at
// pixel centres. The same projection is compiled into the kernels from kernels/shared/camera.h;
// these double-precision functions define the answer.
#pragma once

#include <clvis/math.hpp>

#include <optional>
#include <string>

namespace clvis {

enum class Projection { Perspective, Orthographic };

/// How a film gate whose aspect differs from the image's is reconciled with it.
enum class FilmFit {
    Fill,     ///< the film gate fills the image: the image shows part of it
    Overscan, ///< the whole film gate is inside the image: the image shows more
};
/// "fill" or "overscan" (render_options.cpp's table, as option_names<FilmFit>()).
const char* to_string(FilmFit fit) noexcept;
/// Throws Error(InvalidArgument) for any other name.
FilmFit film_fit_from_string(const std::string& name);

struct CameraFrame {
    Vec3 r, u, f; ///< right, up, forward (unit vectors); camera space is (r, u, -f)
};

struct Canvas {
    double right = 0, top = 0; ///< half extents at unit distance (perspective) or in world units
};

/// Focal lengths and principal point in pixels of raster space (CONVENTIONS.md "Cameras from
/// intrinsics"): a camera-space point P (P.z < 0) lands at x = cx + fx P.x / -P.z,
/// y = cy - fy P.y / -P.z, pixel i's centre being at i + 0.5.
struct Intrinsics {
    double fx = 0, fy = 0; ///< px per unit of screen space, > 0 (per world unit when orthographic)
    double cx = 0, cy = 0; ///< raster position of the optical axis, px

    /// From OpenCV's camera matrix K, whose pixel centres lie at integers: the same fx, fy and
    /// cx = cx_cv + 0.5, cy = cy_cv + 0.5. (OpenCV's camera axes are this frame's (x, -y, -z):
    /// see Camera::from_opencv for its extrinsics.)
    static Intrinsics from_opencv(double fx, double fy, double cx_cv, double cy_cv);
};

struct Ray {
    Vec3 origin, direction; ///< direction unnormalised: t of a hit is its view depth
};

struct Camera {
    Vec3 eye{0, 0, 0};
    Vec3 target{0, 0, -1};
    Vec3 up{0, 1, 0};
    Projection projection = Projection::Perspective;
    double fov_y = 45;        ///< vertical field of view in degrees, in (0, 180), perspective only
    double ortho_height = 2;  ///< world units, > 0, orthographic only
    double near = 0.1;        ///< view depth, > 0
    double far = 1000;        ///< view depth, > near
    /// Replaces fov_y when set (perspective only): the projection is then fixed in pixels, and
    /// the image size only decides how much of it is seen.
    std::optional<Intrinsics> intrinsics;

    /// The factories validate() what they make: a NaN or out-of-range value is refused here,
    /// with the field named, not when the camera is first used.
    static Camera perspective(Vec3 eye, Vec3 target, Vec3 up, double fov_y_degrees, double near,
                              double far);
    static Camera orthographic(Vec3 eye, Vec3 target, Vec3 up, double height, double near,
                               double far);
    /// The physical camera: a focal length and a film gate (aperture in mm) give the field of
    /// view; `fit` reconciles the gate's aspect with the image's `aspect` (width / height).
    static Camera physical(Vec3 eye, Vec3 target, Vec3 up, double focal_length_mm,
                           double gate_width_mm, double gate_height_mm, FilmFit fit,
                           double aspect, double near, double far);
    /// The framing camera of CONVENTIONS.md for a scene's bounds: looks at the box's centre from
    /// direction (0.3, 0.4, 1) at the distance where the bounding sphere touches the vertical
    /// field of view (45 degrees), or with an orthographic camera of height 2R at distance 2R.
    static Camera framing(const Bounds& scene_bounds, Projection projection = Projection::Perspective);
    /// A perspective camera with intrinsics in pixels, at the look-at frame (eye, target, up).
    static Camera from_intrinsics(Vec3 eye, Vec3 target, Vec3 up, const Intrinsics& k, double near, double far);
    /// A camera whose frame is the camera-to-world matrix `pose` (row by row, column vectors:
    /// its first three columns are r, u, -f and its last column the eye); projection as `lens`
    /// says (its eye, target and up are replaced), or the default camera's. Throws
    /// Error(InvalidArgument) unless the 3x3 part is a rotation within 1e-6 and the last row is
    /// 0 0 0 1.
    static Camera from_pose(const Mat4& pose, const Camera& lens);
    static Camera from_pose(const Mat4& pose);
    /// From OpenCV's pinhole: K = (fx, fy, cx, cy) with pixel centres at integers, and the
    /// world-to-camera extrinsics [R | t] as a 4x4 matrix (camera axes x right, y down, z
    /// forward). The same pixels as cv::projectPoints, shifted by half a pixel.
    static Camera from_opencv(double fx, double fy, double cx, double cy, const Mat4& world_to_camera,
                              double near, double far);

    /// Throws Error(InvalidArgument) naming the first bad field: non-finite values, eye equal
    /// to target, up parallel to the view direction, near <= 0, far <= near, fov outside
    /// (0, 180), ortho height <= 0, intrinsics with fx or fy <= 0 or on an orthographic camera,
    /// and values the kernels' float32 cannot hold (coordinates or far beyond FLT_MAX, near or the
    /// canvas below FLT_MIN). The factories call it; a Camera whose fields are set by hand is
    /// checked here and again by every render.
    void validate() const;

    CameraFrame frame() const;
    /// The camera-to-world matrix: columns r, u, -f and eye (what from_pose takes).
    Mat4 pose() const;
    /// The symmetric canvas of fov_y or ortho_height (intrinsics aside: see raster_map).
    Canvas canvas(double aspect) const;
    /// The map from screen to raster space of a width x height image, x = cx + fx s.x,
    /// y = cy - fy s.y: the intrinsics when given, else the canvas centred on the image.
    Intrinsics raster_map(int width, int height) const;

    /// World -> camera space (x right, y up, z backwards: visible points have z < 0).
    Vec3 to_camera(Vec3 world) const;
    /// Camera space -> raster space of a width x height image; z of the result is the view depth.
    Vec3 camera_to_raster(Vec3 camera_point, int width, int height) const;
    /// World -> raster (x, y in pixels, z = view depth).
    Vec3 to_raster(Vec3 world, int width, int height) const;
    /// The primary ray through raster position (x, y): pixel (i, j) is sampled at (i+.5, j+.5).
    Ray primary_ray(double x, double y, int width, int height) const;

    /// Row-major view matrix (world -> camera space), OpenGL's gluLookAt.
    Mat4 view_matrix() const;
    /// Row-major OpenGL projection matrix (glFrustum / glOrtho, off-centre where the principal
    /// point is) for a width x height image, with near and far mapped to NDC z = -1 and +1.
    /// ndc = (P v).xy / (P v).w equals to_raster's NDC.
    Mat4 projection_matrix(int width, int height) const;

    /// The command-line flags that reproduce this camera (--eye ... [--intrinsics ...] --near ...).
    std::string to_flags() const;
};

} // namespace clvis
