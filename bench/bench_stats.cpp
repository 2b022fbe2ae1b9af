// Summaries of timing samples shared by the reference renderers, the benchmark and the CLI.
#include "bench_stats.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

namespace clvis::bench {

namespace {

double quantile(const std::vector<double>& sorted, double q)
{
    double pos = q * double(sorted.size() - 1);
    std::size_t lo = std::size_t(pos);
    std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (pos - double(lo)) * (sorted[hi] - sorted[lo]);
}

} // namespace

bool enough_frames(const std::vector<double>& frame_ms, int repeats, double budget_ms)
{
    if (int(frame_ms.size()) >= repeats) return true;
    return budget_ms > 0 && int(frame_ms.size()) >= min_budget_frames &&
           std::accumulate(frame_ms.begin(), frame_ms.end(), 0.0) >= budget_ms;
}

Summary summarize(std::vector<double> v)
{
    Summary s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s = {v.front(), quantile(v, 0.25), quantile(v, 0.5), quantile(v, 0.75), v.back(), v.size()};
    return s;
}

double median_of(std::vector<double> samples) { return summarize(std::move(samples)).median; }

double min_of(const std::vector<double>& samples)
{
    return samples.empty() ? 0 : *std::min_element(samples.begin(), samples.end());
}

} // namespace clvis::bench
