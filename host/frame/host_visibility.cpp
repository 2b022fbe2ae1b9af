// Keys read back from the device, split into ids and view depths with the kernels' own helpers.
#include "shared/visibility.h"

#include <clvis/host_visibility.hpp>

namespace clvis {

static_assert(background_key == CLVIS_BACKGROUND_KEY, "host and kernels agree on the background");

HostVisibility split_keys(const std::uint64_t* keys, int width, int height, int samples)
{
    HostVisibility v;
    v.width = width;
    v.height = height;
    v.samples = samples;
    std::size_t n = std::size_t(width) * std::size_t(height) * std::size_t(samples);
    v.ids.resize(n);
    v.depth.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        v.ids[i] = clvis_key_id(keys[i]);
        v.depth[i] = clvis_key_depth(keys[i]);
    }
    return v;
}

} // namespace clvis
