// Visibility buffers on the device and their read-back, split into ids and depths.
#include "runtime/cl_runtime.hpp"

#include "shared/visibility.h"

#include <clvis/render_options.hpp>
#include <clvis/visibility.hpp>

#include <algorithm>
#include <utility>

namespace clvis {

using detail::throw_cl_error;

namespace {

void check_size(int width, int height, const char* call)
{
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, std::string(call) + ": image size must be positive, got " +
                                                      std::to_string(width) + "x" + std::to_string(height));
}

/// The context `mem` was made in; Error(InvalidArgument) when `mem` is not a buffer.
cl_context context_of(cl_mem mem)
{
    cl_context context = nullptr;
    if (clGetMemObjectInfo(mem, CL_MEM_CONTEXT, sizeof context, &context, nullptr) != CL_SUCCESS)
        throw Error(Error::Kind::InvalidArgument, "VisibilityBuffer::wrap: not a valid cl_mem");
    return context;
}

std::shared_ptr<_cl_mem> hold(cl_mem mem) { return std::shared_ptr<_cl_mem>(mem, clReleaseMemObject); }

} // namespace

VisibilityBuffer::VisibilityBuffer(const Device& device, int width, int height, int samples, int layers)
    : device_(device), width_(width), height_(height), samples_(samples), layers_(layers)
{
    auto& impl = detail::DeviceAccess::of(device, "VisibilityBuffer");
    check_size(width, height, "VisibilityBuffer");
    samples_log2(samples);
    check_layers(layers);
    std::uint64_t bytes = std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(samples) * std::uint64_t(layers) * 8;
    impl.check_allocation(bytes, "a " + std::to_string(width) + "x" + std::to_string(height) + " visibility buffer");
    try {
        cl::Buffer buffer(impl.context, CL_MEM_READ_WRITE, bytes);
        clRetainMemObject(buffer());
        keys_ = hold(buffer());
    } catch (const cl::Error& e) {
        throw Error(Error::Kind::Limit, "allocating a " + std::to_string(width) + "x" + std::to_string(height) +
                                            " visibility buffer (" + std::to_string(bytes) + " bytes) failed with " +
                                            detail::cl_error_name(e.err()));
    }
}

VisibilityBuffer::VisibilityBuffer(VisibilityBuffer&& other) noexcept
    : device_(std::move(other.device_)), keys_(std::move(other.keys_)),
      width_(std::exchange(other.width_, 0)), height_(std::exchange(other.height_, 0)),
      samples_(std::exchange(other.samples_, 1)), layers_(std::exchange(other.layers_, 1))
{
}

VisibilityBuffer& VisibilityBuffer::operator=(VisibilityBuffer&& other) noexcept
{
    device_ = std::move(other.device_);
    keys_ = std::move(other.keys_);
    width_ = std::exchange(other.width_, 0);
    height_ = std::exchange(other.height_, 0);
    samples_ = std::exchange(other.samples_, 1);
    layers_ = std::exchange(other.layers_, 1);
    return *this;
}

VisibilityBuffer VisibilityBuffer::wrap(const Device& device, cl_mem keys, int width, int height, int samples,
                                        int layers)
{
    cl_context context = detail::DeviceAccess::of(device, "VisibilityBuffer::wrap").context();
    check_size(width, height, "VisibilityBuffer::wrap");
    samples_log2(samples);
    check_layers(layers);
    if (!keys) throw Error(Error::Kind::InvalidArgument, "VisibilityBuffer::wrap: null buffer");
    if (context_of(keys) != context)
        throw Error(Error::Kind::InvalidArgument,
                    "VisibilityBuffer::wrap: the cl_mem belongs to another OpenCL context than the Device's");
    size_t bytes = 0;
    clGetMemObjectInfo(keys, CL_MEM_SIZE, sizeof bytes, &bytes, nullptr);
    std::size_t needed = std::size_t(width) * std::size_t(height) * std::size_t(samples) * std::size_t(layers) * 8;
    if (bytes < needed)
        throw Error(Error::Kind::InvalidArgument,
                    "VisibilityBuffer::wrap: the buffer holds " + std::to_string(bytes) + " bytes, a " +
                        std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(samples) +
                        " buffer needs " + std::to_string(needed));
    clRetainMemObject(keys);
    VisibilityBuffer v;
    v.device_ = device;
    v.keys_ = hold(keys);
    v.width_ = width;
    v.height_ = height;
    v.samples_ = samples;
    v.layers_ = layers;
    return v;
}

namespace {

[[noreturn]] void empty_buffer(const char* call)
{
    throw Error(Error::Kind::InvalidArgument,
                std::string(call) + ": the VisibilityBuffer is empty (default-constructed or moved-from)");
}

} // namespace

