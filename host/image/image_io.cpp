// Image files through OpenImageIO: id buffers as one UINT32 channel "id" (TIFF or EXR), never
// through float; depth as one FLOAT channel "Z" (EXR); colour images (PNG, EXR, ...). Row 0 is the
// top row of every file, as in memory.
#include "lower_case.hpp"

#include <clvis/error.hpp>
#include <clvis/image_io.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <memory>

namespace clvis {

namespace {

[[noreturn]] void io_error(const std::string& path, const std::string& what)
{
    throw Error(Error::Kind::Io, path + ": " + what);
}

void write_channels(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                    OIIO::TypeDesc type, const void* pixels)
{
    if (width <= 0 || height <= 0) io_error(path, "nothing to write (empty buffer)");
    auto out = OIIO::ImageOutput::create(path);
    if (!out) io_error(path, "cannot write this format: " + OIIO::geterror());
    OIIO::ImageSpec spec(width, height, int(channels.size()), type);
    spec.channelnames = channels;
    if (type == OIIO::TypeDesc::UINT32 || type == OIIO::TypeDesc::FLOAT) spec.attribute("compression", "zip");
    if (!out->open(path, spec)) io_error(path, "cannot open for writing: " + out->geterror());
    if (!out->write_image(type, pixels)) io_error(path, "write failed: " + out->geterror());
    if (!out->close()) io_error(path, "close failed: " + out->geterror());
}

/// Opens `path` and checks it is a single-channel image of `width` x `height` (when > 0).
std::unique_ptr<OIIO::ImageInput> open_single_channel(const std::string& path, const char* what)
{
    auto in = OIIO::ImageInput::open(path);
    if (!in) io_error(path, std::string("cannot read ") + what + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.nchannels != 1)
        io_error(path, std::string(what) + " must have one channel, this file has " + std::to_string(spec.nchannels));
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1) io_error(path, "not a 2D image");
    return in;
}

/// Reads the one channel of `in` as `type` into `out` (width x height values) and closes it.
void read_channel(OIIO::ImageInput& in, const std::string& path, OIIO::TypeDesc type, void* out)
{
    if (!in.read_image(0, 0, 0, 1, type, out)) io_error(path, "read failed: " + in.geterror());
    in.close();
}

} // namespace

void write_ids(const std::string& path, const HostVisibility& vis)
{
    std::string ext = detail::lower_extension(path);
    if (ext != ".tif" && ext != ".tiff" && ext != ".exr")
        io_error(path, "id buffers are written as .tif, .tiff or .exr");
    if (vis.ids.size() != std::size_t(vis.width) * std::size_t(vis.height))
        io_error(path, "the id array does not match the image size");
    write_channels(path, vis.width, vis.height, {"id"}, OIIO::TypeDesc::UINT32, vis.ids.data());
}

void write_depth(const std::string& path, const HostVisibility& vis)
{
    if (detail::lower_extension(path) != ".exr") io_error(path, "depth buffers are written as .exr");
    if (vis.depth.size() != std::size_t(vis.width) * std::size_t(vis.height))
        io_error(path, "the depth array does not match the image size");
    write_channels(path, vis.width, vis.height, {"Z"}, OIIO::TypeDesc::FLOAT, vis.depth.data());
}

void write_float_channels(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                          const std::vector<float>& pixels)
{
    if (detail::lower_extension(path) != ".exr") io_error(path, "float channels are written as .exr");
    if (channels.empty() || pixels.size() != std::size_t(width) * std::size_t(height) * channels.size())
        io_error(path, "the array does not match the image size and channels");
    write_channels(path, width, height, channels, OIIO::TypeDesc::FLOAT, pixels.data());
}

std::vector<float> read_float_channels(const std::string& path, int* width, int* height,
                                       std::vector<std::string>* channels)
{
    auto in = OIIO::ImageInput::open(path);
    if (!in) io_error(path, std::string("cannot read: ") + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1) io_error(path, "not a 2D image");
    std::vector<float> pixels(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
        io_error(path, "read failed: " + in->geterror());
    *width = spec.width;
    *height = spec.height;
    if (channels) *channels = spec.channelnames;
    in->close();
    return pixels;
}

HostVisibility read_ids(const std::string& path)
{
    auto in = open_single_channel(path, "an id buffer");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.format != OIIO::TypeDesc::UINT32)
        io_error(path, "an id buffer must hold 32-bit unsigned integers, this file holds " +
                           std::string(spec.format.c_str()));
    HostVisibility vis;
    vis.width = spec.width;
    vis.height = spec.height;
    vis.ids.resize(std::size_t(spec.width) * std::size_t(spec.height));
    read_channel(*in, path, OIIO::TypeDesc::UINT32, vis.ids.data());
    return vis;
}

void read_depth(const std::string& path, HostVisibility& vis)
{
    auto in = open_single_channel(path, "a depth buffer");
    const OIIO::ImageSpec& spec = in->spec();
    if ((vis.width || vis.height) && (spec.width != vis.width || spec.height != vis.height))
        io_error(path, "depth is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                           ", the ids are " + std::to_string(vis.width) + "x" + std::to_string(vis.height));
    vis.width = spec.width;
    vis.height = spec.height;
    vis.depth.resize(std::size_t(spec.width) * std::size_t(spec.height));
    read_channel(*in, path, OIIO::TypeDesc::FLOAT, vis.depth.data());
}

void write_image(const std::string& path, const Image& image)
{
    if (image.width <= 0 || image.height <= 0 ||
        image.rgba.size() != std::size_t(image.width) * std::size_t(image.height) * 4)
        io_error(path, "the image is empty or its pixels do not match its size");
    auto out = OIIO::ImageOutput::create(path);
    if (!out) io_error(path, "cannot write this format: " + OIIO::geterror());
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
    spec.alpha_channel = 3;
    if (!out->open(path, spec)) io_error(path, "cannot open for writing: " + out->geterror());
    if (!out->write_image(OIIO::TypeDesc::UINT8, image.rgba.data())) io_error(path, "write failed: " + out->geterror());
    if (!out->close()) io_error(path, "close failed: " + out->geterror());
}

} // namespace clvis
