// RasterMapping::Auto: the raster fine stage's mapping chosen per device by measurement, through
// the tuner (runtime/tune_cache.hpp). Consumed by the Renderer when it first needs the raster path.
#pragma once

#include "runtime/tune_cache.hpp"

#include <clvis/device.hpp>
#include <clvis/render_options.hpp>

namespace clvis::detail {

/// The tuner's request for Auto under `options` on `device`: named "raster_mapping", keyed by the
/// device, platform and driver, a hash of the raster kernels' sources and build options with the
/// library version, the depth test (atomics or tile ownership) and the tile size in pixels;
/// candidates "square" and "pixel", each measured as the fastest of up to 3 frames (after one
/// untimed; fewer once they took 500 ms) of a fixed synthetic scene (a UV sphere over a height
/// field, 640x480) rendered by a Renderer of its own.
TuneRequest raster_mapping_request(const Device& device, const RenderOptions& options);

/// The mapping the raster path runs: options.raster_mapping unless Auto, else the tuner's choice
/// with the settings of the environment (TuneSettings::from_environment).
RasterMappingChoice choose_raster_mapping(const Device& device, const RenderOptions& options);

} // namespace clvis::detail
