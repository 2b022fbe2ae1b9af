// Image files, through OpenImageIO (the clvis::image layer). Id buffers are one UINT32 channel
// named "id" in TIFF or OpenEXR, never passed through float; depth buffers one FLOAT channel "Z"
// in OpenEXR; colour images PNG or EXR. Row 0 is the top row in every file. A buffer of N > 1
// samples per pixel (HostVisibility::samples) has N channels "id0" .. "id{N-1}" and "Z0" ..
// "Z{N-1}", the samples of a pixel adjacent as in memory.
#pragma once

#include <clvis/host_visibility.hpp>
#include <clvis/image.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace clvis {

/// Writes the ids of `vis` (.tif, .tiff or .exr). Throws Error(Io) naming the file.
void write_ids(const std::string& path, const HostVisibility& vis);
/// Writes the depths of `vis` (.exr).
void write_depth(const std::string& path, const HostVisibility& vis);
/// Reads an id buffer: fills width, height, samples (its channels: 1, 2, 4, 8 or 16) and ids
/// (depth left empty).
HostVisibility read_ids(const std::string& path);
/// Reads a depth buffer into `vis.depth` (width, height and samples must match when already set).
void read_depth(const std::string& path, HostVisibility& vis);
/// Writes channels.size() float channels per pixel, adjacent (.exr): barycentrics "u", "v";
/// positions and normals "x", "y", "z".
void write_float_channels(const std::string& path, int width, int height, const std::vector<std::string>& channels,
                          const std::vector<float>& pixels);
/// Writes object ids (CONVENTIONS.md "Object ids"): one uint32 channel "object" (.tif, .tiff or
/// .exr, as id buffers), width x height values, row 0 on top.
void write_object_ids(const std::string& path, int width, int height, const std::vector<std::uint32_t>& objects);
/// Object ids of `layers` depth layers (CONVENTIONS.md "Depth layers"), the layers of a pixel
/// adjacent: uint32 channels "L0.object" .. "L{K-1}.object" (a TIFF keeps them in layer order);
/// one layer is the file above.
void write_object_ids(const std::string& path, int width, int height, int layers,
                      const std::vector<std::uint32_t>& objects);
/// Reads every channel of an image as float, adjacent per pixel, with its size and channel names.
std::vector<float> read_float_channels(const std::string& path, int* width, int* height,
                                       std::vector<std::string>* channels = nullptr);
/// Writes a colour image (.png, .exr, or anything OpenImageIO writes). An extension of no
/// writer is Error(Io) listing image_extensions().
void write_image(const std::string& path, const Image& image);

/// The extensions (lowercase, no dot) of the files each writer takes: id buffers, depth
/// buffers, and colour images (every format OpenImageIO writes here).
std::vector<std::string> id_extensions();
std::vector<std::string> depth_extensions();
std::vector<std::string> image_extensions();

} // namespace clvis
