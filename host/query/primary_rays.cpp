// Primary rays as arrays (include/clvis/primary_rays.hpp): the float32 camera of the kernels
// (make_gpu_camera) and the shared header's clvis_primary_ray at each sample's raster position,
// compiled on the host without FMA contraction (CMakeLists.txt's -ffp-contract=off) and with
// IEEE division, which are the device's operations under the program options every kernel gets
// (-cl-fp32-correctly-rounded-divide-sqrt where the device offers it: host/runtime/device.cpp).
// RayQuery::primary_rays writes the same records on the device (kernels/ray_generate.cl).
#include "frame/frame.hpp"
#include "query/ray_query_impl.hpp"

#include <clvis/error.hpp>
#include <clvis/primary_rays.hpp>
#include <clvis/render_options.hpp>

#include "shared/camera.h"
#include "shared/ray_query.h"
#include "shared/raster.h"

namespace clvis {

namespace {

/// The checks of both forms; returns log2 of the samples.
int check(const Camera& camera, int width, int height, int samples)
{
    camera.validate();
    if (width < 1 || height < 1 || width > CLVIS_MAX_IMAGE_SIZE || height > CLVIS_MAX_IMAGE_SIZE)
        throw Error(Error::Kind::InvalidArgument, "primary_rays: the image size must be from 1 to " +
                                                      std::to_string(CLVIS_MAX_IMAGE_SIZE) + " a side, got " +
                                                      std::to_string(width) + "x" + std::to_string(height));
    return samples_log2(samples);
}

} // namespace

void primary_rays(const Camera& camera, int width, int height, int samples, RayRecord* out)
{
    const int log2n = check(camera, width, height, samples);
    if (!out) throw Error(Error::Kind::InvalidArgument, "primary_rays: no storage");
    clvis_camera_gpu g = detail::make_gpu_camera(camera, width, height);
    g.sample_log2 = log2n;
    float fx[16], fy[16];
    for (int k = 0; k < samples; ++k) {
        g.sample = k;
        clvis_vec2 f = clvis_camera_sample(g);
        fx[k] = f.x;
        fy[k] = f.y;
    }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int k = 0; k < samples; ++k) {
                clvis_vec3 o, d;
                clvis_primary_ray(g, (float)x + fx[k], (float)y + fy[k], &o, &d);
                *out++ = RayRecord{o.x, o.y, o.z, g.near_d, d.x, d.y, d.z, g.far_d};
            }
}

std::vector<RayRecord> primary_rays(const Camera& camera, int width, int height, int samples)
{
    check(camera, width, height, samples);
    std::vector<RayRecord> rays(std::size_t(width) * std::size_t(height) * std::size_t(samples));
    primary_rays(camera, width, height, samples, rays.data());
    return rays;
}

void RayQuery::primary_rays(const Camera& camera, int width, int height, int samples, const DeviceRays& out)
{
    const int log2n = check(camera, width, height, samples);
    const std::size_t n = std::size_t(width) * std::size_t(height) * std::size_t(samples);
    Impl& m = *impl_;
    if (out.count < n)
        throw Error(Error::Kind::InvalidArgument, "RayQuery::primary_rays: the buffer holds " +
                                                      std::to_string(out.count) + " rays, the image's samples are " +
                                                      std::to_string(n));
    Impl::Source s = m.source(RayInput(out)); // the context, the stride and the buffer's size
    clvis_camera_gpu g = detail::make_gpu_camera(camera, width, height);
    g.sample_log2 = log2n;
    try {
        if (!m.generate_primary())
            m.generate_primary = cl::Kernel(m.r.dev().program("ray_generate"), "ray_generate_primary");
        cl::Kernel& k = m.generate_primary;
        k.setArg(0, sizeof g, &g);
        k.setArg(1, cl::Buffer(out.buffer, true));
        k.setArg(2, cl_int(out.layout == RayLayout::AoS ? CLVIS_LAYOUT_AOS : CLVIS_LAYOUT_SOA));
        k.setArg(3, cl_ulong(s.stride));
        m.r.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(std::size_t(width), std::size_t(height),
                                                                     std::size_t(samples)));
        m.r.queue.finish();
    } catch (const cl::Error& e) {
        detail::throw_cl_error(e, "writing primary rays on the device");
    }
}

} // namespace clvis
