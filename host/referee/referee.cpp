// The referee of CONVENTIONS.md: each triangle is set up once in double precision (edge functions
// in raster pixels, the depth of its plane along primary rays, its visible part clipped to the
// depth range and projected), binned into pixel tiles, then judged per pixel centre; rows are
// judged in parallel and merged in raster order, so reports do not depend on the thread count.
#include <clvis/error.hpp>
#include <clvis/referee.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

namespace clvis {

namespace {

constexpr double eps = referee_edge_eps;
constexpr double rel = referee_depth_rel;
constexpr double inf = std::numeric_limits<double>::infinity();
/// Binning tiles, in pixels per side.
constexpr int tile_log2 = 3;
constexpr int tile_size = 1 << tile_log2;
/// A plane through the eye (perspective) or parallel to the view direction (orthographic), to
/// within this fraction of its size, is edge-on: its projection has no inside.
constexpr double edge_on_rel = 1e-12;
/// Most vertices of a triangle clipped by two parallel planes.
constexpr int max_poly = 5;
/// A triangle touching more than this share of the tiles is tested at every pixel instead of
/// binned: a few hundred screen-filling triangles would otherwise fill gigabytes of tile lists.
constexpr double everywhere_share = 0.25;

/// a x + b y + c over raster positions.
struct Linear {
    double a = 0, b = 0, c = 0;
    double at(double x, double y) const { return a * x + b * y + c; }
};

/// A triangle set up for one camera and image size.
struct Triangle {
    Linear edge[3];     ///< signed distance in px, positive inside (orientation folded in)
    Linear det, num;    ///< view depth of the plane along the primary ray = num / det
    bool flat = false;  ///< zero area or edge-on: no inside
    int n = 0;          ///< vertices of the visible part (0: nothing in the depth range)
    double px[max_poly], py[max_poly], pd[max_poly]; ///< its raster position and view depth
    double lo_x = inf, lo_y = inf, hi_x = -inf, hi_y = -inf; ///< EPS-expanded raster bounds
};

/// a * b == c * d exactly (fma recovers the rounding error of each product).
bool products_equal(double a, double b, double c, double d)
{
    double p = a * b, q = c * d;
    return p == q && std::fma(a, b, -p) == std::fma(c, d, -q);
}

/// The float32 triangle has zero area: its edge vectors (exact in double for all but extreme
/// exponent gaps) are parallel.
bool zero_area(Vec3 p0, Vec3 p1, Vec3 p2)
{
    Vec3 e1 = p1 - p0, e2 = p2 - p0;
    return products_equal(e1.y, e2.z, e1.z, e2.y) && products_equal(e1.z, e2.x, e1.x, e2.z) &&
           products_equal(e1.x, e2.y, e1.y, e2.x);
}

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

struct Referee::Impl {
    Camera camera;
    int width = 0, height = 0;
    bool perspective = true;
    double near_lo = 0, near_in = 0, far_in = 0, far_hi = 0; ///< depth range with tolerances
    std::vector<Triangle> tris;
    int tiles_x = 0, tiles_y = 0;
    std::vector<std::uint32_t> tile_start; ///< tiles_x * tiles_y + 1 offsets into tile_tris
    std::vector<std::uint32_t> tile_tris;  ///< triangle ids per tile, ascending
    std::vector<std::uint32_t> everywhere; ///< ids of triangles too large to bin, ascending

    /// What the nearest robustly covering triangle is at a sample.
    struct Nearest {
        std::uint32_t id = background_id;
        double depth = inf;
    };

