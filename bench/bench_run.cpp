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
#include <optional>

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

/// Times one clvis path: one untimed warm-up, then `repeat` frames (fewer past `budget_ms`);
/// never throws.
Run run_clvis(Renderer& renderer, const Camera& camera, int width, int height, Path path, int repeat,
              double budget_ms)
{
    Run run;
    run.renderer = to_string(path);
    try {
        renderer.prepare(path);
        VisibilityBuffer target(renderer.device(), width, height);
        renderer.render(camera, path, target); // warm-up: first launches compile per work-group size
        double best = INFINITY;
        while (!enough_frames(run.frame_ms, repeat, budget_ms)) {
            renderer.render(camera, path, target);
            const FrameTiming& t = renderer.last_frame();
            run.frame_ms.push_back(t.frame_ms);
            if (t.frame_ms < best) {
                best = t.frame_ms;
                run.stages = t.stages;
            }
        }
        run.vis = target.read();
    } catch (const std::exception& e) {
        run.error = e.what();
        run.frame_ms.clear();
    }
    return run;
}

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

/// clvis: one renderer for every view; the BVH is built once here (first prepare of the ray
/// path) and again by fresh renderers for the further timed builds.
void make_clvis(Context& ctx, const Workload& w, const Scene& scene, int builds, Renderers& r, Progress& progress)
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
    if (!r.clvis) return;
    // A failing build is left to the ray runs, which report it per point.
    try {
        progress.show(w.mesh + ": clvis BVH build");
        r.clvis->prepare(Path::Ray);
        r.bvh = r.clvis->bvh_stats();
        r.clvis_builds.push_back(r.bvh.build_ms);
        for (int b = 1; b < builds; ++b) {
            Renderer fresh(ctx.device, scene);
            fresh.prepare(Path::Ray);
            r.clvis_builds.push_back(fresh.bvh_stats().build_ms);
        }
    } catch (const std::exception&) {
        r.clvis_builds.clear();
    }
}

void make_references(Context& ctx, const Workload& w, const Scene& scene, int builds, Renderers& r,
                     Progress& progress)
{
    try {
        progress.show(w.mesh + ": Embree build");
        r.embree.emplace(scene, ctx.config.ref_threads, builds);
        ctx.embree_description = r.embree->description();
    } catch (const std::exception& e) {
        r.embree_error = e.what();
    }
    try {
        progress.show(w.mesh + ": GL upload");
        r.gl.emplace(scene, ctx.config.ref_threads);
        ctx.gl_description = r.gl->description();
    } catch (const std::exception& e) {
        r.gl_error = e.what();
    }
}

void run_clvis_paths(const Context& ctx, Renderers& r, const Camera& camera, const std::string& label, Point& p,
                     Progress& progress)
{
    const double brute_budget = ctx.config.quick ? brute_max_tests_quick : brute_max_tests_full;
    std::vector<Path> paths{Path::Raster, Path::Ray};
    if (p.triangles <= brute_max_triangles && double(p.triangles) * p.width * p.height <= brute_budget)
        paths.push_back(Path::Brute);
    for (Path path : paths) {
        progress.show(label + ": clvis " + to_string(path));
        int frames = path == Path::Brute ? std::min(ctx.repeat, brute_repeat) : ctx.repeat;
        Run run = r.clvis ? run_clvis(*r.clvis, camera, p.width, p.height, path, frames, ctx.budget_ms)
                          : failed_run(to_string(path), false, r.clvis_error);
        if (path == Path::Ray && run.error.empty()) {
            run.build_ms = r.clvis_builds;
            run.bvh_nodes = r.bvh.nodes;
            run.bvh_depth = r.bvh.depth;
        }
        p.runs.push_back(std::move(run));
    }
}

void run_references(const Context& ctx, Renderers& r, const Camera& camera, const std::string& label, Point& p,
                    Progress& progress)
{
    for (auto mode : {EmbreeMode::Single, EmbreeMode::Packet16}) {
        std::string name = mode == EmbreeMode::Single ? "embree-intersect1" : "embree-intersect16";
        progress.show(label + ": " + name);
        if (!r.embree) {
            p.runs.push_back(failed_run(name, true, r.embree_error));
            continue;
        }
        try {
            p.runs.push_back(from_reference(r.embree->render(camera, p.width, p.height, mode, ctx.repeat, ctx.budget_ms)));
        } catch (const std::exception& e) {
            p.runs.push_back(failed_run(name, true, e.what()));
        }
    }
    progress.show(label + ": llvmpipe");
    if (!r.gl) {
        p.runs.push_back(failed_run("llvmpipe", true, r.gl_error));
        return;
    }
    try {
        p.runs.push_back(from_reference(r.gl->render(camera, p.width, p.height, ctx.repeat, ctx.budget_ms)));
    } catch (const std::exception& e) {
        p.runs.push_back(failed_run("llvmpipe", true, e.what()));
    }
}

/// One view: every renderer timed, their buffers judged, then dropped.
Point run_view(const Context& ctx, const Workload& w, const ViewSpec& v, const Scene& scene, Renderers& r,
               Progress& progress)
{
    Point p = point_of(w, v);
    p.triangles = scene.triangle_count();
    std::string label = w.mesh + " " + p.camera + " " + std::to_string(v.width) + "x" + std::to_string(v.height);
    Camera camera = Camera::framing(scene.bounds());
    if (v.closeup) camera = closeup_of(camera, scene.bounds());
    p.camera_flags = camera.to_flags();

    run_clvis_paths(ctx, r, camera, label, p, progress);
    run_references(ctx, r, camera, label, p, progress);
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

} // namespace

void run_workload(Context& ctx, const Workload& w, std::vector<Point>& points, Progress& progress)
{
    progress.show(w.mesh + ": loading");
    std::string scene_error;
    std::optional<Scene> scene = make_scene(w, scene_error);
    if (!scene) {
        fail_views(w, scene_error, points, progress);
        return;
    }
    const std::size_t triangles = scene->triangle_count();
    const int builds = triangles > single_build_above ? 1 : ctx.config.quick ? 2 : 3;
    Renderers r;
    make_clvis(ctx, w, *scene, builds, r, progress);
    make_references(ctx, w, *scene, builds, r, progress);
    for (const auto& v : w.views) {
        points.push_back(run_view(ctx, w, v, *scene, r, progress));
        progress.advance();
    }
}

} // namespace clvis::bench
