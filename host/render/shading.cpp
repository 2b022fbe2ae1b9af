// Shading over a visibility buffer (kernels/shade.cl): the buffer's keys and the renderer's
// resident scene in, an RGBA8 image out.
#include "render/renderer_impl.hpp"
#include "render/sample_scene.hpp"

#include "shared/shade.h"

#include <clvis/shading.hpp>

namespace clvis {

using namespace detail;

Image shade(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera, const ShadeOptions& options)
{
    Renderer::Impl& r = RendererAccess::of(renderer, "shade");
    camera.validate();
    if (vis.empty()) throw Error(Error::Kind::InvalidArgument, "shade: empty visibility buffer");
    if (vis.device().context() != r.device.context())
        throw Error(Error::Kind::InvalidArgument, "shade: the buffer belongs to another OpenCL context");
    Vec3 light = options.light_direction;
    if (!is_finite(light) || !(length(light) > 0))
        throw Error(Error::Kind::InvalidArgument, "shade: the light direction must be a finite non-zero vector");
    int mode = options.mode == ShadeMode::Lambert ? CLVIS_SHADE_LAMBERT
               : options.mode == ShadeMode::Depth ? CLVIS_SHADE_DEPTH
                                                   : CLVIS_SHADE_IDS;
    return error_boundary("shading a visibility buffer", [&] {
        Image image;
        image.width = vis.width();
        image.height = vis.height();
        image.rgba.resize(std::size_t(image.width) * image.height * 4);
        cl::Kernel kernel(r.dev().program("shade"), "shade");
        cl::Buffer out(r.dev().context, CL_MEM_WRITE_ONLY, image.rgba.size());
        clvis_camera_gpu g = make_gpu_camera(camera, image.width, image.height);
        g.sample_log2 = samples_log2(vis.samples()); // the mean of each pixel's samples
        // A scene with instances: only the triangles the keys name, and only for Lambert.
        SampleScene scene = sample_scene(r, vis, mode == CLVIS_SHADE_LAMBERT);
        kernel.setArg(0, scene.keys);
        kernel.setArg(1, out);
        kernel.setArg(2, sizeof g, &g);
        scene.scene.set_args(kernel, 3);
        kernel.setArg(8, cl_int(mode));
        kernel.setArg(9, float(light.x));
        kernel.setArg(10, float(light.y));
        kernel.setArg(11, float(light.z));
        r.queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                                     cl::NDRange(round_up(image.width, 8), round_up(image.height, 8)),
                                     cl::NDRange(8, 8));
        r.queue.enqueueReadBuffer(out, CL_TRUE, 0, image.rgba.size(), image.rgba.data());
        return image;
    });
}

} // namespace clvis
