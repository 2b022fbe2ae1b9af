// Misuse of the public objects: empty and moved-from handles, buffers of another context, queues
// without profiling. Each answers with clvis::Error (invalid argument) naming the object and the
// call, never with a crash or silence.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <CL/cl.h>

#include <string>
#include <utility>

using namespace clvis;

namespace {

/// Runs `fn`, which must throw Error(InvalidArgument) whose message contains `call`.
template <class Fn> void refused(Fn&& fn, const std::string& call)
{
    INFO(call);
    try {
        fn();
        FAIL("accepted: " << call);
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::InvalidArgument);
        CHECK_THAT(e.what(), Catch::Contains(call));
    }
}

Scene one_triangle()
{
    Scene s;
    MeshData m;
    m.positions = {-1, -1, -3, 1, -1, -3, 0, 1, -3};
    m.indices = {0, 1, 2};
    s.add_mesh(m);
    return s;
}

Camera front() { return Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.1, 10); }

} // namespace

TEST_CASE("an empty Device answers every call with an error naming the call")
{
    Device empty;
    refused([&] { empty.info(); }, "Device::info");
    refused([&] { empty.context(); }, "Device::context");
    refused([&] { empty.id(); }, "Device::id");
    refused([&] { empty.queue(); }, "Device::queue");
    refused([&] { VisibilityBuffer(empty, 4, 4); }, "VisibilityBuffer");
    refused([&] { VisibilityBuffer::wrap(empty, nullptr, 4, 4); }, "VisibilityBuffer::wrap");
    refused([&] { Renderer(empty, one_triangle()); }, "Renderer");
}

TEST_CASE("a moved-from Device is empty and says so", "[device]")
{
    Device d = Device::open();
    Device taken = std::move(d);
    CHECK(taken);
    CHECK_FALSE(d);
    refused([&] { d.info(); }, "Device::info");
    refused([&] { VisibilityBuffer(d, 4, 4); }, "VisibilityBuffer");
}

TEST_CASE("an empty or moved-from VisibilityBuffer refuses reads by name", "[device]")
{
    VisibilityBuffer empty;
    CHECK(empty.empty());
    refused([&] { empty.keys(); }, "VisibilityBuffer::keys");
    refused([&] { empty.read(); }, "VisibilityBuffer::read");
    refused([&] { empty.read_keys(); }, "VisibilityBuffer::read_keys");

    VisibilityBuffer owned(Device::open(), 8, 4);
    VisibilityBuffer taken = std::move(owned);
    CHECK(taken.width() == 8);
    CHECK(owned.empty());
    CHECK(owned.width() == 0);
    CHECK(owned.height() == 0);
    refused([&] { owned.read(); }, "VisibilityBuffer::read");
    refused([&] { owned.keys(); }, "VisibilityBuffer::keys");

    Renderer r(Device::open(), one_triangle());
    refused([&] { r.render(front(), Path::Raster, owned); }, "Renderer::render");
    refused([&] { shade(r, owned, front()); }, "shade");
}

TEST_CASE("a moved-from Renderer answers every call with an error naming it", "[device]")
{
    Scene s = one_triangle();
    Renderer r(Device::open(), s);
    Renderer taken = std::move(r);
    CHECK(taken.render(front(), 4, 4, Path::Ray).read().id(2, 2) == 0);
    VisibilityBuffer vis = taken.render(front(), 4, 4, Path::Raster);
    refused([&] { r.render(front(), 4, 4, Path::Raster); }, "Renderer::render");
    refused([&] { r.render(front(), Path::Ray, vis); }, "Renderer::render");
    refused([&] { r.prepare(Path::Ray); }, "Renderer::prepare");
    refused([&] { r.update(s); }, "Renderer::update");
    refused([&] { r.last_frame(); }, "Renderer::last_frame");
    refused([&] { r.bvh_stats(); }, "Renderer::bvh_stats");
    refused([&] { r.options(); }, "Renderer::options");
    refused([&] { r.device(); }, "Renderer::device");
    refused([&] { shade(r, vis, front()); }, "shade");
}

TEST_CASE("a moved-from Referee answers every call with an error naming it")
{
    Referee ref(one_triangle(), front(), 4, 4);
    Referee taken = std::move(ref);
    CHECK(taken.reference(2, 2) == 0);
    HostVisibility h;
    refused([&] { ref.width(); }, "Referee::width");
    refused([&] { ref.height(); }, "Referee::height");
    refused([&] { ref.classify(0, 1, 1); }, "Referee::classify");
    refused([&] { ref.judge(1, 1, 0); }, "Referee::judge");
    refused([&] { ref.reference(1, 1); }, "Referee::reference");
    refused([&] { ref.compare(h, h); }, "Referee::compare");
    refused([&] { ref.check(h); }, "Referee::check");
}

TEST_CASE("a cl_mem made in another context is refused by name", "[device]")
{
    Device a = Device::open();
    Device b = Device::open(); // the same device, but a context of its own
    REQUIRE(a.context() != b.context());
    cl_int err = CL_SUCCESS;
    cl_mem foreign = clCreateBuffer(b.context(), CL_MEM_READ_WRITE, 16 * 16 * 8, nullptr, &err);
    REQUIRE(err == CL_SUCCESS);
    try {
        VisibilityBuffer::wrap(a, foreign, 16, 16);
        FAIL("a buffer of another context was wrapped");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::InvalidArgument);
        CHECK_THAT(e.what(), Catch::Contains("VisibilityBuffer::wrap") && Catch::Contains("another OpenCL context"));
    }
    VisibilityBuffer mine = VisibilityBuffer::wrap(b, foreign, 16, 16);
    clReleaseMemObject(foreign);
    Renderer r(a, one_triangle());
    CHECK_THROWS_WITH(r.render(front(), Path::Raster, mine), Catch::Contains("another OpenCL context"));
}

TEST_CASE("a wrapped queue without profiling reports stage times as absent", "[device]")
{
    Device own = Device::open();
    cl_int err = CL_SUCCESS;
    cl_command_queue plain = clCreateCommandQueue(own.context(), own.id(), 0, &err);
    REQUIRE(err == CL_SUCCESS);
    Device wrapped = Device::wrap(own.context(), plain);
    clReleaseCommandQueue(plain);

    Renderer profiled(own, one_triangle());
    profiled.render(front(), 8, 8, Path::Raster);
    CHECK(profiled.last_frame().stages_measured);
    CHECK_FALSE(profiled.last_frame().stages.empty());

    Renderer unprofiled(wrapped, one_triangle());
    for (Path p : {Path::Raster, Path::Ray}) {
        HostVisibility h = unprofiled.render(front(), 8, 8, p).read();
        CHECK(h.id(4, 4) == 0);
        CHECK_FALSE(unprofiled.last_frame().stages_measured);
        CHECK(unprofiled.last_frame().stages.empty());
        CHECK(unprofiled.last_frame().frame_ms > 0);
    }
}
