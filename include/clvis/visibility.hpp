// The visibility buffer: what both paths produce and everything downstream reads. Per pixel, one
// 64-bit key (as_uint(view depth) << 32) | triangle id, row 0 on top; the background is
// (as_uint(+inf) << 32) | 0xFFFFFFFF. One atomic min on the key keeps the nearest triangle and,
// at an exact depth tie, the lower id.
#pragma once

#include <clvis/device.hpp>
#include <clvis/host_visibility.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace clvis {

class VisibilityBuffer {
public:
    /// An empty buffer, as is a moved-from one: 0x0, empty(); keys(), read_keys() and read()
    /// throw Error(InvalidArgument) naming the call. Copies share the device buffer.
    VisibilityBuffer() = default;
    VisibilityBuffer(const VisibilityBuffer&) = default;
    VisibilityBuffer& operator=(const VisibilityBuffer&) = default;
    VisibilityBuffer(VisibilityBuffer&& other) noexcept;
    VisibilityBuffer& operator=(VisibilityBuffer&& other) noexcept;
    /// Allocates width * height keys on the device. Throws Error(InvalidArgument) for sizes
    /// <= 0 and Error(Limit) when the buffer exceeds the device's largest allocation.
    /// With `samples` per pixel (1, 2, 4, 8 or 16; Error(InvalidArgument) otherwise):
    /// width * height * samples keys, the samples of a pixel adjacent.
    /// With `layers` (RenderOptions::layers, 1 to 8; Error(InvalidArgument) otherwise): `layers`
    /// times as many keys, layer-major: layer k's width * height * samples keys start at key
    /// k * width * height * samples, so layer 0 is laid out as a one-layer buffer.
    VisibilityBuffer(const Device& device, int width, int height, int samples = 1, int layers = 1);
    /// Wraps a caller's buffer of at least width * height cl_ulong (retained). Throws
    /// Error(InvalidArgument) for an empty Device, a null or invalid cl_mem, a buffer made in
    /// another OpenCL context than the Device's, or one too small.
    static VisibilityBuffer wrap(const Device& device, cl_mem keys, int width, int height, int samples = 1,
                                 int layers = 1);

    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; } ///< samples per pixel (RenderOptions::samples)
    int layers() const { return layers_; } ///< depth layers per sample (RenderOptions::layers)
    /// width() * height() * samples() * layers(): the keys it holds.
    std::size_t key_count() const { return layer_keys() * std::size_t(layers_); }
    /// width() * height() * samples(): the keys of one layer.
    std::size_t layer_keys() const { return std::size_t(width_) * std::size_t(height_) * std::size_t(samples_); }
    bool empty() const { return !keys_; }
    /// The device buffer of keys, for the caller's own kernels.
    cl_mem keys() const;
    const Device& device() const { return device_; }

    /// Depth layer `k` (0 <= k < layers()) as a one-layer buffer of its own: a device copy of the
    /// layer's keys, finished before it returns. Everything that reads a one-layer buffer then
    /// reads that layer: resolve (barycentrics, attributes, object ids), flow, shading, the
    /// referees. Error(InvalidArgument) for an empty buffer or a layer it does not hold.
    VisibilityBuffer layer(int k) const;

    /// Blocking read of the keys on the device's queue, as the device holds them (layer-major).
    std::vector<std::uint64_t> read_keys() const;
    /// Blocking read, split into ids and depths (the layers of a sample adjacent: HostVisibility).
    HostVisibility read() const;

    // Reads into storage the caller owns and reuses: a vector keeps its capacity (no allocation
    // once it has held key_count() elements), a pointer must address that many. Each is
    // one mapping of the buffer and one pass over it, about the cost of clEnqueueReadBuffer.
    void read(HostVisibility& out) const;
    /// either may be null: not written; key_count() of each, in HostVisibility's order
    void read(std::uint32_t* ids, float* depth) const;
    void read_ids(std::vector<std::uint32_t>& ids) const;
    std::vector<std::uint32_t> read_ids() const;
    void read_keys(std::vector<std::uint64_t>& keys) const;

private:
    Device device_;
    std::shared_ptr<struct _cl_mem> keys_;
    int width_ = 0, height_ = 0;
    int samples_ = 1;
    int layers_ = 1;
};

} // namespace clvis
