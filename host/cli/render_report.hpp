// What `clvis render` (one device, one process) says of its frames: each path's summary line on
// standard error, the referee's verdict (--path all), the first frame's costs (--timings), and
// the whole of CONVENTIONS.md's --json object, stage times and resolved mappings included.
#pragma once

#include <clvis/clvis.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace clvis::cli {

/// One path's run: its frames' times, its BVH, the buffer read back, what its first frame cost.
struct PathResult {
    Path path;
    std::vector<double> samples;
    FrameTiming fastest;
    double build_ms = 0;
    BvhStats bvh;
    HostVisibility vis;
    /// Host wall time of prepare() (programs; BVH for ray) and of the first render() (-1: none).
    double prepare_ms = 0, first_frame_ms = -1;
};

/// The summary line of one path on standard error.
std::string path_line(const PathResult& r);

/// --timings: what a one-off render paid on the host before each path's first frame: Device::open
/// (platform, context, queue), the Renderer (scene upload), then per path prepare and the frames.
std::string first_frame_line(double open_ms, double renderer_ms, const std::vector<PathResult>& results);

/// The referee's verdict on raster (a) against ray (b): a summary line, then one per first error.
std::vector<std::string> compare_lines(const CompareReport& report);

/// Depth layers: every layer's report summed into one (first errors in layer order, up to `max`).
CompareReport sum_layers(const std::vector<CompareReport>& layers, std::size_t max);

/// Depth layers: one line per layer, "layer k: N equal, N explained, N errors; depths: ...".
std::vector<std::string> layer_lines(const std::vector<CompareReport>& layers);

/// What --json says of one render beside its paths' results.
struct RenderJson {
    std::size_t triangles = 0;
    int width = 0, height = 0;
    RenderOptions options;    ///< as the flags gave them (Auto unresolved)
    double load_ms = 0;
    bool warm_up = false;     ///< an untimed frame ran first (--repeat, --timings)
    std::string camera;       ///< Camera::to_flags()
    const CompareReport* compare = nullptr; ///< --path all: the referee's verdict
    /// --timings: Device::open and Renderer construction, host wall ms (negative: not asked)
    double open_ms = -1, renderer_ms = -1;
};

/// --json: one object for standard output. `renderer` reports the device and the mappings it ran.
nlohmann::json render_json(const RenderJson& run, Renderer& renderer, const std::vector<PathResult>& results);

} // namespace clvis::cli
