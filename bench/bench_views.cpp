// clvis bench --views N: the multi-view workload of issue #16 (bench_views.hpp). Every renderer
// renders the same N views of the bunny at SIZE x SIZE per timed frame; the frames are
// interleaved round by round (bench_stats.cpp), so a change of the machine's load falls on all
// alike. Writes bench-views.json and bench-views.csv.
#include "bench.hpp"
#include "bench_machine.hpp"
#include "bench_report.hpp"
#include "bench_stats.hpp"
#include "bench_views.hpp"
#include "reference.hpp"

#include <clvis/clvis.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

namespace clvis::bench {

namespace {

namespace fs = std::filesystem;

/// One clvis path over the views, as one batch (render_views) or as a loop of single renders:
/// each frame is the wall time of the whole set, its kernel times summed beside it.
struct ClvisViews {
    Renderer& renderer;
    const std::vector<Camera>& cameras;
    Path path;
    bool batch;
    VisibilityBatch target;
    VisibilityBuffer single;
    std::vector<double> kernels_ms; ///< per timed frame: the sum of every view's stage times

    /// Makes the buffers and renders one untimed warm-up set (first launches compile).
    ClvisViews(Renderer& r, const std::vector<Camera>& c, int size, Path p, bool b)
        : renderer(r), cameras(c), path(p), batch(b)
    {
        renderer.prepare(path);
        if (batch) target = VisibilityBatch(renderer.device(), int(cameras.size()), size, size);
        else single = VisibilityBuffer(renderer.device(), size, size);
        run();
    }

    double stage_sum() const
    {
        double k = 0;
        for (const StageTiming& s : renderer.last_frame().stages) k += s.ms;
        return k;
    }

