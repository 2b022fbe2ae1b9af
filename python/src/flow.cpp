// Flow between two views from Python (include/clvis/flow.hpp): Renderer.flow(a, b) takes two
// Visibility results of this Renderer and the cameras they were rendered with (or others given),
// and items moved between them as {item: 4x4}; the device works with the GIL released.
#include "arrays.hpp"

#include <nanobind/stl/optional.h>

namespace clvis::python {

namespace {

ItemTransforms items_of(nb::handle items, const char* what)
{
    ItemTransforms out;
    if (items.is_none()) return out;
    if (!nb::isinstance<nb::dict>(items))
        throw Error(Error::Kind::InvalidArgument, std::string("Renderer.flow: ") + what + ": expected a dict {item: 4x4}");
    for (auto [key, value] : nb::borrow<nb::dict>(items)) {
        const long long item = nb::cast<long long>(key);
        if (item < 0)
            throw Error(Error::Kind::InvalidArgument,
                        std::string("Renderer.flow: ") + what + ": item " + std::to_string(item) + " is negative");
        const std::string where = std::string("Renderer.flow: ") + what + "[" + std::to_string(item) + "]";
        out[std::size_t(item)] = to_mat4(value, where.c_str());
    }
    return out;
}

/// A bool array of `shape` from the masks at channel `channel` of the flow buffer.
nb::object mask(const std::vector<float>& flow, std::size_t h, std::size_t w, int channel)
{
    auto owner = std::make_shared<std::unique_ptr<bool[]>>(new bool[h * w]);
    for (std::size_t p = 0; p < h * w; ++p) (*owner)[p] = flow[p * flow_channels + std::size_t(channel)] == 1.0f;
    const bool* data = owner->get();
    return nb::cast(nb::ndarray<nb::numpy, const bool>(data, {h, w}, keep_alive(owner)));
}

nb::dict flow_between(PyRenderer& r, const PyVisibility& a, const PyVisibility& b, nb::handle items_a,
                      nb::handle items_b, std::optional<Camera> camera_a, std::optional<Camera> camera_b)
{
    const VisibilityBuffer& va = device_buffer(a, "flow");
    const VisibilityBuffer& vb = device_buffer(b, "flow");
    if (!camera_a) camera_a = a.camera;
    if (!camera_b) camera_b = b.camera;
    if (!camera_a || !camera_b)
        throw Error(Error::Kind::InvalidArgument, "Renderer.flow: a Visibility without its camera: give camera_a, camera_b");
    const ItemTransforms ia = items_of(items_a, "items_a"), ib = items_of(items_b, "items_b");
    std::vector<float> values;
    unlocked(r.lock, [&] { flow(r.renderer, va, *camera_a, vb, *camera_b, ia, ib).read(values); });
    const auto h = std::size_t(va.height()), w = std::size_t(va.width());
    std::vector<float> xy(h * w * 2);
    for (std::size_t p = 0; p < h * w; ++p) {
        xy[p * 2] = values[p * flow_channels];
        xy[p * 2 + 1] = values[p * flow_channels + 1];
    }
    nb::dict out;
    out["valid"] = mask(values, h, w, 2);
    out["occluded"] = mask(values, h, w, 3);
    out["flow"] = owned_array(std::move(xy), {h, w, 2});
    return out;
}

} // namespace

void bind_flow(nb::class_<PyRenderer>& r)
{
    r.def("flow", &flow_between, nb::arg("a"), nb::arg("b"), nb::arg("items_a") = nb::none(),
          nb::arg("items_b") = nb::none(), nb::arg("camera_a") = nb::none(), nb::arg("camera_b") = nb::none(),
          nb::sig("def flow(self, a: Visibility, b: Visibility, items_a: dict[int, numpy.typing.ArrayLike] | None = None, "
                  "items_b: dict[int, numpy.typing.ArrayLike] | None = None, camera_a: Camera | None = None, "
                  "camera_b: Camera | None = None) -> dict[str, numpy.typing.NDArray]"),
          "The flow from view `a` to view `b` (two Visibility results of this Renderer, one sample per pixel,\n"
          "one size), computed on the device (CONVENTIONS.md 'Motion between views (flow)'): a dict with\n"
          "'flow' (H, W, 2) float32, where each sample of `a` lands in `b` minus where it is, in raster px\n"
          "(x right, y down; NaN for the background and invalid samples), 'valid' (H, W) bool (inside b's\n"
          "image and depth range) and 'occluded' (H, W) bool (valid, and b sees something nearer there).\n"
          "The cameras are those the results were rendered with unless camera_a, camera_b are given.\n"
          "Objects that move: the triangles are placed as this Renderer's scene (as made or last update()d)\n"
          "with items_a / items_b ({item: 4x4}) replacing the transforms of the items they name.\n\n"
          "Example:\n    a = renderer.render(cam, 640, 360)\n    scene.set_transform(1, moved); renderer.update(scene)\n"
          "    b = renderer.render(cam, 640, 360)\n    f = renderer.flow(a, b, items_a={1: placed})  # the scene is at b");
}

} // namespace clvis::python
