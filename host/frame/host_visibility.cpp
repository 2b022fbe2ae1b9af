// Keys read back from the device, split into ids and view depths with the kernels' own helpers.
#include "shared/visibility.h"

#include <clvis/error.hpp>
#include <clvis/host_visibility.hpp>

#include <string>

namespace clvis {

static_assert(background_key == CLVIS_BACKGROUND_KEY, "host and kernels agree on the background");

HostVisibility split_keys(const std::uint64_t* keys, int width, int height, int samples, int layers)
{
    HostVisibility v;
    v.width = width;
    v.height = height;
    v.samples = samples;
    v.layers = layers;
    std::size_t plane = std::size_t(width) * std::size_t(height) * std::size_t(samples);
    std::size_t n = plane * std::size_t(layers);
    v.ids.resize(n);
    v.depth.resize(n);
    for (std::size_t i = 0; i < plane; ++i)
        for (std::size_t k = 0; k < std::size_t(layers); ++k) {
            std::uint64_t key = keys[k * plane + i];
            v.ids[i * layers + k] = clvis_key_id(key);
            v.depth[i * layers + k] = clvis_key_depth(key);
        }
    return v;
}

HostVisibility HostVisibility::layer(int k) const
{
    if (k < 0 || k >= layers)
        throw Error(Error::Kind::InvalidArgument, "HostVisibility::layer: layer " + std::to_string(k) +
                                                      " of a buffer of " + std::to_string(layers) + " layer(s)");
    HostVisibility v;
    v.width = width;
    v.height = height;
    v.samples = samples;
    std::size_t plane = std::size_t(width) * std::size_t(height) * std::size_t(samples);
    v.ids.resize(plane);
    v.depth.resize(plane);
    for (std::size_t i = 0; i < plane; ++i) {
        v.ids[i] = ids[i * layers + k];
        v.depth[i] = depth[i * layers + k];
    }
    return v;
}

} // namespace clvis
