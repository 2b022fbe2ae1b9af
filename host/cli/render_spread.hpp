// clvis render spread over several devices (--devices, render_multi.cpp) or MPI ranks
// (--distribute, render_dist.cpp): their flags, the checks of what they can be combined with,
// and the hand-over from render.cpp.
#pragma once

#include <clvis/clvis.hpp>

#include "output_plan.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace clvis::cli {

struct SpreadArgs {
    std::string distribute;          ///< --distribute frames|screen|scene (under mpirun)
    std::string devices, device_map; ///< --devices SPEC,SPEC,...: one frame on several devices
    int screen_tile = 64;            ///< --screen-tile: their tiles' edge in pixels
    void add_to(CLI::App& cmd);
    bool any() const { return !distribute.empty() || !devices.empty() || !device_map.empty(); }
};

/// What clvis render hands to --devices (render_multi.cpp) and --distribute (render_dist.cpp):
/// the spread flags and what the rest of clvis render resolved, built field by field by name.
struct SpreadRequest {
    SpreadArgs spread;
    std::string path, views, image, device_spec; ///< --path, --views, --image, --device as given
    SceneFile* file = nullptr; ///< --distribute scene keeps only its rank's share of the scene
    double load_ms = 0;
    std::vector<Camera> cameras; ///< the views file's, else the one camera
    int width = 0, height = 0;
    RenderOptions options;
    std::string ids, depth; ///< --distribute frames: "{view}" in a name is the view's index
    int repeat = 0;
    bool json = false, quiet = false;
    /// The run's files, named and checked before rendering (--devices writes through it;
    /// --distribute plans each rank's own files again).
    OutputPlan* plan = nullptr;
};

/// Refuses (Error(InvalidArgument), the flag named) what --devices or --distribute cannot do
/// from the flags alone: --path all, --image, and the flags of the other. Returns the path.
Path check_spread(const SpreadRequest& request);

/// Renders on several devices or ranks as the flags say, after refusing (Error(InvalidArgument),
/// the flag named) what they cannot do: --path all, --image, and the flags of the other.
void render_spread(const SpreadRequest& request);

} // namespace clvis::cli
