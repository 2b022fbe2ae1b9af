// RasterMapping::Auto (raster_tune.hpp): the key that a raster mapping depends on, and its
// measurement, a fixed synthetic frame drawn with each mapping by a Renderer of its own.
#include "render/raster_tune.hpp"

#include "raster/raster_pipeline.hpp"
#include "render/tune_workload.hpp"

#include <string>

namespace clvis::detail {

namespace {

/// The tuning frames of the raster path drawn with `mapping` (render/tune_workload.hpp).
double measure_mapping(const Device& device, const RenderOptions& base, RasterMapping mapping)
{
    RenderOptions o;
    o.tile_size = base.tile_size;
    o.raster_atomics = base.raster_atomics;
    o.raster_mapping = mapping;
    return measure_tune_frames(device, o, Path::Raster);
}

} // namespace

TuneRequest raster_mapping_request(const Device& device, const RenderOptions& options)
{
    TuneRequest r;
    r.name = "raster_mapping";
    r.key = tune_device_key(device, {"raster_setup", "raster_bin", "raster_fine", "visibility_clear"});
    r.key.insert(r.key.end(), {{"depth_test", raster_owned(device.info(), options) ? "owned" : "atomics"},
                               {"tile", std::to_string(1 << raster_tile_log2(options))},
                               {"workload", tune_workload_name()}});
    r.candidates = {to_string(RasterMapping::Square), to_string(RasterMapping::Pixel)};
    r.measure = [device, options](const std::string& candidate) {
        return measure_mapping(device, options, raster_mapping_from_string(candidate));
    };
    return r;
}

RasterMappingChoice choose_raster_mapping(const Device& device, const RenderOptions& options)
{
    if (options.raster_mapping != RasterMapping::Auto) return {options.raster_mapping};
    TunedMapping t = tune_mapping(raster_mapping_request(device, options));
    return {raster_mapping_from_string(t.choice), t.source, t.ms[0], t.ms[1]};
}

} // namespace clvis::detail
