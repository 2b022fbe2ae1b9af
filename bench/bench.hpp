// clvis bench, the driver: plans the sweep (bench_plan), times clvis's paths and the reference
// renderers on every point and has the referee judge their buffers (bench_run), then writes
// bench.json, bench.csv, a table and plots (bench_report). `clvis bench` parses its flags into a
// BenchConfig and calls run_bench. Ratios within one run are what count: the machine is shared.
#pragma once

#include "bench_stats.hpp"

#include <clvis/device.hpp>

#include <functional>
#include <string>
#include <vector>

namespace clvis::bench {

struct BenchConfig {
    bool quick = false;
    std::string out = "bench-out"; ///< output folder (created)
    int frames = 0;      ///< > 0: exactly this many timed frames per renderer and point
    int passes = 1;      ///< --repeat: the whole sweep this many times, the spread reported across them
    int ref_threads = 2; ///< threads of the reference renderers (trace, raster and build)
    bool no_plot = false;
    int views = 0;       ///< --views N: > 0 runs the multi-view workload (run_views_bench) instead
    int view_size = 256; ///< --view-size: the views' width and height
    std::vector<std::string> only; ///< --only: the sweep's workloads of these names only (empty: all)
};

/// The stopping rule of a run: exactly config.frames frames, or until each median is known to
/// 3 % (quick: 5 %) within 5..30 frames (quick 3..10) and a time budget per renderer and point.
StopRule stop_rule(const BenchConfig& config);

/// "clvis bench --out DIR ..." with the flags that shaped the run.
std::string command_line(const BenchConfig& config);

/// Runs the whole benchmark into config.out. When `open_device` throws, only the references are
/// timed (the error is reported); throws Error(Io) when the output cannot be written.
void run_bench(const BenchConfig& config, const std::function<Device()>& open_device);

/// The ray-query workloads of bench_rays.cpp on `device` (config.quick, out, frames, ref_threads,
/// no_plot): prints a table and writes bench-rays.json, bench-rays.csv and rays_mrays.png.
void run_ray_bench(const BenchConfig& config, const Device& device);

/// The multi-view workload of bench_views.cpp on `device`: config.views views of the bunny at
/// config.view_size around it, clvis's batch and a loop of single renders on each path, Embree
/// and llvmpipe view after view, in interleaved rounds (stop_rule(config)); prints a table and
/// writes bench-views.json and bench-views.csv.
void run_views_bench(const BenchConfig& config, const Device& device);

/// The dataset outputs and depth layers of bench_datasets.cpp on `device`: on spot at 1920x1080,
/// each path's visibility frame, resolve (uv, barycentrics, object ids), flow to a second view and
/// 2, 4 and 8 layers, in interleaved rounds, each over its path's visibility frame; prints a table
/// and writes bench-datasets.json.
void run_datasets_bench(const BenchConfig& config, const Device& device);

} // namespace clvis::bench
