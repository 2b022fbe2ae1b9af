// The benchmark's outputs (see bench_report.hpp).
#include "bench_report.hpp"

#include "bench_stats.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>

namespace clvis::bench {

namespace fs = std::filesystem;

std::string fmt(const char* format, double v)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

namespace {

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

std::vector<double> samples_of(const Point& p, const char* renderer, bool build)
{
    const Run* r = p.find(renderer);
    if (!r) return {};
    return build ? r->build_ms : r->frame_ms;
}

/// Folds one pass's run into the pooled point: samples appended; a failure kept only while no
/// pass has succeeded.
void pool_run(Point& into, const Run& run)
{
    for (Run& q : into.runs) {
        if (q.renderer != run.renderer) continue;
        if (!run.error.empty()) return;
        if (!q.error.empty()) {
            q = run;
            return;
        }
        q.frame_ms.insert(q.frame_ms.end(), run.frame_ms.begin(), run.frame_ms.end());
        q.build_ms.insert(q.build_ms.end(), run.build_ms.begin(), run.build_ms.end());
        return;
    }
    into.runs.push_back(run);
}


nlohmann::json summary_json(const std::vector<double>& samples)
{
    Summary s = summarize(samples);
    Interval ci = median_ci(samples);
    return {{"min", s.min},        {"p25", s.p25},       {"median", s.median}, {"p75", s.p75},
            {"max", s.max},        {"median_ci", {ci.lo, ci.hi}}, {"samples", samples}};
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

nlohmann::json run_json(const Run& r)
{
    nlohmann::json rj{{"renderer", r.renderer}, {"reference", r.reference}};
    if (!r.error.empty()) {
        rj["error"] = r.error;
        return rj;
    }
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
    return rj;
}

/// Each pass's own figures at a point: rounds, load, medians and ratios.
nlohmann::json pass_json(const Point& p)
{
    nlohmann::json medians = nlohmann::json::object(), ratios = nlohmann::json::object();
    for (const auto& r : p.runs)
        if (p.find(r.renderer)) medians[r.renderer] = summarize(r.frame_ms).median;
    for (const RatioDef& d : ratio_defs()) {
        RatioSpread s = ratio_spread(samples_of(p, d.a, d.build), samples_of(p, d.b, d.build));
        ratios[d.key] = s.valid() ? nlohmann::json(s.ratio) : nlohmann::json(nullptr);
    }
    return {{"pass", p.pass},
            {"rounds", p.rounds},
            {"load_before", load_json(p.load_before)},
            {"load_after", load_json(p.load_after)},
            {"median_ms", medians},
            {"ratios", ratios}};
}

} // namespace

nlohmann::json load_json(const Load& l)
{
    if (!l.known()) return nullptr;
    return nlohmann::json::array({l.one, l.five, l.fifteen});
}

const std::vector<RatioDef>& ratio_defs()
{
    static const std::vector<RatioDef> defs{
        {"raster_over_llvmpipe", "raster", "llvmpipe", target_raster_over_llvmpipe, false},
        {"ray_over_embree_intersect16", "ray", "embree-intersect16", target_ray_over_embree16, false},
        {"ray_over_embree_intersect1", "ray", "embree-intersect1", 0, false},
        {"bvh_build_over_embree_build", "ray", "embree-intersect1", target_build_over_embree, true},
        {"raster_over_ray", "raster", "ray", 0, false}};
    return defs;
}

std::vector<PooledPoint> pool_passes(const std::vector<Point>& points)
{
    std::vector<PooledPoint> out;
    for (const Point& p : points) {
        auto same = [&](const PooledPoint& q) {
            return q.pooled.mesh == p.mesh && q.pooled.camera == p.camera && q.pooled.width == p.width &&
                   q.pooled.height == p.height;
        };
        auto it = std::find_if(out.begin(), out.end(), same);
        if (it == out.end()) {
            out.push_back({p, {&p}});
            continue;
        }
        it->passes.push_back(&p);
        it->pooled.rounds += p.rounds;
        for (const Run& r : p.runs) pool_run(it->pooled, r);
    }
    return out;
}

RatioFigure ratio_figure(const PooledPoint& p, const RatioDef& d)
{
    RatioFigure f;
    f.pooled = ratio_spread(samples_of(p.pooled, d.a, d.build), samples_of(p.pooled, d.b, d.build));
    if (!f.valid()) return f;
    f.lo = f.pooled.lo;
    f.hi = f.pooled.hi;
    for (const Point* pass : p.passes) {
        RatioSpread r = ratio_spread(samples_of(*pass, d.a, d.build), samples_of(*pass, d.b, d.build));
        if (!r.valid()) continue;
        f.passes.push_back(r.ratio);
        f.lo = std::min(f.lo, r.ratio);
        f.hi = std::max(f.hi, r.ratio);
    }
    return f;
}

Crossover crossover_of(const PooledPoint& pp)
{
    const Point& p = pp.pooled;
    Crossover c;
    for (const RatioDef& d : ratio_defs())
        if (std::string(d.key) == "raster_over_ray") {
            RatioFigure f = ratio_figure(pp, d);
            if (f.valid()) {
                c.lo = f.lo;
                c.hi = f.hi;
            }
        }
    if (const Run* r = p.find("raster")) c.raster_ms = summarize(r->frame_ms).median;
    if (const Run* r = p.find("ray")) {
        c.ray_ms = summarize(r->frame_ms).median;
        if (!r->build_ms.empty()) c.build_ms = summarize(r->build_ms).median;
    }
    return c;
}

nlohmann::json point_json(const PooledPoint& pp)
{
    const Point& p = pp.pooled;
    nlohmann::json j{{"mesh", p.mesh},   {"camera", p.camera},   {"sweeps", p.sweeps},
                     {"triangles", p.triangles}, {"width", p.width}, {"height", p.height},
                     {"camera_flags", p.camera_flags}, {"rounds", p.rounds}};
    j["coverage"] = p.coverage >= 0 ? nlohmann::json(p.coverage) : nlohmann::json(nullptr);
    j["runs"] = nlohmann::json::array();
    for (const auto& r : p.runs) j["runs"].push_back(run_json(r));
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
    j["ratios"] = nlohmann::json::object();
    j["ratio_spread"] = nlohmann::json::object();
    for (const RatioDef& d : ratio_defs()) {
        RatioFigure f = ratio_figure(pp, d);
        j["ratios"][d.key] = f.valid() ? nlohmann::json(f.pooled.ratio) : nlohmann::json(nullptr);
        if (!f.valid()) continue;
        nlohmann::json sj{{"lo", f.lo}, {"hi", f.hi}, {"ci", {f.pooled.lo, f.pooled.hi}}, {"passes", f.passes}};
        if (d.target > 0) {
            sj["target"] = d.target;
            sj["verdict"] = to_string(judge(f.lo, f.hi, d.target));
        }
        j["ratio_spread"][d.key] = sj;
    }
    Crossover c = crossover_of(pp);
    if (c.valid()) {
        long long n = c.ray_pays_from();
        j["crossover"] = {{"raster_over_ray", c.raster_over_ray()},
                          {"build_in_raster_frames", c.build_in_raster_frames()},
                          {"ray_pays", pays_word(c)},
                          {"ray_pays_from_frame", n > 0 ? nlohmann::json(n) : nlohmann::json(nullptr)},
                          {"text", crossover_words(p.mesh + " " + p.camera, p.width, p.height, c)}};
    }
    j["passes"] = nlohmann::json::array();
    for (const Point* pass : pp.passes) j["passes"].push_back(pass_json(*pass));
    return j;
}

void write_csv(const fs::path& file, const std::vector<Point>& points)
{
    std::ofstream out(file);
    if (!out) throw Error(Error::Kind::Io, file.string() + ": cannot write");
    out << "mesh,camera,sweeps,triangles,width,height,pass,rounds,load1_before,load1_after,renderer,frames,"
           "frame_min_ms,frame_p25_ms,frame_median_ms,frame_p75_ms,frame_max_ms,median_ci_lo_ms,median_ci_hi_ms,"
           "build_median_ms,build_min_ms,bvh_nodes,stages_ms,error\n";
    for (const auto& p : points) {
        std::string sweeps;
        for (const auto& s : p.sweeps) sweeps += (sweeps.empty() ? "" : "+") + s;
        auto load1 = [](const Load& l) { return l.known() ? fmt("%.2f", l.one) : std::string(); };
        for (const auto& r : p.runs) {
            Summary f = summarize(r.frame_ms), b = summarize(r.build_ms);
            Interval ci = median_ci(r.frame_ms);
            std::string stages;
            for (const auto& s : r.stages) stages += (stages.empty() ? "" : ";") + s.name + "=" + fmt("%.4f", s.ms);
            out << csv_field(p.mesh) << ',' << p.camera << ',' << sweeps << ',' << p.triangles << ',' << p.width << ','
                << p.height << ',' << p.pass << ',' << p.rounds << ',' << load1(p.load_before) << ','
                << load1(p.load_after) << ',' << r.renderer << ',' << f.n << ',' << f.min << ',' << f.p25 << ','
                << f.median << ',' << f.p75 << ',' << f.max << ',' << ci.lo << ',' << ci.hi << ','
                << (b.n ? fmt("%.4f", b.median) : "") << ',' << (b.n ? fmt("%.4f", b.min) : "") << ','
                << (r.bvh_nodes ? std::to_string(r.bvh_nodes) : "") << ',' << csv_field(stages) << ','
                << csv_field(r.error) << '\n';
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

} // namespace clvis::bench
