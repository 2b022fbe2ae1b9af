// Rasterization or ray casting, and the bench table's legend (see bench_crossover.hpp).
#include "bench_crossover.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace clvis::bench {

namespace {

std::string num(const char* format, double v)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

} // namespace

long long Crossover::ray_pays_from() const
{
    if (!valid() || ray_ms >= raster_ms) return 0;
    // build + N ray < N raster  <=>  N > build / (raster - ray)
    double n = std::floor(std::max(build_ms, 0.0) / (raster_ms - ray_ms)) + 1;
    return n > 9e15 ? 0 : static_cast<long long>(n);
}

const char* pays_word(const Crossover& c)
{
    if (!c.valid()) return "";
    long long n = c.ray_pays_from();
    return n == 0 ? "never" : n == 1 ? "always" : "after";
}

std::string pays_cell(const Crossover& c)
{
    if (!c.valid()) return "-";
    long long n = c.ray_pays_from();
    return n == 0 ? "never" : n == 1 ? "always" : "from " + std::to_string(n);
}

std::string crossover_words(const std::string& mesh, int width, int height, const Crossover& c)
{
    std::string at = mesh + " " + std::to_string(width) + "x" + std::to_string(height) + ": ";
    if (!c.valid()) return at + "no answer (a path has no frame time)";
    std::string times = " (" + num("%.2f", c.raster_ms) + " vs " + num("%.2f", c.ray_ms) + " ms)";
    std::string build_ms = num("%.1f", c.build_ms) + " ms", frames = num("%.1f", c.build_in_raster_frames());
    std::string noise = c.lo > 0 && c.lo <= 1 && c.hi >= 1
                            ? " The spread of raster/ray (" + num("%.2f", c.lo) + "-" + num("%.2f", c.hi) +
                                  ") holds 1: per frame the two are not told apart here."
                            : "";
    long long n = c.ray_pays_from();
    if (n == 0) {
        std::string faster = c.ray_ms > c.raster_ms ? num("%.2f", c.ray_ms / c.raster_ms) + "x faster" : "as fast";
        return at + "rasterization is " + faster + " per frame" + times +
               ": rasterize; ray casting never catches up (its BVH build, " + build_ms + ", costs another " + frames +
               " raster frames)." + noise;
    }
    std::string faster = num("%.2f", c.raster_ms / c.ray_ms) + "x faster";
    std::string build = "its BVH build (" + build_ms + ") costs " + frames + " raster frames";
    if (n == 1)
        return at + "ray casting is " + faster + " per frame" + times + " and " + build +
               ", paid back by the first frame: ray-cast." + noise;
    return at + "ray casting is " + faster + " per frame" + times + ", but " + build + ": it pays from frame " +
           std::to_string(n) + " on; rasterize fewer than " + std::to_string(n) + " frames of this scene, ray-cast more." +
           noise;
}

const std::vector<Column>& ratio_table_columns()
{
    static const std::vector<Column> columns{
        {"mesh", "the scene"},
        {"camera", "the view (framing, closeup)"},
        {"tris", "triangles"},
        {"size", "image width x height"},
        {"cover", "share of the pixels with a triangle"},
        {"raster/ray", "clvis raster frame / clvis ray frame (medians) and spread: below 1 rasterization is "
                       "faster per frame"},
        {"ray pays", "frames from which ray casting, its BVH build included, costs less than rasterization "
                     "(never: a ray frame is not faster; always: from the first frame)"},
        {"raster", "clvis rasterization, median ms per frame"},
        {"llvmpipe", "Mesa's llvmpipe OpenGL (the rasterization reference), median ms"},
        {"r/gl", "raster / llvmpipe: ratio of medians, its spread, and the target mark"},
        {"ray", "clvis ray casting, median ms per frame (BVH build not included)"},
        {"e-16", "Embree rtcIntersect16 packets (the ray reference), median ms"},
        {"ray/e16", "ray / e-16 and spread"},
        {"e-1", "Embree rtcIntersect1 single rays, median ms"},
        {"ray/e1", "ray / e-1 and spread"},
        {"bvh", "clvis BVH build, median ms (paid once per scene, before the first ray frame)"},
        {"e-build", "Embree's BVH build, median ms"},
        {"b/e", "bvh / e-build and spread"},
        {"brute", "clvis brute-force path (every triangle per pixel), median ms"},
        {"raster|ray", "referee verdict raster vs ray: pixels with an unacceptable answer (e) / explained "
                       "mismatches (x); not a speed"},
        {"raster|gl", "referee verdict raster vs llvmpipe (e/x)"},
        {"ray|e1", "referee verdict ray vs Embree single rays (e/x)"},
        {"ray|e16", "referee verdict ray vs Embree packets (e/x)"},
        {"brute|ray", "referee verdict brute vs ray (e/x)"},
    };
    return columns;
}

std::string legend(const std::vector<Column>& columns)
{
    std::size_t width = 0;
    for (const Column& c : columns) width = std::max(width, std::string(c.name).size());
    std::string out;
    for (const Column& c : columns) {
        std::string name = c.name;
        out += "  " + name + std::string(width - name.size() + 2, ' ') + c.meaning + "\n";
    }
    return out;
}

} // namespace clvis::bench
