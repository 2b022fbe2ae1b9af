// OpenCL's C++ bindings with their defaults (OpenCL 3.0), included before clvis: the application
// makes the context, queue and buffer; clvis renders into the buffer.
//
//   opencl_first MESH
#include <CL/opencl.hpp>

#include <clvis/clvis.hpp>

#include <cstdio>
#include <vector>

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s MESH\n", argv[0]);
        return 2;
    }
    try {
        clvis::Device picked = clvis::Device::open();
        cl::Device device(picked.id(), true);
        cl::Context context(device);
        cl::CommandQueue queue(context, device);
        const int width = 64, height = 48;
        cl::Buffer keys(context, CL_MEM_READ_WRITE, sizeof(cl_ulong) * width * height);

        clvis::Scene scene;
        scene.add_mesh(clvis::load_mesh(argv[1]));
        clvis::Camera camera = clvis::Camera::framing(scene.bounds());
        clvis::Device mine = clvis::Device::wrap(context(), queue());
        clvis::Renderer renderer(mine, scene);
        clvis::VisibilityBuffer target = clvis::VisibilityBuffer::wrap(mine, keys(), width, height);
        renderer.render(camera, clvis::Path::Raster, target);
        std::vector<cl_ulong> host(std::size_t(width) * height);
        queue.enqueueReadBuffer(keys, CL_TRUE, 0, host.size() * sizeof(cl_ulong), host.data());
        std::size_t covered = 0;
        for (cl_ulong k : host) covered += (k & 0xFFFFFFFFu) != clvis::background_id;
        std::printf("opencl.hpp first: %zu of %zu pixels covered\n", covered, host.size());
        if (covered == 0) return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "opencl_first: %s\n", e.what());
        return 1;
    }
    return 0;
}
