// What a benchmark run reports: bench.json (per point: summaries, stage times, verdicts and
// ratios), bench.csv (one row per renderer and point), the table on standard output, and the
// plots of bench/plot.py.
#pragma once

#include "bench_run.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace clvis::bench {

/// Targets of issue #7 (clvis / reference, medians).
constexpr double target_raster_over_llvmpipe = 0.5;
constexpr double target_ray_over_embree1 = 1.0;
constexpr double target_build_over_embree = 1.5;

/// printf of one number.
std::string fmt(const char* format, double v);
/// The current time, ISO 8601 in UTC.
std::string utc_now();

nlohmann::json point_json(const Point& p);
/// Throws Error(Io) naming the file when it cannot be written.
void write_csv(const std::filesystem::path& file, const std::vector<Point>& points);
void print_table(const std::vector<Point>& points);
/// Runs bench/plot.py with Debian's python3 (matplotlib); a failure is reported, not fatal.
void plot(const std::filesystem::path& json, const std::filesystem::path& out_dir);

} // namespace clvis::bench
