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

std::vector<std::string> split(const std::string& text, char sep)
{
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t end = text.find(sep, start);
        if (end == std::string::npos) end = text.size();
        if (end > start) out.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

std::string listed(const std::vector<std::string>& extensions)
{
    std::string s;
    for (const auto& e : extensions) s += (s.empty() ? "." : ", .") + e;
    return s;
}

/// Whether `path`'s extension (any case) is one of `extensions` (lowercase, no dot).
bool has_extension(const std::string& path, const std::vector<std::string>& extensions)
{
    std::string ext = detail::lower_extension(path);
    return !ext.empty() && std::find(extensions.begin(), extensions.end(), ext.substr(1)) != extensions.end();
}

} // namespace

std::vector<std::string> id_extensions() { return {"exr", "tif", "tiff"}; }
std::vector<std::string> depth_extensions() { return {"exr"}; }

std::vector<std::string> image_extensions()
{
    // OpenImageIO's writers, and their extensions from its table "format:ext,ext;format:...";
    // "null" and "term" write no file.
    std::vector<std::string> writers = split(OIIO::get_string_attribute("output_format_list"), ',');
    std::vector<std::string> out;
    for (const std::string& entry : split(OIIO::get_string_attribute("extension_list"), ';')) {
        std::size_t colon = entry.find(':');
        std::string format = entry.substr(0, colon);
        if (colon == std::string::npos || format == "null" || format == "term" ||
            std::find(writers.begin(), writers.end(), format) == writers.end())
            continue;
        for (const std::string& ext : split(entry.substr(colon + 1), ',')) out.push_back(ext);
    }
    std::sort(out.begin(), out.end());
    return out;
}

void write_ids(const std::string& path, const HostVisibility& vis)
{
    if (!has_extension(path, id_extensions())) io_error(path, "id buffers are written as " + listed(id_extensions()));
    if (vis.ids.size() != std::size_t(vis.width) * std::size_t(vis.height))
        io_error(path, "the id array does not match the image size");
    write_channels(path, vis.width, vis.height, {"id"}, OIIO::TypeDesc::UINT32, vis.ids.data());
}

void write_depth(const std::string& path, const HostVisibility& vis)
{
    if (!has_extension(path, depth_extensions()))
        io_error(path, "depth buffers are written as " + listed(depth_extensions()));
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
    if (!has_extension(path, image_extensions()))
        io_error(path, "cannot write images of this kind; the formats written are " + listed(image_extensions()));
    auto out = OIIO::ImageOutput::create(path);
    if (!out) io_error(path, "cannot write this format: " + OIIO::geterror());
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
    spec.alpha_channel = 3;
    if (!out->open(path, spec)) io_error(path, "cannot open for writing: " + out->geterror());
    if (!out->write_image(OIIO::TypeDesc::UINT8, image.rgba.data())) io_error(path, "write failed: " + out->geterror());
    if (!out->close()) io_error(path, "close failed: " + out->geterror());
}

} // namespace clvis