    void setup(const Scene& scene);
    void setup_triangle(Triangle& t, const Vec3 world[3], const Vec3 cam[3]) const;
    void bin();
    TriangleAtSample classify(const Triangle& t, double x, double y) const;
    TriangleAtSample classify_id(std::uint32_t id, int x, int y) const
    {
        return classify(tris[id], x + 0.5, y + 0.5);
    }
    template <class Fn> void for_candidates(int x, int y, Fn fn) const;
    Nearest nearest(int x, int y) const;
    PixelVerdict judge(int x, int y, std::uint32_t id, const Nearest& n) const;
    template <class RowFn> CompareReport by_rows(std::size_t max_reported, RowFn row) const;
    /// A screen-space linear function k.x sx + k.y sy + k.z as a function of raster (x, y).
    Linear to_raster(double kx, double ky, double k0) const;
    void project(Vec3 cam, double* x, double* y) const;
};

Linear Referee::Impl::to_raster(double kx, double ky, double k0) const
{
    // sx = (2x/W - 1) right, sy = (1 - 2y/H) top.
    Canvas cv = camera.canvas(double(width) / height);
    return {kx * 2 * cv.right / width, -ky * 2 * cv.top / height, -kx * cv.right + ky * cv.top + k0};
}

void Referee::Impl::project(Vec3 p, double* x, double* y) const
{
    Vec3 r = camera.camera_to_raster(p, width, height);
    *x = r.x;
    *y = r.y;
}

void Referee::Impl::setup(const Scene& scene)
{
    perspective = camera.projection == Projection::Perspective;
    near_lo = camera.near * (1 - rel);
    near_in = camera.near * (1 + rel);
    far_in = camera.far * (1 - rel);
    far_hi = camera.far * (1 + rel);

    const std::vector<float>& pos = scene.world_positions();
    const std::vector<std::uint32_t>& idx = scene.world_indices();
    CameraFrame fr = camera.frame();
    std::vector<Vec3> cam(pos.size() / 3);
    for (std::size_t v = 0; v < cam.size(); ++v) {
        Vec3 d = Vec3{pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]} - camera.eye;
        cam[v] = {dot(d, fr.r), dot(d, fr.u), -dot(d, fr.f)}; // Camera::to_camera
    }
    tris.resize(idx.size() / 3);
    for (std::size_t i = 0; i < tris.size(); ++i) {
        Vec3 w[3], c[3];
        for (int k = 0; k < 3; ++k) {
            std::uint32_t v = idx[3 * i + k];
            w[k] = {pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]};
            c[k] = cam[v];
        }
        setup_triangle(tris[i], w, c);
    }
    bin();
}

void Referee::Impl::setup_triangle(Triangle& t, const Vec3 world[3], const Vec3 p[3]) const
{
    Vec3 nc = cross(p[1] - p[0], p[2] - p[0]);
    double nlen = length(nc);
    // Scaled barycentrics of the ray's hit, edge by edge: dot(D, cross(Pa - O, Pb - O)), with
    // D = (sx, sy, -1), O = 0 (perspective) or D = (0, 0, -1), O = (sx, sy, 0) (orthographic).
    // Their sum is det = dot(D, nc), and the ray's t (its view depth) is num / det.
    double sign = 0;
    if (perspective) {
        double num0 = dot(p[0], nc);
        t.flat = !(std::fabs(num0) > edge_on_rel * length(p[0]) * nlen);
        sign = num0 > 0 ? 1 : -1; // a visible hit has t > 0: det takes the sign of num
        t.det = to_raster(nc.x, nc.y, -nc.z);
        t.num = {0, 0, num0};
    } else {
        t.flat = !(std::fabs(nc.z) > edge_on_rel * nlen);
        sign = -nc.z > 0 ? 1 : -1;
        t.det = {0, 0, -nc.z};
        t.num = to_raster(-nc.x, -nc.y, dot(p[0], nc));
    }
    if (zero_area(world[0], world[1], world[2])) t.flat = true;
    for (int k = 0; k < 3; ++k) {
        Vec3 a = p[k], b = p[(k + 1) % 3];
        Linear e;
        if (perspective) {
            Vec3 n = cross(a, b);
            e = to_raster(n.x, n.y, -n.z);
        } else {
            e = to_raster(b.y - a.y, a.x - b.x, -(a.x * b.y - a.y * b.x));
        }
        double g = std::hypot(e.a, e.b);
        if (g > 0) {
            e = {sign * e.a / g, sign * e.b / g, sign * e.c / g};
        } else {
            // The edge lies in the eye's plane: its projection is at infinity (or the edge
            // passes through the eye, and the triangle is edge-on).
            double c = sign * e.c;
            e = {0, 0, c > 0 ? inf : c < 0 ? -inf : 0};
        }
        t.edge[k] = e;
    }

    // The visible part: the triangle clipped to the depth range (tolerance included), in
    // camera space, then projected. Nothing is projected through the eye: near > 0.
    Vec3 poly[max_poly + 2], next[max_poly + 2];
    int n = 3;
    for (int k = 0; k < 3; ++k) poly[k] = p[k];
    for (int plane = 0; plane < 2 && n > 0; ++plane) {
        auto inside = [&](Vec3 q) { return plane == 0 ? -q.z - near_lo : far_hi + q.z; };
        int m = 0;
        for (int k = 0; k < n; ++k) {
            Vec3 a = poly[k], b = poly[(k + 1) % n];
            double fa = inside(a), fb = inside(b);
            if (fa >= 0) next[m++] = a;
            if ((fa >= 0) != (fb >= 0)) next[m++] = a + (b - a) * (fa / (fa - fb));
        }
        n = m;
        std::copy(next, next + m, poly);
    }
    t.n = n;
    for (int k = 0; k < n; ++k) {
        project(poly[k], &t.px[k], &t.py[k]);
        t.pd[k] = -poly[k].z;
        t.lo_x = std::fmin(t.lo_x, t.px[k]);
        t.hi_x = std::fmax(t.hi_x, t.px[k]);
        t.lo_y = std::fmin(t.lo_y, t.py[k]);
        t.hi_y = std::fmax(t.hi_y, t.py[k]);
    }
    if (n > 0) {
        // EPS, plus room for the rounding of the set-up itself.
        double mx = eps + 1e-9 * std::fmax(1.0, std::fmax(std::fabs(t.lo_x), std::fabs(t.hi_x)));
        double my = eps + 1e-9 * std::fmax(1.0, std::fmax(std::fabs(t.lo_y), std::fabs(t.hi_y)));
        t.lo_x -= mx;
        t.hi_x += mx;
        t.lo_y -= my;
        t.hi_y += my;
    }
}

