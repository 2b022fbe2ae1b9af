// Runs one workload of the benchmark (see bench_run.hpp): clvis's paths and the references on
// the same scene and cameras, each buffer kept until the referee has judged it.
#include "bench_run.hpp"

#include "reference.hpp"

#include <clvis/renderer.hpp>
#include <clvis/visibility.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>

namespace clvis::bench {

Progress::Progress(std::size_t total) : total_(total), tty_(isatty(STDERR_FILENO) == 1) {}

void Progress::show(const std::string& what)
{
    if (!tty_) return;
    constexpr int width = 30;
    int filled = total_ ? int(width * done_ / total_) : width;
    std::string bar(std::size_t(filled), '#');
    bar.resize(width, '.');
    std::string line = "[" + bar + "] " + std::to_string(done_) + "/" + std::to_string(total_) + " " + what;
    if (line.size() > 110) line.resize(110);
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
    std::fflush(stderr);
}

void Progress::finish()
{
    if (tty_) std::fprintf(stderr, "\r\033[K");
}

namespace {

/// One clvis path at one point, framed by the interleaved rounds: its target and the stages of
/// its fastest frame.
struct ClvisLane {
    Renderer& renderer;
    Camera camera;
    Path path;
    VisibilityBuffer target;
    double best = INFINITY;
    std::vector<StageTiming> stages;

    /// Prepares the path and renders one untimed warm-up frame (first launches compile per
    /// work-group size). Throws on failure.
    ClvisLane(Renderer& r, const Camera& c, int width, int height, Path p) : renderer(r), camera(c), path(p)
    {
        renderer.prepare(path);
        target = VisibilityBuffer(renderer.device(), width, height);
        renderer.render(camera, path, target);
    }

