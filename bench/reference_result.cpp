// Summaries of timing samples shared by the reference renderers and the benchmark.
#include "reference_result.hpp"

#include <algorithm>

namespace clvis::bench {

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
