// The referee of CONVENTIONS.md: each triangle is set up once in double precision (edge functions
// in raster pixels, the depth of its plane along primary rays, its visible part clipped to the
// depth range and projected; referee_setup.cpp), binned into pixel tiles, then classified per
// pixel centre here and judged in referee_judge.cpp.
#include "referee/referee_impl.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

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
            if (emin > eps && t.culled) { // robustly inside: its orientation is beyond doubt
                r.culled = true;
                return r;
            }
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

template <class Fn> void Referee::Impl::for_candidates(int x, int y, Fn fn, int log2n, int k) const
{
    std::size_t tile = std::size_t(y >> tile_log2) * tiles_x + (x >> tile_log2);
    double cx = sample_position(x, log2n, k, 0), cy = sample_position(y, log2n, k, 1);
    auto visit = [&](std::uint32_t i) {
        const Triangle& t = kept[i];
        if (cx < t.lo_x || cx > t.hi_x || cy < t.lo_y || cy > t.hi_y) return;
        fn(kept_ids[i], classify(t, cx, cy));
    };
    for (std::uint32_t k = tile_start[tile]; k < tile_start[tile + 1]; ++k) visit(tile_tris[k]);
    for (std::uint32_t i : everywhere) visit(i);
}

Referee::Impl::Nearest Referee::Impl::nearest(int x, int y, int log2n, int k) const
{
    Nearest n;
    for_candidates(
        x, y,
        [&](std::uint32_t id, const TriangleAtSample& s) {
            if (s.cls == SampleClass::In && (s.depth < n.depth || (s.depth == n.depth && id < n.id))) {
                n.id = id;
                n.depth = s.depth;
            }
        },
        log2n, k);
    return n;
}

Referee::Impl::Nearest Referee::Impl::nearest_excluding(int x, int y, const std::uint32_t* excluded, int count,
                                                        int log2n, int k) const
{
    Nearest n;
    for_candidates(
        x, y,
        [&](std::uint32_t id, const TriangleAtSample& s) {
            if (s.cls != SampleClass::In || !(s.depth < n.depth || (s.depth == n.depth && id < n.id))) return;
            for (int e = 0; e < count; ++e)
                if (excluded[e] == id) return;
            n.id = id;
            n.depth = s.depth;
        },
        log2n, k);
    return n;
}

Referee::Referee(const Scene& scene, const Camera& camera, int width, int height, const RenderOptions& options,
                 RefereeTolerance tolerance)
    : impl_(std::make_unique<Impl>())
{
    camera.validate();
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument,
                    "referee: image size must be positive, got " + std::to_string(width) + "x" + std::to_string(height));
    if (!(tolerance.edge_eps >= referee_edge_eps && tolerance.edge_eps < 1e6) ||
        !(tolerance.depth_rel >= referee_depth_rel && tolerance.depth_rel < 1))
        throw Error(Error::Kind::InvalidArgument,
                    "referee: tolerance must be at least CONVENTIONS.md's (edge_eps " + std::to_string(referee_edge_eps) +
                        " px, depth_rel " + std::to_string(referee_depth_rel) + ") and finite, got edge_eps " +
                        std::to_string(tolerance.edge_eps) + ", depth_rel " + std::to_string(tolerance.depth_rel));
    impl_->eps = tolerance.edge_eps;
    impl_->rel = tolerance.depth_rel;
    impl_->camera = camera;
    impl_->width = width;
    impl_->height = height;
    impl_->cull = options.cull;
    impl_->setup(scene);
}

Referee::~Referee() = default;
Referee::Referee(Referee&&) noexcept = default;
Referee& Referee::operator=(Referee&&) noexcept = default;

const Referee::Impl& Referee::checked(const char* call) const
{
    if (!impl_) throw Error(Error::Kind::InvalidArgument, std::string(call) + ": the Referee was moved from");
    return *impl_;
}

int Referee::width() const { return checked("Referee::width").width; }
int Referee::height() const { return checked("Referee::height").height; }

void referee_check_pixel(const Referee::Impl& impl, int x, int y)
{
    if (x < 0 || y < 0 || x >= impl.width || y >= impl.height)
        throw Error(Error::Kind::InvalidArgument, "referee: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                      ") outside the " + std::to_string(impl.width) + "x" +
                                                      std::to_string(impl.height) + " image");
}

TriangleAtSample Referee::classify(std::uint32_t id, int x, int y) const
{
    referee_check_pixel(checked("Referee::classify"), x, y);
    if (id >= impl_->triangle_count)
        throw Error(Error::Kind::InvalidArgument, "referee: triangle id " + std::to_string(id) + " not in the scene (" +
                                                      std::to_string(impl_->triangle_count) + " triangles)");
    return impl_->classify_id(id, x, y);
}

std::uint32_t Referee::reference(int x, int y, bool* ambiguous, double* depth) const
{
    referee_check_pixel(checked("Referee::reference"), x, y);
    Impl::Nearest n = impl_->nearest(x, y);
    if (ambiguous) {
        *ambiguous = false;
        impl_->for_candidates(x, y, [&](std::uint32_t id, const TriangleAtSample& s) {
            if (id != n.id && s.cls != SampleClass::Out && !(s.depth > n.depth * (1 + impl_->rel))) *ambiguous = true;
        });
    }
    if (depth) *depth = n.depth;
    return n.id;
}

} // namespace clvis
