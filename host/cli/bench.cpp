// clvis bench: times both paths (and brute force on small scenes) against the reference renderers
// of bench/ (Embree for rays, Mesa's llvmpipe for rasterization) on the same meshes and cameras in
// one run, judges every answer with the referee, and writes bench.csv, bench.json and plots.
// Ratios within one run are what count: the machine is shared, absolute times are noisy.
#include "commands.hpp"
#include "options.hpp"
#include "reference.hpp"

#include <clvis/clvis.hpp>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

namespace clvis::cli {

namespace {

namespace fs = std::filesystem;

/// The close-up camera of a real mesh: the framing camera's eye moved toward its target to this
/// fraction of the framing distance (the bounding sphere then overfills the vertical field of
/// view by about 3x: the mesh covers the whole image). Near and far follow below.
constexpr double closeup_fraction = 0.35;
/// Close-up near plane as a fraction of the close-up distance: the eye may be inside the
/// bounding sphere, so the framing rule 0.9 (dist - R) could be negative.
constexpr double closeup_near_fraction = 0.05;
/// Brute force (one ray against every triangle) only on small scenes, and only while
/// triangles x pixels (ray-triangle tests per frame) stays under a budget: it ran at about 25M
/// tests/s here (PoCL, 2 busy cores), so 6e7 tests are a few seconds a frame. Small images of
/// small meshes (the "brute" sweep) give it points of its own.
constexpr std::size_t brute_max_triangles = 16384;
constexpr double brute_max_tests_full = 6e7;
constexpr double brute_max_tests_quick = 2.5e7;
/// Timed brute-force frames at most (each may take a second).
constexpr int brute_repeat = 3;
/// Scenes above this many triangles get one timed BVH build per builder (each takes seconds).
constexpr std::size_t single_build_above = 1u << 20;
/// Without --repeat, each renderer stops timing a point once its timed frames add up to this
/// (after at least bench::min_budget_frames): the 4M-triangle points take seconds per frame.
constexpr double frame_budget_ms_full = 3000;
constexpr double frame_budget_ms_quick = 1500;
/// Targets of issue #7 (clvis / reference, medians).
constexpr double target_raster_over_llvmpipe = 0.5;
constexpr double target_ray_over_embree1 = 1.0;
constexpr double target_build_over_embree = 1.5;

struct BenchArgs {
    bool quick = false;
    std::string out = "bench-out";
    DeviceOptions device;
    int repeat = 0;      ///< 0: up to 10 timed frames (5 with --quick) within a time budget
    int ref_threads = 2; ///< threads of the reference renderers (trace, raster and build)
    bool no_plot = false;
};

struct Summary {
    double min = 0, p25 = 0, median = 0, p75 = 0, max = 0;
    std::size_t n = 0;
};

double quantile(const std::vector<double>& sorted, double q)
{
    double pos = q * double(sorted.size() - 1);
    std::size_t lo = std::size_t(pos);
    std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (pos - double(lo)) * (sorted[hi] - sorted[lo]);
}

Summary summarize(std::vector<double> v)
{
    Summary s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s = {v.front(), quantile(v, 0.25), quantile(v, 0.5), quantile(v, 0.75), v.back(), v.size()};
    return s;
}

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
    std::vector<Run> runs;
    std::vector<Comparison> comparisons;

