// Runs one workload of the plan: its scene, clvis's renderer and the reference renderers made
// once, then every view timed by each of them and their buffers judged by the referee. A
// renderer's failure is recorded in the point (bench.json reports it), never thrown.
#pragma once

#include "bench.hpp"
#include "bench_machine.hpp"
#include "bench_plan.hpp"
#include "bench_stats.hpp"

#include <clvis/host_visibility.hpp>
#include <clvis/referee.hpp>
#include <clvis/render_options.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace clvis::bench {

/// One renderer's figures at one point: a clvis path or a reference.
struct Run {
    std::string renderer; ///< raster, ray, brute, embree-intersect1, embree-intersect16, llvmpipe
    bool reference = false;
    std::string error;
    std::vector<double> frame_ms;
    std::vector<StageTiming> stages; ///< of the fastest frame (clvis paths)
    std::vector<double> build_ms;    ///< ray path and Embree: every timed build
    std::size_t bvh_nodes = 0;
    int bvh_depth = 0;
    HostVisibility vis; ///< kept until the comparisons are done
};

struct Comparison {
    std::string a, b;
    std::string error;
    CompareReport report;
};

struct Point {
    std::string mesh, camera;
    std::vector<std::string> sweeps; ///< "triangles", "resolution", "mesh"
    std::size_t triangles = 0;
    int width = 0, height = 0;
    std::string camera_flags;
    double coverage = -1; ///< fraction of pixels with a triangle (first buffer available), -1 if none
    int pass = 0;   ///< which pass of the whole sweep (--repeat), 0-based
    int rounds = 0; ///< interleaved rounds timed (each renderer one frame per round)
    Load load_before, load_after; ///< /proc/loadavg around the rounds
    std::vector<Run> runs; ///< raster, ray, [brute,] embree-intersect1, embree-intersect16, llvmpipe
    std::vector<Comparison> comparisons;

    const Run* find(const std::string& renderer) const
    {
        for (const auto& r : runs)
            if (r.renderer == renderer && r.error.empty() && !r.frame_ms.empty()) return &r;
        return nullptr;
    }
};

/// A progress bar on standard error when it is a terminal; silent otherwise.
class Progress {
public:
    explicit Progress(std::size_t total);
    void show(const std::string& what);
    void advance() { ++done_; }
    void finish();

private:
    std::size_t total_, done_ = 0;
    bool tty_;
};

/// What every workload of one run shares.
struct Context {
    const BenchConfig& config;
    StopRule rule; ///< when each renderer at a point has enough frames (brute stops at brute_repeat)
    int pass = 0;  ///< the pass of the whole sweep being run (--repeat)
    Device device;
    std::string device_error; ///< why there is no device: clvis's runs fail with it
    std::string embree_description, gl_description;
};

/// Every point of one workload, appended to `points`: at each point every renderer is warmed
/// up, then timed in interleaved rounds (bench_stats.hpp, interleave) under ctx.rule.
void run_workload(Context& ctx, const Workload& w, std::vector<Point>& points, Progress& progress);

} // namespace clvis::bench
