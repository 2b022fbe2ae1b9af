// clvis render --devices SPEC,SPEC,...: one frame drawn by several devices of this process
// (MultiDeviceRenderer), their screen tiles handed out dynamically; writes --ids/--depth and the
// map of which device drew each tile (--device-map), and says each device's share.
#pragma once

#include "render_spread.hpp"

#include <string>
#include <vector>

namespace clvis::cli {

/// Splits "0,1" or "cpu,gpu" into specs; Error(InvalidArgument) naming --devices for an empty one.
std::vector<std::string> device_specs(const std::string& list);

/// Renders the request's one camera by `path` on the devices of its --devices.
void render_multi_device(const SpreadRequest& request, Path path);

} // namespace clvis::cli
