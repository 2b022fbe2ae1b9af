// Image files through OpenImageIO: id buffers as one UINT32 channel "id" (TIFF or EXR), never
// through float; depth as one FLOAT channel "Z" (EXR); colour images (PNG, EXR, ...). Row 0 is the
// top row of every file, as in memory. A buffer of N > 1 samples per pixel has N channels, "id0"
// .. "id{N-1}" and "Z0" .. "Z{N-1}", read back by name (OpenEXR keeps channels sorted by name).
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

/// The channels of a buffer of `samples` per pixel: `base` alone, or base0 .. base{samples-1}.
std::vector<std::string> sample_channels(const std::string& base, int samples)
{
    if (samples == 1) return {base};
    std::vector<std::string> names;
    for (int k = 0; k < samples; ++k) names.push_back(base + std::to_string(k));
    return names;
}

/// The channels of a buffer's ids or depths ("id" or "Z"): with depth layers L0.<base> ..
/// L{K-1}.<base> (one sample per pixel), else sample_channels.
std::vector<std::string> buffer_channels(const std::string& base, const HostVisibility& vis)
{
    if (vis.layers <= 1) return sample_channels(base, vis.samples);
    std::vector<std::string> names;
    for (int k = 0; k < vis.layers; ++k) names.push_back("L" + std::to_string(k) + "." + base);
    return names;
}

/// Opens `path` and checks it is an image of 1, 2, 4, 8 or 16 channels (samples per pixel).
/// Depth layers: K when the channels of `spec` are exactly L0.<base> .. L{K-1}.<base> (any
/// order, K in 1 .. 8), else 0.
int layered_channels(const OIIO::ImageSpec& spec, const std::string& base)
{
    int n = spec.nchannels;
    if (n < 1 || n > 8 || spec.channelnames.size() != std::size_t(n)) return 0;
    std::vector<bool> seen(std::size_t(n), false);
    for (const std::string& name : spec.channelnames) {
        int k = -1;
        for (int j = 0; j < n; ++j)
            if (name == "L" + std::to_string(j) + "." + base) k = j;
        if (k < 0 || seen[std::size_t(k)]) return 0;
        seen[std::size_t(k)] = true;
    }
    return n;
}

std::unique_ptr<OIIO::ImageInput> open_samples(const std::string& path, const char* what, const std::string& base)
{
    auto in = OIIO::ImageInput::open(path);
    if (!in) io_error(path, std::string("cannot read ") + what + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    int n = spec.nchannels;
    if (n != 1 && n != 2 && n != 4 && n != 8 && n != 16 && layered_channels(spec, base) == 0)
        io_error(path, std::string(what) + " must have 1, 2, 4, 8 or 16 channels (samples per pixel), this file has " +
                           std::to_string(n));
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1) io_error(path, "not a 2D image");
    return in;
}

/// Reads every channel of `in` as `type` (of `size` bytes) into `out`, the samples of a pixel
/// adjacent, and closes it. Channels named base0 .. base{N-1} go to their sample whatever their
/// order in the file; a file whose names are not those (a TIFF keeps none) is taken in file order.
void read_samples(OIIO::ImageInput& in, const std::string& path, const std::string& base, OIIO::TypeDesc type,
                  std::size_t size, void* out)
{
    const OIIO::ImageSpec& spec = in.spec();
    std::size_t n = std::size_t(spec.nchannels), pixels = std::size_t(spec.width) * std::size_t(spec.height);
    std::vector<unsigned char> raw(pixels * n * size);
    if (!in.read_image(0, 0, 0, int(n), type, raw.data())) io_error(path, "read failed: " + in.geterror());
    in.close();
    std::vector<std::size_t> sample(n);
    std::vector<bool> seen(n, false);
    bool named = n > 1;
    for (std::size_t c = 0; c < n && named; ++c) {
        std::string name = c < spec.channelnames.size() ? spec.channelnames[c] : std::string();
        std::size_t k = n;
        for (std::size_t j = 0; j < n; ++j)
            if (name == base + std::to_string(j) || name == "L" + std::to_string(j) + "." + base) k = j;
        named = k < n && !seen[k];
        if (named) seen[k] = true;
        sample[c] = named ? k : c;
    }
    for (std::size_t c = 0; c < n; ++c)
        if (!named) sample[c] = c;
    auto* dst = static_cast<unsigned char*>(out);
    for (std::size_t p = 0; p < pixels; ++p)
        for (std::size_t c = 0; c < n; ++c)
            std::copy_n(raw.data() + (p * n + c) * size, size, dst + (p * n + sample[c]) * size);
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
    if (vis.ids.size() != std::size_t(vis.width) * std::size_t(vis.height) * std::size_t(vis.samples) *
                              std::size_t(vis.layers) ||
        (vis.layers > 1 && vis.samples != 1))
        io_error(path, "the id array does not match the image size, samples and layers");
    write_channels(path, vis.width, vis.height, buffer_channels("id", vis), OIIO::TypeDesc::UINT32, vis.ids.data());
}

