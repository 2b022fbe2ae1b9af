// The visibility buffer: what both paths produce and everything downstream reads. Per pixel, one
// 64-bit key (as_uint(view depth) << 32) | triangle id, row 0 on top; the background is
// (as_uint(+inf) << 32) | 0xFFFFFFFF. One atomic min on the key keeps the nearest triangle and,
// at an exact depth tie, the lower id.
#pragma once

#include <clvis/device.hpp>

#include <CL/cl.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace clvis {

/// The key of a background pixel.
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

class VisibilityBuffer {
public:
    VisibilityBuffer() = default;
    /// Allocates width * height keys on the device. Throws Error(InvalidArgument) for sizes
    /// <= 0 and Error(Limit) when the buffer exceeds the device's largest allocation.
    VisibilityBuffer(const Device& device, int width, int height);
    /// Wraps a caller's buffer of at least width * height cl_ulong (retained).
    static VisibilityBuffer wrap(const Device& device, cl_mem keys, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return !keys_; }
    /// The device buffer of keys, for the caller's own kernels.
    cl_mem keys() const;
    const Device& device() const { return device_; }

    /// Blocking read of the keys on the device's queue.
    std::vector<std::uint64_t> read_keys() const;
    /// Blocking read, split into ids and depths.
    HostVisibility read() const;

private:
    Device device_;
    std::shared_ptr<struct _cl_mem> keys_;
    int width_ = 0, height_ = 0;
};

} // namespace clvis
