// OpenCL devices: listing them, picking one, or wrapping a context and queue the caller owns.
// A Device is a shared handle: copies refer to the same OpenCL context, device and program
// cache. It may be shared between threads (its program cache is locked); each Renderer makes its
// own command queue on it, unless the Device wraps a caller's queue.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

// The OpenCL handles of the API, declared exactly as <CL/cl.h> declares them (a repeated identical
// typedef is valid C++), so that these headers neither include <CL/cl.h> nor choose an OpenCL
// version for the caller: <CL/cl.h> or <CL/opencl.hpp>, with the caller's own
// CL_TARGET_OPENCL_VERSION, may come before or after <clvis/clvis.hpp>.
typedef struct _cl_context* cl_context;
typedef struct _cl_command_queue* cl_command_queue;
typedef struct _cl_device_id* cl_device_id;
typedef struct _cl_mem* cl_mem;

namespace clvis {

enum class DeviceType { Cpu, Gpu, Accelerator, Other };

const char* to_string(DeviceType type) noexcept;

struct DeviceInfo {
    std::size_t index = 0;          ///< position in list_devices(): platforms in order, then devices
    std::string platform;           ///< platform name
    std::string name;               ///< device name
    std::string vendor;
    std::string version;            ///< CL_DEVICE_VERSION
    std::string driver_version;
    std::string opencl_c_version;   ///< CL_DEVICE_OPENCL_C_VERSION
    DeviceType type = DeviceType::Other;
    unsigned compute_units = 0;
    std::uint64_t global_memory = 0;    ///< bytes
    std::uint64_t max_allocation = 0;   ///< bytes, largest single buffer
    std::uint64_t local_memory = 0;     ///< bytes per work-group
    std::size_t max_work_group_size = 0;
    bool int64_atomics = false;         ///< cl_khr_int64_base_atomics and _extended_atomics
    bool fp64 = false;
    bool correctly_rounded_divide_sqrt = false;
};

/// Every device of every OpenCL platform. Throws Error(Device) when no platform is installed,
/// with a message that says how to install one (PoCL).
std::vector<DeviceInfo> list_devices();

/// A choice clvis measured on a device and keeps in its cache folder (RasterMapping::Auto,
/// RayMapping::Auto).
struct TunedChoice {
    std::string name; ///< what was chosen: "raster_mapping" or "ray_mapping"
    /// What else it depends on (field, value): the kernels' hash, depth test, tile size, ...
    std::vector<std::pair<std::string, std::string>> key;
    std::string choice;                                   ///< "square", "pixel", "packet", "single"
    std::vector<std::pair<std::string, double>> times_ms; ///< each candidate's measured time
};

/// The choices kept in the cache folder for `device` (the same name, platform and driver);
/// none when there is no cache folder.
std::vector<TunedChoice> tuned_choices(const DeviceInfo& device);

namespace detail {
struct DeviceAccess;
}

class Device {
public:
    /// An empty handle, as is a moved-from Device: every accessor, and every object made from
    /// it, throws Error(InvalidArgument) naming the call.
    Device() = default;
    explicit operator bool() const { return impl_ != nullptr; }

    /// Opens a device by `spec`: an index into list_devices(), "cpu", "gpu", "accelerator", or a
    /// case-insensitive substring of the device or platform name. An empty spec reads the
    /// environment variable CLVIS_DEVICE, and with that empty too takes the first GPU, else the
    /// first CPU device, else the first device. Throws Error(Device) naming the spec when
    /// nothing matches, or Error(InvalidArgument) for an index out of range.
    static Device open(const std::string& spec = {});

    /// Wraps a context and an in-order command queue that the caller created (both retained,
    /// released with the last copy). Renderers then enqueue on that queue and render into
    /// buffers of that context, so the caller's own kernels can read them without a copy.
    static Device wrap(cl_context context, cl_command_queue queue);

    const DeviceInfo& info() const;
    cl_context context() const;
    cl_device_id id() const;
    /// The wrapped queue, or the device's own default queue.
    cl_command_queue queue() const;

    struct Impl;

private:
    friend struct detail::DeviceAccess;
    explicit Device(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
    Impl& checked(const char* call) const;
    std::shared_ptr<Impl> impl_;
};

} // namespace clvis
