// Primary rays as arrays (include/clvis/primary_rays.hpp): the float32 camera of the kernels
// (make_gpu_camera) and the shared header's clvis_primary_ray at each sample's raster position,
// compiled on the host without FMA contraction (CMakeLists.txt's -ffp-contract=off) and with
// IEEE division, which are the device's operations under the program options every kernel gets
// (-cl-fp32-correctly-rounded-divide-sqrt where the device offers it: host/runtime/device.cpp).
#include "frame/frame.hpp"

#include <clvis/error.hpp>
#include <clvis/primary_rays.hpp>
#include <clvis/render_options.hpp>

#include "shared/camera.h"
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

} // namespace clvis
