// The referee's judging: one answer (its id and its depth) at a sample, then whole buffers, one or
// two, judged row by row in parallel and merged in raster order, so reports do not depend on the
// thread count.
#include "referee/referee_impl.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>

namespace clvis {

using namespace detail;

namespace {

std::string number(double v)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// Error(InvalidArgument) unless v is a buffer of the referee's size, its depths absent or whole.
/// Error(InvalidArgument) unless v is a buffer of the referee's size with a valid sample count,
/// its ids whole and its depths absent or whole; returns log2 of its samples per pixel.
int check_size(const Referee::Impl& impl, const HostVisibility& v, const char* which)
{
    int log2n = samples_log2(v.samples);
    std::size_t keys = std::size_t(impl.width) * std::size_t(impl.height) * std::size_t(v.samples);
    if (v.width != impl.width || v.height != impl.height || v.ids.size() != keys)
        throw Error(Error::Kind::InvalidArgument,
                    std::string("referee: ") + which + " buffer is " + std::to_string(v.width) + "x" +
                        std::to_string(v.height) + " with " + std::to_string(v.ids.size()) + " ids for " +
                        std::to_string(v.samples) + " sample(s) per pixel, the referee's image " +
                        std::to_string(impl.width) + "x" + std::to_string(impl.height));
    if (!v.depth.empty() && v.depth.size() != keys)
        throw Error(Error::Kind::InvalidArgument, std::string("referee: ") + which + " buffer holds " +
                                                      std::to_string(v.depth.size()) + " depths for " +
                                                      std::to_string(keys) + " samples");
    return log2n;
}

void check_options(const CompareOptions& o)
{
    if (!(o.depth_px >= referee_depth_judge_px && o.depth_px < 1))
        throw Error(Error::Kind::InvalidArgument, "referee: CompareOptions::depth_px must lie in [1/65536, 1) px, got " +
                                                      std::to_string(o.depth_px));
}

SampleAnswer answer_at(const HostVisibility& v, int x, int y, int k, bool depths)
{
    SampleAnswer a;
    a.id = v.id(x, y, k);
    a.has_depth = depths;
    if (depths) a.depth = v.depth_at(x, y, k);
    return a;
}

/// Every count of a CompareReport, summed over rows.
constexpr std::size_t CompareReport::*counts[] = {
    &CompareReport::pixels,         &CompareReport::judged,          &CompareReport::equal,
    &CompareReport::explained,      &CompareReport::errors,          &CompareReport::errors_a,
    &CompareReport::errors_b,       &CompareReport::depth_equal,     &CompareReport::depth_explained,
    &CompareReport::depth_errors,   &CompareReport::depth_errors_a,  &CompareReport::depth_errors_b,
};

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Counts one pixel's verdicts of the answers of two buffers (vb null: one buffer, checked); same_id
/// and same_depth say whether the two answers (check(): the answer and the reference) are equal.
void tally(CompareReport& r, const PixelVerdict& va, const PixelVerdict* pb, bool same_id, bool same_depth,
           std::size_t max_reported)
{
    const PixelVerdict& vb = pb ? *pb : va;
    bool ids_ok = va.acceptable() && vb.acceptable();
    if (ids_ok) ++(same_id ? r.equal : r.explained);
    else ++r.errors;
    r.errors_a += !va.acceptable();
    r.errors_b += pb && !vb.acceptable();
    if (va.depth_judged) {
        bool ok = va.depth_acceptable() && vb.depth_acceptable();
        if (ok) ++(same_depth ? r.depth_equal : r.depth_explained);
        else ++r.depth_errors;
        r.depth_errors_a += !va.depth_acceptable();
        r.depth_errors_b += pb && !vb.depth_acceptable();
    }
    auto report = [&](PixelVerdict v, int source) {
        if ((v.acceptable() && v.depth_acceptable()) || r.first_errors.size() >= max_reported) return;
        v.source = source;
        r.first_errors.push_back(v);
    };
    if (!pb) {
        report(va, -1);
    } else if (same_id && same_depth) {
        report(va, 2);
    } else {
        report(va, 0);
        report(vb, 1);
    }
}

} // namespace

void referee_tally(CompareReport& r, const PixelVerdict& va, const PixelVerdict* pb, bool same_id, bool same_depth,
                   std::size_t max_reported)
{
    tally(r, va, pb, same_id, same_depth, max_reported);
}

void referee_check_options(const CompareOptions& o) { check_options(o); }

PixelVerdict Referee::Impl::judge(int x, int y, const SampleAnswer& answer, const Nearest& n, double depth_px,
                                  int log2n, int k) const
{
    PixelVerdict v;
    v.x = x;
    v.y = y;
    v.samples = 1 << log2n;
    v.sample = k;
    v.id = answer.id;
    v.nearest_id = n.id;
    v.nearest_depth = n.depth;
    v.depth_judged = answer.has_depth;
    v.answer_depth = answer.depth;
    if (answer.id == background_id) {
        if (n.id != background_id) v.error = AnswerError::Missed;
        v.depth_expected = v.depth_lo = v.depth_hi = inf;
        if (answer.has_depth && !(answer.depth == float(inf))) v.depth_error = DepthError::Wrong;
        return v;
    }
    if (answer.id >= triangle_count) {
        v.error = AnswerError::InvalidId;
        v.depth_expected = v.depth_lo = v.depth_hi = std::numeric_limits<double>::quiet_NaN();
        if (answer.has_depth) v.depth_error = DepthError::NoTriangle;
        return v;
    }
    Triangle scratch;
    if (answer.has_depth)
        judge_depth(triangle(answer.id, scratch), sample_position(x, log2n, k, 0), sample_position(y, log2n, k, 1),
                    depth_px, v);
    TriangleAtSample s = classify_id(answer.id, x, y, log2n, k);
    v.depth = s.depth;
    if (s.cls == SampleClass::Out) {
        if (s.culled) {
            v.error = AnswerError::Culled;
        } else if (s.out_by_depth) {
            v.error = AnswerError::Clipped;
        } else {
            v.error = AnswerError::Coverage;
            v.edge_distance = s.outside;
        }
        return v;
    }
    if (n.id != background_id && s.depth > n.depth * (1 + rel)) {
        v.error = AnswerError::HiddenSurface;
        v.depth_excess = s.depth / n.depth - 1;
    }
    return v;
}

bool Referee::Impl::window_depths(const Triangle& t, double x, double y, double* lo, double* hi) const
{
    // Clip the visible part, with 1/d (perspective) or d (orthographic) as an attribute affine in
    // raster space, to the square of half-side EPS (and the set-up's rounding) around the sample;
    // the attribute's extremes over the convex result lie at its vertices.
    double r = eps + 1e-9 * std::fmax(1.0, std::fmax(std::fabs(x), std::fabs(y)));
    struct P { double x, y, a; };
    P poly[max_poly + 4], next[max_poly + 4];
    int n = t.n;
    for (int k = 0; k < n; ++k) poly[k] = {t.px[k], t.py[k], perspective ? 1 / t.pd[k] : t.pd[k]};
    for (int side = 0; side < 4 && n > 0; ++side) {
        auto inside = [&](const P& p) {
            switch (side) {
            case 0: return p.x - (x - r);
            case 1: return (x + r) - p.x;
            case 2: return p.y - (y - r);
            default: return (y + r) - p.y;
            }
        };
        int m = 0;
        for (int k = 0; k < n; ++k) {
            const P& a = poly[k];
            const P& b = poly[(k + 1) % n];
            double fa = inside(a), fb = inside(b);
            if (fa >= 0) next[m++] = a;
            if ((fa >= 0) != (fb >= 0)) {
                double s = fa / (fa - fb);
                next[m++] = {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.a + s * (b.a - a.a)};
            }
        }
        n = m;
        std::copy(next, next + m, poly);
    }
    if (n == 0) return false;
    double amin = inf, amax = -inf;
    for (int k = 0; k < n; ++k) {
        amin = std::fmin(amin, poly[k].a);
        amax = std::fmax(amax, poly[k].a);
    }
    *lo = perspective ? 1 / amax : amin;
    *hi = perspective ? 1 / amin : amax;
    return true;
}

void Referee::Impl::judge_depth(const Triangle& t, double x, double y, double depth_px, PixelVerdict& v) const
{
    double nan = std::numeric_limits<double>::quiet_NaN();
    v.depth_expected = v.depth_lo = v.depth_hi = nan;
    double emin = inf;
    bool plane = false;
    // An explicit RefereeTolerance that loosens the depth range (float32 cannot honour it) loosens
    // the judged depths as much; the default keeps CONVENTIONS.md's 1e-5.
    const double judge_rel = std::fmax(referee_depth_judge_rel, rel);
    if (!t.flat) {
        double den = t.det.at(x, y), d = t.num.at(x, y) / den;
        if (std::isfinite(d) && d > 0) {
            // d = num / det, so grad d = (grad num - d grad det) / det, in depth per raster pixel.
            double gx = (t.num.a - d * t.det.a) / den, gy = (t.num.b - d * t.det.b) / den;
            double tol = judge_rel * d + std::hypot(gx, gy) * depth_px;
            v.depth_expected = d;
            v.depth_lo = d - tol;
            v.depth_hi = d + tol;
            plane = true;
        }
        for (const Linear& e : t.edge) emin = std::fmin(emin, e.at(x, y));
    }
    double lo = 0, hi = 0;
    if (!(plane && emin >= 0) && window_depths(t, x, y, &lo, &hi)) {
        // The ray misses the triangle (or it has no inside): along a ray that misses a plane seen
        // almost edge-on the plane's depth means nothing, so the depths of its visible part within
        // EPS of the sample are accepted too.
        lo *= 1 - judge_rel;
        hi *= 1 + judge_rel;
        v.depth_lo = plane ? std::fmin(v.depth_lo, lo) : lo;
        v.depth_hi = plane ? std::fmax(v.depth_hi, hi) : hi;
    }
    double z = v.answer_depth;
    if (!(z >= v.depth_lo && z <= v.depth_hi)) v.depth_error = DepthError::Wrong;
}

template <class RowFn> CompareReport Referee::Impl::by_rows(std::size_t max_reported, RowFn row) const
{
    std::vector<CompareReport> rows(height);
    std::atomic<int> next{0};
    auto work = [&] {
        for (int y; (y = next++) < height;) row(y, rows[y]);
    };
    unsigned n = std::max(1u, std::min(std::thread::hardware_concurrency(), unsigned(height)));
    std::vector<std::thread> threads;
    for (unsigned k = 1; k < n; ++k) threads.emplace_back(work);
    work();
    for (auto& t : threads) t.join();

    CompareReport total;
    for (const CompareReport& r : rows) {
        for (std::size_t CompareReport::*count : counts) total.*count += r.*count;
        for (const PixelVerdict& v : r.first_errors)
            if (total.first_errors.size() < max_reported) total.first_errors.push_back(v);
    }
    return total;
}

const char* to_string(AnswerError error) noexcept
{
    switch (error) {
    case AnswerError::None: return "none";
    case AnswerError::Coverage: return "coverage";
    case AnswerError::HiddenSurface: return "hidden surface";
    case AnswerError::Missed: return "missed";
    case AnswerError::Clipped: return "clipped";
    case AnswerError::InvalidId: return "invalid id";
    case AnswerError::Culled: return "culled";
    case AnswerError::Repeated: return "repeated";
    }
    return "unknown";
}

const char* to_string(DepthError error) noexcept
{
    switch (error) {
    case DepthError::None: return "none";
    case DepthError::Wrong: return "wrong depth";
    case DepthError::NoTriangle: return "no triangle";
    }
    return "unknown";
}

std::string PixelVerdict::describe() const
{
    std::string s = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
    if (samples > 1) s += " sample " + std::to_string(sample) + " of " + std::to_string(samples);
    if (source == 0) s += " [first]";
    else if (source == 1) s += " [second]";
    else if (source == 2) s += " [both]";
    s += ": ";
    s += id == background_id ? std::string("background") : "id " + std::to_string(id);
    if (id != background_id && error != AnswerError::InvalidId && std::isfinite(depth))
        s += " at depth " + number(depth);
    switch (error) {
    case AnswerError::None: s += ": acceptable"; break;
    case AnswerError::Coverage: s += " (coverage: " + number(edge_distance) + " px outside an edge)"; break;
    case AnswerError::HiddenSurface:
        s += " (hidden surface: " + number(depth_excess) + " relative behind the nearest)";
        break;
    case AnswerError::Missed: s += " (missed: a triangle covers the sample)"; break;
    case AnswerError::Clipped: s += " (clipped: depth outside [near, far])"; break;
    case AnswerError::InvalidId: s += " (invalid id: not a triangle of the scene)"; break;
    case AnswerError::Culled: s += " (culled: it faces the way the cull option drops)"; break;
    case AnswerError::Repeated: s += " (repeated: an earlier depth layer of the sample holds it)"; break;
    }
    if (nearest_id != background_id)
        s += "; nearest covering: id " + std::to_string(nearest_id) + " at depth " + number(nearest_depth);
    else if (error != AnswerError::None)
        s += "; no triangle covers the sample";
    if (depth_error == DepthError::Wrong) {
        s += "; wrong depth " + number(answer_depth) + ": ";
        if (id == background_id) s += "the background's is +inf";
        else if (std::isnan(depth_lo)) s += "the triangle shows nothing in [near, far]";
        else s += "outside [" + number(depth_lo) + ", " + number(depth_hi) + "]";
        if (id != background_id && std::isfinite(depth_expected)) s += " (exact " + number(depth_expected) + ")";
    } else if (depth_error == DepthError::NoTriangle) {
        s += "; depth " + number(answer_depth) + " not judged: no such triangle";
    }
    return s;
}

PixelVerdict Referee::judge(int x, int y, std::uint32_t id) const
{
    SampleAnswer a;
    a.id = id;
    return judge(x, y, a);
}

PixelVerdict Referee::judge(int x, int y, const SampleAnswer& answer) const
{
    referee_check_pixel(checked("Referee::judge"), x, y);
    return impl_->judge(x, y, answer, impl_->nearest(x, y), referee_depth_judge_px);
}

CompareReport Referee::compare(const HostVisibility& a, const HostVisibility& b, const CompareOptions& options) const
{
    const Impl& im = checked("Referee::compare");
    int log2n = check_size(im, a, "first");
    check_size(im, b, "second");
    if (a.samples != b.samples)
        throw Error(Error::Kind::InvalidArgument, "referee: the first buffer holds " + std::to_string(a.samples) +
                                                      " sample(s) per pixel, the second " + std::to_string(b.samples));
    check_options(options);
    bool depths = !a.depth.empty() && !b.depth.empty();
    CompareReport total = im.by_rows(options.max_reported, [&](int y, CompareReport& r) {
        for (int x = 0; x < im.width; ++x) for (int k = 0; k < 1 << log2n; ++k) {
            SampleAnswer sa = answer_at(a, x, y, k, depths), sb = answer_at(b, x, y, k, depths);
            bool same_id = sa.id == sb.id, same_depth = same_bits(sa.depth, sb.depth);
            ++r.pixels;
            if (options.differing_only && same_id && same_depth) {
                ++r.equal;
                r.depth_equal += depths;
                continue;
            }
            ++r.judged;
            Impl::Nearest n = im.nearest(x, y, log2n, k);
            PixelVerdict va = im.judge(x, y, sa, n, options.depth_px, log2n, k);
            PixelVerdict vb = same_id && same_depth ? va : im.judge(x, y, sb, n, options.depth_px, log2n, k);
            tally(r, va, &vb, same_id, same_depth, options.max_reported);
        }
    });
    total.depths_judged = depths;
    return total;
}

CompareReport Referee::check(const HostVisibility& a, const CompareOptions& options) const
{
    const Impl& im = checked("Referee::check");
    int log2n = check_size(im, a, "checked");
    check_options(options);
    bool depths = !a.depth.empty();
    CompareReport total = im.by_rows(options.max_reported, [&](int y, CompareReport& r) {
        for (int x = 0; x < im.width; ++x) for (int k = 0; k < 1 << log2n; ++k) {
            ++r.pixels;
            ++r.judged;
            Impl::Nearest n = im.nearest(x, y, log2n, k);
            PixelVerdict v = im.judge(x, y, answer_at(a, x, y, k, depths), n, options.depth_px, log2n, k);
            // As a comparison with the reference answer: ids equal to it, depths equal to the
            // exact depth rounded to float.
            bool same_depth = depths && (v.answer_depth == float(v.depth_expected));
            tally(r, v, nullptr, v.id == n.id, same_depth, options.max_reported);
        }
    });
    total.depths_judged = depths;
    return total;
}

} // namespace clvis
