// clvis bench: the flags of the benchmark; the driver itself lives in bench/ (bench.hpp).
#include "commands.hpp"
#include "options.hpp"

#include "bench.hpp"

#include "shared/raster.h"

#include <memory>

namespace clvis::cli {

namespace {

struct BenchArgs {
    bench::BenchConfig config;
    DeviceOptions device;
    bool rays = false; ///< the ray-query workloads (bench/bench_rays.cpp) instead of the sweep
    bool datasets = false; ///< the dataset outputs and depth layers (bench/bench_datasets.cpp) instead
};

} // namespace

void add_bench_command(CLI::App& app)
{
    auto args = std::make_shared<BenchArgs>();
    bench::BenchConfig& c = args->config;
    auto* cmd = app.add_subcommand(
        "bench", "Time raster, ray and brute force against Embree and llvmpipe over triangle counts, resolutions "
                 "and the bundled meshes; the referee judges every buffer. Writes bench.csv, bench.json and plots.\n"
                 "Example: clvis bench --quick --out bench-out");
    cmd->add_flag("--quick", c.quick, "a sweep of a few small points (under a minute on 2 cores)");
    cmd->add_option("--out", c.out, "output folder (created)");
    args->device.add_to(*cmd);
    cmd->add_option("--frames", c.frames,
                    "exactly N timed frames per renderer and point after one warm-up (default: until each median "
                    "is known to 3 %, quick 5 %, within 5..30 frames, quick 3..10, and 3 s, quick 1.5 s)")
        ->check(CLI::Range(1, 100000));
    cmd->add_option("--repeat", c.passes,
                    "run the whole sweep K times; ratios pool every pass and report the spread across passes")
        ->check(CLI::Range(1, 1000));
    cmd->add_option("--ref-threads", c.ref_threads, "threads of the reference renderers (default 2)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("--only", c.only,
                    "the sweep's workloads of these names only, e.g. sphere-1k,suzanne (with --quick: of its sweep)")
        ->delimiter(',');
    cmd->add_flag("--no-plot", c.no_plot, "skip the plots (bench/plot.py, matplotlib)");
    cmd->add_flag("--rays", args->rays,
                  "the ray-query workloads instead: ambient occlusion rays (bunny, 1M sphere) and random rays "
                  "through a 1M soup, clvis closest/any against rtcIntersect1/16 and rtcOccluded1/16");
    auto* views = cmd->add_option("--views", c.views,
                                  "the multi-view workload instead: N views of the bunny around it (issue #16 uses 64), "
                                  "clvis's batch (render_views) and a loop of single renders on each path against "
                                  "Embree and llvmpipe doing the same views; frames per second and batch / kernels")
                      ->check(CLI::Range(1, 4096));
    cmd->add_option("--view-size", c.view_size, "width and height of the --views views (default 256)")
        ->check(CLI::Range(1, CLVIS_MAX_IMAGE_SIZE))
        ->needs(views);
    views->excludes(cmd->get_option("--rays"));
    cmd->add_flag("--datasets", args->datasets,
                  "the dataset outputs and depth layers instead: on spot at 1920x1080, each path's visibility "
                  "frame, resolve (uv, barycentrics, object ids), flow to a second view and 2, 4, 8 layers, each "
                  "over its path's visibility frame")
        ->excludes(views)
        ->excludes(cmd->get_option("--rays"));
    cmd->callback([args] {
        if (args->config.views > 0) bench::run_views_bench(args->config, args->device.open());
        else if (args->rays) bench::run_ray_bench(args->config, args->device.open());
        else if (args->datasets) bench::run_datasets_bench(args->config, args->device.open());
        else bench::run_bench(args->config, [args] { return args->device.open(); });
    });
}

} // namespace clvis::cli