    double frame()
    {
        renderer.render(camera, path, target);
        const FrameTiming& t = renderer.last_frame();
        if (t.frame_ms < best) {
            best = t.frame_ms;
            stages = t.stages;
        }
        return t.frame_ms;
    }
};

Run from_reference(ReferenceResult r)
{
    Run run;
    run.renderer = r.name;
    run.reference = true;
    run.error = r.error;
    run.frame_ms = std::move(r.frame_ms);
    run.build_ms = std::move(r.build_samples_ms);
    run.vis.width = r.width;
    run.vis.height = r.height;
    run.vis.ids = std::move(r.ids);
    run.vis.depth = std::move(r.depth);
    return run;
}

Run failed_run(const std::string& renderer, bool reference, const std::string& error)
{
    Run run;
    run.renderer = renderer;
    run.reference = reference;
    run.error = error;
    return run;
}

void compare_runs(Point& p, const Scene& scene, const Camera& camera)
{
    const std::pair<const char*, const char*> pairs[] = {{"raster", "ray"},
                                                         {"raster", "llvmpipe"},
                                                         {"ray", "embree-intersect1"},
                                                         {"ray", "embree-intersect16"},
                                                         {"brute", "ray"}};
    std::optional<Referee> referee;
    std::string referee_error;
    for (auto [a, b] : pairs) {
        const Run* ra = p.find(a);
        const Run* rb = p.find(b);
        if (!ra && !rb) continue;
        if (std::string(a) == "brute" && !ra) continue;
        Comparison c;
        c.a = a;
        c.b = b;
        if (!ra || !rb) {
            c.error = std::string("no buffer from ") + (!ra ? a : b);
        } else {
            try {
                if (!referee && referee_error.empty()) referee.emplace(scene, camera, p.width, p.height);
            } catch (const std::exception& e) {
                referee_error = std::string("referee: ") + e.what();
            }
            if (!referee_error.empty()) {
                c.error = referee_error;
            } else {
                try {
                    c.report = referee->compare(ra->vis, rb->vis);
                } catch (const std::exception& e) {
                    c.error = std::string("referee: ") + e.what();
                }
            }
        }
        p.comparisons.push_back(std::move(c));
    }
}

/// The renderers of one workload, made once for all its views; each error is why one is missing.
struct Renderers {
    std::optional<Renderer> clvis;
    std::string clvis_error;
    std::vector<double> clvis_builds; ///< every timed BVH build of the ray path
    BvhStats bvh;
    std::optional<EmbreeReference> embree;
    std::string embree_error;
    std::optional<GlReference> gl;
    std::string gl_error;
};

std::optional<Scene> make_scene(const Workload& w, std::string& error)
{
    std::optional<Scene> scene;
    try {
        scene = w.make();
    } catch (const std::exception& e) {
        error = e.what();
    }
    if (scene && scene->empty()) {
        error = w.mesh + ": no triangles";
        scene.reset();
    }
    return scene;
}

Point point_of(const Workload& w, const ViewSpec& v)
{
    Point p;
    p.mesh = w.mesh;
    p.camera = v.closeup ? "closeup" : "framing";
    p.sweeps = v.sweeps;
    p.width = v.width;
    p.height = v.height;
    return p;
}

/// Every view of a workload whose scene could not be made, each renderer failing with `error`.
void fail_views(const Workload& w, const std::string& error, std::vector<Point>& points, Progress& progress)
{
    for (const auto& v : w.views) {
        Point p = point_of(w, v);
        for (const char* r : {"raster", "ray", "embree-intersect1", "embree-intersect16", "llvmpipe"})
            p.runs.push_back(failed_run(r, r[0] == 'e' || r[0] == 'l', error));
        points.push_back(std::move(p));
        progress.advance();
    }
}

/// The renderers of one workload and their timed builds, alternating: clvis's first build (the
/// first prepare of the ray path), Embree's first (its constructor), then a fresh clvis renderer
/// and an Embree rebuild in turn, so that a change of load falls on both builders alike.
void make_renderers(Context& ctx, const Workload& w, const Scene& scene, int builds, Renderers& r, Progress& progress)
{
    r.clvis_error = ctx.device_error;
    if (r.clvis_error.empty()) {
        try {
            progress.show(w.mesh + ": clvis upload");
            r.clvis.emplace(ctx.device, scene);
        } catch (const std::exception& e) {
            r.clvis_error = e.what();
        }
    }
    // A failing clvis build is left to the ray runs, which report it per point.
    bool clvis_builds = r.clvis.has_value();
    auto clvis_build = [&](bool first) {
        if (!clvis_builds) return;
        try {
            if (first) {
                r.clvis->prepare(Path::Ray);
                r.bvh = r.clvis->bvh_stats();
                r.clvis_builds.push_back(r.bvh.build_ms);
                return;
            }
            Renderer fresh(ctx.device, scene);
            fresh.prepare(Path::Ray);
            r.clvis_builds.push_back(fresh.bvh_stats().build_ms);
        } catch (const std::exception&) {
            r.clvis_builds.clear();
            clvis_builds = false;
        }
    };
    progress.show(w.mesh + ": BVH builds");
    clvis_build(true);
    try {
        r.embree.emplace(scene, ctx.config.ref_threads, 1);
        ctx.embree_description = r.embree->description();
    } catch (const std::exception& e) {
        r.embree_error = e.what();
    }
    for (int b = 1; b < builds; ++b) {
        clvis_build(false);
        try {
            if (r.embree) r.embree->rebuild(scene);
        } catch (const std::exception& e) {
            r.embree.reset();
            r.embree_error = e.what();
        }
    }
    try {
        progress.show(w.mesh + ": GL upload");
        r.gl.emplace(scene, ctx.config.ref_threads);
        ctx.gl_description = r.gl->description();
    } catch (const std::exception& e) {
        r.gl_error = e.what();
    }
}

/// Everything timed at one point, in the order of Point::runs: each renderer's lane, made (and
/// warmed up) before the rounds, or the error that kept it out.
struct PointLanes {
    std::vector<std::unique_ptr<ClvisLane>> clvis;
    std::vector<std::unique_ptr<ReferenceView>> references;
    std::vector<Lane> lanes;
    std::vector<Run> runs; ///< one per lane: name, reference, error of its set-up
};

template <class Make> void add_lane(PointLanes& pl, const std::string& name, bool reference, int max_frames, Make make)
{
    Run run = failed_run(name, reference, "");
    Lane lane;
    lane.name = name;
    lane.max_frames = max_frames;
    try {
        lane.frame = make();
    } catch (const std::exception& e) {
        run.error = e.what();
    }
    if (!run.error.empty()) lane.error = run.error;
    pl.runs.push_back(std::move(run));
    pl.lanes.push_back(std::move(lane));
}

void make_lanes(const Context& ctx, Renderers& r, const Camera& camera, const std::string& label, const Point& p,
                PointLanes& pl, Progress& progress)
{
    const double brute_budget = ctx.config.quick ? brute_max_tests_quick : brute_max_tests_full;
    std::vector<Path> paths{Path::Raster, Path::Ray};
    if (p.triangles <= brute_max_triangles && double(p.triangles) * p.width * p.height <= brute_budget)
        paths.push_back(Path::Brute);
    for (Path path : paths) {
        progress.show(label + ": clvis " + to_string(path) + " warm-up");
        add_lane(pl, to_string(path), false, path == Path::Brute ? brute_repeat : 0, [&]() -> std::function<double()> {
            if (!r.clvis) throw std::runtime_error(r.clvis_error);
            pl.clvis.push_back(std::make_unique<ClvisLane>(*r.clvis, camera, p.width, p.height, path));
            return [l = pl.clvis.back().get()] { return l->frame(); };
        });
    }
    for (auto mode : {EmbreeMode::Single, EmbreeMode::Packet16}) {
        std::string name = mode == EmbreeMode::Single ? "embree-intersect1" : "embree-intersect16";
        progress.show(label + ": " + name + " warm-up");
        add_lane(pl, name, true, 0, [&]() -> std::function<double()> {
            if (!r.embree) throw std::runtime_error(r.embree_error);
            pl.references.push_back(r.embree->view(camera, p.width, p.height, mode));
            return [v = pl.references.back().get()] { return v->frame(); };
        });
    }
    progress.show(label + ": llvmpipe warm-up");
    add_lane(pl, "llvmpipe", true, 0, [&]() -> std::function<double()> {
        if (!r.gl) throw std::runtime_error(r.gl_error);
        pl.references.push_back(r.gl->view(camera, p.width, p.height));
        return [v = pl.references.back().get()] { return v->frame(); };
    });
}

/// A set-up lane's figures after the rounds: stages, builds and buffer. Throws when a
/// reference's result fails.
void collect_run(Renderers& r, PointLanes& pl, const Lane& lane, Run& run, std::size_t& next_clvis,
                 std::size_t& next_reference)
{
    if (run.reference) {
        run.vis = std::move(from_reference(pl.references[next_reference++]->result()).vis);
        if (run.renderer == "embree-intersect1" || run.renderer == "embree-intersect16")
            run.build_ms = r.embree->build_samples_ms();
        return;
    }
    ClvisLane& c = *pl.clvis[next_clvis++];
    if (!lane.error.empty()) return;
    run.stages = c.stages;
    run.vis = c.target.read();
    if (c.path == Path::Ray) {
        run.build_ms = r.clvis_builds;
        run.bvh_nodes = r.bvh.nodes;
        run.bvh_depth = r.bvh.depth;
    }
}

/// The runs of one point after its rounds, in lane order.
void collect_runs(Renderers& r, PointLanes& pl, Point& p)
{
    std::size_t next_clvis = 0, next_reference = 0;
    for (std::size_t k = 0; k < pl.lanes.size(); ++k) {
        Run run = std::move(pl.runs[k]);
        Lane& lane = pl.lanes[k];
        if (run.error.empty()) {
            try {
                collect_run(r, pl, lane, run, next_clvis, next_reference);
            } catch (const std::exception& e) {
                lane.error = e.what();
            }
            run.error = lane.error;
        }
        if (run.error.empty()) run.frame_ms = std::move(lane.ms);
        else run.vis = HostVisibility{};
        p.runs.push_back(std::move(run));
    }
}

/// One view: every renderer warmed up, then timed in interleaved rounds, their buffers judged,
/// then dropped.
Point run_view(const Context& ctx, const Workload& w, const ViewSpec& v, const Scene& scene, Renderers& r,
               Progress& progress)
{
    Point p = point_of(w, v);
    p.triangles = scene.triangle_count();
    std::string label = w.mesh + " " + p.camera + " " + std::to_string(v.width) + "x" + std::to_string(v.height);
    Camera camera = Camera::framing(scene.bounds());
    if (v.closeup) camera = closeup_of(camera, scene.bounds());
    p.camera_flags = camera.to_flags();

    {
        PointLanes pl;
        make_lanes(ctx, r, camera, label, p, pl, progress);
        progress.show(label + ": timing, interleaved");
        p.load_before = read_load();
        p.rounds = interleave(pl.lanes, ctx.rule);
        p.load_after = read_load();
        collect_runs(r, pl, p);
    }
    progress.show(label + ": referee");
    compare_runs(p, scene, camera);
    for (const auto& run : p.runs)
        if (p.coverage < 0 && !run.vis.ids.empty()) {
            auto covered = std::count_if(run.vis.ids.begin(), run.vis.ids.end(),
                                         [](std::uint32_t id) { return id != background_id; });
            p.coverage = double(covered) / double(run.vis.ids.size());
        }
    for (auto& run : p.runs) run.vis = HostVisibility{};
    return p;
}

/// Every view of one workload.
void run_views(Context& ctx, const Workload& w, std::vector<Point>& points, Progress& progress)
{
    progress.show(w.mesh + ": loading");
    std::string scene_error;
    std::optional<Scene> scene = make_scene(w, scene_error);
    if (!scene) {
        fail_views(w, scene_error, points, progress);
        return;
    }
    const std::size_t triangles = scene->triangle_count();
    const int builds = triangles > single_build_above ? 1 : ctx.config.quick ? builds_quick : builds_full;
    Renderers r;
    make_renderers(ctx, w, *scene, builds, r, progress);
    for (const auto& v : w.views) {
        points.push_back(run_view(ctx, w, v, *scene, r, progress));
        progress.advance();
    }
}

} // namespace

void run_workload(Context& ctx, const Workload& w, std::vector<Point>& points, Progress& progress)
{
    const std::size_t first = points.size();
    run_views(ctx, w, points, progress);
    for (std::size_t k = first; k < points.size(); ++k) points[k].pass = ctx.pass;
}

} // namespace clvis::bench
