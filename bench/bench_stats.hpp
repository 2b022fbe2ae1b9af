// Timing samples of the benchmark and the reference renderers: wall-clock milliseconds, the
// frame budget rule, and the summaries (median, quartiles) every report uses.
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

namespace clvis::bench {

/// Milliseconds of wall time since `t0`. The library keeps its own (host/ray/ray_pipeline.cpp):
/// bench/ links only the public API.
inline double ms_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// Frames a time budget keeps at least (for a median and a spread).
constexpr int min_budget_frames = 3;

/// True once `frame_ms` holds `repeats` samples, or, with `budget_ms` > 0, at least
/// min_budget_frames samples whose sum reaches the budget (large scenes stop early).
bool enough_frames(const std::vector<double>& frame_ms, int repeats, double budget_ms);

/// Five-number summary of samples (all zero for none); quartiles interpolate linearly.
struct Summary {
    double min = 0, p25 = 0, median = 0, p75 = 0, max = 0;
    std::size_t n = 0;
};
Summary summarize(std::vector<double> samples);

/// Median of samples (0 for none): summarize(samples).median.
double median_of(std::vector<double> samples);
/// Smallest sample (0 for none).
double min_of(const std::vector<double>& samples);

} // namespace clvis::bench
