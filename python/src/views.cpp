// Primary rays as arrays (Camera.rays) and views files of any format (read_views: clvis's JSON,
// NeRF's transforms.json, a COLMAP text model, a glTF file's cameras), CONVENTIONS.md "Primary
// rays as arrays" and "Cameras from other tools".
#include "arrays.hpp"

#include <clvis/primary_rays.hpp>
#include <clvis/views_file.hpp>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <cstring>
#include <optional>

namespace clvis::python {

void bind_camera_rays(nb::class_<Camera>& c)
{
    c.def(
        "rays",
        [](const Camera& cam, int width, int height, int samples) {
            std::vector<RayRecord> rays = primary_rays(cam, width, height, samples);
            std::vector<float> flat(rays.size() * 8);
            if (!rays.empty()) std::memcpy(flat.data(), rays.data(), flat.size() * sizeof(float));
            return owned_array(std::move(flat), {std::size_t(height), std::size_t(width), std::size_t(samples), 8});
        },
        nb::sig("def rays(self, width: int, height: int, samples: int = 1) -> numpy.typing.NDArray[numpy.float32]"),
        nb::arg("width"), nb::arg("height"), nb::arg("samples") = 1,
        "The primary rays of every sample as a read-only (H, W, N, 8) float32 array of ray records\n"
        "ox, oy, oz, tmin, dx, dy, dz, tmax (tmin = near, tmax = far, t = view depth): the rays the ray\n"
        "path casts, bit for bit, so RayQuery.closest / Renderer.cast_rays of them give that path's ids\n"
        "and depths (as t) exactly (watertight coverage, no culling). N is 1, 2, 4, 8 or 16.\n\n"
        "Example:\n    hits = renderer.cast_rays(camera.rays(640, 360).reshape(-1, 8))");
}

void bind_views(nb::module_& m)
{
    m.def(
        "read_views",
        [](const std::string& path, std::optional<int> width, std::optional<int> height) {
            ViewsFile f = load_views_file(path, width, height);
            return nb::make_tuple(f.views, f.width, f.height, std::string(to_string(f.format)));
        },
        nb::arg("path"), nb::arg("width") = nb::none(), nb::arg("height") = nb::none(),
        nb::sig("def read_views(path: str, width: int | None = None, height: int | None = None) -> "
                "tuple[list[Camera], int, int, str]"),
        "The cameras of a views file, told by content: clvis's JSON views file, NeRF / instant-ngp\n"
        "transforms.json, a COLMAP text model (its folder, with cameras.txt and images.txt: PINHOLE\n"
        "and SIMPLE_PINHOLE), or the camera nodes of a glTF 2.0 file. Returns (cameras, width,\n"
        "height, format) with format 'clvis', 'nerf', 'colmap' or 'gltf'; width and height give the\n"
        "size where the file has none (glTF always, NeRF without w, h). Each camera is the one the\n"
        "command line's --views reads, bit for bit. Raises IoError naming the file and the field or line.\n\n"
        "Example:\n    cameras, w, h, _ = clvis.read_views('transforms.json')\n"
        "    ids, depth = renderer.render_views(cameras, w, h)");
}

} // namespace clvis::python
