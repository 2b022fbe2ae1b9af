// RayMapping::Auto: the ray path's primary-ray mapping chosen per device by measurement, through
// the tuner (runtime/tune_cache.hpp). Consumed by the Renderer when it first runs the ray path.
#pragma once

#include "runtime/tune_cache.hpp"

#include <clvis/device.hpp>
#include <clvis/render_options.hpp>

namespace clvis::detail {

/// The tuner's request for Auto under `options` on `device`: named "ray_mapping", keyed by the
/// device, platform and driver, a hash of both trace kernels' sources and build options with the
/// library version, and the coverage mode; candidates "packet" and "single", each measured as the
/// fastest frame of the ray path on the tuning workload (render/tune_workload.hpp).
TuneRequest ray_mapping_request(const Device& device, const RenderOptions& options);

/// The mapping the ray path runs: options.ray_mapping unless Auto, else the tuner's choice with
/// the settings of the environment (TuneSettings::from_environment).
RayMappingChoice choose_ray_mapping(const Device& device, const RenderOptions& options);

} // namespace clvis::detail
