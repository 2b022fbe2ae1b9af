// The ambient-occlusion image of clvis render --ao (render_ao.hpp): rays cast on the device by
// RayQuery, the visible fraction turned into grey levels on the host.
#include "render_ao.hpp"

#include <cstdio>
#include <iostream>

namespace clvis::cli {

Image ao_image(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera, int rays, bool quiet)
{
    RayQuery query(renderer);
    AoOptions o;
    o.rays = rays;
    PixelRays ao = query.ambient_occlusion(vis, camera, o);
    if (!quiet) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "clvis: ambient occlusion: %zu rays (covered pixels only) in %.2f ms on the device (%.2f Mrays/s), "
                      "%.2f ms in all",
                      ao.stats.rays, ao.stats.device_ms, double(ao.stats.rays) / (ao.stats.device_ms * 1e3),
                      ao.stats.wall_ms);
        std::cerr << buf << "\n";
    }
    HostVisibility ids = vis.read();
    Image img;
    img.width = ao.width;
    img.height = ao.height;
    img.rgba.resize(ao.value.size() * 4);
    for (std::size_t i = 0; i < ao.value.size(); ++i) {
        auto g = ids.ids[i] == background_id ? std::uint8_t(0) : std::uint8_t(ao.value[i] * 255.0f + 0.5f);
        img.rgba[4 * i] = img.rgba[4 * i + 1] = img.rgba[4 * i + 2] = g;
        img.rgba[4 * i + 3] = 255;
    }
    return img;
}

} // namespace clvis::cli
