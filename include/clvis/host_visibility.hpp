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
    std::vector<std::uint32_t> ids; ///< width * height, row 0 on top; background_id where empty
    std::vector<float> depth;       ///< view depth; +inf where empty

    std::uint32_t id(int x, int y) const { return ids[std::size_t(y) * width + x]; }
    float depth_at(int x, int y) const { return depth[std::size_t(y) * width + x]; }
};

/// Splits keys into ids and depths.
HostVisibility split_keys(const std::uint64_t* keys, int width, int height);

} // namespace clvis
