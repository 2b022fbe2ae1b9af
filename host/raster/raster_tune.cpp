// RasterMapping::Auto (raster_tune.hpp): the key that a raster mapping depends on, and its
// measurement, a fixed synthetic frame drawn with each mapping by a Renderer of its own.
#include "raster/raster_tune.hpp"

#include "render/pipeline.hpp"
#include "runtime/cl_runtime.hpp"
#include "runtime/embedded_kernels.hpp"

#include <clvis/procedural.hpp>
#include <clvis/renderer.hpp>
#include <clvis/version.hpp>

#include <algorithm>
#include <cstdint>
#include <string>

namespace clvis::detail {

namespace {

/// The tuning frame: large enough that the fine stage dominates (triangles of tens of pixels,
/// binned rather than drawn at setup, two layers deep), short enough to cost well under a second
/// on a CPU device. Changing it changes the key (workload_name).
constexpr int tune_width = 640, tune_height = 480;
constexpr std::size_t tune_sphere_triangles = 6000, tune_grid_triangles = 6000;
constexpr int tune_frames = 3; ///< timed frames per mapping at most, after one untimed
/// Timed frames stop once they took this long (ms) in all, after the first: a slow mapping on a
/// slow device (the pixel mapping on llvmpipe, 2 s a frame) is not timed three times.
constexpr double tune_budget_ms = 500;
constexpr const char* workload_name = "sphere6000+grid6000@640x480 min(3 frames, 500 ms) frame_ms v3";

const Scene& tuning_scene()
{
    static const Scene scene = [] {
        Scene s;
        s.add_mesh(make_grid(tune_grid_triangles, 21));
        s.add_mesh(make_uv_sphere(tune_sphere_triangles));
        return s;
    }();
    return scene;
}

/// A hash of the raster kernels' sources and build options: a changed kernel measures again.
std::string kernels_hash(const Device& device)
{
    std::string text = version() + "\n" + device.impl()->build_options("");
    for (const char* name : {"raster_setup", "raster_bin", "raster_fine", "visibility_clear"})
        text += embedded_kernel(name);
    return stable_hash(text);
}

/// The fastest of the timed frames of the tuning scene drawn with `mapping`, in host wall time
/// (FrameTiming::frame_ms): every driver measures it alike, where profiling timestamps need not
/// mean anything (Rusticl on llvmpipe reported 1 ns for every stage).
double measure_mapping(const Device& device, const RenderOptions& base, RasterMapping mapping)
{
    RenderOptions o;
    o.tile_size = base.tile_size;
    o.raster_atomics = base.raster_atomics;
    o.raster_mapping = mapping;
    Renderer renderer(device, tuning_scene(), o);
    Camera camera = Camera::perspective({0.3, 1.4, 2.6}, {0, 0, 0}, {0, 1, 0}, 50, 0.1, 20);
    VisibilityBuffer target(device, tune_width, tune_height);
    renderer.render(camera, Path::Raster, target); // untimed: the driver's first launch
    double best = -1, spent = 0;
    for (int frame = 0; frame < tune_frames && spent < tune_budget_ms; ++frame) {
        renderer.render(camera, Path::Raster, target);
        double ms = renderer.last_frame().frame_ms;
        best = best < 0 ? ms : std::min(best, ms);
        spent += ms;
    }
    return best;
}

} // namespace

TuneRequest raster_mapping_request(const Device& device, const RenderOptions& options)
{
    const DeviceInfo& info = device.info();
    TuneRequest r;
    r.name = "raster_mapping";
    r.key = {{"device", info.name},
             {"platform", info.platform},
             {"driver", info.driver_version},
             {"kernels", kernels_hash(device)},
             {"depth_test", raster_owned(info, options) ? "owned" : "atomics"},
             {"tile", std::to_string(1 << raster_tile_log2(options))},
             {"workload", workload_name}};
    r.candidates = {to_string(RasterMapping::Square), to_string(RasterMapping::Pixel)};
    r.measure = [device, options](const std::string& candidate) {
        return measure_mapping(device, options, raster_mapping_from_string(candidate));
    };
    return r;
}

RasterMappingChoice choose_raster_mapping(const Device& device, const RenderOptions& options)
{
    RasterMappingChoice choice;
    if (options.raster_mapping != RasterMapping::Auto) {
        choice.mapping = options.raster_mapping;
        return choice;
    }
    TuneRequest request = raster_mapping_request(device, options);
    TuneResult result = tune(request, TuneSettings::from_environment(request));
    choice.mapping = raster_mapping_from_string(result.choice);
    choice.source = to_string(result.source);
    for (const TuneTime& t : result.times)
        (raster_mapping_from_string(t.candidate) == RasterMapping::Pixel ? choice.pixel_ms : choice.square_ms) = t.ms;
    return choice;
}

} // namespace clvis::detail
