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
    const StopRule& rule = ctx.rule;
    return {{"quick", config.quick},
            {"passes", config.passes},
            {"interleaved", "at each point every renderer is warmed up, then timed one frame per round in turn"},
            {"warm_up_frames", 1},
            {"frames", {{"exact", rule.exact},
                        {"min", rule.min_frames},
                        {"max", rule.max_frames},
                        {"median_ci_rel", rule.rel_ci},
                        {"budget_ms", rule.budget_ms},
                        {"min_budget_frames", min_budget_frames}}},
            {"brute_repeat", brute_repeat},
            {"brute_max_triangles", brute_max_triangles},
            {"brute_max_tests", config.quick ? brute_max_tests_quick : brute_max_tests_full},
            {"builds", config.quick ? builds_quick : builds_full},
            {"single_build_above_triangles", single_build_above},
            {"closeup", "framing eye moved to " + fmt("%.2f", closeup_fraction) +
                            " x the framing distance; near " + fmt("%.2f", closeup_near_fraction) +
                            " x that distance, far 1.1 (distance + R)"},
            {"targets", {{"raster_over_llvmpipe", target_raster_over_llvmpipe},
                         {"ray_over_embree_intersect16", target_ray_over_embree16},
                         {"bvh_build_over_embree_build", target_build_over_embree}}}};
}

/// One pass of the whole sweep: its load around it and its duration.
struct PassRecord {
    Load before, after;
    double seconds = 0;
};

nlohmann::json machine_json(const Machine& m, const std::vector<PassRecord>& passes)
{
    nlohmann::json j{{"cores", m.cores}, {"cpu_model", m.cpu_model}};
    j["load_before"] = passes.empty() ? nlohmann::json(nullptr) : load_json(passes.front().before);
    j["load_after"] = passes.empty() ? nlohmann::json(nullptr) : load_json(passes.back().after);
    j["passes"] = nlohmann::json::array();
    for (const auto& p : passes)
        j["passes"].push_back({{"load_before", load_json(p.before)}, {"load_after", load_json(p.after)},
                               {"seconds", p.seconds}});
    return j;
}

nlohmann::json run_json(const Context& ctx, const std::vector<PooledPoint>& points, const Machine& machine,
                        const std::vector<PassRecord>& passes, double total_ms)
{
    nlohmann::json j;
    j["tool"] = "clvis bench";
    j["command"] = command_line(ctx.config);
    j["clvis_version"] = clvis::version();
    j["date"] = utc_now();
    j["device"] = device_json(ctx);
    j["machine"] = machine_json(machine, passes);
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

StopRule stop_rule(const BenchConfig& config)
{
    StopRule rule;
    rule.exact = config.frames;
    rule.min_frames = config.quick ? 3 : 5;
    rule.max_frames = config.quick ? 10 : 30;
    rule.rel_ci = config.quick ? 0.05 : 0.03;
    rule.budget_ms = config.quick ? frame_budget_ms_quick : frame_budget_ms_full;
    return rule;
}

std::string command_line(const BenchConfig& config)
{
    std::string c = "clvis bench";
    if (config.quick) c += " --quick";
    c += " --out " + config.out;
    if (config.frames > 0) c += " --frames " + std::to_string(config.frames);
    if (config.passes > 1) c += " --repeat " + std::to_string(config.passes);
    if (config.ref_threads != 2) c += " --ref-threads " + std::to_string(config.ref_threads);
    if (config.no_plot) c += " --no-plot";
    for (std::size_t i = 0; i < config.only.size(); ++i) c += (i == 0 ? " --only " : ",") + config.only[i];
    return c;
}

void run_bench(const BenchConfig& config, const std::function<Device()>& open_device)
{
    auto t_start = std::chrono::steady_clock::now();
    fs::path out_dir(config.out);
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec) throw Error(Error::Kind::Io, "--out " + config.out + ": " + ec.message());

    Context ctx{config, stop_rule(config), 0, Device{}, {}, {}, {}};
    try {
        ctx.device = open_device();
    } catch (const std::exception& e) {
        ctx.device_error = e.what();
        std::cerr << "clvis bench: no OpenCL device (" << e.what() << "): timing the references only\n";
    }

    const Machine machine = read_machine();
    std::vector<Workload> workloads = plan(config.quick);
    if (!config.only.empty()) {
        for (const auto& name : config.only)
            if (std::none_of(workloads.begin(), workloads.end(), [&](const Workload& w) { return w.mesh == name; }))
                throw Error(Error::Kind::InvalidArgument, "--only: no workload '" + name + "' in the sweep");
        workloads.erase(std::remove_if(workloads.begin(), workloads.end(),
                                       [&](const Workload& w) {
                                           return std::find(config.only.begin(), config.only.end(), w.mesh) ==
                                                  config.only.end();
                                       }),
                        workloads.end());
    }
    std::size_t total = 0;
    for (const auto& w : workloads) total += w.views.size();
    Progress progress(total * std::size_t(config.passes));
    std::vector<Point> points;
    std::vector<PassRecord> passes;
    for (ctx.pass = 0; ctx.pass < config.passes; ++ctx.pass) {
        auto t_pass = std::chrono::steady_clock::now();
        PassRecord record;
        record.before = read_load();
        for (const auto& w : workloads) run_workload(ctx, w, points, progress);
        record.after = read_load();
        record.seconds = ms_since(t_pass) / 1000;
        passes.push_back(record);
    }
    progress.finish();
    const std::vector<PooledPoint> pooled = pool_passes(points);

    fs::path json_file = out_dir / "bench.json";
    {
        std::ofstream out(json_file);
        if (!out) throw Error(Error::Kind::Io, json_file.string() + ": cannot write");
        out << run_json(ctx, pooled, machine, passes, ms_since(t_start)).dump(2) << "\n";
    }
    write_csv(out_dir / "bench.csv", points);
    print_table(pooled);
    if (!config.no_plot) plot(json_file, out_dir);
    std::printf("\nclvis bench: %zu points x %d pass(es) in %.1f s on %s (%d cores, %s; load %s before, %s after); "
                "wrote %s and %s%s\n",
                pooled.size(), config.passes, ms_since(t_start) / 1000,
                ctx.device ? ctx.device.info().name.c_str() : "no device", machine.cores, machine.cpu_model.c_str(),
                to_string(passes.front().before).c_str(), to_string(passes.back().after).c_str(),
                json_file.string().c_str(), (out_dir / "bench.csv").string().c_str(),
                config.no_plot ? "" : " (plots beside them)");
}

} // namespace clvis::bench
