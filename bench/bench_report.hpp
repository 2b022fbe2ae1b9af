// What a benchmark run reports: bench.json (per point: summaries over every pass of the sweep,
// stage times, verdicts, ratios with their spread and each pass's figures and load), bench.csv
// (one row per renderer, point and pass), the table on standard output, and the plots of
// bench/plot.py.
#pragma once

#include "bench_crossover.hpp"
#include "bench_run.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace clvis::bench {

/// Targets of issue #22 (clvis / reference, medians, at every point).
constexpr double target_raster_over_llvmpipe = 0.35;
constexpr double target_ray_over_embree16 = 0.8;
constexpr double target_build_over_embree = 1.0;

/// A ratio reported at every point: clvis `a` over `b` (frame times, or with `build` the BVH
/// builds of the ray path over Embree's); target 0: none.
struct RatioDef {
    const char* key; ///< its name in bench.json
    const char* a;
    const char* b;
    double target;
    bool build;
};
const std::vector<RatioDef>& ratio_defs();

/// One point of the plan over every pass: each renderer's samples pooled, and each pass's point.
struct PooledPoint {
    Point pooled;
    std::vector<const Point*> passes;
};
/// Groups the points of every pass by mesh, camera and size, in the plan's order.
std::vector<PooledPoint> pool_passes(const std::vector<Point>& points);

/// A ratio at a pooled point: from the pooled medians with the interval their samples allow,
/// each pass's own ratio, and the envelope of both, judged against the target.
struct RatioFigure {
    RatioSpread pooled;
    std::vector<double> passes; ///< each pass's ratio of medians (where both ran)
    double lo = 0, hi = 0;      ///< the envelope of pooled.lo..hi and every pass's ratio
    bool valid() const { return pooled.valid(); }
};
RatioFigure ratio_figure(const PooledPoint& p, const RatioDef& d);

/// The medians of clvis's raster frames, ray frames and ray-path BVH builds at a point (0 where
/// a path failed) and the spread of raster / ray: rasterization or ray casting there.
Crossover crossover_of(const PooledPoint& p);

/// printf of one number.
std::string fmt(const char* format, double v);
/// The current time, ISO 8601 in UTC.
std::string utc_now();

/// [1, 5, 15 minute load], or null.
nlohmann::json load_json(const Load& load);
nlohmann::json point_json(const PooledPoint& p);
/// Every pass's points, one row per renderer. Throws Error(Io) naming the file when it cannot be
/// written.
void write_csv(const std::filesystem::path& file, const std::vector<Point>& points);
void print_table(const std::vector<PooledPoint>& points);
/// Runs bench/plot.py with Debian's python3 (matplotlib); a failure is reported, not fatal.
void plot(const std::filesystem::path& json, const std::filesystem::path& out_dir);

} // namespace clvis::bench
