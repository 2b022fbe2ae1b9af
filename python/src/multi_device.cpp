// clvis.MultiDeviceRenderer: one frame drawn by several OpenCL devices (the command line's
// --devices), the scene uploaded once per device and screen tiles handed out to whichever device
// is free; the frame is bit-identical to one device's. Results are Visibility objects with host
// arrays only (no device buffer: no single device holds the frame), read into the caller's arrays
// with out= as Renderer.render does.
#include "arrays.hpp"

#include <clvis/multi_device.hpp>

#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstring>

namespace clvis::python {

namespace {

struct PyMultiRenderer {
    MultiDeviceRenderer renderer;
    Lock lock;
    MultiDeviceFrame frame; ///< the last frame (its vectors reused by the next)
};

/// Splits keys into ids and depths (either may be null: not written).
void split(const std::vector<std::uint64_t>& keys, std::uint32_t* ids, float* depth)
{
    for (std::size_t i = 0; i < keys.size(); ++i) {
        if (ids) ids[i] = std::uint32_t(keys[i]);
        if (depth) {
            const auto bits = std::uint32_t(keys[i] >> 32);
            std::memcpy(depth + i, &bits, sizeof bits);
        }
    }
}

PyVisibility render(PyMultiRenderer& r, const Camera& camera, int width, int height, const std::string& path_name,
                    int tile, bool device_map, nb::handle out)
{
    PyVisibility vis;
    vis.path = path_from_string(path_name);
    vis.camera = camera;
    MultiDeviceOptions options;
    options.tile = tile;
    options.device_map = device_map;
    const ReadTarget target = read_target(vis, out, width, height);
    unlocked(r.lock, [&] {
        timed(vis, [&] {
            r.renderer.render(camera, width, height, *vis.path, options, r.frame);
            split(r.frame.keys, target.ids, target.depth);
        });
        vis.timing.frame_ms = r.frame.frame_ms;
    });
    vis.host->width = width;
    vis.host->height = height;
    return vis;
}

const char* multi_doc =
    "One frame drawn by several devices (the command line's --devices): one Renderer per device, each\n"
    "with its own copy of the scene, and screen tiles of `tile` pixels handed out to whichever device is\n"
    "free; the frame is bit-identical to one device's render. A device may appear twice (two queues).\n"
    "Options as Renderer takes them. render() returns a Visibility with host arrays only (for the\n"
    "Referee and files; shade and resolve need a Renderer's). Calls release the GIL.\n\n"
    "Example:\n"
    "    devices = [clvis.Device(d.index) for d in clvis.devices()]\n"
    "    multi = clvis.MultiDeviceRenderer(devices, scene)\n"
    "    vis = multi.render(camera, 1920, 1080)\n"
    "    print([(s.index, s.device, s.tiles) for s in multi.shares])";

} // namespace

void bind_multi_device(nb::module_& m)
{
    nb::class_<DeviceShare>(m, "DeviceShare", "What one device did for a MultiDeviceRenderer's last frame.")
        .def_ro("device", &DeviceShare::device, "Its name (two devices of one kind share it: see index).")
        .def_ro("index", &DeviceShare::index, "Its DeviceInfo.index (position in clvis.devices()): a spec for clvis.Device.")
        .def_ro("tiles", &DeviceShare::tiles, "Tiles it drew.")
        .def_ro("busy_ms", &DeviceShare::busy_ms, "Host wall time in its tiles' renders and read-backs.")
        .def("__repr__", [](const DeviceShare& s) {
            return "<clvis.DeviceShare device " + std::to_string(s.index) + " (" + s.device +
                   "): " + std::to_string(s.tiles) + " tiles>";
        });
    nb::class_<PyMultiRenderer> c(m, "MultiDeviceRenderer", multi_doc);
    c.def(
        "__init__",
        [](PyMultiRenderer* self, const std::vector<Device>& devices, PyScene& scene, const nb::kwargs& options) {
            // samples > 1: the C++ MultiDeviceRenderer refuses it, naming it.
            const RenderOptions o = render_options(options, "MultiDeviceRenderer");
            unlocked(scene.lock,
                     [&] { new (self) PyMultiRenderer{MultiDeviceRenderer(devices, scene.scene, o), {}, {}}; });
        },
        nb::sig(options_signature("devices: collections.abc.Sequence[Device], scene: Scene")), nb::arg("devices"),
        nb::arg("scene"), nb::arg("options"));
    c.def("render", &render,
             nb::sig("def render(self, camera: Camera, width: int, height: int, path: str = 'raster', *, "
                     "screen_tile: int = 64, device_map: bool = False, "
                     "out: numpy.typing.NDArray[numpy.uint32] | tuple[numpy.typing.NDArray[numpy.uint32], "
                     "numpy.typing.NDArray[numpy.float32] | None] | None = None) -> Visibility"),
             nb::arg("camera"), nb::arg("width"), nb::arg("height"), nb::arg("path") = "raster", nb::kw_only(),
             nb::arg("screen_tile") = 64, nb::arg("device_map") = false, nb::arg("out") = nb::none(),
             "Renders a width x height frame on every device, `screen_tile` pixels square per tile (1..4096).\n"
             "device_map=True records which device drew each pixel (device_of). out= as Renderer.render.")
        .def(
            "prepare",
            [](PyMultiRenderer& r, const std::string& path) {
                const Path p = path_from_string(path);
                unlocked(r.lock, [&] { r.renderer.prepare(p); });
            },
            nb::arg("path"), "Builds what `path` needs on every device before the first frame.")
        .def_prop_ro("device_count", [](PyMultiRenderer& r) { return r.renderer.device_count(); })
        .def_prop_ro("shares", [](PyMultiRenderer& r) { return unlocked(r.lock, [&] { return r.frame.devices; }); },
                     "A DeviceShare per device for the last frame, in the devices' order.")
        .def_prop_ro("tiles", [](PyMultiRenderer& r) { return unlocked(r.lock, [&] { return r.frame.tiles; }); },
                     "Tiles of the last frame.")
        .def_prop_ro(
            "device_of",
            [](PyMultiRenderer& r) -> nb::object {
                auto map = unlocked(r.lock, [&] { return r.frame.device_of; });
                if (map.empty()) return nb::none();
                const std::size_t h = std::size_t(r.frame.height), w = std::size_t(r.frame.width);
                return owned_array(std::move(map), {h, w});
            },
            "(H, W) uint8: the index of the device that drew each pixel of the last frame rendered with\n"
            "device_map=True; None otherwise.");
}

} // namespace clvis::python
