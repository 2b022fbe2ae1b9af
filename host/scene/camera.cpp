// The double-precision camera of CONVENTIONS.md: validation, the look-at frame and poses, the
// canvas and intrinsics, the projection to raster space, primary rays, OpenGL matrices, and the
// framing camera.
#include <clvis/camera.hpp>
#include <clvis/error.hpp>

#include <charconv>
#include <cmath>
#include <limits>

namespace clvis {

namespace {

constexpr double pi = 3.14159265358979323846;

[[noreturn]] void invalid(const std::string& message)
{
    throw Error(Error::Kind::InvalidArgument, "camera: " + message);
}

std::string number(double v)
{
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v); // shortest text that reads back exactly
    return std::string(buf, r.ptr);
}

std::string vec(Vec3 v) { return number(v.x) + "," + number(v.y) + "," + number(v.z); }

/// A camera's placement, projection and depth range; the factories add the projection's size.
Camera placed(Vec3 eye, Vec3 target, Vec3 up, Projection projection, double near, double far)
{
    Camera c;
    c.eye = eye; c.target = target; c.up = up;
    c.projection = projection;
    c.near = near; c.far = far;
    return c;
}

/// Tolerance of a pose's rotation: CONVENTIONS.md "Cameras from intrinsics".
constexpr double pose_tolerance = 1e-6;

void check_pose(const Mat4& m)
{
    for (double v : m.m)
        if (!std::isfinite(v)) invalid("pose has a non-finite entry");
    if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1)
        invalid("pose: the last row must be 0 0 0 1");
    for (int a = 0; a < 3; ++a)
        for (int b = a; b < 3; ++b) {
            double d = m(0, a) * m(0, b) + m(1, a) * m(1, b) + m(2, a) * m(2, b);
            if (!(std::fabs(d - (a == b ? 1.0 : 0.0)) <= pose_tolerance))
                invalid("pose: the 3x3 part is not orthonormal within 1e-6 (columns " + std::to_string(a) +
                        " and " + std::to_string(b) + " have dot product " + number(d) + ")");
        }
    Vec3 c0{m(0, 0), m(1, 0), m(2, 0)}, c1{m(0, 1), m(1, 1), m(2, 1)}, c2{m(0, 2), m(1, 2), m(2, 2)};
    if (!(dot(cross(c0, c1), c2) > 0)) invalid("pose: the 3x3 part is a reflection, not a rotation");
}

/// The kernels take the camera in float32: a value that float32 cannot hold is out of range.
constexpr double float_max = std::numeric_limits<float>::max();
constexpr double float_min = std::numeric_limits<float>::min(); // smallest normal

bool in_float_range(Vec3 v)
{
    return std::fabs(v.x) <= float_max && std::fabs(v.y) <= float_max && std::fabs(v.z) <= float_max;
}

void check_point(Vec3 v, const char* name)
{
    if (!is_finite(v)) invalid(std::string(name) + " is not finite (" + vec(v) + ")");
    if (!in_float_range(v)) invalid(std::string(name) + " is outside float32's range (" + vec(v) + ")");
}

} // namespace

Intrinsics Intrinsics::from_opencv(double fx, double fy, double cx_cv, double cy_cv)
{
    return {fx, fy, cx_cv + 0.5, cy_cv + 0.5};
}

Camera Camera::from_intrinsics(Vec3 eye, Vec3 target, Vec3 up, const Intrinsics& k, double near, double far)
{
    Camera c = perspective(eye, target, up, 45, near, far);
    c.intrinsics = k;
    c.validate();
    return c;
}

Camera Camera::from_pose(const Mat4& pose, const Camera& lens)
{
    check_pose(pose);
    Camera c = lens;
    c.eye = {pose(0, 3), pose(1, 3), pose(2, 3)};
    c.target = c.eye - Vec3{pose(0, 2), pose(1, 2), pose(2, 2)}; // the third column is -f
    c.up = {pose(0, 1), pose(1, 1), pose(2, 1)};
    c.validate();
    return c;
}

Camera Camera::from_pose(const Mat4& pose) { return from_pose(pose, Camera{}); }

