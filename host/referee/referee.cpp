// The referee of CONVENTIONS.md: each triangle is set up once in double precision (edge functions
// in raster pixels, the depth of its plane along primary rays, its visible part clipped to the
// depth range and projected), binned into pixel tiles, then judged per pixel centre; rows are
// judged in parallel and merged in raster order, so reports do not depend on the thread count.
#include "referee/referee_impl.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

namespace clvis {

using namespace detail;

namespace {

/// Distance from (x, y) to segment a-b, and the parameter of the closest point.
double segment_distance(double x, double y, double ax, double ay, double bx, double by, double* u)
{
    double dx = bx - ax, dy = by - ay;
    double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((x - ax) * dx + (y - ay) * dy) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    *u = t;
    return std::hypot(x - (ax + t * dx), y - (ay + t * dy));
}

std::string number(double v)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

} // namespace

TriangleAtSample Referee::Impl::classify(const Triangle& t, double x, double y) const
{
    TriangleAtSample r;
    r.depth = std::numeric_limits<double>::quiet_NaN();
    if (t.n == 0) { // nothing of it lies in the depth range
        r.out_by_depth = true;
        return r;
    }
    bool hits = false; // the sample's ray meets the triangle outside the depth range
    if (!t.flat) {
        double emin = inf;
        for (const Linear& e : t.edge) emin = std::fmin(emin, e.at(x, y));
        if (emin < -eps) {
            r.outside = -emin;
            return r;
        }
        if (emin >= 0) {
            // Inside every edge: the ray meets the triangle, at its plane's depth along the ray.
            r.depth = t.num.at(x, y) / t.det.at(x, y);
            if (r.depth >= near_lo && r.depth <= far_hi) {
                bool in = emin > eps && r.depth >= near_in && r.depth <= far_in;
                r.cls = in ? SampleClass::In : SampleClass::Ambiguous;
                return r;
            }
            if (emin > eps) {
                r.out_by_depth = true;
                return r;
            }
            hits = true;
        }
    }
    // Within EPS outside an edge, near an edge with the hit clipped, or flat: the distance to the
    // visible part decides, at the depth of its nearest point. The plane's depth along a ray that
    // misses the triangle means nothing (under a plane seen almost edge-on it may lie anywhere);
    // this also keeps samples beyond a sliver's sharp tip out, and judges a flat triangle by its
    // segment.
    double best = inf, depth = 0;
    for (int k = 0; k < t.n; ++k) {
        int j = t.n == 1 ? k : (k + 1) % t.n;
        double u = 0;
        double d = segment_distance(x, y, t.px[k], t.py[k], t.px[j], t.py[j], &u);
        if (d < best) {
            best = d;
            depth = perspective ? 1 / ((1 - u) / t.pd[k] + u / t.pd[j]) : (1 - u) * t.pd[k] + u * t.pd[j];
        }
    }
    if (best > eps) {
        r.out_by_depth = hits;
        r.outside = hits ? 0 : best;
        return r;
    }
    r.depth = depth;
    r.cls = SampleClass::Ambiguous;
    return r;
}

template <class Fn> void Referee::Impl::for_candidates(int x, int y, Fn fn) const
{
    std::size_t tile = std::size_t(y >> tile_log2) * tiles_x + (x >> tile_log2);
    double cx = x + 0.5, cy = y + 0.5;
    auto visit = [&](std::uint32_t id) {
        const Triangle& t = tris[id];
        if (cx < t.lo_x || cx > t.hi_x || cy < t.lo_y || cy > t.hi_y) return;
        fn(id, classify(t, cx, cy));
    };
    for (std::uint32_t k = tile_start[tile]; k < tile_start[tile + 1]; ++k) visit(tile_tris[k]);
    for (std::uint32_t id : everywhere) visit(id);
}

Referee::Impl::Nearest Referee::Impl::nearest(int x, int y) const
{
    Nearest n;
    for_candidates(x, y, [&](std::uint32_t id, const TriangleAtSample& s) {
        if (s.cls == SampleClass::In && (s.depth < n.depth || (s.depth == n.depth && id < n.id))) {
            n.id = id;
            n.depth = s.depth;
        }
    });
    return n;
}

PixelVerdict Referee::Impl::judge(int x, int y, std::uint32_t id, const Nearest& n) const
{
    PixelVerdict v;
    v.x = x;
    v.y = y;
    v.id = id;
    v.nearest_id = n.id;
    v.nearest_depth = n.depth;
    if (id == background_id) {
        if (n.id != background_id) v.error = AnswerError::Missed;
        return v;
    }
    if (id >= tris.size()) {
        v.error = AnswerError::InvalidId;
        return v;
    }
    TriangleAtSample s = classify_id(id, x, y);
    v.depth = s.depth;
    if (s.cls == SampleClass::Out) {
        if (s.out_by_depth) {
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
        total.pixels += r.pixels;
        total.equal += r.equal;
        total.explained += r.explained;
        total.errors += r.errors;
        total.errors_a += r.errors_a;
        total.errors_b += r.errors_b;
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
    }
    return "unknown";
}

std::string PixelVerdict::describe() const
{
    std::string s = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
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
    }
    if (nearest_id != background_id)
        s += "; nearest covering: id " + std::to_string(nearest_id) + " at depth " + number(nearest_depth);
    else if (error != AnswerError::None)
        s += "; no triangle covers the sample";
    return s;
}

Referee::Referee(const Scene& scene, const Camera& camera, int width, int height) : impl_(std::make_unique<Impl>())
{
    camera.validate();
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument,
                    "referee: image size must be positive, got " + std::to_string(width) + "x" + std::to_string(height));
    impl_->camera = camera;
    impl_->width = width;
    impl_->height = height;
    impl_->setup(scene);
}

