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
#include <optional>

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

} // namespace

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
