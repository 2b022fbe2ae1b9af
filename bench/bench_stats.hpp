// Timing samples of the benchmark and the reference renderers: wall-clock milliseconds, the
// stopping rules (a frame budget; a median known to a few percent), the summaries every report
// uses, the spread of a ratio of medians, and the interleaved timing of several renderers.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
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

/// A distribution-free interval around the median: the k-th smallest and k-th largest samples,
/// k the largest rank with P(binomial(n, 1/2) < k) <= 2.5 % (at least 95 % for independent
/// samples of any distribution): [min, max] up to 8 samples, the 2nd and 9th of 10, the 40th and
/// 61st of 100. All zero for none.
struct Interval {
    double lo = 0, hi = 0;
};
Interval median_ci(std::vector<double> samples);
/// Half the width of median_ci over the median (0 for no samples or a zero median).
double median_ci_rel(const std::vector<double>& samples);

/// When one renderer at one point has been timed enough.
struct StopRule {
    int exact = 0;          ///< > 0: exactly this many frames, nothing else applies
    int min_frames = 5;     ///< never fewer (but see budget_ms)
    int max_frames = 30;    ///< never more
    double rel_ci = 0.03;   ///< done once median_ci_rel <= this (after min_frames)
    double budget_ms = 0;   ///< > 0: capped once the frames add up to this (after min_budget_frames)
};
/// The median is known well enough (or the frame count is reached with `exact`).
bool converged(const std::vector<double>& frame_ms, const StopRule& rule);
/// No further frame may be taken: max_frames (or `max_frames` when > 0 and smaller), the exact
/// count, or the budget.
bool capped(const std::vector<double>& frame_ms, const StopRule& rule, int max_frames = 0);

/// One renderer timed at one point, a frame at a time.
struct Lane {
    std::string name;
    std::function<double()> frame; ///< one timed frame, ms; may throw
    int max_frames = 0;            ///< > 0: a tighter cap than the rule's (slow renderers)
    std::vector<double> ms;        ///< every timed frame, in order
    std::string error;             ///< what the frame threw; the lane then left the rounds
};
/// Times the lanes in rounds, one frame of every lane per round in order (A B C A B C ...), so
/// that a change of the machine's load falls on every lane alike. Lanes keep running while any
/// lane has not converged and stop only at their cap or on an error. Returns the rounds run.
int interleave(std::vector<Lane>& lanes, const StopRule& rule);

/// A ratio of medians a / b with the interval its samples allow: lo = a's median_ci.lo over b's
/// hi, hi = a's hi over b's lo. All zero when either side has no positive samples.
struct RatioSpread {
    double ratio = 0, lo = 0, hi = 0;
    bool valid() const { return ratio > 0; }
};
RatioSpread ratio_spread(const std::vector<double>& a, const std::vector<double>& b);

/// Where a spread stands against a target (a ratio that must be <= target).
enum class Verdict { Met, Crosses, Missed };
Verdict judge(double lo, double hi, double target);
/// "met", "crosses", "missed".
const char* to_string(Verdict v) noexcept;

} // namespace clvis::bench
