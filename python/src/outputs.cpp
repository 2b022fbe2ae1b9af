// Visibility outputs from Python as Renderer methods: attributes resolved on the device
// (barycentrics, position, normals) as (H, W, C) arrays, the visible set of one or many views as
// sorted ids, and batches of views rendered in one call as stacked (V, H, W) arrays. The device
// works with the GIL released; results own their storage.
#include "arrays.hpp"

#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstdlib>

namespace clvis::python {

namespace {

bool builtin_name(const std::string& name)
{
    for (const std::string& n : option_names<Attribute>())
        if (n == name) return true;
    return false;
}

nb::dict resolve_attributes(PyRenderer& r, const PyVisibility& vis, const std::vector<std::string>& names,
                            const std::string& normals_space)
{
    const VisibilityBuffer& buffer = device_buffer(vis, "resolve");
    AttributeRequest request;
    try {
        request.normal_space = normal_space_from_string(normals_space);
    } catch (const Error& e) {
        throw Error(e.kind(), std::string("resolve: normals_space: ") + e.what());
    }
    // The built-in attributes by name, 'object', and any other name as a named corner attribute
    // (resolve() refuses one the scene lacks, listing those it has).
    for (const std::string& name : names) {
        if (name == "object") {
            request.object = true;
        } else if (builtin_name(name)) {
            const Attribute a = attribute_from_string(name);
            request.barycentrics |= a == Attribute::Barycentrics;
            request.position |= a == Attribute::Position;
            request.normal |= a == Attribute::Normal;
            request.smooth_normal |= a == Attribute::SmoothNormal;
        } else {
            request.named.push_back(name);
        }
    }
    if (!request.any()) throw Error(Error::Kind::InvalidArgument, "resolve: no attribute asked for");
    std::vector<std::vector<float>> values(names.size());
    std::vector<int> components(names.size(), 0);
    std::vector<std::uint32_t> objects;
    unlocked(r.lock, [&] {
        const AttributeBuffers resolved = resolve(r.renderer, buffer, *vis.camera, request);
        for (std::size_t k = 0; k < names.size(); ++k) {
            if (names[k] == "object") {
                if (objects.empty()) resolved.read_objects(objects);
            } else if (builtin_name(names[k])) {
                const Attribute a = attribute_from_string(names[k]);
                resolved.read(a, values[k]);
                components[k] = channels(a);
            } else {
                resolved.read(names[k], values[k]);
                components[k] = -resolved.components(names[k]); // named: one component gives (H, W)
            }
        }
    });
    nb::dict out;
    const auto h = std::size_t(buffer.height()), w = std::size_t(buffer.width());
    for (std::size_t k = 0; k < names.size(); ++k) { // keyed by the names asked for ('smooth_normal')
        if (out.contains(names[k].c_str())) continue;
        if (names[k] == "object") {
            out["object"] = owned_array(std::move(objects), {h, w});
        } else if (components[k] == -1) {
            out[names[k].c_str()] = owned_array(std::move(values[k]), {h, w});
        } else {
            out[names[k].c_str()] = owned_array(std::move(values[k]), {h, w, std::size_t(std::abs(components[k]))});
        }
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
          nb::arg("normals_space") = "world",
          "Attributes of the visible triangle per pixel of `visibility` (rendered by this Renderer), resolved\n"
          "on the device: a dict of (H, W, C) float32 arrays named by `attributes`: 'barycentrics' (u, v with\n"
          "P = (1-u-v) v0 + u v1 + v v2; background 0, 0), 'position' (world, background NaN), 'normal' (unit\n"
          "geometric, cross(v1 - v0, v2 - v0)) and 'smooth_normal' (interpolated vertex normals), in world\n"
          "axes or, with normals_space='camera', the camera's (x = r, y = u, z = -f); 'object' (uint32 (H, W):\n"
          "the item index of each pixel's triangle, background 0xFFFFFFFF); and any named vertex attribute\n"
          "of the scene ('uv' (H, W, 2), 'color' (H, W, 4), a one-component one (H, W)), interpolated with\n"
          "the exact barycentrics, NaN on the background and where a mesh lacks it.\n\n"
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
