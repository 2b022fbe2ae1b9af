// Visibility outputs from Python as Renderer methods: attributes resolved on the device
// (barycentrics, position, normals) as (H, W, C) arrays, the visible set of one or many views as
// sorted ids, and batches of views rendered in one call as stacked (V, H, W) arrays. The device
// works with the GIL released; results own their storage.
#include "arrays.hpp"

#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

namespace clvis::python {

namespace {

Attribute attribute_named(const std::string& name)
{
    try {
        return attribute_from_string(name);
    } catch (const Error& e) {
        throw Error(e.kind(), std::string("resolve: ") + e.what());
    }
}

nb::dict resolve_attributes(PyRenderer& r, const PyVisibility& vis, const std::vector<std::string>& names)
{
    const VisibilityBuffer& buffer = device_buffer(vis, "resolve");
    AttributeRequest request;
    std::vector<Attribute> wanted;
    for (const std::string& name : names) {
        const Attribute a = attribute_named(name);
        wanted.push_back(a);
        request.barycentrics |= a == Attribute::Barycentrics;
        request.position |= a == Attribute::Position;
        request.normal |= a == Attribute::Normal;
        request.smooth_normal |= a == Attribute::SmoothNormal;
    }
    if (!request.any()) throw Error(Error::Kind::InvalidArgument, "resolve: no attribute asked for");
    std::vector<std::vector<float>> values(attribute_count);
    unlocked(r.lock, [&] {
        const AttributeBuffers resolved = resolve(r.renderer, buffer, *vis.camera, request);
        for (const Attribute a : wanted) resolved.read(a, values[std::size_t(a)]);
    });
    nb::dict out;
    const auto h = std::size_t(buffer.height()), w = std::size_t(buffer.width());
    for (std::size_t k = 0; k < names.size(); ++k) { // keyed by the names asked for ('smooth_normal')
        const Attribute a = wanted[k];
        auto& v = values[std::size_t(a)];
        if (!v.empty()) out[names[k].c_str()] = owned_array(std::move(v), {h, w, std::size_t(channels(a))});
    }
    return out;
}

nb::object visible_ids(PyRenderer& r, nb::handle views)
{
    std::vector<const PyVisibility*> list;
    if (nb::isinstance<PyVisibility>(views)) {
        list.push_back(&nb::cast<const PyVisibility&>(views));
    } else {
        for (nb::handle v : views) list.push_back(&nb::cast<const PyVisibility&>(v));
    }
    for (const PyVisibility* v : list) device_buffer(*v, "visible_ids", false);
    std::vector<std::uint32_t> ids;
    unlocked(r.lock, [&] {
        VisibleSet set(r.renderer.device(), r.triangles);
        for (const PyVisibility* v : list) set.mark(v->device);
        set.read_ids(ids);
    });
    const std::size_t n = ids.size();
    return owned_array(std::move(ids), {n});
}

nb::tuple render_views(PyRenderer& r, const std::vector<Camera>& cameras, int width, int height,
                       const std::string& path_name)
{
    const Path path = path_from_string(path_name);
    if (cameras.empty()) throw Error(Error::Kind::InvalidArgument, "render_views: no cameras");
    const std::size_t pixels = std::size_t(width > 0 ? width : 0) * std::size_t(height > 0 ? height : 0);
    std::vector<std::uint32_t> ids;
    std::vector<float> depth;
    unlocked(r.lock, [&] {
        VisibilityBatch batch(r.renderer.device(), int(cameras.size()), width, height);
        clvis::render_views(r.renderer, cameras, path, batch);
        ids.resize(pixels * cameras.size());
        depth.resize(pixels * cameras.size());
        for (int v = 0; v < batch.views(); ++v)
            batch.view(v).read(ids.data() + std::size_t(v) * pixels, depth.data() + std::size_t(v) * pixels);
    });
    const std::size_t views = cameras.size(), h = std::size_t(height), w = std::size_t(width);
    return nb::make_tuple(owned_array(std::move(ids), {views, h, w}), owned_array(std::move(depth), {views, h, w}));
}

} // namespace

void bind_outputs(nb::class_<PyRenderer>& r)
{
    r.def("resolve", &resolve_attributes, nb::arg("visibility"),
          nb::arg("attributes") = std::vector<std::string>{"barycentrics", "position", "normal"},
          "Attributes of the visible triangle per pixel of `visibility` (rendered by this Renderer), resolved\n"
          "on the device: a dict of (H, W, C) float32 arrays named by `attributes`: 'barycentrics' (u, v with\n"
          "P = (1-u-v) v0 + u v1 + v v2; background 0, 0), 'position' (world, background NaN), 'normal' (unit\n"
          "geometric, cross(v1 - v0, v2 - v0)) and 'smooth_normal' (interpolated vertex normals).\n\n"
          "Example:\n    vis = renderer.render(camera, 640, 360)\n"
          "    position = renderer.resolve(vis, ['position'])['position']  # (360, 640, 3)")
        .def("visible_ids", &visible_ids, nb::sig("def visible_ids(self, views: Visibility | typing.Sequence[Visibility]) -> numpy.typing.NDArray[numpy.uint32]"),
             nb::arg("views"),
             "The ids of the triangles that cover at least one pixel of `views` (a Visibility rendered by this\n"
             "Renderer, or a list of them), ascending, as a uint32 array; computed on the device.")
        .def("render_views", &render_views, nb::arg("cameras"), nb::arg("width"), nb::arg("height"),
             nb::arg("path") = "raster",
             "Renders a batch of views of one size in one call (the ray path in one launch): (ids, depth) as\n"
             "(V, H, W) uint32 and float32 arrays, view v equal to render(cameras[v], width, height, path).");
}

} // namespace clvis::python
