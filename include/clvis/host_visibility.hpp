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
    std::vector<std::uint32_t> ids; ///< width * height * samples, row 0 on top, the samples of a
                                    ///< pixel adjacent; background_id where empty
    std::vector<float> depth;       ///< view depth; +inf where empty

    std::size_t index(int x, int y, int sample = 0) const
    {
        return (std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(samples) + std::size_t(sample);
    }
    std::uint32_t id(int x, int y, int sample = 0) const { return ids[index(x, y, sample)]; }
    float depth_at(int x, int y, int sample = 0) const { return depth[index(x, y, sample)]; }
};

/// Splits keys into ids and depths.
HostVisibility split_keys(const std::uint64_t* keys, int width, int height, int samples = 1);

} // namespace clvis
