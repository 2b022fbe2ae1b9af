// A mesh built in memory (a procedural sphere) rendered into the caller's own OpenCL buffer:
// the application owns the context, the queue and the cl_mem, and reads the result itself, as it
// would hand it to its own kernels. No copy through clvis.
//
//   memory_sphere [TRIANGLES]
#define CL_TARGET_OPENCL_VERSION 120 // the application's choice: clvis's headers make none
#include <CL/cl.h>

#include <clvis/clvis.hpp>

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

void check(cl_int err, const char* what)
{
    if (err != CL_SUCCESS) {
        std::fprintf(stderr, "memory_sphere: %s failed (%d)\n", what, err);
        std::exit(1);
    }
}

} // namespace

int main(int argc, char** argv)
{
    std::size_t triangles = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 20000;
    try {
        // The application's own OpenCL objects, on the device clvis would pick.
        clvis::Device picked = clvis::Device::open();
        cl_device_id device_id = picked.id();
        cl_int err = CL_SUCCESS;
        cl_context context = clCreateContext(nullptr, 1, &device_id, nullptr, nullptr, &err);
        check(err, "clCreateContext");
        cl_command_queue queue = clCreateCommandQueue(context, device_id, CL_QUEUE_PROFILING_ENABLE, &err);
        check(err, "clCreateCommandQueue");
        const int width = 256, height = 256;
        cl_mem keys = clCreateBuffer(context, CL_MEM_READ_WRITE, sizeof(cl_ulong) * width * height, nullptr, &err);
        check(err, "clCreateBuffer");

        // A scene from memory: positions and indices, here a sphere moved in front of the camera.
        clvis::MeshData sphere = clvis::make_uv_sphere(triangles);
        clvis::Mat4 move;
        move(2, 3) = -3; // translate z by -3
        clvis::Scene scene;
        scene.add_mesh(sphere.positions.data(), sphere.vertex_count(), sphere.indices.data(),
                       sphere.triangle_count(), move, "sphere");

        clvis::Device device = clvis::Device::wrap(context, queue);
        clvis::Renderer renderer(device, scene);
        clvis::Camera camera = clvis::Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.1, 10);
        clvis::VisibilityBuffer target = clvis::VisibilityBuffer::wrap(device, keys, width, height);
        for (clvis::Path path : {clvis::Path::Raster, clvis::Path::Ray}) {
            renderer.render(camera, path, target);
            // The application reads its own buffer: (depth bits << 32) | triangle id per pixel.
            std::vector<cl_ulong> host(std::size_t(width) * height);
            check(clEnqueueReadBuffer(queue, keys, CL_TRUE, 0, host.size() * 8, host.data(), 0, nullptr, nullptr),
                  "clEnqueueReadBuffer");
            std::size_t covered = 0;
            for (cl_ulong k : host) covered += (k & 0xFFFFFFFFu) != clvis::background_id;
            // The sphere of radius 1 at distance 3 under a 60 degree view covers a disc of radius
            // tan(asin(1/3)) / tan(30 deg) of the half-height: about 30% of the square image.
            std::printf("%s: %zu of %d pixels covered in %.2f ms\n", clvis::to_string(path), covered,
                        width * height, renderer.last_frame().frame_ms);
            if (covered < std::size_t(0.25 * width * height) || covered > std::size_t(0.35 * width * height)) {
                std::fprintf(stderr, "memory_sphere: unexpected coverage\n");
                return 1;
            }
        }
        clReleaseMemObject(keys);
        clReleaseCommandQueue(queue);
        clReleaseContext(context);
        return 0;
    } catch (const clvis::Error& e) {
        std::fprintf(stderr, "memory_sphere: %s\n", e.what());
        return 1;
    }
}
