// Summaries of timing samples shared by the reference renderers, the benchmark and the CLI, and
// the interleaved timing of bench_run.cpp.
#include "bench_stats.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
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

double sum_of(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

} // namespace

bool enough_frames(const std::vector<double>& frame_ms, int repeats, double budget_ms)
{
    if (int(frame_ms.size()) >= repeats) return true;
    return budget_ms > 0 && int(frame_ms.size()) >= min_budget_frames && sum_of(frame_ms) >= budget_ms;
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

Interval median_ci(std::vector<double> v)
{
    if (v.empty()) return {};
    std::sort(v.begin(), v.end());
    // The largest k with P(B <= k - 1) <= 2.5 % for B ~ binomial(n, 1/2): the median lies between
    // the k-th smallest and the k-th largest sample with at least 95 % probability.
    const std::size_t n = v.size();
    const double log_half_n = double(n) * std::log(0.5);
    double cdf = 0;
    std::size_t k = 0;
    for (std::size_t i = 0; i < n / 2; ++i) {
        double log_choose = std::lgamma(double(n) + 1) - std::lgamma(double(i) + 1) - std::lgamma(double(n - i) + 1);
        cdf += std::exp(log_choose + log_half_n);
        if (cdf > 0.025) break;
        k = i + 1;
    }
    k = std::max<std::size_t>(k, 1);
    return {v[k - 1], v[n - k]};
}

double median_ci_rel(const std::vector<double>& samples)
{
    double m = median_of(samples);
    if (!(m > 0)) return 0;
    Interval ci = median_ci(samples);
    return (ci.hi - ci.lo) / (2 * m);
}

bool converged(const std::vector<double>& frame_ms, const StopRule& rule)
{
    int n = int(frame_ms.size());
    if (rule.exact > 0) return n >= rule.exact;
    return n >= rule.min_frames && median_ci_rel(frame_ms) <= rule.rel_ci;
}

bool capped(const std::vector<double>& frame_ms, const StopRule& rule, int max_frames)
{
    int n = int(frame_ms.size());
    if (rule.exact > 0) return n >= (max_frames > 0 ? std::min(max_frames, rule.exact) : rule.exact);
    int cap = max_frames > 0 ? std::min(max_frames, rule.max_frames) : rule.max_frames;
    if (n >= cap) return true;
    return rule.budget_ms > 0 && n >= min_budget_frames && sum_of(frame_ms) >= rule.budget_ms;
}

int interleave(std::vector<Lane>& lanes, const StopRule& rule)
{
    auto running = [&](const Lane& l) { return l.error.empty() && !capped(l.ms, rule, l.max_frames); };
    auto unsettled = [&](const Lane& l) { return running(l) && !converged(l.ms, rule); };
    int rounds = 0;
    while (std::any_of(lanes.begin(), lanes.end(), unsettled)) {
        for (Lane& l : lanes) {
            if (!running(l)) continue;
            try {
                l.ms.push_back(l.frame());
            } catch (const std::exception& e) {
                l.error = e.what();
            }
        }
        ++rounds;
    }
    return rounds;
}

RatioSpread ratio_spread(const std::vector<double>& a, const std::vector<double>& b)
{
    double ma = median_of(a), mb = median_of(b);
    if (!(ma > 0) || !(mb > 0)) return {};
    Interval ca = median_ci(a), cb = median_ci(b);
    if (!(ca.lo > 0) || !(cb.lo > 0)) return {ma / mb, ma / mb, ma / mb};
    return {ma / mb, ca.lo / cb.hi, ca.hi / cb.lo};
}

Verdict judge(double lo, double hi, double target)
{
    if (hi <= target) return Verdict::Met;
    if (lo > target) return Verdict::Missed;
    return Verdict::Crosses;
}

const char* to_string(Verdict v) noexcept
{
    switch (v) {
    case Verdict::Met: return "met";
    case Verdict::Crosses: return "crosses";
    case Verdict::Missed: return "missed";
    }
    return "?";
}

} // namespace clvis::bench
