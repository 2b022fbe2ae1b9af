// Images from Python: shading on the device into an (H, W, 4) uint8 array, and files through the
// C++ image layer (OpenImageIO): ids as UINT32 TIFF/EXR, depths as EXR, colour as PNG/EXR. The
// file functions exist where the library was built with the image layer (clvis.HAVE_IMAGE_IO).
#include "arrays.hpp"

#include <nanobind/stl/array.h>
#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include <filesystem>

namespace clvis::python {

namespace {

nb::ndarray<nb::numpy, const std::uint8_t> image_array(Image image)
{
    auto owned = std::make_shared<Image>(std::move(image));
    return numpy_view(owned->rgba.data(), {std::size_t(owned->height), std::size_t(owned->width), 4}, keep_alive(owned));
}

nb::ndarray<nb::numpy, const std::uint8_t> shade_buffer(PyRenderer& r, const PyVisibility& vis,
                                                       std::optional<Camera> camera, const std::string& mode,
                                                       std::array<double, 3> light)
{
    const VisibilityBuffer& buffer = device_buffer(vis, "shade");
    ShadeOptions o;
    try {
        o.mode = shade_mode_from_string(mode);
    } catch (const Error& e) {
        throw Error(e.kind(), std::string("shade: ") + e.what()); // "shade: mode: expected one of ..."
    }
    o.light_direction = to_vec3(light);
    const Camera& cam = camera ? *camera : *vis.camera;
    return image_array(unlocked(r.lock, [&] { return shade(r.renderer, buffer, cam, o); }));
}

#if CLVIS_WITH_IMAGE_IO
Image image_of(nb::handle rgba)
{
    nb::object a = nb::module_::import_("numpy").attr("asarray")(rgba);
    const auto ndim = nb::cast<int>(a.attr("ndim"));
    const long channels = ndim == 3 ? nb::cast<long>(a.attr("shape")[2]) : 0;
    if (ndim != 3 || (channels != 3 && channels != 4) || text_of(a.attr("dtype")) != "uint8")
        throw Error(Error::Kind::InvalidArgument, "write_image: expected an (H, W, 4) or (H, W, 3) uint8 array, got shape " +
                                                      text_of(a.attr("shape")) + " of " +
                                                      text_of(a.attr("dtype")));
    auto p = as_host_array<std::uint8_t>(a, {"write_image", "(H, W, C)", 3, channels, true}, "uint8");
    Image image;
    image.height = int(p.shape(0));
    image.width = int(p.shape(1));
    image.rgba.resize(std::size_t(image.width) * image.height * 4, 255);
    for (std::size_t i = 0; i < std::size_t(image.width) * image.height; ++i)
        for (long c = 0; c < channels; ++c) image.rgba[4 * i + c] = p.data()[channels * i + c];
    return image;
}

void bind_files(nb::module_& m)
{
    m.def(
        "write_image",
        [](const std::filesystem::path& path, nb::handle rgba) {
            const Image image = image_of(rgba);
            nb::gil_scoped_release nogil;
            write_image(path.string(), image);
        },
        nb::sig("def write_image(path: str | os.PathLike, rgba: numpy.typing.ArrayLike) -> None"),
        nb::arg("path"), nb::arg("rgba"), "Writes an (H, W, 4) or (H, W, 3) uint8 image (.png, .exr, ...).");
    m.def(
        "write_ids",
        [](const std::filesystem::path& path, const PyVisibility& vis) {
            HostVisibility scratch;
            const HostVisibility& host = host_of(vis, scratch);
            nb::gil_scoped_release nogil;
            write_ids(path.string(), host);
        },
        nb::arg("path"), nb::arg("vis"), "Writes the ids as one UINT32 channel 'id' (.tif, .tiff or .exr).");
    m.def(
        "write_depth",
        [](const std::filesystem::path& path, const PyVisibility& vis) {
            HostVisibility scratch;
            const HostVisibility& host = host_of(vis, scratch);
            if (host.depth.empty()) throw Error(Error::Kind::InvalidArgument, "write_depth: this Visibility has no depths");
            nb::gil_scoped_release nogil;
            write_depth(path.string(), host);
        },
        nb::arg("path"), nb::arg("vis"), "Writes the depths as one FLOAT channel 'Z' (.exr).");
    m.def(
        "read_ids",
        [](const std::filesystem::path& ids, std::optional<std::filesystem::path> depth) {
            PyVisibility v;
            nb::gil_scoped_release nogil;
            *v.host = read_ids(ids.string());
            if (depth) read_depth(depth->string(), *v.host);
            return v;
        },
        nb::arg("ids"), nb::arg("depth") = nb::none(),
        "Reads an id file (and a depth file of the same size) into a Visibility, e.g. for the Referee.");
}
#endif

} // namespace

void bind_image(nb::module_& m)
{
    m.def("shade", &shade_buffer, nb::arg("renderer"), nb::arg("vis"), nb::arg("camera") = nb::none(),
          nb::arg("mode") = "lambert", nb::arg("light_direction") = std::array<double, 3>{0.4, -0.8, -0.6},
          "Shades a Visibility made by `renderer` on its device: 'lambert', 'depth' or 'ids' colours, as an\n"
          "(H, W, 4) uint8 array. `camera` defaults to the one it was rendered with.\n\n"
          "Example:\n    rgba = clvis.shade(renderer, vis)\n    clvis.write_image('bunny.png', rgba)");
#if CLVIS_WITH_IMAGE_IO
    bind_files(m);
#endif
}

} // namespace clvis::python