Camera Camera::from_opencv(double fx, double fy, double cx, double cy, const Mat4& world_to_camera, double near,
                           double far)
{
    // Camera-to-world of OpenCV's frame is [R^T | -R^T t]; its axes (x, y, z) are this frame's
    // (r, -u, f), so the pose's columns r, u, -f are R^T's columns negated after the first.
    Mat4 pose;
    for (int i = 0; i < 3; ++i) {
        pose(i, 0) = world_to_camera(0, i);
        pose(i, 1) = -world_to_camera(1, i);
        pose(i, 2) = -world_to_camera(2, i);
        pose(i, 3) = -(world_to_camera(0, i) * world_to_camera(0, 3) + world_to_camera(1, i) * world_to_camera(1, 3) +
                       world_to_camera(2, i) * world_to_camera(2, 3));
    }
    return from_pose(pose, from_intrinsics({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, Intrinsics::from_opencv(fx, fy, cx, cy),
                                           near, far));
}

Camera Camera::perspective(Vec3 eye, Vec3 target, Vec3 up, double fov_y_degrees, double near, double far)
{
    Camera c = placed(eye, target, up, Projection::Perspective, near, far);
    c.fov_y = fov_y_degrees;
    c.validate();
    return c;
}

Camera Camera::orthographic(Vec3 eye, Vec3 target, Vec3 up, double height, double near, double far)
{
    Camera c = placed(eye, target, up, Projection::Orthographic, near, far);
    c.ortho_height = height;
    c.validate();
    return c;
}

Camera Camera::physical(Vec3 eye, Vec3 target, Vec3 up, double focal_length_mm, double gate_width_mm,
                        double gate_height_mm, FilmFit fit, double aspect, double near, double far)
{
    if (!(focal_length_mm > 0) || !std::isfinite(focal_length_mm))
        invalid("focal length must be a positive number of mm, got " + number(focal_length_mm));
    if (!(gate_width_mm > 0) || !(gate_height_mm > 0) || !std::isfinite(gate_width_mm) ||
        !std::isfinite(gate_height_mm))
        invalid("film gate must be two positive numbers of mm, got " + number(gate_width_mm) + "," +
                number(gate_height_mm));
    if (!(aspect > 0) || !std::isfinite(aspect)) invalid("image aspect must be positive, got " + number(aspect));
    // The gate's half extents at unit distance; the fit scales one of them so that the canvas
    // takes the image's aspect (Scratchapixel's "Implementing a virtual pinhole camera").
    double top = gate_height_mm / 2 / focal_length_mm;
    double film_aspect = gate_width_mm / gate_height_mm;
    bool wider = film_aspect > aspect;
    if ((fit == FilmFit::Fill) != wider) top *= film_aspect / aspect;
    return perspective(eye, target, up, 2 * std::atan(top) * 180 / pi, near, far);
}

Camera Camera::framing(const Bounds& b, Projection projection)
{
    if (b.empty() || !is_finite(b.lo) || !is_finite(b.hi))
        throw Error(Error::Kind::InvalidArgument, "camera: cannot frame an empty or non-finite scene");
    Vec3 c = b.center();
    double radius = length(b.extent()) / 2;
    double scale = std::fmax(std::fmax(std::fabs(c.x), std::fabs(c.y)), std::fmax(std::fabs(c.z), 1.0));
    if (!(radius > 1e-9 * scale)) radius = 1e-3 * scale; // a point: frame a small sphere around it
    Vec3 dir = normalize(Vec3{0.3, 0.4, 1.0});
    const double fov = 45;
    if (projection == Projection::Orthographic) {
        double dist = 2 * radius;
        return orthographic(c + dir * dist, c, {0, 1, 0}, 2 * radius, 0.9 * (dist - radius),
                            1.1 * (dist + radius));
    }
    double dist = radius / std::sin(fov / 2 * pi / 180);
    return perspective(c + dir * dist, c, {0, 1, 0}, fov, 0.9 * (dist - radius), 1.1 * (dist + radius));
}

void Camera::validate() const
{
    check_point(eye, "eye");
    check_point(target, "target");
    check_point(up, "up");
    Vec3 view = target - eye;
    double view_len = length(view);
    if (!(view_len > 0)) invalid("eye equals target (" + vec(eye) + ")");
    double up_len = length(up);
    if (!(up_len > 0)) invalid("up is the zero vector");
    Vec3 f = view * (1 / view_len);
    if (!(length(cross(f, up * (1 / up_len))) > 1e-9))
        invalid("up (" + vec(up) + ") is parallel to the view direction");
    if (!std::isfinite(near) || !(near > 0)) invalid("near must be a finite view depth > 0, got " + number(near));
    if (!(near >= float_min)) invalid("near " + number(near) + " is below float32's smallest normal number");
    if (!std::isfinite(far) || !(far > near))
        invalid("far must be finite and greater than near (" + number(near) + "), got " + number(far));
    if (!(far <= float_max)) invalid("far " + number(far) + " is outside float32's range");
    if (intrinsics) {
        const Intrinsics& k = *intrinsics;
        if (projection != Projection::Perspective) invalid("intrinsics need a perspective camera");
        if (!std::isfinite(k.fx) || !(k.fx > 0) || !std::isfinite(k.fy) || !(k.fy > 0))
            invalid("intrinsics: fx and fy must be finite and > 0, got " + number(k.fx) + "," + number(k.fy));
        if (!std::isfinite(k.cx) || !std::isfinite(k.cy))
            invalid("intrinsics: cx and cy must be finite, got " + number(k.cx) + "," + number(k.cy));
    } else if (projection == Projection::Perspective) {
        if (!std::isfinite(fov_y) || !(fov_y > 0 && fov_y < 180))
            invalid("fov must lie in (0, 180) degrees, got " + number(fov_y));
        if (!(std::tan(fov_y / 2 * pi / 180) >= float_min))
            invalid("fov " + number(fov_y) + " is too small for float32");
    } else if (!std::isfinite(ortho_height) || !(ortho_height > 0)) {
        invalid("ortho height must be > 0, got " + number(ortho_height));
    } else if (!(ortho_height / 2 >= float_min && ortho_height <= float_max)) {
        invalid("ortho height " + number(ortho_height) + " is outside float32's range");
    }
}

CameraFrame Camera::frame() const
{
    CameraFrame fr;
    fr.f = normalize(target - eye);
    fr.r = normalize(cross(fr.f, up));
    fr.u = cross(fr.r, fr.f);
    return fr;
}

Mat4 Camera::pose() const
{
    CameraFrame fr = frame();
    Vec3 cols[4] = {fr.r, fr.u, fr.f * -1.0, eye};
    Mat4 m;
    for (int j = 0; j < 4; ++j) {
        m(0, j) = cols[j].x;
        m(1, j) = cols[j].y;
        m(2, j) = cols[j].z;
    }
    return m;
}

Intrinsics Camera::raster_map(int width, int height) const
{
    if (intrinsics) return *intrinsics;
    Canvas cv = canvas(double(width) / height);
    return {width / (2 * cv.right), height / (2 * cv.top), width / 2.0, height / 2.0};
}

Canvas Camera::canvas(double aspect) const
{
    Canvas c;
    c.top = projection == Projection::Perspective ? std::tan(fov_y / 2 * pi / 180) : ortho_height / 2;
    c.right = aspect * c.top;
    return c;
}

Vec3 Camera::to_camera(Vec3 world) const
{
    CameraFrame fr = frame();
    Vec3 d = world - eye;
    return {dot(d, fr.r), dot(d, fr.u), -dot(d, fr.f)};
}

Vec3 Camera::camera_to_raster(Vec3 p, int width, int height) const
{
    Intrinsics k = raster_map(width, height);
    double sx = p.x, sy = p.y;
    if (projection == Projection::Perspective) {
        sx = p.x / -p.z;
        sy = p.y / -p.z;
    }
    return {k.cx + k.fx * sx, k.cy - k.fy * sy, -p.z};
}

Vec3 Camera::to_raster(Vec3 world, int width, int height) const
{
    return camera_to_raster(to_camera(world), width, height);
}

Ray Camera::primary_ray(double x, double y, int width, int height) const
{
    CameraFrame fr = frame();
    Intrinsics k = raster_map(width, height);
    double sx = (x - k.cx) / k.fx;
    double sy = (k.cy - y) / k.fy;
    if (projection == Projection::Orthographic) return {eye + fr.r * sx + fr.u * sy, fr.f};
    return {eye, fr.r * sx + fr.u * sy + fr.f};
}

Mat4 Camera::view_matrix() const
{
    CameraFrame fr = frame();
    Mat4 m;
    Vec3 rows[3] = {fr.r, fr.u, fr.f * -1.0};
    for (int i = 0; i < 3; ++i) {
        m(i, 0) = rows[i].x;
        m(i, 1) = rows[i].y;
        m(i, 2) = rows[i].z;
        m(i, 3) = -dot(rows[i], eye);
    }
    return m;
}

Mat4 Camera::projection_matrix(int width, int height) const
{
    // ndc.x = 2 x / width - 1 and ndc.y = 1 - 2 y / height of the raster position (x, y).
    Intrinsics k = raster_map(width, height);
    double ox = 2 * k.cx / width - 1, oy = 1 - 2 * k.cy / height;
    Mat4 m;
    m(0, 0) = 2 * k.fx / width;
    m(1, 1) = 2 * k.fy / height;
    if (projection == Projection::Perspective) {
        m(0, 2) = -ox; // times w = -z
        m(1, 2) = -oy;
        m(2, 2) = -(far + near) / (far - near);
        m(2, 3) = -2 * far * near / (far - near);
        m(3, 2) = -1;
        m(3, 3) = 0;
    } else {
        m(0, 3) = ox;
        m(1, 3) = oy;
        m(2, 2) = -2 / (far - near);
        m(2, 3) = -(far + near) / (far - near);
    }
    return m;
}

std::string Camera::to_flags() const
{
    std::string s = "--eye " + vec(eye) + " --target " + vec(target) + " --up " + vec(up);
    if (intrinsics)
        s += " --intrinsics " + number(intrinsics->fx) + "," + number(intrinsics->fy) + "," + number(intrinsics->cx) +
             "," + number(intrinsics->cy);
    else if (projection == Projection::Perspective) s += " --fov " + number(fov_y);
    else s += " --ortho " + number(ortho_height);
    return s + " --near " + number(near) + " --far " + number(far);
}

} // namespace clvis
