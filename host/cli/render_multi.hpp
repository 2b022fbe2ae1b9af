// clvis render --devices SPEC,SPEC,...: one frame drawn by several devices of this process
// (MultiDeviceRenderer), their screen tiles handed out dynamically; writes --ids/--depth and the
// map of which device drew each tile (--device-map), and says each device's share.
#pragma once

#include <clvis/clvis.hpp>

#include <string>
#include <vector>

namespace clvis::cli {

struct MultiRequest {
    std::vector<std::string> specs; ///< one Device::open spec per device, in order
    const SceneFile* file = nullptr;
    double load_ms = 0;
    Camera camera;
    int width = 0, height = 0;
    Path path = Path::Raster;
    RenderOptions options;
    int screen_tile = 64;
    std::string ids, depth, device_map;
    int repeat = 0;
    bool json = false, quiet = false;
};

/// Splits "0,1" or "cpu,gpu" into specs; Error(InvalidArgument) naming --devices for an empty one.
std::vector<std::string> device_specs(const std::string& list);

void render_multi_device(const MultiRequest& request);

} // namespace clvis::cli
