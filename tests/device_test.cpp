// The OpenCL runtime: listing and picking devices, errors that name the call and the code, build
// failures that carry the log, limits refused before allocating, and no platform at all.
#include "shared/ray_query.h"
#include "catch.hpp"

#include "runtime/cl_runtime.hpp"
#include "runtime/cpus.hpp"
#include "runtime/embedded_kernels.hpp"

#include <clvis/clvis.hpp>

#include <cstdlib>
#include <string>

using namespace clvis;

namespace {
// Read during static initialization, before any OpenCL call of this process.
const char* const caller_pocl_affinity = std::getenv("POCL_AFFINITY");
const char* const caller_pocl_max_cu = std::getenv("POCL_CPU_MAX_CU_COUNT");
const char* const caller_pocl_threads = std::getenv("POCL_MAX_PTHREAD_COUNT");
} // namespace

TEST_CASE("the CPUs a process owns are 0 to n-1, all online, at least two", "[device][pocl]")
{
    using detail::owned_cpus;
    CHECK(owned_cpus(2, {0, 1}) == 2);
    CHECK(owned_cpus(4, {3, 1, 0, 2}) == 4);
    CHECK(owned_cpus(4, {2, 3}) == 0); // taskset, cpuset, mpirun binding
    CHECK(owned_cpus(4, {0, 1}) == 0); // CPU 2 would be outside the mask
    CHECK(owned_cpus(2, {1, 2}) == 0); // CPU 0 not ours
    CHECK(owned_cpus(1, {0}) == 0);    // one CPU: nothing to place
    CHECK(owned_cpus(2, {}) == 0);     // no mask read
}

TEST_CASE("PoCL's workers are pinned only where the caller left it to clvis and every CPU is ours", "[device][pocl]")
{
    using detail::pin_pocl_workers;
    CHECK(pin_pocl_workers(nullptr, nullptr, nullptr, 2));
    CHECK_FALSE(pin_pocl_workers("0", nullptr, nullptr, 2));     // the caller's value wins
    CHECK_FALSE(pin_pocl_workers("1", nullptr, nullptr, 2));     // already theirs: left as it is
    CHECK_FALSE(pin_pocl_workers(nullptr, "8", nullptr, 2));     // a pool larger than the CPUs
    CHECK_FALSE(pin_pocl_workers(nullptr, nullptr, "8", 2));     // the same by the older name
    CHECK(pin_pocl_workers(nullptr, "2", nullptr, 2));           // a pool within them
    CHECK(pin_pocl_workers(nullptr, "1", "2", 4));
    CHECK_FALSE(pin_pocl_workers(nullptr, "0", nullptr, 2));
    CHECK_FALSE(pin_pocl_workers(nullptr, "2x", nullptr, 2));    // not a number: PoCL's to read
    CHECK_FALSE(pin_pocl_workers(nullptr, "", nullptr, 2));
    CHECK_FALSE(pin_pocl_workers(nullptr, nullptr, nullptr, 0)); // the CPUs are not all ours

    // This process: listing the devices made the decision once, before PoCL started its workers.
    (void)list_devices();
    const char* now = std::getenv("POCL_AFFINITY");
    if (caller_pocl_affinity) {
        REQUIRE(now != nullptr);
        CHECK(std::string(now) == caller_pocl_affinity);
    } else {
        bool pinned = pin_pocl_workers(nullptr, caller_pocl_max_cu, caller_pocl_threads, detail::owned_cpus());
        CHECK((now != nullptr) == pinned);
        if (now) CHECK(std::string(now) == "1");
    }
}

TEST_CASE("the test device is PoCL's CPU device with 64-bit atomics", "[device][pocl]")
{
    auto devices = list_devices();
    REQUIRE_FALSE(devices.empty());
    Device d = Device::open(); // ctest pins CLVIS_DEVICE=cpu
    CHECK(d.info().type == DeviceType::Cpu);
    CHECK(d.info().int64_atomics);
    CHECK(d.info().compute_units >= 1);
    CHECK(d.info().max_allocation > 0);
    CHECK(d.context() != nullptr);
    CHECK(d.queue() != nullptr);
}

TEST_CASE("devices are picked by index, type and name, and a bad spec is named", "[device][rusticl]")
{
    auto devices = list_devices();
    Device by_index = Device::open("0");
    CHECK(by_index.info().name == devices[0].name);
    Device by_type = Device::open("cpu");
    CHECK(by_type.info().type == DeviceType::Cpu);
    std::string part = by_type.info().name.substr(0, 4);
    CHECK(Device::open(part).info().name.find(part) != std::string::npos);
    try {
        Device::open("no-such-device-xyz");
        FAIL("opened a device that does not exist");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Device);
        CHECK(std::string(e.what()).find("no-such-device-xyz") != std::string::npos);
    }
    try {
        Device::open("999");
        FAIL("opened a device index out of range");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::InvalidArgument);
        CHECK(std::string(e.what()).find("999") != std::string::npos);
    }
}