cl_mem VisibilityBuffer::keys() const
{
    if (!keys_) empty_buffer("VisibilityBuffer::keys");
    return keys_.get();
}

VisibilityBuffer VisibilityBuffer::layer(int k) const
{
    if (!keys_) empty_buffer("VisibilityBuffer::layer");
    if (k < 0 || k >= layers_)
        throw Error(Error::Kind::InvalidArgument, "VisibilityBuffer::layer: layer " + std::to_string(k) +
                                                      " of a buffer of " + std::to_string(layers_) + " layer(s)");
    VisibilityBuffer out(device_, width_, height_, samples_, 1);
    auto& impl = detail::DeviceAccess::of(device_, "VisibilityBuffer::layer");
    std::size_t bytes = layer_keys() * 8;
    try {
        std::lock_guard<std::mutex> lock(impl.mutex);
        cl::Buffer from(keys(), true), to(out.keys(), true);
        impl.queue.enqueueCopyBuffer(from, to, std::size_t(k) * bytes, 0, bytes);
        impl.queue.finish();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "copying a depth layer of a visibility buffer");
    }
    return out;
}

namespace {

/// Runs `fn` on the keys mapped for reading (blocking), then unmaps them. A mapping lets the
/// split read the device's memory once (PoCL maps in place; a GPU copies to pinned memory), with
/// no intermediate copy of the keys.
template <class Fn> void with_mapped_keys(const VisibilityBuffer& v, const char* call, Fn fn)
{
    if (v.width() == 0) empty_buffer(call);
    auto& impl = detail::DeviceAccess::of(v.device(), call);
    std::size_t bytes = v.key_count() * 8;
    try {
        std::lock_guard<std::mutex> lock(impl.mutex);
        cl::Buffer buffer(v.keys(), true);
        void* mapped = impl.queue.enqueueMapBuffer(buffer, CL_TRUE, CL_MAP_READ, 0, bytes);
        try {
            fn(static_cast<const std::uint64_t*>(mapped));
        } catch (...) {
            impl.queue.enqueueUnmapMemObject(buffer, mapped);
            impl.queue.finish();
            throw;
        }
        impl.queue.enqueueUnmapMemObject(buffer, mapped);
        impl.queue.finish();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "reading a visibility buffer back");
    }
}

} // namespace

void VisibilityBuffer::read_keys(std::vector<std::uint64_t>& keys) const
{
    keys.resize(key_count());
    with_mapped_keys(*this, "VisibilityBuffer::read_keys", [&](const std::uint64_t* k) { std::copy(k, k + keys.size(), keys.data()); });
}

std::vector<std::uint64_t> VisibilityBuffer::read_keys() const
{
    std::vector<std::uint64_t> keys;
    read_keys(keys);
    return keys;
}

void VisibilityBuffer::read(std::uint32_t* ids, float* depth) const
{
    std::size_t n = key_count();
    if (layers_ > 1) { // layer-major on the device, the layers of a sample adjacent here
        std::size_t plane = layer_keys(), layers = std::size_t(layers_);
        with_mapped_keys(*this, "VisibilityBuffer::read", [&](const std::uint64_t* k) {
            for (std::size_t i = 0; i < plane; ++i)
                for (std::size_t l = 0; l < layers; ++l) {
                    std::uint64_t key = k[l * plane + i];
                    if (ids) ids[i * layers + l] = clvis_key_id(key);
                    if (depth) depth[i * layers + l] = clvis_key_depth(key);
                }
        });
        return;
    }
    with_mapped_keys(*this, "VisibilityBuffer::read", [&](const std::uint64_t* k) {
        if (ids && depth) {
            for (std::size_t i = 0; i < n; ++i) {
                ids[i] = clvis_key_id(k[i]);
                depth[i] = clvis_key_depth(k[i]);
            }
        } else if (ids) {
            for (std::size_t i = 0; i < n; ++i) ids[i] = clvis_key_id(k[i]);
        } else if (depth) {
            for (std::size_t i = 0; i < n; ++i) depth[i] = clvis_key_depth(k[i]);
        }
    });
}

void VisibilityBuffer::read(HostVisibility& out) const
{
    std::size_t n = key_count();
    out.width = width_;
    out.height = height_;
    out.samples = samples_;
    out.layers = layers_;
    out.ids.resize(n);
    out.depth.resize(n);
    read(out.ids.data(), out.depth.data());
}

HostVisibility VisibilityBuffer::read() const
{
    HostVisibility v;
    read(v);
    return v;
}

void VisibilityBuffer::read_ids(std::vector<std::uint32_t>& ids) const
{
    ids.resize(key_count());
    read(ids.data(), nullptr);
}

std::vector<std::uint32_t> VisibilityBuffer::read_ids() const
{
    std::vector<std::uint32_t> ids;
    read_ids(ids);
    return ids;
}

} // namespace clvis
