// The multi-view workload of `clvis bench --views N` (issue #16): N views of one mesh around it,
// rendered by clvis's batch (render_views into a VisibilityBatch) and by a loop of single
// renders on each path, and view after view by Embree (rtcIntersect1) and llvmpipe, timed in
// interleaved rounds of whole view sets. The host logic here (cameras, figures) is untimed and
// tested; the timing lives in bench_views.cpp.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>

#include <string>
#include <vector>

namespace clvis::bench {

/// Issue #16's target: a batch's wall time over the sum of its views' kernel times.
constexpr double target_batch_over_kernels = 1.3;

/// `views` cameras around the scene: the framing camera (CONVENTIONS.md) with its eye turned
/// about the axis through the bounds' centre along the camera's up vector, by 360 / views
/// degrees from one view to the next (view 0 is the framing camera; all keep its distance,
/// projection and planes). Error(InvalidArgument) naming --views for views < 1.
std::vector<Camera> orbit_cameras(const Bounds& bounds, int views);

/// Views per second of a set of `views` views rendered in `ms` milliseconds (0 when ms <= 0).
double views_per_second(double ms, int views);

/// scenes/FILE under the working directory when it is there, else in the source tree.
std::string bundled_mesh(const std::string& file);

} // namespace clvis::bench