Referee::~Referee() = default;
Referee::Referee(Referee&&) noexcept = default;
Referee& Referee::operator=(Referee&&) noexcept = default;

int Referee::width() const { return impl_->width; }
int Referee::height() const { return impl_->height; }

namespace {

void check_pixel(const Referee::Impl& impl, int x, int y)
{
    if (x < 0 || y < 0 || x >= impl.width || y >= impl.height)
        throw Error(Error::Kind::InvalidArgument, "referee: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                      ") outside the " + std::to_string(impl.width) + "x" +
                                                      std::to_string(impl.height) + " image");
}

void check_size(const Referee::Impl& impl, const HostVisibility& v, const char* which)
{
    if (v.width != impl.width || v.height != impl.height ||
        v.ids.size() != std::size_t(impl.width) * std::size_t(impl.height))
        throw Error(Error::Kind::InvalidArgument,
                    std::string("referee: ") + which + " buffer is " + std::to_string(v.width) + "x" +
                        std::to_string(v.height) + ", the referee's image " + std::to_string(impl.width) + "x" +
                        std::to_string(impl.height));
}

} // namespace

TriangleAtSample Referee::classify(std::uint32_t id, int x, int y) const
{
    check_pixel(*impl_, x, y);
    if (id >= impl_->tris.size())
        throw Error(Error::Kind::InvalidArgument, "referee: triangle id " + std::to_string(id) + " not in the scene (" +
                                                      std::to_string(impl_->tris.size()) + " triangles)");
    return impl_->classify_id(id, x, y);
}

PixelVerdict Referee::judge(int x, int y, std::uint32_t id) const
{
    check_pixel(*impl_, x, y);
    return impl_->judge(x, y, id, impl_->nearest(x, y));
}

std::uint32_t Referee::reference(int x, int y, bool* ambiguous, double* depth) const
{
    check_pixel(*impl_, x, y);
    Impl::Nearest n = impl_->nearest(x, y);
    if (ambiguous) {
        *ambiguous = false;
        impl_->for_candidates(x, y, [&](std::uint32_t id, const TriangleAtSample& s) {
            if (id != n.id && s.cls != SampleClass::Out && !(s.depth > n.depth * (1 + rel))) *ambiguous = true;
        });
    }
    if (depth) *depth = n.depth;
    return n.id;
}

CompareReport Referee::compare(const HostVisibility& a, const HostVisibility& b, const CompareOptions& options) const
{
    const Impl& im = *impl_;
    check_size(im, a, "first");
    check_size(im, b, "second");
    return im.by_rows(options.max_reported, [&](int y, CompareReport& r) {
        for (int x = 0; x < im.width; ++x) {
            std::uint32_t ia = a.id(x, y), ib = b.id(x, y);
            ++r.pixels;
            if (ia == ib) ++r.equal;
            if (ia == ib && !options.all) continue;
            Impl::Nearest n = im.nearest(x, y);
            PixelVerdict va = im.judge(x, y, ia, n);
            if (ia == ib) {
                if (!va.acceptable()) {
                    ++r.errors;
                    ++r.errors_a;
                    ++r.errors_b;
                    va.source = 2;
                    if (r.first_errors.size() < options.max_reported) r.first_errors.push_back(va);
                }
                continue;
            }
            PixelVerdict vb = im.judge(x, y, ib, n);
            va.source = 0;
            vb.source = 1;
            if (va.acceptable() && vb.acceptable()) {
                ++r.explained;
                continue;
            }
            ++r.errors;
            for (const PixelVerdict* v : {&va, &vb}) {
                if (v->acceptable()) continue;
                ++(v->source == 0 ? r.errors_a : r.errors_b);
                if (r.first_errors.size() < options.max_reported) r.first_errors.push_back(*v);
            }
        }
    });
}

CompareReport Referee::check(const HostVisibility& a, const CompareOptions& options) const
{
    const Impl& im = *impl_;
    check_size(im, a, "checked");
    return im.by_rows(options.max_reported, [&](int y, CompareReport& r) {
        for (int x = 0; x < im.width; ++x) {
            ++r.pixels;
            Impl::Nearest n = im.nearest(x, y);
            PixelVerdict v = im.judge(x, y, a.id(x, y), n);
            if (!v.acceptable()) {
                ++r.errors;
                ++r.errors_a;
                if (r.first_errors.size() < options.max_reported) r.first_errors.push_back(v);
            } else if (v.id == n.id) {
                ++r.equal;
            } else {
                ++r.explained;
            }
        }
    });
}

} // namespace clvis
