// The benchmark's statistics (bench/bench_stats.cpp): the median's interval, the stopping rules,
// the interleaved rounds (A B A B ...) and the spread of a ratio against its target. Frame
// functions here return made-up times: nothing is timed and nothing depends on the machine.
#include "catch.hpp"

#include "bench_stats.hpp"

#include <stdexcept>
#include <string>
#include <vector>

using namespace clvis::bench;

namespace {

std::vector<double> one_to(int n)
{
    std::vector<double> v;
    for (int k = n; k >= 1; --k) v.push_back(k); // unsorted on purpose
    return v;
}

/// A lane whose frames return `times` in turn (the last one again once they run out) and log
/// its name into `order`.
Lane scripted_lane(const std::string& name, std::vector<double> times, std::vector<std::string>& order)
{
    Lane l;
    l.name = name;
    l.frame = [name, times, &order, k = std::size_t(0)]() mutable {
        order.push_back(name);
        double t = times[std::min(k, times.size() - 1)];
        ++k;
        return t;
    };
    return l;
}

StopRule frames_between(int min_frames, int max_frames)
{
    StopRule rule;
    rule.min_frames = min_frames;
    rule.max_frames = max_frames;
    return rule;
}

} // namespace

TEST_CASE("The median's interval spans min to max up to eight samples")
{
    Interval ci = median_ci({5, 1, 3, 2, 4});
    CHECK(ci.lo == 1);
    CHECK(ci.hi == 5);
    CHECK(median_ci(one_to(8)).lo == 1);
    CHECK(median_ci(one_to(8)).hi == 8);
    CHECK(median_ci({3}).lo == 3);
    Interval none = median_ci({});
    CHECK(none.lo == 0);
    CHECK(none.hi == 0);
}

TEST_CASE("The median's interval holds ranks 2 to 9 of 10 and 40 to 61 of 100")
{
    CHECK(median_ci(one_to(10)).lo == 2);
    CHECK(median_ci(one_to(10)).hi == 9);
    Interval ci = median_ci(one_to(100));
    CHECK(ci.lo == 40);
    CHECK(ci.hi == 61);
    CHECK(median_ci_rel(one_to(100)) == Approx(21.0 / (2 * 50.5)));
    CHECK(median_ci_rel({7, 7, 7, 7, 7, 7, 7}) == 0);
}

TEST_CASE("A median converges after min_frames once its interval is narrow")
{
    StopRule rule;
    rule.min_frames = 5;
    rule.rel_ci = 0.03;
    CHECK_FALSE(converged({10, 10, 10, 10}, rule));
    CHECK(converged({10, 10, 10, 10, 10}, rule));
    CHECK_FALSE(converged({10, 20, 10, 20, 10, 20, 10, 20}, rule));
    rule.exact = 3;
    CHECK_FALSE(converged({10, 20}, rule));
    CHECK(converged({10, 20, 30}, rule));
}

TEST_CASE("A lane is capped by max_frames, its own cap, the exact count or the budget")
{
    StopRule rule;
    rule.max_frames = 4;
    CHECK_FALSE(capped({1, 1, 1}, rule));
    CHECK(capped({1, 1, 1, 1}, rule));
    CHECK(capped({1, 1}, rule, 2));
    rule.budget_ms = 100;
    CHECK_FALSE(capped({60, 60}, rule)); // the budget needs min_budget_frames first
    CHECK(capped({60, 60, 60}, rule));
    StopRule exact;
    exact.exact = 2;
    CHECK_FALSE(capped({1}, exact));
    CHECK(capped({1, 1}, exact));
    CHECK(capped({1}, exact, 1));
}

TEST_CASE("Interleaved lanes alternate frame by frame")
{
    std::vector<std::string> order;
    std::vector<Lane> lanes{scripted_lane("A", {10}, order), scripted_lane("B", {20}, order),
                            scripted_lane("C", {30}, order)};
    int rounds = interleave(lanes, frames_between(3, 30));
    CHECK(rounds == 3);
    CHECK(order == std::vector<std::string>{"A", "B", "C", "A", "B", "C", "A", "B", "C"});
    CHECK(lanes[1].ms == std::vector<double>{20, 20, 20});
}

TEST_CASE("A settled lane keeps alternating while another is noisy, up to the cap")
{
    std::vector<std::string> order;
    std::vector<Lane> lanes{scripted_lane("steady", {10}, order),
                            scripted_lane("noisy", {10, 30, 10, 30, 10, 30, 10, 30, 10, 30}, order)};
    CHECK(interleave(lanes, frames_between(3, 8)) == 8);
    CHECK(lanes[0].ms.size() == 8);
    CHECK(lanes[1].ms.size() == 8);
    CHECK(order[6] == "steady");
    CHECK(order[7] == "noisy");
}

TEST_CASE("A slow lane stops at its own cap while the others go on")
{
    std::vector<std::string> order;
    std::vector<Lane> lanes{scripted_lane("fast", {1, 2, 1, 2, 1, 2, 1, 2}, order),
                            scripted_lane("brute", {500}, order)};
    lanes[1].max_frames = 2;
    CHECK(interleave(lanes, frames_between(3, 6)) == 6);
    CHECK(order == std::vector<std::string>{"fast", "brute", "fast", "brute", "fast", "fast", "fast", "fast"});
    CHECK(lanes[1].ms == std::vector<double>{500, 500});
}

TEST_CASE("A lane that throws leaves the rounds with its error")
{
    std::vector<std::string> order;
    std::vector<Lane> lanes{scripted_lane("good", {5}, order), scripted_lane("bad", {5}, order)};
    int calls = 0;
    lanes[1].frame = [&calls]() -> double {
        if (++calls == 2) throw std::runtime_error("device lost");
        return 5;
    };
    StopRule rule;
    rule.min_frames = 4;
    interleave(lanes, rule);
    CHECK(lanes[0].ms.size() == 4);
    CHECK(lanes[1].ms.size() == 1);
    CHECK(lanes[1].error == "device lost");
}

TEST_CASE("A ratio of medians is bounded by the intervals of both sides")
{
    RatioSpread r = ratio_spread({4, 5, 6}, {10, 10, 10});
    CHECK(r.ratio == Approx(0.5));
    CHECK(r.lo == Approx(0.4));
    CHECK(r.hi == Approx(0.6));
    CHECK_FALSE(ratio_spread({}, {1}).valid());
    CHECK_FALSE(ratio_spread({1}, {0}).valid());
}

TEST_CASE("A spread meets, crosses or misses its target")
{
    CHECK(judge(0.30, 0.34, 0.35) == Verdict::Met);
    CHECK(judge(0.30, 0.40, 0.35) == Verdict::Crosses);
    CHECK(judge(0.36, 0.40, 0.35) == Verdict::Missed);
    CHECK(std::string(to_string(Verdict::Crosses)) == "crosses");
}
