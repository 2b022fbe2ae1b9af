// clvis render --distribute: one frame shared by the ranks of an mpirun (host/dist/), rank 0
// writing the buffers and reporting each rank's time and the composite's.
#pragma once

#include <clvis/clvis.hpp>

#include <string>

namespace clvis::cli {

struct DistRequest {
    std::string mode;  ///< "screen" or "scene"
    SceneFile file;    ///< the whole scene as loaded (scene mode keeps only this rank's share)
    double load_ms = 0;
    Camera camera;
    int width = 0, height = 0;
    Path path = Path::Raster;
    RenderOptions options;
    std::string device_spec;
    std::string ids, depth;
    int repeat = 0;
    bool json = false, quiet = false;
};

/// Initialises MPI, renders, composites on rank 0, finalises. An error on any rank aborts the job
/// (MPI_Abort) after printing it, so no rank waits forever.
void render_distributed(DistRequest request);

} // namespace clvis::cli
