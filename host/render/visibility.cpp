// Visibility buffers on the device and their read-back, split into ids and depths.
#include "runtime/cl_runtime.hpp"

#include "shared/visibility.h"

#include <clvis/visibility.hpp>

namespace clvis {

using detail::throw_cl_error;

namespace {

void check_size(int width, int height)
{
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "image size must be positive, got " + std::to_string(width) +
                                                      "x" + std::to_string(height));
}

std::shared_ptr<_cl_mem> hold(cl_mem mem) { return std::shared_ptr<_cl_mem>(mem, clReleaseMemObject); }

} // namespace

VisibilityBuffer::VisibilityBuffer(const Device& device, int width, int height)
    : device_(device), width_(width), height_(height)
{
    check_size(width, height);
    std::uint64_t bytes = std::uint64_t(width) * std::uint64_t(height) * 8;
    auto& impl = *device.impl();
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

VisibilityBuffer VisibilityBuffer::wrap(const Device& device, cl_mem keys, int width, int height)
{
    check_size(width, height);
    if (!keys) throw Error(Error::Kind::InvalidArgument, "VisibilityBuffer::wrap: null buffer");
    size_t bytes = 0;
    if (clGetMemObjectInfo(keys, CL_MEM_SIZE, sizeof bytes, &bytes, nullptr) != CL_SUCCESS)
        throw Error(Error::Kind::InvalidArgument, "VisibilityBuffer::wrap: not a valid cl_mem");
    if (bytes < std::size_t(width) * std::size_t(height) * 8)
        throw Error(Error::Kind::InvalidArgument,
                    "VisibilityBuffer::wrap: the buffer holds " + std::to_string(bytes) + " bytes, a " +
                        std::to_string(width) + "x" + std::to_string(height) + " buffer needs " +
                        std::to_string(std::size_t(width) * height * 8));
    clRetainMemObject(keys);
    VisibilityBuffer v;
    v.device_ = device;
    v.keys_ = hold(keys);
    v.width_ = width;
    v.height_ = height;
    return v;
}

cl_mem VisibilityBuffer::keys() const
{
    if (!keys_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibilityBuffer");
    return keys_.get();
}

std::vector<std::uint64_t> VisibilityBuffer::read_keys() const
{
    std::vector<std::uint64_t> keys(std::size_t(width_) * std::size_t(height_));
    auto& impl = *device_.impl();
    try {
        std::lock_guard<std::mutex> lock(impl.mutex);
        cl::Buffer buffer(this->keys(), true);
        impl.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, keys.size() * 8, keys.data());
    } catch (const cl::Error& e) {
        throw_cl_error(e, "reading a visibility buffer back");
    }
    return keys;
}

HostVisibility VisibilityBuffer::read() const
{
    auto keys = read_keys();
    return split_keys(keys.data(), width_, height_);
}

} // namespace clvis
