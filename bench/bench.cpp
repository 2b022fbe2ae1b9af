// The benchmark driver (see bench.hpp): opens the device, runs the plan's workloads, and hands
// the points to the reports.
#include "bench.hpp"

#include "bench_plan.hpp"
#include "bench_report.hpp"
#include "bench_run.hpp"
#include "bench_stats.hpp"

#include <clvis/error.hpp>
#include <clvis/version.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>

namespace clvis::bench {

namespace {

namespace fs = std::filesystem;

nlohmann::json device_json(const Context& ctx)
{
    if (!ctx.device) return {{"error", ctx.device_error}};
    const DeviceInfo& info = ctx.device.info();
    return {{"name", info.name},       {"platform", info.platform},
            {"vendor", info.vendor},   {"version", info.version},
            {"driver", info.driver_version}, {"compute_units", info.compute_units}};
}

/// The plan's limits and the targets, as this run applied them.
nlohmann::json parameters_json(const Context& ctx)
{
    const BenchConfig& config = ctx.config;
    return {{"quick", config.quick},
            {"repeat", ctx.repeat},
            {"warm_up_frames", 1},
            {"frame_budget_ms", ctx.budget_ms},
            {"min_budget_frames", min_budget_frames},
            {"brute_repeat", std::min(ctx.repeat, brute_repeat)},
            {"brute_max_triangles", brute_max_triangles},
            {"brute_max_tests", config.quick ? brute_max_tests_quick : brute_max_tests_full},
            {"builds", config.quick ? 2 : 3},
            {"single_build_above_triangles", single_build_above},
            {"closeup", "framing eye moved to " + fmt("%.2f", closeup_fraction) +
                            " x the framing distance; near " + fmt("%.2f", closeup_near_fraction) +
                            " x that distance, far 1.1 (distance + R)"},
            {"targets", {{"raster_over_llvmpipe", target_raster_over_llvmpipe},
                         {"ray_over_embree_intersect1", target_ray_over_embree1},
                         {"bvh_build_over_embree_build", target_build_over_embree}}}};
}

nlohmann::json run_json(const Context& ctx, const std::vector<Point>& points, double total_ms)
{
    nlohmann::json j;
    j["tool"] = "clvis bench";
    j["clvis_version"] = clvis::version();
    j["date"] = utc_now();
    j["device"] = device_json(ctx);
    j["references"] = {{"embree", ctx.embree_description.empty() ? "unavailable" : ctx.embree_description},
                       {"gl", ctx.gl_description.empty() ? "unavailable" : ctx.gl_description},
                       {"threads", ctx.config.ref_threads}};
    j["parameters"] = parameters_json(ctx);
    j["points"] = nlohmann::json::array();
    for (const auto& p : points) j["points"].push_back(point_json(p));
    j["total_s"] = total_ms / 1000;
    return j;
}

} // namespace

void run_bench(const BenchConfig& config, const std::function<Device()>& open_device)
{
    auto t_start = std::chrono::steady_clock::now();
    fs::path out_dir(config.out);
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec) throw Error(Error::Kind::Io, "--out " + config.out + ": " + ec.message());

    Context ctx{config,   config.repeat > 0 ? config.repeat : config.quick ? 5 : 10,
                config.repeat > 0 ? 0 : config.quick ? frame_budget_ms_quick : frame_budget_ms_full,
                Device{}, {}, {}, {}};
    try {
        ctx.device = open_device();
    } catch (const std::exception& e) {
        ctx.device_error = e.what();
        std::cerr << "clvis bench: no OpenCL device (" << e.what() << "): timing the references only\n";
    }

    std::vector<Workload> workloads = plan(config.quick);
    std::size_t total = 0;
    for (const auto& w : workloads) total += w.views.size();
    Progress progress(total);
    std::vector<Point> points;
    for (const auto& w : workloads) run_workload(ctx, w, points, progress);
    progress.finish();

    fs::path json_file = out_dir / "bench.json";
    {
        std::ofstream out(json_file);
        if (!out) throw Error(Error::Kind::Io, json_file.string() + ": cannot write");
        out << run_json(ctx, points, ms_since(t_start)).dump(2) << "\n";
    }
    write_csv(out_dir / "bench.csv", points);
    print_table(points);
    if (!config.no_plot) plot(json_file, out_dir);
    std::printf("\nclvis bench: %zu points in %.1f s on %s; wrote %s and %s%s\n", points.size(),
                ms_since(t_start) / 1000, ctx.device ? ctx.device.info().name.c_str() : "no device",
                json_file.string().c_str(), (out_dir / "bench.csv").string().c_str(),
                config.no_plot ? "" : " (plots beside them)");
}

} // namespace clvis::bench
