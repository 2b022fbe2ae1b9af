// Rendering from Python: a Renderer keeps a scene on a device; render() answers for a camera by
// either path (all of the image or a region) and returns a Visibility whose NumPy arrays are the
// ones the single read-back wrote (new, reused once dropped, or the caller's with out=), valid on
// their own after the Visibility and the Renderer are gone.
#include "arrays.hpp"

#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <chrono>
#include <initializer_list>
#include <limits>
#include <utility>

namespace clvis::python {

const HostVisibility& host_of(const PyVisibility& vis, HostVisibility& scratch)
{
    if (!vis.ids_out.is_valid()) return *vis.host;
    scratch.width = vis.host->width;
    scratch.height = vis.host->height;
    scratch.samples = vis.host->samples;
    scratch.layers = vis.host->layers;
    const std::size_t n = std::size_t(scratch.width) * std::size_t(scratch.height) * std::size_t(scratch.samples) *
                          std::size_t(scratch.layers);
    const auto* ids = nb::cast<HostArray<std::uint32_t>>(vis.ids_out, false).data();
    scratch.ids.assign(ids, ids + n);
    scratch.depth.clear();
    if (vis.depth_out.is_valid()) {
        const auto* depth = nb::cast<HostArray<float>>(vis.depth_out, false).data();
        scratch.depth.assign(depth, depth + n);
    }
    return scratch;
}

const VisibilityBuffer& device_buffer(const PyVisibility& vis, const char* what, bool whole)
{
    if (vis.device.empty() || !vis.camera)
        throw Error(Error::Kind::InvalidArgument,
                    std::string(what) + ": the Visibility must come from Renderer.render (it has no device buffer)");
    if (whole && vis.region)
        throw Error(Error::Kind::InvalidArgument,
                    std::string(what) + ": the Visibility holds a region of its camera's image; render it whole");
    return vis.device;
}

namespace {

/// A Region from (x, y, width, height).
Region region_of(nb::handle region)
{
    const char* what = "render: region";
    std::vector<int> v;
    if (!nb::try_cast(region, v) || v.size() != 4)
        throw Error(Error::Kind::InvalidArgument,
                    std::string(what) + ": expected (x, y, width, height) integers, got " + text_of(region));
    if (v[2] <= 0 || v[3] <= 0)
        throw Error(Error::Kind::InvalidArgument, std::string(what) + ": width and height must be positive, got " +
                                                      text_of(region));
    return Region{v[0], v[1], v[2], v[3]};
}

} // namespace

namespace {

/// numpy.empty((height, width), dtype), or (height, width, samples) when samples > 1, read-only to
/// Python, and its data for the read-back. Error(Limit) when the host cannot hold it.
template <class T>
nb::object new_array(std::size_t height, std::size_t width, std::size_t samples, const char* dtype, T*& data)
{
    static PyObject* empty = nb::object(nb::module_::import_("numpy").attr("empty")).release().ptr();
    nb::object a;
    try {
        a = nb::handle(empty)(samples > 1 ? nb::make_tuple(height, width, samples) : nb::make_tuple(height, width), dtype);
    } catch (const nb::python_error& e) {
        if (!e.matches(PyExc_MemoryError)) throw;
        throw Error(Error::Kind::Limit, "render: the host cannot hold the " + std::to_string(width) + "x" +
                                            std::to_string(height) + " visibility buffer's " + dtype + " array");
    }
    data = static_cast<T*>(samples > 1 ? writable_data(a, format_of<T>(), sizeof(T), {height, width, samples})
                                       : writable_data(a, format_of<T>(), sizeof(T), {height, width}));
    a.attr("setflags")(nb::arg("write") = false); // NumPy's flag: the read-back writes through `data`
    return a;
}

} // namespace

/// The caller's output array `obj` for `what`: C-contiguous, writable, (h, w) or (h, w, n) when n > 1.
template <class T>
T* caller_array(nb::handle obj, const char* what, const char* dtype, std::size_t h, std::size_t w, std::size_t n)
{
    return n > 1 ? output_array<T>(obj, what, dtype, {h, w, n}) : output_array<T>(obj, what, dtype, {h, w});
}

ReadTarget read_target(PyVisibility& vis, nb::handle out, int width, int height, int samples)
{
    ReadTarget target;
    const std::size_t h = std::size_t(height > 0 ? height : 0), w = std::size_t(width > 0 ? width : 0);
    const std::size_t n = std::size_t(samples > 1 ? samples : 1);
    if (out.is_none()) {
        vis.ids_out = new_array(h, w, n, "uint32", target.ids);
        vis.depth_out = new_array(h, w, n, "float32", target.depth);
        return target;
    }
    nb::handle ids = out, depth;
    if (nb::isinstance<nb::tuple>(out) || nb::isinstance<nb::list>(out)) {
        if (nb::len(out) != 2)
            throw Error(Error::Kind::InvalidArgument,
                        "render: out: expected an ids array or (ids, depth), got " + std::to_string(nb::len(out)) + " items");
        ids = out[0];
        depth = out[1];
    }
    target.ids = caller_array<std::uint32_t>(ids, "render: out ids", "uint32", h, w, n);
    vis.ids_out = nb::borrow(ids);
    if (depth.is_valid() && !depth.is_none()) {
        target.depth = caller_array<float>(depth, "render: out depth", "float32", h, w, n);
        vis.depth_out = nb::borrow(depth);
    }
    return target;
}

namespace {

/// The renderer's spare arrays as the target of a width x height read-back, when nothing but the
/// renderer refers to them; else false.
bool take_spare(PyRenderer& r, PyVisibility& vis, int width, int height, ReadTarget& target)
{
    PyRenderer::Spare& s = r.spare;
    if (!s.ids.is_valid() || s.width != width || s.height != height || Py_REFCNT(s.ids.ptr()) != 1 ||
        Py_REFCNT(s.depth.ptr()) != 1)
        return false;
    vis.ids_out = std::move(s.ids);
    vis.depth_out = std::move(s.depth);
    target = ReadTarget{s.ids_data, s.depth_data};
    return true;
}

/// Keeps the arrays render() made for `vis` as the renderer's spare.
void keep_spare(PyRenderer& r, const PyVisibility& vis, int width, int height, const ReadTarget& target)
{
    r.spare = PyRenderer::Spare{vis.ids_out, vis.depth_out, target.ids, target.depth, width, height};
}

/// Renders (all of the image or `region`) and reads back once, into the Visibility's own arrays
/// or into the caller's (`out`), the GIL released and the renderer locked.
/// The Python object is made before the device works, so that little is left to do after it (the
/// first things run after a long call pay for caches gone cold).
nb::object render(PyRenderer& r, const Camera& camera, int width, int height, const std::string& path_name,
                  nb::handle region, nb::handle out)
{
    nb::object result = nb::cast(PyVisibility{}, nb::rv_policy::move);
    PyVisibility& vis = nb::cast<PyVisibility&>(result);
    vis.path = path_from_string(path_name);
    vis.camera = camera;
    if (!region.is_none()) vis.region = region_of(region);
    const int w = vis.region ? vis.region->width : width, h = vis.region ? vis.region->height : height;
    const int samples = r.renderer.options().samples; // fixed at construction: no lock needed
    const int layers = r.renderer.options().layers;   // depth layers: (H, W, layers) arrays (samples 1)
    ReadTarget target;
    if (!out.is_none() || !take_spare(r, vis, w, h, target))
        target = read_target(vis, out, w, h, layers > 1 ? layers : samples);
    unlocked(r.lock, [&] {
        timed(vis, [&] {
            if (vis.region) {
                vis.device = layers > 1 ? VisibilityBuffer(r.renderer.device(), w, h, 1, layers)
                                        : VisibilityBuffer(r.renderer.device(), w, h);
                r.renderer.render(camera, width, height, *vis.region, *vis.path, vis.device);
            } else {
                vis.device = r.renderer.render(camera, width, height, *vis.path);
            }
            vis.device.read(target.ids, target.depth);
        });
        vis.timing = r.renderer.last_frame();
    });
    if (out.is_none()) keep_spare(r, vis, w, h, target);
    vis.host->width = w;
    vis.host->height = h;
    vis.host->samples = samples;
    vis.host->layers = layers;
    return result;
}

void bind_timing(nb::module_& m)
{
    nb::class_<StageTiming>(m, "StageTiming", "Device time of one pipeline stage.")
        .def_ro("name", &StageTiming::name)
        .def_ro("ms", &StageTiming::ms)
        .def("__repr__", [](const StageTiming& s) { return "<clvis.StageTiming " + s.name + " " + std::to_string(s.ms) + " ms>"; });
    nb::class_<FrameTiming>(m, "FrameTiming", "Times of one frame: host wall time and device time per stage.")
        .def_ro("frame_ms", &FrameTiming::frame_ms, "Host wall time from the first enqueue to finish (read-back excluded).")
        .def_ro("stages", &FrameTiming::stages)
        .def_ro("stages_measured", &FrameTiming::stages_measured,
                "False when the queue has no profiling (a wrapped queue made without it): stages are then absent.")
        .def_prop_ro(
            "raster_atomics", [](const FrameTiming& t) { return std::string(to_string(t.raster_atomics)); },
            "The raster path's depth test in this frame, as raster_atomics='auto' resolved it: 'on' (64-bit "
            "atomics) or 'off' (tile ownership); 'auto' for the other paths.")
        .def("__repr__", [](const FrameTiming& t) { return "<clvis.FrameTiming " + std::to_string(t.frame_ms) + " ms>"; });
    nb::class_<BvhStats>(m, "BvhStats", "The ray path's BVH as last built or refitted.")
        .def_ro("build_ms", &BvhStats::build_ms)
        .def_ro("upload_ms", &BvhStats::upload_ms)
        .def_ro("nodes", &BvhStats::nodes)
        .def_ro("leaves", &BvhStats::leaves)
        .def_ro("depth", &BvhStats::depth)
        .def_ro("sah_cost", &BvhStats::sah_cost)
        .def_ro("refitted", &BvhStats::refitted)
        .def_ro("instances", &BvhStats::instances, "top-level entries of a two-level BVH (0 without instances)")
        .def_ro("top_build_ms", &BvhStats::top_build_ms, "the top level's last build, in ms")
        .def_ro("prototype_builds", &BvhStats::prototype_builds, "prototype trees built so far")
        .def_ro("device_bytes", &BvhStats::device_bytes, "the BVH's device buffers, in bytes");
}

/// `obj` as an (H, W) array of `dtype` ("uint32" ids, "float32" depths), its size in width and
/// height (which, when already set, it must match).
template <class T>
std::vector<T> image_array(nb::handle obj, const char* what, bool integer, const char* dtype, int& width, int& height)
{
    auto a = as_host_array<T>(obj, {what, "(H, W)", 2, 0, integer}, dtype);
    const auto h = a.shape(0), w = a.shape(1);
    if (h > std::size_t(std::numeric_limits<int>::max()) || w > std::size_t(std::numeric_limits<int>::max()))
        throw Error(Error::Kind::Limit, std::string(what) + ": image too large");
    if (width && (int(w) != width || int(h) != height))
        throw Error(Error::Kind::InvalidArgument, std::string(what) + ": shape differs from the ids'");
    width = int(w);
    height = int(h);
    return std::vector<T>(a.data(), a.data() + a.size());
}

void bind_visibility(nb::module_& m)
{
    nb::class_<PyVisibility>(m, "Visibility", nb::is_weak_referenceable(),
                             "A visibility buffer: per pixel the nearest triangle's id (background_id where none) and its\n"
                             "view depth (+inf where none), row 0 on top. `ids` and `depth` are the NumPy arrays the one\n"
                             "read-back wrote (read-only; the caller's own with render(out=...)); they stay valid on\n"
                             "their own (after the Visibility and the Renderer).\n\n"
                             "Example:\n    vis = renderer.render(camera, 640, 360)\n    covered = vis.ids != clvis.background_id")
        .def(
            "__init__",
            [](PyVisibility* self, nb::handle ids, nb::handle depth) {
                PyVisibility v;
                v.host->ids = image_array<std::uint32_t>(ids, "Visibility: ids", true, "uint32", v.host->width, v.host->height);
                if (!depth.is_none())
                    v.host->depth = image_array<float>(depth, "Visibility: depth", false, "float32", v.host->width, v.host->height);
                if (v.host->width == 0 || v.host->height == 0)
                    throw Error(Error::Kind::InvalidArgument, "Visibility: an empty image");
                new (self) PyVisibility(std::move(v));
            },
            nb::sig("def __init__(self, ids: numpy.typing.ArrayLike, depth: numpy.typing.ArrayLike | None = None) -> None"),
            nb::arg("ids"), nb::arg("depth") = nb::none(),
            "A visibility buffer from (H, W) arrays (copied), e.g. another renderer's, for the Referee or files.")
        .def_prop_ro("width", [](const PyVisibility& v) { return v.host->width; })
        .def_prop_ro("height", [](const PyVisibility& v) { return v.host->height; })
        .def_prop_ro("samples", [](const PyVisibility& v) { return v.host->samples; }, "Samples per pixel.")
        .def_prop_ro("layers", [](const PyVisibility& v) { return v.host->layers; },
                     "Depth layers per pixel (the Renderer's layers=): with more than 1, ids and depth are\n"
                     "(H, W, layers), each pixel's nearest triangles in order.")
        .def(
            "layer",
            [](const PyVisibility& v, int k) {
                if (v.device.empty())
                    throw Error(Error::Kind::InvalidArgument,
                                "Visibility.layer: this Visibility holds no device buffer (made from arrays, a file "
                                "or several devices); render with layers= on one Renderer");
                PyVisibility out;
                out.device = v.device.layer(k);
                out.device.read(*out.host);
                out.camera = v.camera;
                out.path = v.path;
                out.region = v.region;
                return out;
            },
            nb::arg("k"),
            "Depth layer k (0 <= k < layers) as a one-layer Visibility of its own (a device copy):\n"
            "Renderer.resolve and Renderer.flow read it as they read a plain render.\n\n"
            "Example:\n    vis = clvis.Renderer(device, scene, layers=4).render(camera, 640, 360)\n"
            "    back = renderer.resolve(vis.layer(1), ['barycentrics', 'object'])")
        .def_prop_ro("ids", [](const PyVisibility& v) {
            if (v.ids_out.is_valid()) return v.ids_out;
            const HostVisibility& h = *v.host;
            return nb::cast(numpy_view(h.ids.data(), {std::size_t(h.height), std::size_t(h.width)}, keep_alive(v.host)));
        }, "(H, W) uint32, or (H, W, samples) with several samples per pixel: the same array at every\n"
           "access; read-only unless the caller's (out=).")
        .def_prop_ro("depth", [](const PyVisibility& v) -> nb::object {
            if (v.ids_out.is_valid()) return v.depth_out.is_valid() ? v.depth_out : nb::none();
            const HostVisibility& h = *v.host;
            if (h.depth.empty()) return nb::none();
            return nb::cast(numpy_view(h.depth.data(), {std::size_t(h.height), std::size_t(h.width)}, keep_alive(v.host)));
        }, "(H, W) float32 view depths, as `ids`; None for ids read from a file without depths or out=ids alone.")
        .def_prop_ro("camera", [](const PyVisibility& v) { return v.camera; }, "The camera it was rendered with, or None.")
        .def_prop_ro("path", [](const PyVisibility& v) {
            return v.path ? std::optional<std::string>(to_string(*v.path)) : std::nullopt;
        }, "'raster', 'ray' or 'brute'; None when made from arrays or a file.")
        .def_prop_ro("region", [](const PyVisibility& v) {
            return v.region ? std::optional<std::tuple<int, int, int, int>>(
                                  std::make_tuple(v.region->x, v.region->y, v.region->width, v.region->height))
                            : std::nullopt;
        }, "(x, y, width, height) of the camera's image that it holds, or None for the whole image.")
        .def_prop_ro("timing", [](const PyVisibility& v) { return v.timing; })
        .def_prop_ro("_call_seconds", [](const PyVisibility& v) { return v.call_seconds; },
                     "Seconds of the C++ render and read-back inside render(): bench/python_overhead.py.")
        .def_prop_ro("_call_span_ns", [](const PyVisibility& v) { return std::make_pair(v.call_start_ns, v.call_end_ns); },
                     "(start, end) of that C++ part on time.perf_counter_ns()'s clock: bench/python_overhead.py.")
        .def("__repr__", [](const PyVisibility& v) {
            return "<clvis.Visibility " + std::to_string(v.host->width) + "x" + std::to_string(v.host->height) +
                   (v.path ? std::string(" by ") + to_string(*v.path) : std::string()) + ">";
        });
}

/// A tuned mapping as Python sees it: {"mapping", "source", then each candidate's measured ms, None
/// where not measured (negative)}.
nb::dict choice_dict(const char* mapping, const std::string& source,
                     std::initializer_list<std::pair<const char*, double>> times)
{
    nb::dict d;
    d["mapping"] = mapping;
    d["source"] = source;
    for (const auto& [name, ms] : times) d[name] = ms < 0 ? nb::none() : nb::cast(ms);
    return d;
}

const char* renderer_doc =
    "Keeps a scene (a copy) on a device between frames and answers the visibility question by\n"
    "rasterization ('raster') or by ray casting through a BVH ('ray'); 'brute' tests every triangle.\n"
    "Options as the command line names them: tile (raster tile edge, a power of two; 0 the default),\n"
    "cull ('none', 'back', 'front'), leaf_size and sah_bins (the BVH), bvh_update ('refit', 'rebuild'),\n"
    "raster_atomics ('auto', 'on': 64-bit atomic depth test, 'off': tile ownership; the same keys),\n"
    "raster_mapping (the raster fine stage: 'square' for CPUs, 'pixel' for GPUs, 'auto' measured per\n"
    "device and cached; the same keys), ray_mapping (the ray path's primary rays: 'packet' for CPUs,\n"
    "'single' for GPUs, 'auto' measured per device and cached; the same keys),\n"
    "coverage (the ray paths' inside test: 'watertight', or 'raster-rule': the raster path's own\n"
    "rule, so that ray and raster buffers are bit-identical), samples (per pixel: 1, 2, 4, 8 or 16 at\n"
    "the standard positions; with more than 1, render() returns (H, W, samples) arrays, the samples of\n"
    "a pixel adjacent, and shade() averages them; resolve and ambient occlusion take 1 only).\n"
    "Methods release the GIL while the device works; one Renderer serves one call at a time.\n\n"
    "Example:\n    renderer = clvis.Renderer(clvis.Device('cpu'), scene)\n"
    "    vis = renderer.render(camera, 640, 360, path='ray')";

} // namespace

void bind_render(nb::module_& m)
{
    bind_timing(m);
    bind_visibility(m);
    nb::class_<PyRenderer> r(m, "Renderer", nb::is_weak_referenceable(), renderer_doc);
    r.def(
        "__init__",
        [](PyRenderer* self, const Device& device, PyScene& scene, const nb::kwargs& options) {
            const RenderOptions o = render_options(options, "Renderer");
            unlocked(scene.lock, [&] {
                const auto triangles = std::uint32_t(scene.scene.triangle_count());
                new (self) PyRenderer{Renderer(device, scene.scene, o), {}, triangles, nullptr, {}};
            });
        },
        nb::sig(options_signature("device: Device, scene: Scene")), nb::arg("device"), nb::arg("scene"),
        nb::arg("options"));
    r.def("render", &render,
             nb::sig("def render(self, camera: Camera, width: int, height: int, path: str = 'raster', *, "
                     "region: tuple[int, int, int, int] | None = None, "
                     "out: numpy.typing.NDArray[numpy.uint32] | tuple[numpy.typing.NDArray[numpy.uint32], "
                     "numpy.typing.NDArray[numpy.float32] | None] | None = None) -> Visibility"),
             nb::arg("camera"), nb::arg("width"), nb::arg("height"), nb::arg("path") = "raster", nb::kw_only(),
             nb::arg("region") = nb::none(), nb::arg("out") = nb::none(),
             "Renders a width x height Visibility by `path` ('raster', 'ray' or 'brute').\n\n"
             "region=(x, y, w, h) renders only that rectangle of the image (row 0 on top) into a w x h\n"
             "Visibility, bit-identical to those pixels of the whole render. out=ids or out=(ids, depth)\n"
             "reads back into the caller's writable C-contiguous (H, W) uint32 and float32 arrays (depth\n"
             "may be None: not read); the Visibility's ids and depth are then those arrays.\n\n"
             "Example:\n    ids = np.empty((360, 640), np.uint32)\n    depth = np.empty((360, 640), np.float32)\n"
             "    for camera in cameras:\n        renderer.render(camera, 640, 360, out=(ids, depth))")
        .def(
            "update",
            [](PyRenderer& r, PyScene& s) {
                nb::gil_scoped_release nogil;
                std::scoped_lock both(r.lock.mutex, s.lock.mutex);
                r.renderer.update(s.scene);
            },
            nb::arg("scene"),
            "Uploads the meshes of `scene` (the one given at construction, changed since with\n"
            "set_positions or set_transform) and refits or rebuilds the BVH.")
        .def(
            "prepare", [](PyRenderer& r, const std::string& path) {
                const Path p = path_from_string(path);
                unlocked(r.lock, [&] { r.renderer.prepare(p); });
            },
            nb::arg("path"), "Builds what `path` needs (kernels, BVH) so that the first render is not charged for it.")
        .def_prop_ro("last_frame", [](PyRenderer& r) { return unlocked(r.lock, [&] { return r.renderer.last_frame(); }); })
        .def_prop_ro("bvh_stats", [](PyRenderer& r) { return unlocked(r.lock, [&] { return r.renderer.bvh_stats(); }); })
        .def_prop_ro("device", [](PyRenderer& r) { return unlocked(r.lock, [&] { return r.renderer.device(); }); })
        .def_prop_ro(
            "raster_mapping",
            [](PyRenderer& r) {
                const RasterMappingChoice c = unlocked(r.lock, [&] { return r.renderer.raster_mapping(); });
                return choice_dict(to_string(c.mapping), c.source, {{"square_ms", c.square_ms}, {"pixel_ms", c.pixel_ms}});
            },
            "The raster fine stage's mapping this Renderer runs, as a dict: mapping ('square' or 'pixel'),\n"
            "source ('option', 'forced', 'cache' or 'measured': raster_mapping='auto' measures both once\n"
            "per device and keeps the answer in the cache folder) and the measured square_ms and pixel_ms\n"
            "(None when not measured). Reading it resolves 'auto' when no raster frame has yet.")
        .def_prop_ro(
            "ray_mapping",
            [](PyRenderer& r) {
                const RayMappingChoice c = unlocked(r.lock, [&] { return r.renderer.ray_mapping(); });
                return choice_dict(to_string(c.mapping), c.source, {{"packet_ms", c.packet_ms}, {"single_ms", c.single_ms}});
            },
            "The ray path's primary-ray mapping this Renderer runs, as a dict: mapping ('packet' or\n"
            "'single'), source ('option', 'forced', 'cache' or 'measured', as raster_mapping) and the measured\n"
            "packet_ms and single_ms (None when not measured). Reading it resolves 'auto' when no ray frame\n"
            "has yet.");
    bind_ray_queries(r);
    bind_outputs(r);
    bind_flow(r);
}

} // namespace clvis::python