TEST_CASE("a wrapped context and queue are used as they are", "[device][rusticl]")
{
    Device own = Device::open();
    Device wrapped = Device::wrap(own.context(), own.queue());
    CHECK(wrapped.context() == own.context());
    CHECK(wrapped.queue() == own.queue());
    CHECK(wrapped.info().name == own.info().name);
    CHECK_THROWS_AS(Device::wrap(nullptr, own.queue()), Error);
    Device empty;
    CHECK_FALSE(empty);
    CHECK_THROWS_AS(empty.info(), Error);
}

TEST_CASE("every embedded kernel builds on the device", "[device][rusticl]")
{
    Device d = Device::open();
    // Build-time parameters that a pipeline derives from its data (the ray stack from the BVH's
    // depth; the query kind of a ray query); the kernel refuses to build without them. The raster
    // path's atomic depth test only where the device has 64-bit atomics, tile ownership everywhere.
    auto options = [&d](const std::string& name) -> std::vector<std::string> {
        if (name == "raster_setup") {
            if (d.info().int64_atomics) return {"", "-DCLVIS_RASTER_OWNED"};
            return {"-DCLVIS_RASTER_OWNED"};
        }
        if (name == "ray_trace" || name == "ray_trace_single") return {"-DCLVIS_RAY_STACK=64"};
        if (name == "ray_query") {
            std::vector<std::string> kinds;
            for (int kind : {CLVIS_QUERY_CLOSEST, CLVIS_QUERY_ANY, CLVIS_QUERY_COUNT})
                kinds.push_back("-DCLVIS_QUERY=" + std::to_string(kind) + " -DCLVIS_RAY_STACK=64");
            return kinds;
        }
        return {""};
    };
    for (const auto& k : detail::embedded_kernels()) {
        for (const std::string& o : options(k.name)) {
            INFO("kernel file " << k.name << " with '" << o << "'");
            CHECK_NOTHROW(detail::DeviceAccess::of(d, "test").program(k.name, o));
        }
    }
}

TEST_CASE("a kernel that fails to build raises an error carrying the build log", "[device][rusticl]")
{
    Device d = Device::open();
    try {
        detail::DeviceAccess::of(d, "test").build_source(
            "broken.cl", "__kernel void broken(__global int* p) { p[0] = undeclared_name; }", "");
        FAIL("a broken kernel built");
    } catch (const Error& e) {
        std::string msg = e.what();
        CHECK(e.kind() == Error::Kind::Build);
        CHECK(msg.find("broken.cl") != std::string::npos);
        CHECK(msg.find("CL_BUILD_PROGRAM_FAILURE") != std::string::npos);
        CHECK(msg.find("undeclared_name") != std::string::npos); // the compiler's own words
    }
    CHECK_THROWS_AS(detail::embedded_kernel("no_such_kernel"), Error);
}

TEST_CASE("OpenCL error codes are named, never bare numbers", "[device][rusticl]")
{
    CHECK(detail::cl_error_name(CL_OUT_OF_RESOURCES) == "CL_OUT_OF_RESOURCES");
    CHECK(detail::cl_error_name(CL_INVALID_WORK_GROUP_SIZE) == "CL_INVALID_WORK_GROUP_SIZE");
    CHECK(detail::cl_error_name(-9999) == "CL_UNKNOWN_ERROR(-9999)");
}

TEST_CASE("absurd and empty image sizes are refused before any allocation", "[device][rusticl]")
{
    Device d = Device::open();
    for (auto [w, h] : {std::pair{0, 10}, {10, 0}, {-5, 10}}) {
        try {
            VisibilityBuffer v(d, w, h);
            FAIL("allocated a " << w << "x" << h << " buffer");
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::InvalidArgument);
            CHECK(std::string(e.what()).find("image size") != std::string::npos);
        }
    }
    try {
        VisibilityBuffer v(d, 100000, 100000);
        FAIL("allocated a 100000x100000 buffer");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Limit);
        CHECK(std::string(e.what()).find("100000x100000") != std::string::npos);
    }
}

// Run by its own CTest entry with OCL_ICD_VENDORS pointing at an empty folder: the ICD loader
// then finds no platform at all.
TEST_CASE("with no OpenCL platform the error says how to install one", "[.no_platform]")
{
    try {
        list_devices();
        FAIL("found an OpenCL platform although OCL_ICD_VENDORS names an empty folder");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Device);
        CHECK(std::string(e.what()).find("no OpenCL platform") != std::string::npos);
        CHECK(std::string(e.what()).find("pocl-opencl-icd") != std::string::npos);
    }
    CHECK_THROWS_AS(Device::open(), Error);
}
