// A visibility buffer read back to the host: per pixel a triangle id and a view depth, row 0 on
// top. Plain data without OpenCL, for the referee, image files and the caller's own code.
#pragma once

#include <cstdint>
#include <vector>

namespace clvis {

/// The key of a background pixel: (as_uint(+inf) << 32) | background_id.
constexpr std::uint64_t background_key = (std::uint64_t(0x7F800000u) << 32) | 0xFFFFFFFFull;

/// A visibility buffer read back to the host.
struct HostVisibility {
    int width = 0, height = 0;
    int samples = 1;                ///< per pixel (RenderOptions::samples)
    std::vector<std::uint32_t> ids; ///< width * height * samples * layers, row 0 on top, the samples of a
                                    ///< pixel adjacent, the layers of a sample adjacent; background_id where empty
    std::vector<float> depth;       ///< view depth; +inf where empty
    int layers = 1;                 ///< depth layers per sample (RenderOptions::layers), nearest first

    std::size_t index(int x, int y, int sample = 0, int layer = 0) const
    {
        return ((std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(samples) + std::size_t(sample)) *
                   std::size_t(layers) +
               std::size_t(layer);
    }
    std::uint32_t id(int x, int y, int sample = 0, int layer = 0) const { return ids[index(x, y, sample, layer)]; }
    float depth_at(int x, int y, int sample = 0, int layer = 0) const { return depth[index(x, y, sample, layer)]; }
    /// Layer `layer` alone, as a one-layer buffer (Error(InvalidArgument) when out of range).
    HostVisibility layer(int layer) const;
};

/// Splits keys into ids and depths. With `layers` > 1 the keys are a VisibilityBuffer's,
/// layer-major (layer k's width * height * samples keys from key k * width * height * samples);
/// the result keeps the layers of a sample adjacent.
HostVisibility split_keys(const std::uint64_t* keys, int width, int height, int samples = 1, int layers = 1);

} // namespace clvis
