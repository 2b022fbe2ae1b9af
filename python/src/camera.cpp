// Cameras from Python, in the command line's words: eye, target, up, fov | ortho | focal_length
// with film_gate and fit, near, far; Camera.framing(bounds) for the conventions' default view.
#include "arrays.hpp"

#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>

#include <optional>

namespace clvis::python {

namespace {

using Vec = std::array<double, 3>;
using Quad = std::tuple<double, double, double, double>;

Quad quad_of(const Intrinsics& k) { return {k.fx, k.fy, k.cx, k.cy}; }

struct Lens {
    std::optional<double> fov, ortho, focal_length;
    std::optional<std::array<double, 2>> film_gate;
    std::string fit;
    std::optional<double> aspect;
};

[[noreturn]] void bad_camera(const std::string& why)
{
    throw Error(Error::Kind::InvalidArgument, "Camera: " + why);
}

Camera make_camera(Vec eye, Vec target, Vec up, const Lens& lens, double near, double far)
{
    const int kinds = lens.fov.has_value() + lens.ortho.has_value() + lens.focal_length.has_value();
    if (kinds > 1) bad_camera("give one of fov, ortho and focal_length");
    Camera c;
    if (lens.ortho) {
        c = Camera::orthographic(to_vec3(eye), to_vec3(target), to_vec3(up), *lens.ortho, near, far);
    } else if (lens.focal_length) {
        if (!lens.film_gate) bad_camera("focal_length needs film_gate=(width_mm, height_mm)");
        if (!lens.aspect) bad_camera("focal_length needs aspect=width/height of the image");
        const FilmFit fit = film_fit_from_string(lens.fit);
        c = Camera::physical(to_vec3(eye), to_vec3(target), to_vec3(up), *lens.focal_length, (*lens.film_gate)[0],
                             (*lens.film_gate)[1], fit, *lens.aspect, near, far);
    } else {
        if (lens.film_gate) bad_camera("film_gate needs focal_length");
        c = Camera::perspective(to_vec3(eye), to_vec3(target), to_vec3(up), lens.fov.value_or(45.0), near, far);
    }
    c.validate();
    return c;
}

const char* camera_doc =
    "A look-at camera (CONVENTIONS.md): perspective with a vertical field of view in degrees, "
    "orthographic with a view height (ortho=), or physical (focal_length= in mm, film_gate=(w, h) in mm, "
    "fit='fill'|'overscan', aspect=width/height). near and far are view depths. Raises "
    "InvalidArgumentError naming the first bad value.\n\n"
    "Example:\n    cam = clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), fov=45.0, near=0.1, far=10.0)\n"
    "    top = clvis.Camera(eye=(0, 5, 0), target=(0, 0, 0), up=(0, 0, -1), ortho=2.5, near=1, far=10)";

void bind_camera_queries(nb::class_<Camera>& c)
{
    c.def_prop_ro("eye", [](const Camera& c) { return from_vec3(c.eye); })
        .def_prop_ro("target", [](const Camera& c) { return from_vec3(c.target); })
        .def_prop_ro("up", [](const Camera& c) { return from_vec3(c.up); })
        .def_prop_ro("projection", [](const Camera& c) {
            return std::string(c.projection == Projection::Orthographic ? "orthographic" : "perspective");
        })
        .def_prop_ro("fov", [](const Camera& c) { return c.projection == Projection::Perspective ? std::optional<double>(c.fov_y) : std::nullopt; },
                     "Vertical field of view in degrees; None for an orthographic camera.")
        .def_prop_ro("ortho", [](const Camera& c) { return c.projection == Projection::Orthographic ? std::optional<double>(c.ortho_height) : std::nullopt; },
                     "View height in world units; None for a perspective camera.")
        .def_ro("near", &Camera::near)
        .def_ro("far", &Camera::far)
        .def("to_flags", &Camera::to_flags, "The command-line flags that reproduce this camera.")
        .def("view_matrix", [](const Camera& c) { return from_mat4(c.view_matrix()); },
             "(4, 4) float64 world-to-camera matrix (gluLookAt).")
        .def("projection_matrix",
             [](const Camera& c, int width, int height) { return from_mat4(c.projection_matrix(width, height)); },
             nb::arg("width"), nb::arg("height"), "(4, 4) float64 OpenGL projection matrix for a width x height image.")
        .def(
            "to_raster",
            [](const Camera& c, Vec p, int width, int height) { return from_vec3(c.to_raster(to_vec3(p), width, height)); },
            nb::arg("point"), nb::arg("width"), nb::arg("height"),
            "World point -> (x, y, view depth) in the raster space of a width x height image.")
        .def(
            "primary_ray",
            [](const Camera& c, double x, double y, int width, int height) {
                const Ray r = c.primary_ray(x, y, width, height);
                return std::make_pair(from_vec3(r.origin), from_vec3(r.direction));
            },
            nb::arg("x"), nb::arg("y"), nb::arg("width"), nb::arg("height"),
            "(origin, direction) of the ray through raster position (x, y); pixel (i, j) is sampled at (i+.5, j+.5).")
        .def_prop_ro("intrinsics", [](const Camera& c) {
            return c.intrinsics ? std::optional<Quad>(quad_of(*c.intrinsics)) : std::nullopt;
        }, "(fx, fy, cx, cy) of a camera made from intrinsics, else None.")
        .def("raster_map", [](const Camera& c, int width, int height) { return quad_of(c.raster_map(width, height)); },
             nb::arg("width"), nb::arg("height"),
             "(fx, fy, cx, cy): the map from screen to raster space of a width x height image, x = cx + fx s.x,\n"
             "y = cy - fy s.y (the intrinsics when given, else the canvas centred on the image).")
        .def("pose", [](const Camera& c) { return from_mat4(c.pose()); },
             "(4, 4) float64 camera-to-world matrix: columns r, u, -f and the eye (what from_pose takes).")
        .def("__repr__", [](const Camera& c) { return "<clvis.Camera " + c.to_flags() + ">"; });
}

void bind_camera_makers(nb::class_<Camera>& c)
{
    c.def_static(
         "from_intrinsics",
         [](Vec eye, Vec target, Vec up, double fx, double fy, double cx, double cy, double near, double far) {
             Camera cam = Camera::from_intrinsics(to_vec3(eye), to_vec3(target), to_vec3(up), Intrinsics{fx, fy, cx, cy},
                                                  near, far);
             cam.validate();
             return cam;
         },
         nb::kw_only(), nb::arg("eye"), nb::arg("target"), nb::arg("up") = Vec{0, 1, 0}, nb::arg("fx"), nb::arg("fy"),
         nb::arg("cx"), nb::arg("cy"), nb::arg("near") = 0.1, nb::arg("far") = 1000.0,
         "A perspective camera from intrinsics in pixels: x = cx + fx s.x, y = cy - fy s.y in raster space\n"
         "(pixel centres at half-integers; see from_opencv for OpenCV's K).\n\n"
         "Example:\n    cam = clvis.Camera.from_intrinsics(eye=(0, 0, 3), target=(0, 0, 0), fx=500, fy=500, cx=320, cy=180)")
        .def_static(
            "from_pose",
            [](nb::handle pose, std::optional<Camera> lens) {
                const Mat4 m = to_mat4(pose, "Camera.from_pose: pose");
                Camera cam = lens ? Camera::from_pose(m, *lens) : Camera::from_pose(m);
                cam.validate();
                return cam;
            },
            nb::sig("def from_pose(pose: numpy.typing.ArrayLike, lens: Camera | None = None) -> Camera"),
            nb::arg("pose"), nb::arg("lens") = nb::none(),
            "A camera whose frame is the (4, 4) camera-to-world matrix `pose` (columns r, u, -f, eye), with the\n"
            "projection of `lens` (its eye, target and up replaced) or the default camera's.")
        .def_static(
            "from_opencv",
            [](double fx, double fy, double cx, double cy, nb::handle world_to_camera, double near, double far) {
                Camera cam = Camera::from_opencv(fx, fy, cx, cy, to_mat4(world_to_camera, "Camera.from_opencv: world_to_camera"),
                                                 near, far);
                cam.validate();
                return cam;
            },
            nb::sig("def from_opencv(fx: float, fy: float, cx: float, cy: float, world_to_camera: numpy.typing.ArrayLike, "
                    "near: float = 0.1, far: float = 1000.0) -> Camera"),
            nb::arg("fx"), nb::arg("fy"), nb::arg("cx"), nb::arg("cy"), nb::arg("world_to_camera"),
            nb::arg("near") = 0.1, nb::arg("far") = 1000.0,
            "From OpenCV's pinhole: K's fx, fy, cx, cy (pixel centres at integers) and the (4, 4) world-to-camera\n"
            "extrinsics [R | t] (camera x right, y down, z forward): the pixels of cv2.projectPoints, shifted by\n"
            "half a pixel.");
}

} // namespace

void bind_camera(nb::module_& m)
{
    nb::class_<Camera> c(m, "Camera", camera_doc);
    c.def(
        "__init__",
        [](Camera* self, Vec eye, Vec target, Vec up, std::optional<double> fov, double near, double far,
           std::optional<double> ortho, std::optional<double> focal_length,
           std::optional<std::array<double, 2>> film_gate, std::string fit, std::optional<double> aspect) {
            new (self) Camera(make_camera(eye, target, up, {fov, ortho, focal_length, film_gate, fit, aspect}, near, far));
        },
        nb::kw_only(), nb::arg("eye"), nb::arg("target"), nb::arg("up") = Vec{0, 1, 0}, nb::arg("fov") = nb::none(),
        nb::arg("near") = 0.1, nb::arg("far") = 1000.0, nb::arg("ortho") = nb::none(),
        nb::arg("focal_length") = nb::none(), nb::arg("film_gate") = nb::none(), nb::arg("fit") = "fill",
        nb::arg("aspect") = nb::none());
    c.def_static(
        "framing",
        [](const Bounds& bounds, bool ortho) {
            return Camera::framing(bounds, ortho ? Projection::Orthographic : Projection::Perspective);
        },
        nb::arg("bounds"), nb::arg("ortho") = false,
        "The conventions' default camera for a scene's bounds: it looks at the box's centre from the\n"
        "direction (0.3, 0.4, 1), where the bounding sphere touches the vertical 45 degree field of view\n"
        "(ortho=True: view height and distance 2R). It depends on the bounds only, not on the image size.\n\n"
        "Example:\n    cam = clvis.Camera.framing(scene.bounds())");
    bind_camera_queries(c);
    bind_camera_makers(c);
    bind_camera_rays(c);
}

} // namespace clvis::python
