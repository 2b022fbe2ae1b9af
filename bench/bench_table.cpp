// The table of a benchmark run on standard output (see bench_report.hpp): median frame times,
// ratios with their spread and verdicts against the targets, then every renderer's min / median
// / max, the machine's load, the failures once each, and last the answer per point: rasterization
// or ray casting (bench_crossover.hpp).
#include "bench_report.hpp"

#include <algorithm>
#include <cstdio>

namespace clvis::bench {

namespace {

/// "0.42 0.40-0.45!" : the ratio of medians, its spread and where the spread stands against the
/// target ('!' missed by all of it, '~' crosses it).
std::string ratio_cell(const PooledPoint& p, const char* key)
{
    for (const RatioDef& d : ratio_defs()) {
        if (std::string(d.key) != key) continue;
        RatioFigure f = ratio_figure(p, d);
        if (!f.valid()) return "-";
        std::string s = fmt("%.2f", f.pooled.ratio) + " " + fmt("%.2f", f.lo) + "-" + fmt("%.2f", f.hi);
        if (d.target > 0) {
            Verdict v = judge(f.lo, f.hi, d.target);
            s += v == Verdict::Missed ? "!" : v == Verdict::Crosses ? "~" : " ";
        }
        return s;
    }
    return "-";
}

std::string ms_cell(const Point& p, const std::string& renderer)
{
    const Run* r = p.find(renderer);
    return r ? fmt("%.2f", summarize(r->frame_ms).median) : "fail";
}

/// "6.50/6.86/7.90" (min/median/max), or "fail".
std::string spread_cell(const Point& p, const std::string& renderer)
{
    const Run* r = p.find(renderer);
    if (!r) return "-";
    Summary s = summarize(r->frame_ms);
    return fmt("%.2f", s.min) + "/" + fmt("%.2f", s.median) + "/" + fmt("%.2f", s.max) + " n" + std::to_string(s.n);
}

std::string build_cell(const Point& p, const char* renderer)
{
    const Run* r = p.find(renderer);
    return r && !r->build_ms.empty() ? fmt("%.1f", summarize(r->build_ms).median) : "-";
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

void print_ratios(const std::vector<PooledPoint>& points)
{
    std::printf("\nMedian frame times (ms); clvis / reference ratios of medians with their spread (the median's "
                "95%% interval and every pass); '!' the whole spread misses the target, '~' it crosses it "
                "(raster/llvmpipe <= %.2f, ray/rtcIntersect16 <= %.2f, BVH build/Embree build <= %.2f).\n"
                "Referee columns: pixels with an unacceptable answer (e) / explained mismatches (x).\n",
                target_raster_over_llvmpipe, target_ray_over_embree16, target_build_over_embree);
    std::printf("%-18s %-7s %8s %9s %5s | %-16s %-10s | %8s %8s %-16s | %8s %8s %-16s %8s %-16s | %8s %8s %-16s | %8s "
                "| %-10s %-10s %-10s %-10s %-10s\n",
                "mesh", "camera", "tris", "size", "cover", "raster/ray", "ray pays", "raster", "llvmpipe", "r/gl", "ray", "e-16", "ray/e16",
                "e-1", "ray/e1", "bvh", "e-build", "b/e", "brute", "raster|ray", "raster|gl", "ray|e1", "ray|e16",
                "brute|ray");
    for (const auto& pp : points) {
        const Point& p = pp.pooled;
        std::string size = std::to_string(p.width) + "x" + std::to_string(p.height);
        std::string cover = p.coverage >= 0 ? fmt("%.0f%%", 100 * p.coverage) : "-";
        std::string brute = p.find("brute") ? ms_cell(p, "brute") : "-";
        std::printf("%-18s %-7s %8zu %9s %5s | %-16s %-10s | %8s %8s %-16s | %8s %8s %-16s %8s %-16s | %8s %8s %-16s "
                    "| %8s | %-10s %-10s %-10s %-10s %-10s\n",
                    p.mesh.c_str(), p.camera.c_str(), p.triangles, size.c_str(), cover.c_str(),
                    ratio_cell(pp, "raster_over_ray").c_str(), pays_cell(crossover_of(pp)).c_str(),
                    ms_cell(p, "raster").c_str(), ms_cell(p, "llvmpipe").c_str(),
                    ratio_cell(pp, "raster_over_llvmpipe").c_str(), ms_cell(p, "ray").c_str(),
                    ms_cell(p, "embree-intersect16").c_str(), ratio_cell(pp, "ray_over_embree_intersect16").c_str(),
                    ms_cell(p, "embree-intersect1").c_str(), ratio_cell(pp, "ray_over_embree_intersect1").c_str(),
                    build_cell(p, "ray").c_str(), build_cell(p, "embree-intersect1").c_str(),
                    ratio_cell(pp, "bvh_build_over_embree_build").c_str(), brute.c_str(),
                    verdict_cell(p, "raster", "ray").c_str(), verdict_cell(p, "raster", "llvmpipe").c_str(),
                    verdict_cell(p, "ray", "embree-intersect1").c_str(),
                    verdict_cell(p, "ray", "embree-intersect16").c_str(), verdict_cell(p, "brute", "ray").c_str());
    }
    std::printf("Columns:\n%s", legend(ratio_table_columns()).c_str());
}

/// The user's question answered per point: rasterization or ray casting, and from how many frames.
void print_crossovers(const std::vector<PooledPoint>& points)
{
    std::printf("\nRasterization or ray casting (clvis's medians; ray casting pays for its BVH build once per "
                "scene):\n");
    for (const auto& pp : points) {
        const Point& p = pp.pooled;
        std::printf("  %s\n", crossover_words(p.mesh + " " + p.camera, p.width, p.height, crossover_of(pp)).c_str());
    }
}

void print_spreads(const std::vector<PooledPoint>& points)
{
    std::printf("\nFrame times min/median/max (ms) and frames (n), every pass pooled; rounds interleaved; "
                "1-minute load before and after each pass's rounds.\n");
    std::printf("%-18s %-7s %9s | %-26s %-26s %-26s %-26s %-26s | %6s %s\n", "mesh", "camera", "size", "raster",
                "llvmpipe", "ray", "embree-intersect16", "embree-intersect1", "rounds", "load");
    for (const auto& pp : points) {
        const Point& p = pp.pooled;
        std::string size = std::to_string(p.width) + "x" + std::to_string(p.height);
        std::string load;
        for (const Point* pass : pp.passes) {
            if (!load.empty()) load += ", ";
            load += pass->load_before.known() ? fmt("%.2f", pass->load_before.one) : "?";
            load += "->" + (pass->load_after.known() ? fmt("%.2f", pass->load_after.one) : "?");
        }
        std::printf("%-18s %-7s %9s | %-26s %-26s %-26s %-26s %-26s | %6d %s\n", p.mesh.c_str(), p.camera.c_str(),
                    size.c_str(), spread_cell(p, "raster").c_str(), spread_cell(p, "llvmpipe").c_str(),
                    spread_cell(p, "ray").c_str(), spread_cell(p, "embree-intersect16").c_str(),
                    spread_cell(p, "embree-intersect1").c_str(), p.rounds, load.c_str());
    }
}

/// Failures and missing comparisons, once per renderer and message.
void print_failures(const std::vector<PooledPoint>& points)
{
    std::vector<std::string> seen;
    auto once = [&](const std::string& line) {
        if (std::find(seen.begin(), seen.end(), line) != seen.end()) return false;
        seen.push_back(line);
        return true;
    };
    for (const auto& pp : points)
        for (const auto& r : pp.pooled.runs)
            if (!r.error.empty() && once(r.renderer + ": " + r.error))
                std::printf("failed: %s: %s (first at %s %s %dx%d)\n", r.renderer.c_str(), r.error.c_str(),
                            pp.pooled.mesh.c_str(), pp.pooled.camera.c_str(), pp.pooled.width, pp.pooled.height);
    for (const auto& pp : points)
        for (const auto& c : pp.pooled.comparisons)
            if (!c.error.empty() && once(c.a + " vs " + c.b + ": " + c.error))
                std::printf("not compared: %s vs %s: %s\n", c.a.c_str(), c.b.c_str(), c.error.c_str());
}

} // namespace

void print_table(const std::vector<PooledPoint>& points)
{
    print_ratios(points);
    print_spreads(points);
    print_failures(points);
    print_crossovers(points);
    std::fflush(stdout);
}

} // namespace clvis::bench