    double run()
    {
        auto t0 = std::chrono::steady_clock::now();
        double k = 0;
        if (batch) {
            render_views(renderer, cameras, path, target);
            k = stage_sum();
        } else {
            for (const Camera& cam : cameras) {
                renderer.render(cam, path, single);
                k += stage_sum();
            }
        }
        double ms = ms_since(t0);
        kernels_ms.push_back(k);
        return ms;
    }
};

/// A reference renderer's views, framed one after the other as one set.
struct ReferenceViews {
    std::vector<std::unique_ptr<ReferenceView>> views;
    double frame()
    {
        double ms = 0;
        for (auto& v : views) ms += v->frame();
        return ms;
    }
};

struct Renderers {
    std::vector<std::unique_ptr<ClvisViews>> clvis;
    std::optional<EmbreeReference> embree;
    std::optional<GlReference> gl;
    std::vector<std::unique_ptr<ReferenceViews>> references;
    std::vector<Lane> lanes;
    std::vector<std::string> errors; ///< references that could not be made
};

void add_clvis(Renderers& r, Renderer& renderer, const std::vector<Camera>& cams, int size, Path p, bool batch)
{
    Lane lane;
    lane.name = std::string("clvis-") + to_string(p) + (batch ? "-batch" : "-loop");
    try {
        r.clvis.push_back(std::make_unique<ClvisViews>(renderer, cams, size, p, batch));
        ClvisViews* c = r.clvis.back().get();
        lane.frame = [c] { return c->run(); };
    } catch (const std::exception& e) {
        lane.error = e.what();
    }
    r.lanes.push_back(std::move(lane));
}

template <class Make> void add_reference(Renderers& r, const std::string& name, const std::vector<Camera>& cams, Make make)
{
    Lane lane;
    lane.name = name;
    try {
        auto views = std::make_unique<ReferenceViews>();
        for (const Camera& cam : cams) views->views.push_back(make(cam));
        r.references.push_back(std::move(views));
        ReferenceViews* v = r.references.back().get();
        lane.frame = [v] { return v->frame(); };
    } catch (const std::exception& e) {
        lane.error = e.what();
    }
    r.lanes.push_back(std::move(lane));
}

void add_references(Renderers& r, const Scene& scene, const std::vector<Camera>& cams, int size, int threads)
{
    try {
        r.embree.emplace(scene, threads);
        for (EmbreeMode mode : {EmbreeMode::Single, EmbreeMode::Packet16})
            add_reference(r, std::string("embree-intersect") + (mode == EmbreeMode::Single ? "1" : "16"), cams,
                          [&](const Camera& c) { return r.embree->view(c, size, size, mode); });
    } catch (const std::exception& e) {
        r.errors.push_back(std::string("embree: ") + e.what());
    }
    try {
        r.gl.emplace(scene, threads);
        add_reference(r, "llvmpipe", cams, [&](const Camera& c) { return r.gl->view(c, size, size); });
    } catch (const std::exception& e) {
        r.errors.push_back(std::string("llvmpipe: ") + e.what());
    }
}

const Lane* lane_named(const Renderers& r, const std::string& name)
{
    for (const Lane& l : r.lanes)
        if (l.name == name && l.error.empty() && !l.ms.empty()) return &l;
    return nullptr;
}

const ClvisViews* clvis_of(const Renderers& r, const std::string& name)
{
    for (const auto& c : r.clvis)
        if (std::string("clvis-") + to_string(c->path) + (c->batch ? "-batch" : "-loop") == name) return c.get();
    return nullptr;
}

nlohmann::json spread_json(const RatioSpread& s)
{
    if (!s.valid()) return nullptr;
    return {{"ratio", s.ratio}, {"lo", s.lo}, {"hi", s.hi}};
}

/// One lane's line of the table and its JSON; batches also against their kernels' sum.
nlohmann::json report_lane(const Renderers& r, const Lane& lane, int views, std::ofstream& csv)
{
    Summary s = summarize(lane.ms);
    Interval ci = median_ci(lane.ms);
    nlohmann::json j{{"renderer", lane.name}, {"ms", lane.ms}, {"median_ms", s.median}, {"ci_ms", {ci.lo, ci.hi}},
                     {"views_per_s", views_per_second(s.median, views)}, {"error", lane.error}};
    std::string against;
    if (const ClvisViews* c = clvis_of(r, lane.name); c && !lane.ms.empty()) {
        std::vector<double> k(c->kernels_ms.end() - std::ptrdiff_t(lane.ms.size()), c->kernels_ms.end());
        RatioSpread over = ratio_spread(lane.ms, k);
        j["kernels_ms"] = k;
        j["kernels_median_ms"] = median_of(k);
        j["over_kernels"] = spread_json(over);
        if (c->batch && over.valid()) {
            Verdict v = judge(over.lo, over.hi, target_batch_over_kernels);
            j["verdict"] = to_string(v);
            against = fmt("%.2f", over.ratio) + " [" + fmt("%.2f", over.lo) + "-" + fmt("%.2f", over.hi) + "] " +
                      to_string(v);
        } else if (over.valid()) {
            against = fmt("%.2f", over.ratio);
        }
        std::string batch = std::string("clvis-") + to_string(c->path) + "-batch";
        if (const Lane* b = lane_named(r, batch); !c->batch && b)
            j["over_batch"] = spread_json(ratio_spread(lane.ms, b->ms));
    }
    csv << lane.name << ',' << lane.ms.size() << ',' << s.median << ',' << ci.lo << ',' << ci.hi << ','
        << views_per_second(s.median, views) << ",\"" << lane.error << "\"\n";
    std::printf("%-20s %6zu %10.1f %17s %9.1f  %s%s\n", lane.name.c_str(), lane.ms.size(), s.median,
                ("[" + fmt("%.1f", ci.lo) + "-" + fmt("%.1f", ci.hi) + "]").c_str(), views_per_second(s.median, views),
                against.c_str(), lane.error.empty() ? "" : ("error: " + lane.error).c_str());
    return j;
}

} // namespace

void run_views_bench(const BenchConfig& config, const Device& device)
{
    auto t_start = std::chrono::steady_clock::now();
    fs::path out_dir(config.out);
    fs::create_directories(out_dir);
    Scene scene = load_scene({bundled_mesh("stanford-bunny.obj")});
    std::vector<Camera> cams = orbit_cameras(scene.bounds(), config.views);
    int size = config.view_size;
    StopRule rule = stop_rule(config);
    rule.budget_ms *= 4; // a frame here is a whole set of views

    Renderer renderer(device, scene);
    Renderers r;
    for (Path p : {Path::Ray, Path::Raster})
        for (bool batch : {true, false}) add_clvis(r, renderer, cams, size, p, batch);
    add_references(r, scene, cams, size, config.ref_threads);
    Load before = read_load();
    int rounds = interleave(r.lanes, rule);
    Load after = read_load();

    std::printf("clvis bench --views %d: the bunny (%zu triangles), %d views at %dx%d around it on %s; %d rounds, "
                "load %s -> %s\n",
                config.views, scene.triangle_count(), config.views, size, size, device.info().name.c_str(), rounds,
                to_string(before).c_str(), to_string(after).c_str());
    std::printf("%-20s %6s %10s %17s %9s  %s\n", "renderer", "frames", "median ms", "95% interval", "views/s",
                "set / its kernels");
    std::ofstream csv(out_dir / "bench-views.csv");
    csv << "renderer,frames,median_ms,ci_lo_ms,ci_hi_ms,views_per_s,error\n";
    nlohmann::json j{{"device", device.info().name}, {"mesh", "stanford-bunny.obj"},
                     {"triangles", scene.triangle_count()}, {"views", config.views}, {"width", size},
                     {"height", size}, {"threads", config.ref_threads}, {"rounds", rounds},
                     {"load_before", load_json(before)}, {"load_after", load_json(after)},
                     {"target_batch_over_kernels", target_batch_over_kernels}, {"runs", nlohmann::json::array()},
                     {"reference_errors", r.errors}};
    for (const Lane& lane : r.lanes) j["runs"].push_back(report_lane(r, lane, config.views, csv));
    for (const std::string& e : r.errors) std::printf("%-20s not run: %s\n", "", e.c_str());
    j["total_s"] = ms_since(t_start) / 1000;
    std::ofstream(out_dir / "bench-views.json") << j.dump(2) << "\n";
    std::printf("\nclvis bench --views: %.1f s; a frame is all %d views; set / its kernels = wall time over the sum "
                "of its views' kernel times (batch target <= %.1f); wrote %s\n",
                ms_since(t_start) / 1000, config.views, target_batch_over_kernels,
                (out_dir / "bench-views.json").string().c_str());
}

} // namespace clvis::bench