void Referee::Impl::bin()
{
    tiles_x = (width + tile_size - 1) / tile_size;
    tiles_y = (height + tile_size - 1) / tile_size;
    // Pixel i's centre is i + 0.5: the pixels whose centres lie in [lo, hi], as tile ranges.
    auto range = [](double lo, double hi, int size, int* first, int* last) {
        double f = std::ceil(lo - 0.5), l = std::floor(hi - 0.5);
        if (!(f <= l) || l < 0 || f > size - 1) return false;
        *first = int(std::fmax(f, 0.0)) >> tile_log2;
        *last = int(std::fmin(l, double(size - 1))) >> tile_log2;
        return true;
    };
    std::size_t tiles = std::size_t(tiles_x) * tiles_y;
    std::vector<std::uint32_t> count(tiles + 1, 0);
    auto visit = [&](auto fn) {
        for (std::size_t i = 0; i < tris.size(); ++i) {
            const Triangle& t = tris[i];
            int x0, x1, y0, y1;
            if (t.n == 0 || !range(t.lo_x, t.hi_x, width, &x0, &x1) || !range(t.lo_y, t.hi_y, height, &y0, &y1))
                continue;
            if (double(x1 - x0 + 1) * (y1 - y0 + 1) > everywhere_share * double(tiles) && tiles > 4) {
                fn(tiles, std::uint32_t(i));
                continue;
            }
            for (int ty = y0; ty <= y1; ++ty)
                for (int tx = x0; tx <= x1; ++tx) fn(std::size_t(ty) * tiles_x + tx, std::uint32_t(i));
        }
    };
    everywhere.clear();
    visit([&](std::size_t tile, std::uint32_t id) {
        if (tile == tiles) everywhere.push_back(id);
        else ++count[tile + 1];
    });
    for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
    if (count.back() > std::numeric_limits<std::uint32_t>::max())
        throw Error(Error::Kind::Limit, "referee: too many triangle-tile pairs to index");
    tile_start = count;
    tile_tris.resize(count.back());
    visit([&](std::size_t tile, std::uint32_t id) {
        if (tile < tiles) tile_tris[count[tile]++] = id;
    });
}

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