    const Run* find(const std::string& renderer) const
    {
        for (const auto& r : runs)
            if (r.renderer == renderer && r.error.empty() && !r.frame_ms.empty()) return &r;
        return nullptr;
    }
};

struct ViewSpec {
    bool closeup = false;
    int width = 1920, height = 1080;
    std::vector<std::string> sweeps;
};

struct Workload {
    std::string mesh;
    std::function<Scene()> make;
    std::vector<ViewSpec> views;
};

/// A progress bar on standard error when it is a terminal; silent otherwise.
class Progress {
public:
    explicit Progress(std::size_t total) : total_(total), tty_(isatty(STDERR_FILENO) == 1) {}
    void show(const std::string& what)
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
    void advance() { ++done_; }
    void finish()
    {
        if (tty_) std::fprintf(stderr, "\r\033[K");
    }

private:
    std::size_t total_, done_ = 0;
    bool tty_;
};

std::string fmt(const char* format, double v)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

double ms_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// Folders that may hold the bundled meshes: ./scenes, then the source tree's.
std::vector<fs::path> scene_dirs()
{
    std::vector<fs::path> dirs{fs::path("scenes")};
#ifdef CLVIS_BENCH_SOURCE_DIR
    dirs.push_back(fs::path(CLVIS_BENCH_SOURCE_DIR) / "scenes");
#endif
    return dirs;
}

std::optional<fs::path> find_scene_dir()
{
    for (const auto& d : scene_dirs()) {
        std::error_code ec;
        if (fs::is_regular_file(d / "stanford-bunny.obj", ec)) return d;
    }
    return std::nullopt;
}

fs::path find_plot_script()
{
    std::vector<fs::path> candidates{fs::path("bench") / "plot.py"};
#ifdef CLVIS_BENCH_SOURCE_DIR
    candidates.push_back(fs::path(CLVIS_BENCH_SOURCE_DIR) / "bench" / "plot.py");
#endif
    for (const auto& c : candidates) {
        std::error_code ec;
        if (fs::is_regular_file(c, ec)) return c;
    }
    return {};
}

Scene scene_of(MeshData mesh)
{
    Scene s;
    s.add_mesh(std::move(mesh));
    return s;
}

/// The mesh named `file` from the scenes folder, or a scene whose loading throws that it is missing.
std::function<Scene()> mesh_file(const std::optional<fs::path>& dir, const std::string& file)
{
    return [dir, file] {
        if (!dir)
            throw Error(Error::Kind::Io, file + ": no scenes folder found (looked in ./scenes and the source tree)");
        return scene_of(load_mesh((*dir / file).string()));
    };
}

std::string count_label(std::size_t n)
{
    if (n >= (1u << 20) && n % (1u << 20) == 0) return std::to_string(n >> 20) + "M";
    if (n >= 1024 && n % 1024 == 0) return std::to_string(n >> 10) + "k";
    return std::to_string(n);
}

/// The sweep: triangle counts on procedural meshes at 1920x1080, resolutions on the bunny, and
/// every bundled mesh under the framing and the close-up camera.
std::vector<Workload> plan(bool quick)
{
    std::optional<fs::path> dir = find_scene_dir();
    std::vector<Workload> w;
    const ViewSpec hd_triangles{false, 1920, 1080, {"triangles"}};
    std::vector<std::size_t> sphere_counts = quick ? std::vector<std::size_t>{1u << 10, 1u << 16}
                                                   : std::vector<std::size_t>{1u << 10, 1u << 12, 1u << 14, 1u << 16,
                                                                              1u << 18, 1u << 20, 1u << 22};
    for (std::size_t n : sphere_counts)
        w.push_back({"sphere-" + count_label(n), [n] { return scene_of(make_uv_sphere(n)); }, {hd_triangles}});
    if (!quick)
        for (std::size_t n : {std::size_t(1) << 16, std::size_t(1) << 20}) {
            w.push_back({"grid-" + count_label(n), [n] { return scene_of(make_grid(n, 7)); }, {hd_triangles}});
            w.push_back({"soup-" + count_label(n), [n] { return scene_of(make_soup(n, 7)); }, {hd_triangles}});
        }

    Workload bunny{"stanford-bunny", mesh_file(dir, "stanford-bunny.obj"), {}};
    bunny.views.push_back({false, 1920, 1080, {"mesh", "resolution"}});
    bunny.views.push_back({true, 1920, 1080, {"mesh"}});
    std::vector<std::pair<int, int>> sizes = quick ? std::vector<std::pair<int, int>>{{640, 480}}
                                                   : std::vector<std::pair<int, int>>{{256, 256},
                                                                                      {640, 480},
                                                                                      {1280, 720},
                                                                                      {2560, 1440},
                                                                                      {3840, 2160}};
    for (auto [width, height] : sizes) bunny.views.push_back({false, width, height, {"resolution"}});
    w.push_back(bunny);

    std::vector<std::string> others;
    if (dir) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(*dir, ec)) {
            std::string ext = entry.path().extension().string();
            std::string name = entry.path().filename().string();
            if ((ext == ".obj" || ext == ".ply" || ext == ".stl") && name != "stanford-bunny.obj") others.push_back(name);
        }
        std::sort(others.begin(), others.end());
    }
    if (quick) others.erase(std::remove_if(others.begin(), others.end(),
                                           [](const std::string& n) { return n != "suzanne.obj"; }),
                            others.end());
    for (const auto& name : others) {
        Workload m{fs::path(name).stem().string(), mesh_file(dir, name), {}};
        m.views.push_back({false, 1920, 1080, {"mesh"}});
        if (!quick) m.views.push_back({true, 1920, 1080, {"mesh"}});
        if (name == "suzanne.obj") m.views.push_back({false, quick ? 192 : 256, quick ? 108 : 144, {"brute"}});
        w.push_back(m);
    }
    if (!quick) w[0].views.push_back({false, 256, 144, {"brute"}}); // the 1k sphere
    return w;
}

