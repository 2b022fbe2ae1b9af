// The referee's judgement of depth layers (CONVENTIONS.md "Depth layers"): layer k of a sample is
// judged as layer 0 is, with the triangles the buffer holds at the sample's earlier layers taken
// out of the reference (the nearest *in* triangle among the others is d*), and a triangle held
// twice is an error. Layer 0 is therefore judged exactly as check() and compare() judge a
// one-layer buffer.
#include "referee/referee_impl.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <string>
#include <thread>

namespace clvis {

using namespace detail;

namespace {

/// Error(InvalidArgument) unless v is a buffer of the referee's size with layers in [1, 8];
/// returns log2 of its samples.
int check_layered(const Referee::Impl& impl, const HostVisibility& v, const char* which)
{
    int log2n = samples_log2(v.samples);
    check_layers(v.layers);
    std::size_t keys = std::size_t(impl.width) * std::size_t(impl.height) * std::size_t(v.samples) *
                       std::size_t(v.layers);
    if (v.width != impl.width || v.height != impl.height || v.ids.size() != keys ||
        (!v.depth.empty() && v.depth.size() != keys))
        throw Error(Error::Kind::InvalidArgument,
                    std::string("referee: ") + which + " buffer is " + std::to_string(v.width) + "x" +
                        std::to_string(v.height) + " with " + std::to_string(v.ids.size()) + " ids and " +
                        std::to_string(v.depth.size()) + " depths for " + std::to_string(v.samples) +
                        " sample(s) and " + std::to_string(v.layers) + " layer(s), the referee's image " +
                        std::to_string(impl.width) + "x" + std::to_string(impl.height));
    return log2n;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Judges every layer of buffer v at sample k of pixel (x, y) into verdicts[0 .. v.layers - 1].
void judge_sample(const Referee::Impl& im, const HostVisibility& v, bool depths, int x, int y, int log2n, int k,
                  double depth_px, PixelVerdict* verdicts)
{
    std::uint32_t held[8];
    int count = 0;
    for (int layer = 0; layer < v.layers; ++layer) {
        SampleAnswer a;
        a.id = v.id(x, y, k, layer);
        a.has_depth = depths;
        if (depths) a.depth = v.depth_at(x, y, k, layer);
        Referee::Impl::Nearest n = im.nearest_excluding(x, y, held, count, log2n, k);
        PixelVerdict verdict = im.judge(x, y, a, n, depth_px, log2n, k);
        if (a.id != background_id) {
            bool repeated = false;
            for (int e = 0; e < count; ++e) repeated |= held[e] == a.id;
            if (repeated) verdict.error = AnswerError::Repeated;
            else held[count++] = a.id;
        }
        verdicts[layer] = verdict;
    }
}

/// Runs row(y, reports) over every row on the hardware's threads (as Referee::Impl::by_rows does
/// for one report), each row with `layers` reports of its own, then sums them per layer.
template <class RowFn>
std::vector<CompareReport> layer_rows(const Referee::Impl& im, int layers, std::size_t max_reported, bool depths,
                                      RowFn row)
{
    std::vector<std::vector<CompareReport>> rows(std::size_t(im.height), std::vector<CompareReport>(std::size_t(layers)));
    std::atomic<int> next{0};
    auto work = [&] {
        for (int y; (y = next++) < im.height;) row(y, rows[std::size_t(y)]);
    };
    unsigned n = std::max(1u, std::min(std::thread::hardware_concurrency(), unsigned(im.height)));
    std::vector<std::thread> threads;
    for (unsigned t = 1; t < n; ++t) threads.emplace_back(work);
    work();
    for (auto& t : threads) t.join();
    static constexpr std::size_t CompareReport::*counts[] = {
        &CompareReport::pixels,       &CompareReport::judged,         &CompareReport::equal,
        &CompareReport::explained,    &CompareReport::errors,         &CompareReport::errors_a,
        &CompareReport::errors_b,     &CompareReport::depth_equal,    &CompareReport::depth_explained,
        &CompareReport::depth_errors, &CompareReport::depth_errors_a, &CompareReport::depth_errors_b,
    };
    std::vector<CompareReport> total(static_cast<std::size_t>(layers));
    for (const auto& per_layer : rows)
        for (std::size_t l = 0; l < per_layer.size(); ++l) {
            for (std::size_t CompareReport::*count : counts) total[l].*count += per_layer[l].*count;
            for (const PixelVerdict& v : per_layer[l].first_errors)
                if (total[l].first_errors.size() < max_reported) total[l].first_errors.push_back(v);
        }
    for (CompareReport& r : total) r.depths_judged = depths;
    return total;
}

} // namespace

std::vector<CompareReport> Referee::check_layers(const HostVisibility& a, const CompareOptions& options) const
{
    const Impl& im = checked("Referee::check_layers");
    int log2n = check_layered(im, a, "checked");
    referee_check_options(options);
    bool depths = !a.depth.empty();
    return layer_rows(im, a.layers, options.max_reported, depths, [&](int y, std::vector<CompareReport>& r) {
        PixelVerdict v[8];
        for (int x = 0; x < im.width; ++x)
            for (int k = 0; k < 1 << log2n; ++k) {
                judge_sample(im, a, depths, x, y, log2n, k, options.depth_px, v);
                for (int layer = 0; layer < a.layers; ++layer) {
                    CompareReport& rl = r[std::size_t(layer)];
                    const PixelVerdict& mine = v[layer];
                    ++rl.pixels;
                    ++rl.judged;
                    bool same_depth = depths && (mine.answer_depth == float(mine.depth_expected));
                    referee_tally(rl, mine, nullptr, mine.id == mine.nearest_id, same_depth, options.max_reported);
                }
            }
    });
}

std::vector<CompareReport> Referee::compare_layers(const HostVisibility& a, const HostVisibility& b,
                                                   const CompareOptions& options) const
{
    const Impl& im = checked("Referee::compare_layers");
    int log2n = check_layered(im, a, "first");
    check_layered(im, b, "second");
    if (a.samples != b.samples || a.layers != b.layers)
        throw Error(Error::Kind::InvalidArgument,
                    "referee: the first buffer holds " + std::to_string(a.samples) + " sample(s) and " +
                        std::to_string(a.layers) + " layer(s), the second " + std::to_string(b.samples) + " and " +
                        std::to_string(b.layers));
    referee_check_options(options);
    bool depths = !a.depth.empty() && !b.depth.empty();
    return layer_rows(im, a.layers, options.max_reported, depths, [&](int y, std::vector<CompareReport>& r) {
        PixelVerdict va[8], vb[8];
        for (int x = 0; x < im.width; ++x)
            for (int k = 0; k < 1 << log2n; ++k) {
                bool judged = false;
                for (int layer = 0; layer < a.layers; ++layer) {
                    CompareReport& rl = r[std::size_t(layer)];
                    bool same_id = a.id(x, y, k, layer) == b.id(x, y, k, layer);
                    bool same_depth = !depths || same_bits(a.depth_at(x, y, k, layer), b.depth_at(x, y, k, layer));
                    ++rl.pixels;
                    if (options.differing_only && same_id && same_depth) {
                        ++rl.equal;
                        rl.depth_equal += depths;
                        continue;
                    }
                    if (!judged) { // every layer of the sample at once: each is judged against the earlier ones
                        judge_sample(im, a, depths, x, y, log2n, k, options.depth_px, va);
                        judge_sample(im, b, depths, x, y, log2n, k, options.depth_px, vb);
                        judged = true;
                    }
                    ++rl.judged;
                    referee_tally(rl, va[layer], &vb[layer], same_id, same_depth, options.max_reported);
                }
            }
    });
}

} // namespace clvis
