// OpenCL platforms and devices: listing, selection by spec, wrapping a caller's context, the
// program cache (in memory, and on disk through program_cache.hpp), and
// the translation of OpenCL errors into clvis::Error.
#include "lower_case.hpp"
#include "runtime/cl_runtime.hpp"
#include "runtime/cpus.hpp"
#include "runtime/program_cache.hpp"

#include "runtime/embedded_kernels.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>

namespace clvis::detail {

std::string cl_error_name(cl_int code)
{
    switch (code) {
#define CLVIS_CASE(name) case name: return #name;
        CLVIS_CASE(CL_SUCCESS)
        CLVIS_CASE(CL_DEVICE_NOT_FOUND)
        CLVIS_CASE(CL_DEVICE_NOT_AVAILABLE)
        CLVIS_CASE(CL_COMPILER_NOT_AVAILABLE)
        CLVIS_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        CLVIS_CASE(CL_OUT_OF_RESOURCES)
        CLVIS_CASE(CL_OUT_OF_HOST_MEMORY)
        CLVIS_CASE(CL_PROFILING_INFO_NOT_AVAILABLE)
        CLVIS_CASE(CL_MEM_COPY_OVERLAP)
        CLVIS_CASE(CL_IMAGE_FORMAT_MISMATCH)
        CLVIS_CASE(CL_IMAGE_FORMAT_NOT_SUPPORTED)
        CLVIS_CASE(CL_BUILD_PROGRAM_FAILURE)
        CLVIS_CASE(CL_MAP_FAILURE)
        CLVIS_CASE(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        CLVIS_CASE(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        CLVIS_CASE(CL_COMPILE_PROGRAM_FAILURE)
        CLVIS_CASE(CL_LINKER_NOT_AVAILABLE)
        CLVIS_CASE(CL_LINK_PROGRAM_FAILURE)
        CLVIS_CASE(CL_DEVICE_PARTITION_FAILED)
        CLVIS_CASE(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        CLVIS_CASE(CL_INVALID_VALUE)
        CLVIS_CASE(CL_INVALID_DEVICE_TYPE)
        CLVIS_CASE(CL_INVALID_PLATFORM)
        CLVIS_CASE(CL_INVALID_DEVICE)
        CLVIS_CASE(CL_INVALID_CONTEXT)
        CLVIS_CASE(CL_INVALID_QUEUE_PROPERTIES)
        CLVIS_CASE(CL_INVALID_COMMAND_QUEUE)
        CLVIS_CASE(CL_INVALID_HOST_PTR)
        CLVIS_CASE(CL_INVALID_MEM_OBJECT)
        CLVIS_CASE(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
        CLVIS_CASE(CL_INVALID_IMAGE_SIZE)
        CLVIS_CASE(CL_INVALID_SAMPLER)
        CLVIS_CASE(CL_INVALID_BINARY)
        CLVIS_CASE(CL_INVALID_BUILD_OPTIONS)
        CLVIS_CASE(CL_INVALID_PROGRAM)
        CLVIS_CASE(CL_INVALID_PROGRAM_EXECUTABLE)
        CLVIS_CASE(CL_INVALID_KERNEL_NAME)
        CLVIS_CASE(CL_INVALID_KERNEL_DEFINITION)
        CLVIS_CASE(CL_INVALID_KERNEL)
        CLVIS_CASE(CL_INVALID_ARG_INDEX)
        CLVIS_CASE(CL_INVALID_ARG_VALUE)
        CLVIS_CASE(CL_INVALID_ARG_SIZE)
        CLVIS_CASE(CL_INVALID_KERNEL_ARGS)
        CLVIS_CASE(CL_INVALID_WORK_DIMENSION)
        CLVIS_CASE(CL_INVALID_WORK_GROUP_SIZE)
        CLVIS_CASE(CL_INVALID_WORK_ITEM_SIZE)
        CLVIS_CASE(CL_INVALID_GLOBAL_OFFSET)
        CLVIS_CASE(CL_INVALID_EVENT_WAIT_LIST)
        CLVIS_CASE(CL_INVALID_EVENT)
        CLVIS_CASE(CL_INVALID_OPERATION)
        CLVIS_CASE(CL_INVALID_GL_OBJECT)
        CLVIS_CASE(CL_INVALID_BUFFER_SIZE)
        CLVIS_CASE(CL_INVALID_MIP_LEVEL)
        CLVIS_CASE(CL_INVALID_GLOBAL_WORK_SIZE)
        CLVIS_CASE(CL_INVALID_PROPERTY)
        CLVIS_CASE(CL_INVALID_IMAGE_DESCRIPTOR)
        CLVIS_CASE(CL_INVALID_COMPILER_OPTIONS)
        CLVIS_CASE(CL_INVALID_LINKER_OPTIONS)
        CLVIS_CASE(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef CLVIS_CASE
    case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
    default: return "CL_UNKNOWN_ERROR(" + std::to_string(code) + ")";
    }
}

void throw_cl_error(const cl::Error& e, const std::string& what)
{
    throw Error(Error::Kind::Device,
                what + ": " + e.what() + " failed with " + cl_error_name(e.err()));
}

const std::string& embedded_kernel(const std::string& name)
{
    for (const auto& k : embedded_kernels())
        if (k.name == name) return k.source;
    throw Error(Error::Kind::Build, "no embedded kernel named '" + name + "'");
}

namespace {

/// Whether a pool size the caller gave PoCL (unset: PoCL's own, one worker per CPU) stays within
/// `cpus`: workers 0 .. n-1 are pinned to CPUs that exist only when n <= cpus.
bool pool_within(const char* size, int cpus)
{
    if (!size) return true;
    char* end = nullptr;
    errno = 0;
    long n = std::strtol(size, &end, 10);
    return errno == 0 && end != size && *end == '\0' && n >= 1 && n <= cpus;
}

} // namespace

bool pin_pocl_workers(const char* pocl_affinity, const char* pocl_max_cu, const char* pocl_max_threads,
                      int owned)
{
    return !pocl_affinity && owned >= 2 && pool_within(pocl_max_cu, owned) && pool_within(pocl_max_threads, owned);
}

void pin_pocl_workers_once()
{
#if defined(__linux__)
    static std::once_flag once;
    std::call_once(once, [] {
        if (pin_pocl_workers(std::getenv("POCL_AFFINITY"), std::getenv("POCL_CPU_MAX_CU_COUNT"),
                             std::getenv("POCL_MAX_PTHREAD_COUNT"), owned_cpus()))
            setenv("POCL_AFFINITY", "1", 0);
    });
#endif
}

namespace {

const char* no_platform_help =
    "no OpenCL platform found: install an OpenCL driver and the ICD loader, e.g. on Debian or "
    "Ubuntu `apt-get install pocl-opencl-icd ocl-icd-libopencl1` for PoCL's CPU device (check "
    "with `clinfo -l`; OCL_ICD_VENDORS names the folder of .icd files)";

std::vector<cl::Platform> platforms()
{
    pin_pocl_workers_once();
    std::vector<cl::Platform> list;
    cl_int err = CL_SUCCESS;
    try {
        err = cl::Platform::get(&list);
    } catch (const cl::Error& e) {
        err = e.err();
    }
    if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || (err == CL_SUCCESS && list.empty()))
        throw Error(Error::Kind::Device, no_platform_help);
    if (err != CL_SUCCESS)
        throw Error(Error::Kind::Device, std::string("clGetPlatformIDs failed with ") + cl_error_name(err));
    return list;
}

DeviceType device_type(cl_device_type t)
{
    if (t & CL_DEVICE_TYPE_GPU) return DeviceType::Gpu;
    if (t & CL_DEVICE_TYPE_CPU) return DeviceType::Cpu;
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return DeviceType::Accelerator;
    return DeviceType::Other;
}

DeviceInfo describe(const cl::Platform& platform, const cl::Device& device, std::size_t index)
{
    DeviceInfo info;
    info.index = index;
    info.platform = platform.getInfo<CL_PLATFORM_NAME>();
    info.name = device.getInfo<CL_DEVICE_NAME>();
    info.vendor = device.getInfo<CL_DEVICE_VENDOR>();
    info.version = device.getInfo<CL_DEVICE_VERSION>();
    info.driver_version = device.getInfo<CL_DRIVER_VERSION>();
    info.opencl_c_version = device.getInfo<CL_DEVICE_OPENCL_C_VERSION>();
    info.type = device_type(device.getInfo<CL_DEVICE_TYPE>());
    info.compute_units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
    info.global_memory = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
    info.max_allocation = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
    info.local_memory = device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
    info.max_work_group_size = device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
    std::string ext = device.getInfo<CL_DEVICE_EXTENSIONS>();
    info.int64_atomics = ext.find("cl_khr_int64_base_atomics") != std::string::npos &&
                         ext.find("cl_khr_int64_extended_atomics") != std::string::npos;
    info.fp64 = ext.find("cl_khr_fp64") != std::string::npos;
    cl_device_fp_config fp = device.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>();
    info.correctly_rounded_divide_sqrt = (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
    return info;
}

struct Candidate {
    cl::Platform platform;
    cl::Device device;
    DeviceInfo info;
};

std::vector<Candidate> candidates()
{
    std::vector<Candidate> out;
    for (auto& p : platforms()) {
        std::vector<cl::Device> devices;
        try {
            p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error& e) {
            if (e.err() == CL_DEVICE_NOT_FOUND) continue;
            throw_cl_error(e, "listing the devices of a platform");
        }
        for (auto& d : devices) out.push_back({p, d, describe(p, d, out.size())});
    }
    return out;
}

std::string describe_all(const std::vector<Candidate>& all)
{
    std::ostringstream os;
    for (const auto& c : all)
        os << "\n  " << c.info.index << ": " << c.info.name << " (" << to_string(c.info.type)
           << ", " << c.info.platform << ")";
    return os.str();
}

const Candidate& pick(const std::vector<Candidate>& all, const std::string& spec_in)
{
    if (all.empty()) throw Error(Error::Kind::Device, std::string("no OpenCL device found; ") + no_platform_help);
    std::string spec = lower_case(spec_in);
    if (spec.empty()) {
        for (auto type : {DeviceType::Gpu, DeviceType::Cpu})
            for (const auto& c : all)
                if (c.info.type == type) return c;
        return all.front();
    }
    if (std::all_of(spec.begin(), spec.end(), [](unsigned char ch) { return std::isdigit(ch); })) {
        std::size_t index = std::stoul(spec);
        if (index >= all.size())
            throw Error(Error::Kind::InvalidArgument,
                        "device index " + spec + " is out of range; devices:" + describe_all(all));
        return all[index];
    }
    for (auto [name, type] : {std::pair{"cpu", DeviceType::Cpu}, {"gpu", DeviceType::Gpu},
                              {"accelerator", DeviceType::Accelerator}})
        if (spec == name) {
            for (const auto& c : all)
                if (c.info.type == type) return c;
            throw Error(Error::Kind::Device, "no " + spec + " device; devices:" + describe_all(all));
        }
    for (const auto& c : all)
        if (lower_case(c.info.name).find(spec) != std::string::npos ||
            lower_case(c.info.platform).find(spec) != std::string::npos)
            return c;
    throw Error(Error::Kind::Device, "no device matches '" + spec_in + "'; devices:" + describe_all(all));
}

std::string hex64(std::uint64_t v)
{
    std::ostringstream os;
    os << std::hex << v;
    return os.str();
}

/// Drivers that cache compiled programs themselves (PoCL keeps a kernel cache of its own; see
/// program_cache.hpp).
bool driver_caches_programs(const DeviceInfo& info)
{
    return info.platform.find("Portable Computing Language") != std::string::npos;
}

/// CLVIS_EXACT_FLOAT=1 builds every kernel with the float-only form of the ray path's exact edge
/// fallback (kernels/shared/exact.h), the form devices without cl_khr_fp64 always use.
bool exact_float_requested()
{
    const char* v = std::getenv("CLVIS_EXACT_FLOAT");
    if (!v || !*v || std::string(v) == "0") return false;
    if (std::string(v) == "1") return true;
    throw Error(Error::Kind::InvalidArgument, std::string("CLVIS_EXACT_FLOAT must be 0 or 1, got '") + v + "'");
}

/// CLVIS_BUILD_LOG=1 (clvis --verbose): each program built from source prints its build seconds and log,
/// compiler warnings included, on standard error. Otherwise programs are built with -w: PoCL's
/// Clang prints its diagnostics' count ("11 warnings generated.") on the process's standard error
/// itself, which -q and every caller of the library would otherwise get.
bool build_log_requested()
{
    const char* v = std::getenv("CLVIS_BUILD_LOG");
    return v && *v && std::string(v) != "0";
}

std::string build_log(const cl::Program& program)
{
    std::string log;
    try {
        for (auto& [dev, text] : program.getBuildInfo<CL_PROGRAM_BUILD_LOG>()) log += text;
    } catch (const cl::Error&) {
        // Some drivers report no log for a program that failed before compiling: keep the code.
    }
    return log;
}

/// A device and its driver, as the process-wide caches of the probes key them (every Device::open
/// of the same device and driver would measure the same).
std::string driver_identity(const DeviceInfo& info)
{
    return info.platform + "\n" + info.name + "\n" + info.driver_version;
}

} // namespace

} // namespace clvis::detail

namespace clvis {

using namespace detail;

const char* to_string(DeviceType type) noexcept
{
    switch (type) {
    case DeviceType::Cpu: return "cpu";
    case DeviceType::Gpu: return "gpu";
    case DeviceType::Accelerator: return "accelerator";
    case DeviceType::Other: return "other";
    }
    return "other";
}

std::vector<DeviceInfo> list_devices()
{
    try {
        std::vector<DeviceInfo> out;
        for (auto& c : candidates()) out.push_back(c.info);
        return out;
    } catch (const cl::Error& e) {
        throw_cl_error(e, "listing OpenCL devices");
    }
}

Device Device::open(const std::string& spec_in)
{
    std::string spec = spec_in;
    if (spec.empty())
        if (const char* env = std::getenv("CLVIS_DEVICE")) spec = env;
    try {
        auto all = candidates();
        const Candidate& c = pick(all, spec);
        auto impl = std::make_shared<Impl>();
        impl->device = c.device;
        impl->info = c.info;
        impl->context = cl::Context(c.device);
        impl->queue = cl::CommandQueue(impl->context, c.device, CL_QUEUE_PROFILING_ENABLE);
        return Device(std::move(impl));
    } catch (const cl::Error& e) {
        throw_cl_error(e, "opening OpenCL device '" + spec + "'");
    }
}

Device Device::wrap(cl_context context, cl_command_queue queue)
{
    if (!context || !queue)
        throw Error(Error::Kind::InvalidArgument, "Device::wrap: context and queue must not be null");
    try {
        auto impl = std::make_shared<Impl>();
        impl->context = cl::Context(context, true);
        impl->queue = cl::CommandQueue(queue, true);
        impl->device = impl->queue.getInfo<CL_QUEUE_DEVICE>();
        if (impl->queue.getInfo<CL_QUEUE_CONTEXT>()() != context)
            throw Error(Error::Kind::InvalidArgument, "Device::wrap: the queue belongs to another context");
        if (impl->queue.getInfo<CL_QUEUE_PROPERTIES>() & CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE)
            throw Error(Error::Kind::InvalidArgument, "Device::wrap: the queue must be in-order");
        cl::Platform platform(impl->device.getInfo<CL_DEVICE_PLATFORM>(), true);
        impl->info = describe(platform, impl->device, 0);
        impl->wrapped = true;
        return Device(std::move(impl));
    } catch (const cl::Error& e) {
        throw_cl_error(e, "wrapping a caller's OpenCL context");
    }
}

Device::Impl& Device::checked(const char* call) const
{
    if (!impl_)
        throw Error(Error::Kind::InvalidArgument,
                    std::string(call) + ": the Device is empty (default-constructed or moved-from)");
    return *impl_;
}

const DeviceInfo& Device::info() const { return checked("Device::info").info; }
cl_context Device::context() const { return checked("Device::context").context(); }
cl_device_id Device::id() const { return checked("Device::id").device(); }
cl_command_queue Device::queue() const { return checked("Device::queue").queue(); }

cl::CommandQueue Device::Impl::make_queue()
{
    if (wrapped) return queue;
    try {
        return cl::CommandQueue(context, device, CL_QUEUE_PROFILING_ENABLE);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "creating a command queue on " + info.name);
    }
}

void Device::Impl::check_allocation(std::uint64_t bytes, const std::string& what) const
{
    if (bytes > info.global_memory)
        throw Error(Error::Kind::Limit, what + " needs " + std::to_string(bytes) + " bytes, more than " + info.name +
                                            "'s memory (" + std::to_string(info.global_memory) + " bytes)");
    if (bytes > info.max_allocation)
        throw Error(Error::Kind::Limit,
                    what + " needs " + std::to_string(bytes) + " bytes, more than the largest buffer " +
                        info.name + " can allocate (" + std::to_string(info.max_allocation) + " bytes)");
}

std::uint32_t Device::Impl::loop_limit()
{
    // More trips than any kernel's loops run in one work-item on a device that does not cap them.
    constexpr cl_uint trips = 1u << 20;
    // Kept per device and driver for the process: every Device::open of it would measure the same
    // (and a simulator such as Oclgrind takes seconds to run the probe).
    static std::mutex known_mutex;
    static std::map<std::string, std::uint32_t> known;
    const std::string identity = detail::driver_identity(info);
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (measured_loop_limit != 0) return measured_loop_limit;
    }
    {
        std::lock_guard<std::mutex> lock(known_mutex);
        if (auto it = known.find(identity); it != known.end()) {
            std::lock_guard<std::mutex> own(mutex);
            return measured_loop_limit = it->second;
        }
    }
    cl::Kernel probe(program("device_probe"), "device_probe_loops");
    std::lock_guard<std::mutex> lock(mutex);
    try {
        cl_uint words[3] = {0, 0, 0};
        cl::Buffer done(context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof words, words);
        probe.setArg(0, trips);
        probe.setArg(1, done);
        queue.enqueueNDRangeKernel(probe, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
        queue.enqueueReadBuffer(done, CL_TRUE, 0, sizeof words, words);
        measured_loop_limit = words[0] >= trips ? loop_unlimited : std::max<cl_uint>(words[0], 1);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "probing the loops of " + info.name);
    }
    std::lock_guard<std::mutex> known_lock(known_mutex);
    known[identity] = measured_loop_limit;
    return measured_loop_limit;
}

bool Device::Impl::host_memory_in_place()
{
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (measured_in_place >= 0) return measured_in_place != 0;
    }
    bool in_place = false;
    if (cpu_hints()) {
        static std::mutex known_mutex;
        static std::map<std::string, bool> known;
        const std::string identity = detail::driver_identity(info);
        std::lock_guard<std::mutex> known_lock(known_mutex);
        if (auto it = known.find(identity); it != known.end()) {
            in_place = it->second;
        } else {
            try {
                cl::Kernel probe(program("device_probe"), "device_probe_in_place");
                std::lock_guard<std::mutex> lock(mutex);
                // volatile: the compiler may not assume the words unchanged across the driver's calls
                volatile cl_uint words[2] = {0, 1};
                cl::Buffer w(context, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, sizeof words,
                             const_cast<cl_uint*>(words));
                words[1] = 41; // after the buffer was made: a copying driver keeps 1
                probe.setArg(0, w);
                queue.enqueueNDRangeKernel(probe, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
                queue.finish();
                in_place = words[0] == 42;
            } catch (const cl::Error&) {
                in_place = false; // the copying path is always right
            } catch (const Error&) {
                in_place = false;
            }
            known[identity] = in_place;
        }
    }
    std::lock_guard<std::mutex> lock(mutex);
    measured_in_place = in_place ? 1 : 0;
    return in_place;
}

std::string Device::Impl::build_options(const std::string& extra) const
{
    std::string options = "-cl-std=CL1.2";
    if (info.correctly_rounded_divide_sqrt) options += " -cl-fp32-correctly-rounded-divide-sqrt";
    if (exact_float_requested()) options += " -DCLVIS_EXACT_FLOAT=1";
    if (!extra.empty()) options += " " + extra;
    return options;
}

bool Device::Impl::cpu_hints() const
{
    return info.type == DeviceType::Cpu && info.platform.find("Portable Computing Language") != std::string::npos &&
           device.getInfo<CL_DEVICE_ENDIAN_LITTLE>();
}

cl::Program Device::Impl::build_source(const std::string& name, const std::string& source, const std::string& extra)
{
    const bool verbose = build_log_requested();
    std::string options = build_options(extra) + (verbose ? "" : " -w");
    cl::Program program;
    try {
        program = cl::Program(context, source);
        const auto start = std::chrono::steady_clock::now();
        program.build({device}, options.c_str());
        if (verbose) {
            // The build's seconds: a driver's compiler on a cold cache can take longer than the work.
            char took[32];
            std::snprintf(took, sizeof took, "%.2f",
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
            std::string log = build_log(program);
            std::cerr << "clvis: built " << name << " for " << info.name << " in " << took << " s with '"
                      << options << "'"
                      << (log.find_first_not_of(" \n") == std::string::npos ? ": no messages\n" : ":\n" + log);
        }
    } catch (const cl::BuildError& e) {
        std::string log;
        for (auto& [dev, text] : e.getBuildLog()) log += text;
        throw Error(Error::Kind::Build, cl_error_name(e.err()) + " building " + name + " for " + info.name +
                                            " with '" + options + "':\n" + log);
    } catch (const cl::Error& e) {
        std::string log = build_log(program);
        throw Error(Error::Kind::Build, cl_error_name(e.err()) + " building " + name + " for " + info.name +
                                            " with '" + options + "'" + (log.empty() ? "" : ":\n" + log));
    }
    return program;
}

cl::Program Device::Impl::program(const std::string& name, const std::string& extra)
{
    std::string options = build_options(extra);
    std::lock_guard<std::mutex> lock(mutex);
    std::string key = name + "\n" + options;
    if (auto it = programs.find(key); it != programs.end()) return it->second;

    const std::string& source = embedded_kernel(name);
    std::string hash = hex64(std::hash<std::string>{}(source + "\n" + options + "\n" + info.name +
                                                      "\n" + info.driver_version + "\n" + info.platform));
    ProgramCache cache(name, hash, driver_caches_programs(info));
    cl::Program program;
    if (auto cached = cache.load(context, device, options)) {
        program = *cached;
    } else {
        program = build_source("kernels/" + name + ".cl", source, extra);
        cache.built(program);
    }
    programs.emplace(key, program);
    return program;
}

} // namespace clvis