void write_depth(const std::string& path, const HostVisibility& vis)
{
    if (!has_extension(path, depth_extensions()))
        io_error(path, "depth buffers are written as " + listed(depth_extensions()));
    if (vis.depth.size() != std::size_t(vis.width) * std::size_t(vis.height) * std::size_t(vis.samples) *
                                std::size_t(vis.layers) ||
        (vis.layers > 1 && vis.samples != 1))
        io_error(path, "the depth array does not match the image size, samples and layers");
    write_channels(path, vis.width, vis.height, buffer_channels("Z", vis), OIIO::TypeDesc::FLOAT, vis.depth.data());
}

void write_object_ids(const std::string& path, int width, int height, const std::vector<std::uint32_t>& objects)
{
    write_object_ids(path, width, height, 1, objects);
}

void write_object_ids(const std::string& path, int width, int height, int layers,
                      const std::vector<std::uint32_t>& objects)
{
    if (!has_extension(path, id_extensions())) io_error(path, "object ids are written as " + listed(id_extensions()));
    if (layers < 1 || objects.size() != std::size_t(width) * std::size_t(height) * std::size_t(layers))
        io_error(path, "the object array does not match the image size and layers");
    std::vector<std::string> channels{"object"};
    if (layers > 1) channels.clear();
    for (int k = 0; k < layers && layers > 1; ++k) channels.push_back("L" + std::to_string(k) + ".object");
    write_channels(path, width, height, channels, OIIO::TypeDesc::UINT32, objects.data());
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
    auto in = open_samples(path, "an id buffer", "id");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.format != OIIO::TypeDesc::UINT32)
        io_error(path, "an id buffer must hold 32-bit unsigned integers, this file holds " +
                           std::string(spec.format.c_str()));
    HostVisibility vis;
    vis.width = spec.width;
    vis.height = spec.height;
    vis.samples = spec.nchannels;
    if (int layers = layered_channels(spec, "id")) { // depth layers: L0.id .. (one sample per pixel)
        vis.samples = 1;
        vis.layers = layers;
    }
    vis.ids.resize(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    read_samples(*in, path, "id", OIIO::TypeDesc::UINT32, sizeof(std::uint32_t), vis.ids.data());
    return vis;
}

void read_depth(const std::string& path, HostVisibility& vis)
{
    auto in = open_samples(path, "a depth buffer", "Z");
    const OIIO::ImageSpec& spec = in->spec();
    if ((vis.width || vis.height) &&
        (spec.width != vis.width || spec.height != vis.height || spec.nchannels != vis.samples * vis.layers))
        io_error(path, "depth is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " with " +
                           std::to_string(spec.nchannels) + " sample(s) per pixel, the ids are " +
                           std::to_string(vis.width) + "x" + std::to_string(vis.height) + " with " +
                           std::to_string(vis.samples));
    vis.width = spec.width;
    vis.height = spec.height;
    if (int layers = layered_channels(spec, "Z")) {
        vis.samples = 1;
        vis.layers = layers;
    } else {
        vis.samples = spec.nchannels;
        vis.layers = 1;
    }
    vis.depth.resize(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    read_samples(*in, path, "Z", OIIO::TypeDesc::FLOAT, sizeof(float), vis.depth.data());
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
