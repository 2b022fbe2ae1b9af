// clvis bench --datasets: what the dataset outputs (issue 35) and depth layers (issue 36) cost
// against the visibility frame they are made from. On spot (scenes/spot.obj: texture coordinates
// per corner) at 1920x1080, per path: the visibility frame; resolving uv, barycentrics and object
// ids from it; the flow from it to a second view; and the frame with 2, 4 and 8 depth layers. The
// lanes are timed in interleaved rounds (bench_stats.cpp), and each is reported as a ratio of
// medians to its path's visibility frame with the interval its samples allow. Writes
// bench-datasets.json.
#include "bench.hpp"
#include "bench_machine.hpp"
#include "bench_report.hpp"
#include "bench_stats.hpp"
#include "bench_views.hpp"

#include <clvis/attributes.hpp>
#include <clvis/clvis.hpp>
#include <clvis/flow.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

namespace clvis::bench {

namespace {

constexpr int width = 1920, height = 1080;

/// One path's lanes: the visibility frame and what is made from it, on one Renderer.
struct PathLanes {
    Path path;
    Renderer renderer;
    Camera camera, next;
    VisibilityBuffer vis, vis_next;
    AttributeBuffers attributes;
    FlowBuffer flowed;

    PathLanes(const Device& device, const Scene& scene, Path p, const Camera& a, const Camera& b)
        : path(p), renderer(device, scene), camera(a), next(b)
    {
        vis = VisibilityBuffer(device, width, height);
        vis_next = VisibilityBuffer(device, width, height);
        renderer.render(camera, path, vis); // untimed: first launches compile
        renderer.render(next, path, vis_next);
    }
};

Lane make_lane(std::string name, std::function<double()> frame)
{
    Lane l;
    l.name = std::move(name);
    l.frame = std::move(frame);
    return l;
}

double timed(const std::function<void()>& f)
{
    auto t0 = std::chrono::steady_clock::now();
    f();
    return ms_since(t0);
}

} // namespace

void run_datasets_bench(const BenchConfig& config, const Device& device)
{
    auto t_start = std::chrono::steady_clock::now();
    std::filesystem::path out_dir(config.out);
    std::filesystem::create_directories(out_dir);
    Scene scene = load_scene({bundled_mesh("spot.obj")});
    std::vector<Camera> cams = orbit_cameras(scene.bounds(), 24); // the second view: 15 degrees on
    StopRule rule = stop_rule(config);

    std::vector<std::unique_ptr<PathLanes>> paths;
    std::vector<std::unique_ptr<Renderer>> layered; // one Renderer per path and layer count
    std::vector<std::unique_ptr<VisibilityBuffer>> layered_vis;
    std::vector<Lane> lanes;
    for (Path p : {Path::Raster, Path::Ray}) {
        paths.push_back(std::make_unique<PathLanes>(device, scene, p, cams[0], cams[1]));
        PathLanes* l = paths.back().get();
        std::string name = to_string(p);
        lanes.push_back(make_lane(name + " visibility", [l] { return timed([l] { l->renderer.render(l->camera, l->path, l->vis); }); }));
        AttributeRequest uv;
        uv.named = {"uv"};
        lanes.push_back(make_lane(name + " resolve uv", [l, uv] {
                             return timed([&] { resolve(l->renderer, l->vis, l->camera, uv, l->attributes); });
                         }));
        AttributeRequest bary;
        bary.barycentrics = true;
        lanes.push_back(make_lane(name + " resolve barycentrics", [l, bary] {
                             return timed([&] { resolve(l->renderer, l->vis, l->camera, bary, l->attributes); });
                         }));
        AttributeRequest objects;
        objects.object = true;
        lanes.push_back(make_lane(name + " resolve objects", [l, objects] {
                             return timed([&] { resolve(l->renderer, l->vis, l->camera, objects, l->attributes); });
                         }));
        lanes.push_back(make_lane(name + " flow", [l] {
                             return timed([l] { flow(l->renderer, l->vis, l->camera, l->vis_next, l->next, l->flowed); });
                         }));
        for (int k : {2, 4, 8}) {
            RenderOptions o;
            o.layers = k;
            layered.push_back(std::make_unique<Renderer>(device, scene, o));
            layered_vis.push_back(std::make_unique<VisibilityBuffer>(device, width, height, 1, k));
            Renderer* r = layered.back().get();
            VisibilityBuffer* v = layered_vis.back().get();
            r->render(cams[0], p, *v); // untimed
            lanes.push_back(make_lane(name + " layers " + std::to_string(k), [r, v, p, c = cams[0]] {
                                 return timed([&] { r->render(c, p, *v); });
                             }));
        }
    }
    Load before = read_load();
    int rounds = interleave(lanes, rule);
    Load after = read_load();

    std::printf("clvis bench --datasets: spot (%zu triangles, uv per corner) at %dx%d on %s; %d rounds, load %s -> %s\n",
                scene.triangle_count(), width, height, device.info().name.c_str(), rounds,
                to_string(before).c_str(), to_string(after).c_str());
    std::printf("%-28s %6s %10s %17s  %s\n", "workload", "frames", "median ms", "95% interval",
                "over its path's visibility frame [interval]");
    nlohmann::json j{{"device", device.info().name}, {"mesh", "spot.obj"}, {"triangles", scene.triangle_count()},
                     {"width", width}, {"height", height}, {"rounds", rounds}, {"load_before", load_json(before)},
                     {"load_after", load_json(after)}, {"runs", nlohmann::json::array()}};
    for (const Lane& lane : lanes) {
        Summary s = summarize(lane.ms);
        Interval ci = median_ci(lane.ms);
        std::string path = lane.name.substr(0, lane.name.find(' '));
        const Lane* base = nullptr;
        for (const Lane& b : lanes)
            if (b.name == path + " visibility") base = &b;
        nlohmann::json run{{"workload", lane.name}, {"ms", lane.ms}, {"median_ms", s.median},
                           {"ci_ms", {ci.lo, ci.hi}}, {"error", lane.error}};
        std::string over;
        if (base && base != &lane && !lane.ms.empty() && !base->ms.empty()) {
            RatioSpread r = ratio_spread(lane.ms, base->ms);
            if (r.valid()) {
                run["over_visibility"] = {{"ratio", r.ratio}, {"lo", r.lo}, {"hi", r.hi}};
                over = fmt("%.2f", r.ratio) + " [" + fmt("%.2f", r.lo) + "-" + fmt("%.2f", r.hi) + "]";
            }
        }
        std::printf("%-28s %6zu %10.1f %17s  %s%s\n", lane.name.c_str(), lane.ms.size(), s.median,
                    ("[" + fmt("%.1f", ci.lo) + "-" + fmt("%.1f", ci.hi) + "]").c_str(), over.c_str(),
                    lane.error.empty() ? "" : ("error: " + lane.error).c_str());
        j["runs"].push_back(run);
    }
    j["total_s"] = ms_since(t_start) / 1000;
    std::ofstream(out_dir / "bench-datasets.json") << j.dump(2) << "\n";
    std::printf("\nclvis bench --datasets: %.1f s; each workload's median over its path's visibility frame "
                "(issue 36's target: layers 4 at most 2.5); wrote %s\n",
                ms_since(t_start) / 1000, (out_dir / "bench-datasets.json").string().c_str());
}

} // namespace clvis::bench
