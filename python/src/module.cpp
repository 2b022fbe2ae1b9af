// The extension module clvis._clvis: each part binds itself (errors, devices, scenes, cameras,
// rendering, the referee, images); python/clvis/__init__.py re-exports it as `clvis`.
#include "bindings.hpp"

#include <nanobind/stl/string.h>

NB_MODULE(_clvis, m)
{
    using namespace clvis::python;
    m.doc() = "clvis: visibility by rasterization and by ray casting on OpenCL, with an exact referee.";
    m.attr("__version__") = clvis::version();
    m.attr("HAVE_IMAGE_IO") = bool(CLVIS_WITH_IMAGE_IO);
    m.attr("background_id") = clvis::background_id;
    bind_errors(m);
    bind_devices(m);
    bind_scene(m);
    bind_camera(m);
    bind_views(m);
    bind_render(m);
    bind_ray_query(m);
    bind_multi_device(m);
    bind_referee(m);
    bind_image(m);
}
