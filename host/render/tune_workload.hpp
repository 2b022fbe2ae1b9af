// The workload that the mapping tuners (render/raster_tune.hpp, render/ray_tune.hpp) measure their
// candidates on: a fixed synthetic scene rendered by a Renderer of its own, timed in host wall time.
#pragma once

#include "runtime/tune_cache.hpp"

#include <clvis/device.hpp>
#include <clvis/render_options.hpp>

#include <initializer_list>
#include <string>

namespace clvis::detail {

/// Names the workload in the tuners' keys: changing the scene, the size or the timing rule below
/// changes it, so that earlier measurements are not read as this one's. CLVIS_TUNE_WORKLOAD picks
/// the workload: `full` (the default, below) or `small` (160x120, 600 triangles: for a simulator
/// or a test), each with a name of its own; any other value is an Error (InvalidArgument) naming it.
const char* tune_workload_name();

/// The start of a tuner's key: the device, platform and driver, and "kernels", a hash of the library
/// version, the device's build options and the embedded sources of the kernels `names` (a changed
/// kernel measures again).
TuneKey tune_device_key(const Device& device, std::initializer_list<const char*> names);

/// The fastest of up to 3 timed frames (after one untimed: the driver's first launch, the BVH
/// build; fewer once the timed ones took 500 ms in all) of the tuning scene (a UV sphere over a
/// height field, 12,000 triangles, 640x480; CLVIS_TUNE_WORKLOAD=small: 600 triangles, 160x120) drawn by `path` under `options`, in host wall ms
/// (FrameTiming::frame_ms): every driver measures it alike, where profiling timestamps need not
/// mean anything (Rusticl on llvmpipe reported 1 ns for every stage).
double measure_tune_frames(const Device& device, const RenderOptions& options, Path path);

/// A mapping tuner's answer, as RasterMappingChoice and RayMappingChoice hold it.
struct TunedMapping {
    std::string choice; ///< one of the request's candidates
    std::string source; ///< "forced", "cache" or "measured" (to_string(TuneSource))
    /// The measured times of the first two candidates, in the request's order; -1 when not measured
    double ms[2] = {-1, -1};
};

/// tune(request) with the settings of the environment (TuneSettings::from_environment).
TunedMapping tune_mapping(const TuneRequest& request);

} // namespace clvis::detail
