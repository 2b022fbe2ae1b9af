// clvis included before OpenCL's C++ bindings (asked for OpenCL 2.0 here): clvis's headers must
// not have chosen an OpenCL version for this program. clvis renders; the program reads the keys
// with its own OpenCL objects.
//
//   clvis_first MESH
#include <clvis/clvis.hpp>

#define CL_HPP_TARGET_OPENCL_VERSION 200
#include <CL/opencl.hpp>

#include <cstdio>
#include <vector>

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s MESH\n", argv[0]);
        return 2;
    }
    const char* mesh = argv[1];
    try {
        clvis::Scene scene;
        scene.add_mesh(clvis::load_mesh(mesh));
        clvis::Device device = clvis::Device::open();
        clvis::Renderer renderer(device, scene);
        clvis::VisibilityBuffer vis =
            renderer.render(clvis::Camera::framing(scene.bounds()), 64, 48, clvis::Path::Ray);
        cl::CommandQueue queue(device.queue(), true);
        cl::Buffer keys(vis.keys(), true);
        std::vector<cl_ulong> host(std::size_t(vis.width()) * vis.height());
        queue.enqueueReadBuffer(keys, CL_TRUE, 0, host.size() * sizeof(cl_ulong), host.data());
        std::size_t covered = 0;
        for (cl_ulong k : host) covered += (k & 0xFFFFFFFFu) != clvis::background_id;
        std::printf("clvis first: %zu of %zu pixels covered\n", covered, host.size());
        return covered > 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "clvis_first: %s\n", e.what());
        return 1;
    }
}
