// clvis render --distribute: the views of a views file split between the ranks of an mpirun, each
// writing its own views' buffers (frames), or one frame shared by them (screen, scene) with rank 0
// writing the buffers; rank 0 reports each rank's time and the composite's.
#pragma once

#include <clvis/clvis.hpp>

#include <string>
#include <vector>

namespace clvis::cli {

struct DistRequest {
    std::string mode;  ///< "frames", "screen" or "scene"
    SceneFile file;    ///< the whole scene as loaded (scene mode keeps only this rank's share)
    double load_ms = 0;
    std::vector<Camera> cameras; ///< frames: the views file's; screen, scene: the one camera
    int width = 0, height = 0;
    Path path = Path::Raster;
    RenderOptions options;
    std::string device_spec;
    std::string ids, depth; ///< frames: "{view}" in a name is the view's index
    int repeat = 0;
    bool json = false, quiet = false;
};

/// Initialises MPI, renders, composites on rank 0, finalises. An error on any rank aborts the job
/// (MPI_Abort) after printing it, so no rank waits forever.
void render_distributed(DistRequest request);

} // namespace clvis::cli
