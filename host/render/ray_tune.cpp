// RayMapping::Auto (ray_tune.hpp): the key that a ray mapping depends on, and its measurement,
// the tuning frames traced with each mapping by a Renderer of its own.
#include "render/ray_tune.hpp"

#include "render/tune_workload.hpp"
#include "runtime/cl_runtime.hpp"

#include <string>

namespace clvis::detail {

RayMappingChoice choose_ray_mapping(const Device& device, const RenderOptions& options)
{
    if (options.ray_mapping != RayMapping::Auto) return {options.ray_mapping};
    // Depth layers on a device that caps a work-item's loops (llvmpipe, Device::Impl::loop_limit):
    // a packet's 16 lanes inserting into K layers each can pass the cap, and the device then ends
    // the work-item's loops silently; a ray per work-item stays far below it.
    if (options.layers > 1 &&
        DeviceAccess::of(device, "choose_ray_mapping").loop_limit() != Device::Impl::loop_unlimited)
        return {RayMapping::Single, "layers"};
    TunedMapping t = tune_mapping(ray_mapping_request(device, options));
    return {ray_mapping_from_string(t.choice), t.source, t.ms[0], t.ms[1]};
}

TuneRequest ray_mapping_request(const Device& device, const RenderOptions& options)
{
    TuneRequest r;
    r.name = "ray_mapping";
    r.candidates = {to_string(RayMapping::Packet), to_string(RayMapping::Single)};
    r.measure = [device, coverage = options.coverage](const std::string& candidate) {
        RenderOptions o;
        o.coverage = coverage;
        o.ray_mapping = ray_mapping_from_string(candidate);
        return measure_tune_frames(device, o, Path::Ray);
    };
    r.key = tune_device_key(device, {"ray_trace", "ray_trace_single"});
    r.key.insert(r.key.end(), {{"coverage", to_string(options.coverage)}, {"workload", tune_workload_name()}});
    return r;
}

} // namespace clvis::detail
