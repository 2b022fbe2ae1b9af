// clvis render's named attributes, object ids and normal space (CONVENTIONS.md "Vertex
// attributes", "Object ids"): --attributes FILE.exr (every attribute the scene has, channels
// NAME.x ..), --objects FILE (one uint32 channel "object"), --normals-space world|camera. Resolved
// with the other attributes in one call, only when asked; with depth layers once per layer, each
// file holding every layer's channels as L{k}.<channel> (layer_channels).
#pragma once

#include <clvis/clvis.hpp>

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace clvis::cli {

struct CornerOutputs {
    std::string attributes;             ///< --attributes FILE (.exr)
    std::string objects;                ///< --objects FILE (.tif, .tiff, .exr)
    std::string normals_space = "world"; ///< --normals-space
    std::vector<AttributeInfo> scene;   ///< the scene's attributes, once it is loaded

    void add_to(CLI::App& cmd);
    /// Refuses (naming the flag) --objects with several samples per pixel or with --devices or
    /// --distribute; --attributes is refused there as every float output is.
    void check(int samples, bool spread) const;
    /// Reads the scene's attributes; refuses --attributes for a scene without any, naming it.
    void loaded(const Scene& scene);
    /// Adds what the flags ask to `request`.
    void request(AttributeRequest& request) const;
    /// Writes --attributes and --objects of `resolved`, one AttributeBuffers per depth layer
    /// (layer_channels' names when there are several), under the names `file_name` gives.
    void write(const std::vector<AttributeBuffers>& resolved, int width, int height,
               const std::function<std::string(const std::string&)>& file_name) const;
};

/// The channels of a file of `layers` depth layers (CONVENTIONS.md "Depth layers"): `names` as
/// they are for one layer; else L0.<name> .. for layer 0, then L1.<name> .., and so on.
std::vector<std::string> layer_channels(const std::vector<std::string>& names, int layers);

/// Every layer's `per_pixel` values of each pixel side by side, layer 0 first, as layer_channels
/// names them (one layer: its values unchanged).
template <class T>
std::vector<T> interleave_layers(const std::vector<std::vector<T>>& layers, std::size_t per_pixel)
{
    if (layers.size() == 1) return layers[0];
    const std::size_t pixels = layers.empty() || per_pixel == 0 ? 0 : layers[0].size() / per_pixel;
    std::vector<T> all(pixels * per_pixel * layers.size());
    for (std::size_t k = 0; k < layers.size(); ++k)
        for (std::size_t i = 0; i < pixels; ++i)
            for (std::size_t c = 0; c < per_pixel; ++c)
                all[(i * layers.size() + k) * per_pixel + c] = layers[k][i * per_pixel + c];
    return all;
}

} // namespace clvis::cli
