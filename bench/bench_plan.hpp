// The benchmark's sweep: which scenes (procedural triangle counts, the bunny at several sizes,
// every bundled mesh) under which cameras and image sizes, and the limits that keep it short.
// Consumed by bench_run.cpp; bench.cpp writes the limits into bench.json.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace clvis::bench {

/// The close-up camera of a real mesh: the framing camera's eye moved toward its target to this
/// fraction of the framing distance (the bounding sphere then overfills the vertical field of
/// view by about 3x: the mesh covers the whole image). Near and far follow below.
constexpr double closeup_fraction = 0.35;
/// Close-up near plane as a fraction of the close-up distance: the eye may be inside the
/// bounding sphere, so the framing rule 0.9 (dist - R) could be negative.
constexpr double closeup_near_fraction = 0.05;
/// Brute force (one ray against every triangle) only on small scenes, and only while
/// triangles x pixels (ray-triangle tests per frame) stays under a budget of a few seconds a
/// frame on PoCL's CPU device. Small images of small meshes (the "brute" sweep) give it points of
/// its own.
constexpr std::size_t brute_max_triangles = 16384;
constexpr double brute_max_tests_full = 6e7;
constexpr double brute_max_tests_quick = 2.5e7;
/// Timed brute-force frames at most (each may take a second).
constexpr int brute_repeat = 3;
/// Timed BVH builds per builder and pass (alternating, see make_renderers): a build of 1M
/// triangles varies widely from one to the next (its page faults' cost varies), so the full
/// sweep takes five for a steadier median.
constexpr int builds_full = 5;
constexpr int builds_quick = 2;
/// Scenes above this many triangles get one timed BVH build per builder (each takes seconds).
constexpr std::size_t single_build_above = 1u << 20;
/// Without --repeat, each renderer stops timing a point once its timed frames add up to this
/// (after at least bench::min_budget_frames): the 4M-triangle points take seconds per frame.
constexpr double frame_budget_ms_full = 3000;
constexpr double frame_budget_ms_quick = 1500;

struct ViewSpec {
    bool closeup = false;
    int width = 1920, height = 1080;
    std::vector<std::string> sweeps; ///< "triangles", "resolution", "mesh", "brute"
};

struct Workload {
    std::string mesh;
    std::function<Scene()> make; ///< throws when the scene cannot be made (e.g. a missing file)
    std::vector<ViewSpec> views;
};

/// The sweep: triangle counts on procedural meshes at 1920x1080, resolutions on the bunny, and
/// every bundled mesh under the framing and the close-up camera; fewer points when `quick`.
std::vector<Workload> plan(bool quick);

/// The close-up camera of `framing` for a scene of `bounds` (closeup_fraction above).
Camera closeup_of(const Camera& framing, const Bounds& bounds);

} // namespace clvis::bench
