// clvis render --distribute: the views of a views file split between the ranks of an mpirun, each
// writing its own views' buffers (frames), or one frame shared by them (screen, scene) with rank 0
// writing the buffers; rank 0 reports each rank's time and the composite's.
#pragma once

#include "render_spread.hpp"

namespace clvis::cli {

/// Renders by `path` as --distribute says (frames: the views file's cameras split by rank; screen,
/// scene: the one camera). Initialises MPI, renders, composites on rank 0, finalises. An error on
/// any rank aborts the job (MPI_Abort) after printing it, so no rank waits forever.
void render_distributed(const SpreadRequest& request, Path path);

} // namespace clvis::cli