Camera closeup_of(const Camera& framing, const Bounds& bounds)
{
    Camera c = framing;
    double dist = length(framing.eye - framing.target) * closeup_fraction;
    double radius = length(bounds.extent()) / 2;
    c.eye = framing.target + normalize(framing.eye - framing.target) * dist;
    c.near = closeup_near_fraction * dist;
    c.far = 1.1 * (dist + radius);
    return c;
}

struct Context {
    const BenchArgs& args;
    int repeat;
    double budget_ms; ///< 0 with an explicit --repeat: exactly `repeat` frames
    Device device;
    std::string device_error;
    std::string embree_description, gl_description;
};

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
        while (!bench::enough_frames(run.frame_ms, repeat, budget_ms)) {
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

Run from_reference(bench::ReferenceResult r)
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

/// Every point of one workload: the scene, its clvis renderer and references made once.
void run_workload(Context& ctx, const Workload& w, std::vector<Point>& points, Progress& progress)
{
    const int repeat = ctx.repeat;
    progress.show(w.mesh + ": loading");
    std::optional<Scene> scene;
    std::string scene_error;
    try {
        scene = w.make();
    } catch (const std::exception& e) {
        scene_error = e.what();
    }
    if (scene && scene->empty()) {
        scene_error = w.mesh + ": no triangles";
        scene.reset();
    }
    if (!scene) {
        for (const auto& v : w.views) {
            Point p;
            p.mesh = w.mesh;
            p.camera = v.closeup ? "closeup" : "framing";
            p.sweeps = v.sweeps;
            p.width = v.width;
            p.height = v.height;
            for (const char* r : {"raster", "ray", "embree-intersect1", "embree-intersect16", "llvmpipe"})
                p.runs.push_back(failed_run(r, r[0] == 'e' || r[0] == 'l', scene_error));
            points.push_back(std::move(p));
            progress.advance();
        }
        return;
    }
    const std::size_t triangles = scene->triangle_count();
    const int builds = triangles > single_build_above ? 1 : ctx.args.quick ? 2 : 3;

    // clvis: one renderer for every view; the BVH is built once here (first prepare of the ray
    // path) and again by fresh renderers for the further timed builds.
    std::optional<Renderer> renderer;
    std::string renderer_error = ctx.device_error;
    std::vector<double> clvis_builds;
    BvhStats bvh;
    if (renderer_error.empty()) {
        try {
            progress.show(w.mesh + ": clvis upload");
            renderer.emplace(ctx.device, *scene);
        } catch (const std::exception& e) {
            renderer_error = e.what();
        }
    }
    if (renderer) {
        // A failing build is left to the ray runs below, which report it per point.
        try {
            progress.show(w.mesh + ": clvis BVH build");
            renderer->prepare(Path::Ray);
            bvh = renderer->bvh_stats();
            clvis_builds.push_back(bvh.build_ms);
            for (int b = 1; b < builds; ++b) {
                Renderer fresh(ctx.device, *scene);
                fresh.prepare(Path::Ray);
                clvis_builds.push_back(fresh.bvh_stats().build_ms);
            }
        } catch (const std::exception&) {
            clvis_builds.clear();
        }
    }

    std::optional<bench::EmbreeReference> embree;
    std::string embree_error;
    try {
        progress.show(w.mesh + ": Embree build");
        embree.emplace(*scene, ctx.args.ref_threads, builds);
        ctx.embree_description = embree->description();
    } catch (const std::exception& e) {
        embree_error = e.what();
    }
    std::optional<bench::GlReference> gl;
    std::string gl_error;
    try {
        progress.show(w.mesh + ": GL upload");
        gl.emplace(*scene, ctx.args.ref_threads);
        ctx.gl_description = gl->description();
    } catch (const std::exception& e) {
        gl_error = e.what();
    }

    const double brute_budget = ctx.args.quick ? brute_max_tests_quick : brute_max_tests_full;
    for (const auto& v : w.views) {
        Point p;
        p.mesh = w.mesh;
        p.camera = v.closeup ? "closeup" : "framing";
        p.sweeps = v.sweeps;
        p.triangles = triangles;
        p.width = v.width;
        p.height = v.height;
        std::string label = w.mesh + " " + p.camera + " " + std::to_string(v.width) + "x" + std::to_string(v.height);
        Camera camera = Camera::framing(scene->bounds());
        if (v.closeup) camera = closeup_of(camera, scene->bounds());
        p.camera_flags = camera.to_flags();

        std::vector<Path> paths{Path::Raster, Path::Ray};
        if (triangles <= brute_max_triangles && double(triangles) * v.width * v.height <= brute_budget)
            paths.push_back(Path::Brute);
        for (Path path : paths) {
            progress.show(label + ": clvis " + to_string(path));
            int frames = path == Path::Brute ? std::min(repeat, brute_repeat) : repeat;
            Run run = renderer ? run_clvis(*renderer, camera, v.width, v.height, path, frames, ctx.budget_ms)
                               : failed_run(to_string(path), false, renderer_error);
            if (path == Path::Ray && run.error.empty()) {
                run.build_ms = clvis_builds;
                run.bvh_nodes = bvh.nodes;
                run.bvh_depth = bvh.depth;
            }
            p.runs.push_back(std::move(run));
        }
        for (auto mode : {bench::EmbreeMode::Single, bench::EmbreeMode::Packet16}) {
            std::string name = mode == bench::EmbreeMode::Single ? "embree-intersect1" : "embree-intersect16";
            progress.show(label + ": " + name);
            if (!embree) {
                p.runs.push_back(failed_run(name, true, embree_error));
                continue;
            }
            try {
                p.runs.push_back(from_reference(embree->render(camera, v.width, v.height, mode, repeat, ctx.budget_ms)));
            } catch (const std::exception& e) {
                p.runs.push_back(failed_run(name, true, e.what()));
            }
        }
        progress.show(label + ": llvmpipe");
        if (!gl) {
            p.runs.push_back(failed_run("llvmpipe", true, gl_error));
        } else {
            try {
                p.runs.push_back(from_reference(gl->render(camera, v.width, v.height, repeat, ctx.budget_ms)));
            } catch (const std::exception& e) {
                p.runs.push_back(failed_run("llvmpipe", true, e.what()));
            }
        }
        progress.show(label + ": referee");
        compare_runs(p, *scene, camera);
        for (const auto& r : p.runs)
            if (p.coverage < 0 && !r.vis.ids.empty()) {
                auto covered = std::count_if(r.vis.ids.begin(), r.vis.ids.end(),
                                             [](std::uint32_t id) { return id != background_id; });
                p.coverage = double(covered) / double(r.vis.ids.size());
            }
        for (auto& r : p.runs) r.vis = HostVisibility{};
        points.push_back(std::move(p));
        progress.advance();
    }
}

/// clvis median / reference median, or nullopt when either is missing.
std::optional<double> ratio(const Point& p, const std::string& a, const std::string& b)
{
    const Run* ra = p.find(a);
    const Run* rb = p.find(b);
    if (!ra || !rb) return std::nullopt;
    double mb = summarize(rb->frame_ms).median;
    if (!(mb > 0)) return std::nullopt;
    return summarize(ra->frame_ms).median / mb;
}

std::optional<double> build_ratio(const Point& p)
{
    const Run* ray = p.find("ray");
    const Run* e = p.find("embree-intersect1");
    if (!ray || !e || ray->build_ms.empty() || e->build_ms.empty()) return std::nullopt;
    double eb = summarize(e->build_ms).median;
    if (!(eb > 0)) return std::nullopt;
    return summarize(ray->build_ms).median / eb;
}

nlohmann::json optional_json(const std::optional<double>& v)
{
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json summary_json(const std::vector<double>& samples)
{
    Summary s = summarize(samples);
    return {{"min", s.min}, {"p25", s.p25}, {"median", s.median}, {"p75", s.p75}, {"max", s.max},
            {"samples", samples}};
}

nlohmann::json point_json(const Point& p)
{
    nlohmann::json j{{"mesh", p.mesh},   {"camera", p.camera},   {"sweeps", p.sweeps},
                     {"triangles", p.triangles}, {"width", p.width}, {"height", p.height},
                     {"camera_flags", p.camera_flags}};
    j["coverage"] = p.coverage >= 0 ? nlohmann::json(p.coverage) : nlohmann::json(nullptr);
    j["runs"] = nlohmann::json::array();
    for (const auto& r : p.runs) {
        nlohmann::json rj{{"renderer", r.renderer}, {"reference", r.reference}};
        if (!r.error.empty()) rj["error"] = r.error;
        else {
            rj["frame_ms"] = summary_json(r.frame_ms);
            if (!r.stages.empty()) {
                nlohmann::json st = nlohmann::json::object();
                for (const auto& s : r.stages) st[s.name] = s.ms;
                rj["stages_ms"] = st;
            }
            if (!r.build_ms.empty()) rj["build_ms"] = summary_json(r.build_ms);
            if (r.bvh_nodes) {
                rj["bvh_nodes"] = r.bvh_nodes;
                rj["bvh_depth"] = r.bvh_depth;
            }
        }
        j["runs"].push_back(rj);
    }
    j["comparisons"] = nlohmann::json::array();
    for (const auto& c : p.comparisons) {
        nlohmann::json cj{{"a", c.a}, {"b", c.b}};
        if (!c.error.empty()) cj["error"] = c.error;
        else
            cj.update({{"pixels", c.report.pixels},     {"equal", c.report.equal},
                       {"explained", c.report.explained}, {"errors", c.report.errors},
                       {"errors_a", c.report.errors_a},   {"errors_b", c.report.errors_b}});
        j["comparisons"].push_back(cj);
    }
    j["ratios"] = {{"raster_over_llvmpipe", optional_json(ratio(p, "raster", "llvmpipe"))},
                   {"ray_over_embree_intersect1", optional_json(ratio(p, "ray", "embree-intersect1"))},
                   {"ray_over_embree_intersect16", optional_json(ratio(p, "ray", "embree-intersect16"))},
                   {"bvh_build_over_embree_build", optional_json(build_ratio(p))},
                   {"raster_over_ray", optional_json(ratio(p, "raster", "ray"))}};
    return j;
}

std::string csv_field(const std::string& s)
{
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += '"';
        out += c == '\n' ? ' ' : c;
    }
    return out + "\"";
}

void write_csv(const fs::path& file, const std::vector<Point>& points)
{
    std::ofstream out(file);
    if (!out) throw Error(Error::Kind::Io, file.string() + ": cannot write");
    out << "mesh,camera,sweeps,triangles,width,height,renderer,frames,frame_min_ms,frame_p25_ms,frame_median_ms,"
           "frame_p75_ms,frame_max_ms,build_median_ms,build_min_ms,bvh_nodes,stages_ms,error\n";
    for (const auto& p : points) {
        std::string sweeps;
        for (const auto& s : p.sweeps) sweeps += (sweeps.empty() ? "" : "+") + s;
        for (const auto& r : p.runs) {
            Summary f = summarize(r.frame_ms), b = summarize(r.build_ms);
            std::string stages;
            for (const auto& s : r.stages) stages += (stages.empty() ? "" : ";") + s.name + "=" + fmt("%.4f", s.ms);
            out << csv_field(p.mesh) << ',' << p.camera << ',' << sweeps << ',' << p.triangles << ',' << p.width << ','
                << p.height << ',' << r.renderer << ',' << f.n << ',' << f.min << ',' << f.p25 << ',' << f.median << ','
                << f.p75 << ',' << f.max << ',' << (b.n ? fmt("%.4f", b.median) : "") << ','
                << (b.n ? fmt("%.4f", b.min) : "") << ',' << (r.bvh_nodes ? std::to_string(r.bvh_nodes) : "") << ','
                << csv_field(stages) << ',' << csv_field(r.error) << '\n';
        }
    }
    if (!out) throw Error(Error::Kind::Io, file.string() + ": write failed");
}

std::string utc_now()
{
    std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

std::string cell(const std::optional<double>& v, const char* format, double target = 0)
{
    if (!v) return "-";
    std::string s = fmt(format, *v);
    if (target > 0 && *v > target) s += "!";
    return s;
}

std::string ms_cell(const Point& p, const std::string& renderer)
{
    const Run* r = p.find(renderer);
    return r ? fmt("%.2f", summarize(r->frame_ms).median) : "fail";
}

std::string verdict_cell(const Point& p, const std::string& a, const std::string& b)
{
    for (const auto& c : p.comparisons)
        if (c.a == a && c.b == b) {
            if (!c.error.empty()) return "n/a";
            return std::to_string(c.report.errors) + "e/" + std::to_string(c.report.explained) + "x";
        }
    return "-";
}

void print_table(const std::vector<Point>& points)
{
    std::printf("\nMedian frame times (ms) and clvis / reference ratios; '!' misses the target "
                "(raster/llvmpipe <= %.1f, ray/rtcIntersect1 <= %.1f, BVH build/Embree build <= %.1f).\n"
                "Referee columns: pixels with an unacceptable answer (e) / explained mismatches (x).\n",
                target_raster_over_llvmpipe, target_ray_over_embree1, target_build_over_embree);
    std::printf("%-18s %-7s %8s %9s %5s | %8s %8s %6s | %8s %8s %6s %8s %6s | %8s %8s %6s | %8s | %-10s %-10s %-10s "
                "%-10s %-10s\n",
                "mesh", "camera", "tris", "size", "cover", "raster", "llvmpipe", "r/gl", "ray", "e-1", "ray/e1", "e-16",
                "ray/16", "bvh", "e-build", "b/e", "brute", "raster|ray", "raster|gl", "ray|e1", "ray|e16", "brute|ray");
    for (const auto& p : points) {
        const Run* ray = p.find("ray");
        const Run* em = p.find("embree-intersect1");
        std::string size = std::to_string(p.width) + "x" + std::to_string(p.height);
        std::string bvh = ray && !ray->build_ms.empty() ? fmt("%.1f", summarize(ray->build_ms).median) : "-";
        std::string eb = em && !em->build_ms.empty() ? fmt("%.1f", summarize(em->build_ms).median) : "-";
        std::string cover = p.coverage >= 0 ? fmt("%.0f%%", 100 * p.coverage) : "-";
        std::string brute = p.find("brute") ? ms_cell(p, "brute") : "-";
        std::printf("%-18s %-7s %8zu %9s %5s | %8s %8s %6s | %8s %8s %6s %8s %6s | %8s %8s %6s | %8s | %-10s %-10s %-10s "
                    "%-10s %-10s\n",
                    p.mesh.c_str(), p.camera.c_str(), p.triangles, size.c_str(), cover.c_str(), ms_cell(p, "raster").c_str(),
                    ms_cell(p, "llvmpipe").c_str(),
                    cell(ratio(p, "raster", "llvmpipe"), "%.2f", target_raster_over_llvmpipe).c_str(),
                    ms_cell(p, "ray").c_str(), ms_cell(p, "embree-intersect1").c_str(),
                    cell(ratio(p, "ray", "embree-intersect1"), "%.2f", target_ray_over_embree1).c_str(),
                    ms_cell(p, "embree-intersect16").c_str(), cell(ratio(p, "ray", "embree-intersect16"), "%.2f").c_str(),
                    bvh.c_str(), eb.c_str(), cell(build_ratio(p), "%.2f", target_build_over_embree).c_str(),
                    brute.c_str(), verdict_cell(p, "raster", "ray").c_str(), verdict_cell(p, "raster", "llvmpipe").c_str(),
                    verdict_cell(p, "ray", "embree-intersect1").c_str(),
                    verdict_cell(p, "ray", "embree-intersect16").c_str(), verdict_cell(p, "brute", "ray").c_str());
    }
    // Failures, once per renderer and message.
    std::vector<std::string> seen;
    for (const auto& p : points)
        for (const auto& r : p.runs) {
            if (r.error.empty()) continue;
            std::string line = r.renderer + ": " + r.error;
            if (std::find(seen.begin(), seen.end(), line) != seen.end()) continue;
            seen.push_back(line);
            std::printf("failed: %s (first at %s %s %dx%d)\n", line.c_str(), p.mesh.c_str(), p.camera.c_str(), p.width,
                        p.height);
        }
    for (const auto& p : points)
        for (const auto& c : p.comparisons) {
            if (c.error.empty()) continue;
            std::string line = c.a + " vs " + c.b + ": " + c.error;
            if (std::find(seen.begin(), seen.end(), line) != seen.end()) continue;
            seen.push_back(line);
            std::printf("not compared: %s\n", line.c_str());
        }
    std::fflush(stdout);
}

/// Runs bench/plot.py with Debian's python3 (matplotlib); a failure is reported, not fatal.
void plot(const fs::path& json, const fs::path& out_dir)
{
    fs::path script = find_plot_script();
    if (script.empty()) {
        std::cerr << "clvis bench: bench/plot.py not found: no plots\n";
        return;
    }
    std::error_code ec;
    std::string python = fs::exists("/usr/bin/python3", ec) ? "/usr/bin/python3" : "python3";
    auto quote = [](const std::string& s) {
        std::string q = "'";
        for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
        return q + "'";
    };
    std::string command = python + " " + quote(script.string()) + " " + quote(json.string()) + " " + quote(out_dir.string());
    int rc = std::system(command.c_str());
    if (rc != 0) std::cerr << "clvis bench: plotting failed (" << command << ", status " << rc << ")\n";
}

void bench_command(const BenchArgs& args)
{
    auto t_start = std::chrono::steady_clock::now();
    fs::path out_dir(args.out);
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec) throw Error(Error::Kind::Io, "--out " + args.out + ": " + ec.message());

    Context ctx{args,     args.repeat > 0 ? args.repeat : args.quick ? 5 : 10,
                args.repeat > 0 ? 0 : args.quick ? frame_budget_ms_quick : frame_budget_ms_full,
                Device{}, {}, {}, {}};
    try {
        ctx.device = args.device.open();
    } catch (const std::exception& e) {
        ctx.device_error = e.what();
        std::cerr << "clvis bench: no OpenCL device (" << e.what() << "): timing the references only\n";
    }

    std::vector<Workload> workloads = plan(args.quick);
    std::size_t total = 0;
    for (const auto& w : workloads) total += w.views.size();
    Progress progress(total);
    std::vector<Point> points;
    for (const auto& w : workloads) run_workload(ctx, w, points, progress);
    progress.finish();

    nlohmann::json j;
    j["tool"] = "clvis bench";
    j["clvis_version"] = clvis::version();
    j["date"] = utc_now();
    if (ctx.device) {
        const DeviceInfo& info = ctx.device.info();
        j["device"] = {{"name", info.name},       {"platform", info.platform},
                       {"vendor", info.vendor},   {"version", info.version},
                       {"driver", info.driver_version}, {"compute_units", info.compute_units}};
    } else {
        j["device"] = {{"error", ctx.device_error}};
    }
    j["references"] = {{"embree", ctx.embree_description.empty() ? "unavailable" : ctx.embree_description},
                       {"gl", ctx.gl_description.empty() ? "unavailable" : ctx.gl_description},
                       {"threads", args.ref_threads}};
    j["parameters"] = {{"quick", args.quick},
                       {"repeat", ctx.repeat},
                       {"warm_up_frames", 1},
                       {"frame_budget_ms", ctx.budget_ms},
                       {"min_budget_frames", bench::min_budget_frames},
                       {"brute_repeat", std::min(ctx.repeat, brute_repeat)},
                       {"brute_max_triangles", brute_max_triangles},
                       {"brute_max_tests", args.quick ? brute_max_tests_quick : brute_max_tests_full},
                       {"builds", args.quick ? 2 : 3},
                       {"single_build_above_triangles", single_build_above},
                       {"closeup", "framing eye moved to " + fmt("%.2f", closeup_fraction) +
                                       " x the framing distance; near " + fmt("%.2f", closeup_near_fraction) +
                                       " x that distance, far 1.1 (distance + R)"},
                       {"targets", {{"raster_over_llvmpipe", target_raster_over_llvmpipe},
                                    {"ray_over_embree_intersect1", target_ray_over_embree1},
                                    {"bvh_build_over_embree_build", target_build_over_embree}}}};
    j["points"] = nlohmann::json::array();
    for (const auto& p : points) j["points"].push_back(point_json(p));
    j["total_s"] = ms_since(t_start) / 1000;

    fs::path json_file = out_dir / "bench.json";
    {
        std::ofstream out(json_file);
        if (!out) throw Error(Error::Kind::Io, json_file.string() + ": cannot write");
        out << j.dump(2) << "\n";
    }
    write_csv(out_dir / "bench.csv", points);
    print_table(points);
    if (!args.no_plot) plot(json_file, out_dir);
    std::printf("\nclvis bench: %zu points in %.1f s on %s; wrote %s and %s%s\n", points.size(),
                ms_since(t_start) / 1000, ctx.device ? ctx.device.info().name.c_str() : "no device",
                json_file.string().c_str(), (out_dir / "bench.csv").string().c_str(),
                args.no_plot ? "" : " (plots beside them)");
}

} // namespace

void add_bench_command(CLI::App& app)
{
    auto args = std::make_shared<BenchArgs>();
    auto* cmd = app.add_subcommand(
        "bench", "Time raster, ray and brute force against Embree and llvmpipe over triangle counts, resolutions "
                 "and the bundled meshes; the referee judges every buffer. Writes bench.csv, bench.json and plots.\n"
                 "Example: clvis bench --quick --out bench-out");
    cmd->add_flag("--quick", args->quick, "a sweep of a few small points (under a minute on 2 cores)");
    cmd->add_option("--out", args->out, "output folder (created)");
    args->device.add_to(*cmd);
    cmd->add_option("--repeat", args->repeat,
                    "exactly N timed frames per renderer and point after one warm-up (default: up to 10, "
                    "quick 5, stopping after 3 once they add up to 3 s, quick 1.5 s)")
        ->check(CLI::Range(1, 100000));
    cmd->add_option("--ref-threads", args->ref_threads, "threads of the reference renderers (default 2)")
        ->check(CLI::Range(1, 1024));
    cmd->add_flag("--no-plot", args->no_plot, "skip the plots (bench/plot.py, matplotlib)");
    cmd->callback([args] { bench_command(*args); });
}

} // namespace clvis::cli
