// The error boundary every public entry runs inside (host/runtime/cl_runtime.hpp): no cl::Error
// or std::bad_alloc leaves the library, library errors pass unchanged. Host-only: the OpenCL
// failures are thrown by hand, as a driver would throw them from deep inside a path.
#include "catch.hpp"

#include "runtime/cl_runtime.hpp"

#include <new>
#include <string>

using namespace clvis;
using detail::error_boundary;

TEST_CASE("an OpenCL error at a public entry becomes a device error naming it")
{
    try {
        error_boundary("preparing the ray path", [] { throw cl::Error(CL_INVALID_KERNEL_NAME, "clCreateKernel"); });
        FAIL("no error thrown");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Device);
        std::string what = e.what();
        CHECK(what.find("preparing the ray path") != std::string::npos);
        CHECK(what.find("clCreateKernel") != std::string::npos);
        CHECK(what.find("CL_INVALID_KERNEL_NAME") != std::string::npos);
    }
}

TEST_CASE("host memory running out at a public entry becomes a limit error")
{
    try {
        error_boundary("making a Renderer", [] { throw std::bad_alloc(); });
        FAIL("no error thrown");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Limit);
        CHECK(std::string(e.what()).find("making a Renderer") != std::string::npos);
    }
}

TEST_CASE("library errors and results pass through the error boundary unchanged")
{
    CHECK(error_boundary("x", [] { return 42; }) == 42);
    try {
        error_boundary("x", [] { throw Error(Error::Kind::InvalidArgument, "bad tile size"); });
        FAIL("no error thrown");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::InvalidArgument);
        CHECK(std::string(e.what()) == "bad tile size");
    }
}
