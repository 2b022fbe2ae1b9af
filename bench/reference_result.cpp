// Summaries of timing samples shared by the reference renderers and the benchmark.
#include "reference_result.hpp"

#include <algorithm>
#include <numeric>

namespace clvis::bench {

bool enough_frames(const std::vector<double>& frame_ms, int repeats, double budget_ms)
{
    if (int(frame_ms.size()) >= repeats) return true;
    return budget_ms > 0 && int(frame_ms.size()) >= min_budget_frames &&
           std::accumulate(frame_ms.begin(), frame_ms.end(), 0.0) >= budget_ms;
}

double median_of(std::vector<double> samples)
{
    if (samples.empty()) return 0;
    std::sort(samples.begin(), samples.end());
    std::size_t n = samples.size();
    return n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
}

double min_of(const std::vector<double>& samples)
{
    return samples.empty() ? 0 : *std::min_element(samples.begin(), samples.end());
}

} // namespace clvis::bench
