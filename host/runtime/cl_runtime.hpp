// The OpenCL runtime behind clvis::Device: the context, device, default queue and program cache
// (Device::Impl, reached through detail::DeviceAccess), and the translation of OpenCL errors into
// clvis::Error with the call's and the code's names.
#pragma once

#include "runtime/cl.hpp"

#include <clvis/device.hpp>
#include <clvis/error.hpp>

#include <map>
#include <new>
#include <mutex>
#include <string>

namespace clvis::detail {

/// "CL_OUT_OF_RESOURCES" for -5, ..., "CL_UNKNOWN_ERROR(-1234)" otherwise.
std::string cl_error_name(cl_int code);

/// Whether clvis asks PoCL to pin its CPU device's worker threads (POCL_AFFINITY=1: worker i on
/// CPU i). PoCL's workers sleep between commands; unpinned, the scheduler often leaves the woken
/// worker on the core of the worker that woke it, and a kernel of a few milliseconds ends before
/// the load balancer moves it: frames then run on one core in streaks (on 2 cores the bunny's
/// 1280x720 ray frame took 5.2 or 9.3 ms, round after round, when interleaved with other
/// renderers in `clvis bench`; pinned, 5.0-5.8). Only where it is safe and wanted:
///  - pocl_affinity (the caller's POCL_AFFINITY) unset: any value of theirs wins, 0 turns it off;
///  - pocl_max_cu and pocl_max_threads (POCL_CPU_MAX_CU_COUNT, POCL_MAX_PTHREAD_COUNT, by which
///    PoCL 3.1 sizes its pool) unset or integers from 1 to owned: a larger pool would be pinned to
///    CPUs that do not exist, which PoCL treats as fatal;
///  - owned (runtime/cpus.hpp, owned_cpus) at least 2: the process may run on exactly the online
///    CPUs 0 to owned-1.
bool pin_pocl_workers(const char* pocl_affinity, const char* pocl_max_cu, const char* pocl_max_threads,
                      int owned);

void pin_pocl_workers_once();

/// Throws Error(Device): "<what>: <CL call> failed with <CL_ERROR_NAME>".
[[noreturn]] void throw_cl_error(const cl::Error& e, const std::string& what);

/// The error boundary of a public entry: runs `body` and lets clvis::Error through, but turns an
/// escaping cl::Error into Error(Device) and std::bad_alloc into Error(Limit), both naming `what`
/// ("preparing the ray path"), so that no OpenCL or allocation exception leaves the library.
template <class Body> decltype(auto) error_boundary(const std::string& what, Body&& body)
{
    try {
        return body();
    } catch (const cl::Error& e) {
        throw_cl_error(e, what);
    } catch (const std::bad_alloc&) {
        throw Error(Error::Kind::Limit, what + ": out of host memory");
    }
}

} // namespace clvis::detail

namespace clvis {

struct Device::Impl {
    cl::Context context;
    cl::Device device;
    cl::CommandQueue queue; ///< the wrapped queue, or one made by open()
    bool wrapped = false;
    DeviceInfo info;

    /// The built program of kernels/<name>.cl with `options` added to the standard options
    /// (-cl-std=CL1.2, correctly rounded division where the device offers it). Built once per
    /// (name, options) and kept; on drivers that do not cache programs themselves, binaries are
    /// also kept on disk keyed by device, driver, options and source hash. Thread-safe.
    /// Throws Error(Build) carrying the build log.
    cl::Program program(const std::string& name, const std::string& options = {});

    /// Builds `source` (named `name` in messages) with the standard options plus `options`,
    /// without caching. Throws Error(Build) carrying the build log.
    cl::Program build_source(const std::string& name, const std::string& source, const std::string& options);

    /// The standard build options plus `extra`.
    std::string build_options(const std::string& extra) const;

    /// Whether kernels may use what PoCL's CPU device is known to do: its compiler (clang) turns
    /// __builtin_prefetch into the CPU's prefetch (-DCLVIS_PREFETCH), and an aligned 32-bit load
    /// that races with 64-bit atomics returns a value stored there, little-endian (-DCLVIS_PEEK,
    /// kernels/raster_setup.cl). Elsewhere (other compilers, Oclgrind's interpreter, GPUs) the
    /// kernels keep to what OpenCL defines.
    bool cpu_hints() const;

    /// A new in-order queue with profiling on, or the wrapped queue.
    cl::CommandQueue make_queue();

    /// Throws Error(Limit) naming `what` when `bytes` exceeds the largest allocation.
    void check_allocation(std::uint64_t bytes, const std::string& what) const;

    /// The loop iterations one work-item may run in all (kernels/device_probe.cl, measured once
    /// and kept): loop_unlimited, or the cap of a driver that ends the loops of an invocation
    /// after that many iterations together. Kernels whose loops run longer split their work.
    std::uint32_t loop_limit();
    static constexpr std::uint32_t loop_unlimited = 0xFFFFFFFFu;
    std::uint32_t measured_loop_limit = 0; ///< 0 until measured (tests may set it to force a cap)

    /// Whether kernels read and write a CL_MEM_USE_HOST_PTR buffer's host memory itself, so that
    /// the host sees a finished kernel's writes and the kernel the host's latest values without a
    /// map or a copy (kernels/device_probe.cl, run once per device and driver where cpu_hints()
    /// holds, on a real buffer; false elsewhere and where the probe fails).
    bool host_memory_in_place();
    int measured_in_place = -1; ///< -1 until probed

    std::mutex mutex; ///< guards programs and the default queue's host reads
    std::map<std::string, cl::Program> programs;
};

namespace detail {
/// The way in to a Device's implementation for the library and its tests (include/clvis/device.hpp
/// keeps it private, as renderer.hpp keeps Renderer::Impl).
struct DeviceAccess {
    /// The implementation; throws Error(InvalidArgument) naming `call` when the Device is empty.
    static Device::Impl& of(const Device& device, const char* call) { return device.checked(call); }
};
} // namespace detail

} // namespace clvis
