// The referee's set-up for one camera and image size: each triangle in double precision from the
// scene's float32 vertices (edge functions in raster pixels, the depth of its plane along primary
// rays, its visible part clipped to the depth range and projected), then binned into pixel tiles.
#include "referee/referee_impl.hpp"
#include "scene/instance_transform.hpp"

#include <clvis/error.hpp>

#include "shared/raster.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace clvis {

static_assert(referee_depth_judge_px == 1.0 / double(CLVIS_SUBPIXEL_ONE), "the raster path's snapping step");

using namespace detail;

namespace {

/// a * b == c * d exactly (fma recovers the rounding error of each product).
bool products_equal(double a, double b, double c, double d)
{
    double p = a * b, q = c * d;
    return p == q && std::fma(a, b, -p) == std::fma(c, d, -q);
}

/// Whether a - b is exact in double, componentwise: TwoSum's error term of a + (-b) is zero.
bool exact_difference(Vec3 a, Vec3 b)
{
    auto exact = [](double x, double y) {
        double s = x - y, bb = s - x;
        return (x - (s - bb)) + (-y - bb) == 0;
    };
    return exact(a.x, b.x) && exact(a.y, b.y) && exact(a.z, b.z);
}

/// The float32 triangle has zero area: its edge vectors (exact in double for all but extreme
/// exponent gaps) are parallel.
bool zero_area(Vec3 p0, Vec3 p1, Vec3 p2)
{
    Vec3 e1 = p1 - p0, e2 = p2 - p0;
    // Beyond that exponent gap (a vertex near 1e30 beside ordinary ones) the edge vectors round:
    // decide from the exact expansion of the normal instead, zero only if every term cancels.
    if (!exact_difference(p1, p0) || !exact_difference(p2, p0)) {
        Vec3 n = cross(p0, p1) + cross(p1, p2) + cross(p2, p0);
        return n.x == 0 && n.y == 0 && n.z == 0;
    }
    return products_equal(e1.y, e2.z, e1.z, e2.y) && products_equal(e1.z, e2.x, e1.x, e2.z) &&
           products_equal(e1.x, e2.y, e1.y, e2.x);
}

/// |a_y b_z| + |a_z b_y| and so on: the size of the products cross(a, b) sums, per component.
Vec3 cross_terms(Vec3 a, Vec3 b)
{
    return {std::fabs(a.y * b.z) + std::fabs(a.z * b.y), std::fabs(a.z * b.x) + std::fabs(a.x * b.z),
            std::fabs(a.x * b.y) + std::fabs(a.y * b.x)};
}

/// The triangle's normal cross(p1 - p0, p2 - p0), and in *terms the size of the products it is
/// summed from. From the edge vectors when they are exact in double (vertices of similar
/// magnitude, always so for float32 coordinates less than 2^29 apart in exponent); else as
/// cross(p0, p1) + cross(p1, p2) + cross(p2, p0), the same in exact arithmetic, which keeps a
/// vertex near 1e30 from swallowing the others' differences (the edge vectors would be parallel).
Vec3 normal_of(const Vec3 p[3], Vec3* terms)
{
    Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    if (exact_difference(p[1], p[0]) && exact_difference(p[2], p[0])) {
        *terms = cross_terms(e1, e2);
        return cross(e1, e2);
    }
    Vec3 t0 = cross_terms(p[0], p[1]), t1 = cross_terms(p[1], p[2]), t2 = cross_terms(p[2], p[0]);
    *terms = {t0.x + t1.x + t2.x, t0.y + t1.y + t2.y, t0.z + t1.z + t2.z};
    return cross(p[0], p[1]) + cross(p[1], p[2]) + cross(p[2], p[0]);
}

} // namespace

Linear Referee::Impl::to_raster(double kx, double ky, double k0) const
{
    // sx = (x - cx) / fx, sy = (cy - y) / fy.
    Intrinsics k = raster_camera.raster_map(width, height);
    return {kx / k.fx, -ky / k.fy, -kx * k.cx / k.fx + ky * k.cy / k.fy + k0};
}

void Referee::Impl::project(Vec3 p, double* x, double* y) const
{
    Vec3 r = raster_camera.camera_to_raster(p, width, height);
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
    frame = camera.frame();
    raster_camera = camera;
    raster_camera.intrinsics = camera.raster_map(width, height);
    // Item by item, through each item's transform as world_positions() computes it: the expansion's
    // float32 vertices without the expansion (a scene of many instances need not fit expanded),
    // and only the triangles a sample can meet kept set up.
    copy_items(scene);
    set_up_candidates();
    bin();
}

void Referee::Impl::setup_triangle(Triangle& t, const Vec3 world[3], const Vec3 p[3]) const
{
    setup_plane(t, world, p);
    setup_visible_part(t, p);
}

void Referee::Impl::setup_plane(Triangle& t, const Vec3 world[3], const Vec3 p[3]) const
{
    // The normal and, for the edge-on test, the size of the products it sums (see normal_of).
    Vec3 terms;
    Vec3 nc = normal_of(p, &terms);
    double nlen = length(nc);
    // The vertex nearest the eye carries the plane's offset with the least rounding.
    int near_k = 0;
    for (int k = 1; k < 3; ++k) near_k = length(p[k]) < length(p[near_k]) ? k : near_k;
    // Scaled barycentrics of the ray's hit, edge by edge: dot(D, cross(Pa - O, Pb - O)), with
    // D = (sx, sy, -1), O = 0 (perspective) or D = (0, 0, -1), O = (sx, sy, 0) (orthographic).
    // Their sum is det = dot(D, nc), and the ray's t (its view depth) is num / det.
    double sign = 0;
    if (perspective) {
        const Vec3& q = p[near_k];
        double num0 = dot(q, nc);
        // Edge-on when num0 (the plane's distance from the eye times |nc|) is lost in the
        // rounding of its own terms: their size bounds it, not |q| |nc|, which for a huge
        // triangle whose plane passes at an ordinary distance is 1e38 times larger.
        double size = std::fabs(q.x) * terms.x + std::fabs(q.y) * terms.y + std::fabs(q.z) * terms.z;
        t.flat = !(std::fabs(num0) > edge_on_rel * size);
        sign = num0 > 0 ? 1 : -1; // a visible hit has t > 0: det takes the sign of num
        t.det = to_raster(nc.x, nc.y, -nc.z);
        t.num = {0, 0, num0};
    } else {
        t.flat = !(std::fabs(nc.z) > edge_on_rel * nlen);
        sign = -nc.z > 0 ? 1 : -1;
        t.det = {0, 0, -nc.z};
        t.num = to_raster(-nc.x, -nc.y, dot(p[near_k], nc));
    }
    if (zero_area(world[0], world[1], world[2])) t.flat = true;
    // Front-facing (render_options.hpp) when the normal points towards the eye: then num < 0,
    // or, orthographic, nc.z > 0: sign < 0 either way.
    bool front = sign < 0;
    t.culled = !t.flat && (cull == Cull::Back ? !front : cull == Cull::Front && front);
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
}

void Referee::Impl::setup_visible_part(Triangle& t, const Vec3 p[3]) const
{
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
    }
    set_bounds(t);
}

void Referee::Impl::set_bounds(Triangle& t) const
{
    for (int k = 0; k < t.n; ++k) {
        t.lo_x = std::fmin(t.lo_x, t.px[k]);
        t.hi_x = std::fmax(t.hi_x, t.px[k]);
        t.lo_y = std::fmin(t.lo_y, t.py[k]);
        t.hi_y = std::fmax(t.hi_y, t.py[k]);
    }
    if (t.n > 0) {
        // EPS, plus room for the rounding of the set-up itself.
        double mx = eps + 1e-9 * std::fmax(1.0, std::fmax(std::fabs(t.lo_x), std::fabs(t.hi_x)));
        double my = eps + 1e-9 * std::fmax(1.0, std::fmax(std::fabs(t.lo_y), std::fabs(t.hi_y)));
        t.lo_x -= mx;
        t.hi_x += mx;
        t.lo_y -= my;
        t.hi_y += my;
    }
}

namespace {

/// Bit dx + 8 of pairs[dy + 8]: some sample count has a sample at offset (dx, dy) in 1/16 px
/// (shared/samples.h).
std::array<std::uint16_t, 16> sample_offset_pairs()
{
    std::array<std::uint16_t, 16> pairs{};
    for (int log2n = 0; log2n <= CLVIS_MAX_SAMPLES_LOG2; ++log2n)
        for (int k = 0; k < 1 << log2n; ++k)
            pairs[std::size_t(clvis_sample_offset(log2n, k, 1) + 8)] |=
                std::uint16_t(1u << (clvis_sample_offset(log2n, k, 0) + 8));
    return pairs;
}

/// Bit d + 8 set for each offset d (1/16 px) of a sample position of pixels 0 .. size - 1 inside
/// [lo, hi]. Sample positions are the multiples g / 16 of 1/16 px, g = 16 i + 8 + d: those
/// inside are exactly ceil(16 lo) <= g <= floor(16 hi) (16 x is exact in double).
unsigned offsets_inside(double lo, double hi, int size)
{
    if (!(lo <= hi)) return 0; // NaN bounds too, which bin() never bins
    double g0 = std::fmax(std::ceil(16 * lo), 0.0), g1 = std::fmin(std::floor(16 * hi), 16.0 * size - 1);
    if (!(g0 <= g1)) return 0;
    if (g1 - g0 >= 15) return 0xFFFFu;
    unsigned mask = 0;
    for (long g = long(g0); g <= long(g1); ++g) mask |= 1u << (g & 15);
    return mask;
}

} // namespace

bool Referee::Impl::may_be_candidate(const Triangle& t) const
{
    static const std::array<std::uint16_t, 16> pairs = sample_offset_pairs();
    if (t.n == 0) return false;
    unsigned xs = offsets_inside(t.lo_x, t.hi_x, width);
    if (xs == 0) return false;
    unsigned ys = offsets_inside(t.lo_y, t.hi_y, height);
    for (int dy = 0; dy < 16; ++dy)
        if ((ys >> dy & 1u) && (pairs[std::size_t(dy)] & xs)) return true;
    return false;
}

void Referee::Impl::bin()
{
    tiles_x = (width + tile_size - 1) / tile_size;
    tiles_y = (height + tile_size - 1) / tile_size;
    // Pixel i's samples lie in [i, i + 1) (its centre i + 0.5, or the positions of
    // shared/samples.h): the pixels with a sample that may lie in [lo, hi], as tile ranges.
    auto range = [](double lo, double hi, int size, int* first, int* last) {
        double f = std::ceil(lo - 1), l = std::floor(hi);
        if (!(f <= l) || l < 0 || f > size - 1) return false;
        *first = int(std::fmax(f, 0.0)) >> tile_log2;
        *last = int(std::fmin(l, double(size - 1))) >> tile_log2;
        return true;
    };
    std::size_t tiles = std::size_t(tiles_x) * tiles_y;
    std::vector<std::uint32_t> count(tiles + 1, 0);
    // Over the kept triangles only: any other has no sample inside its bounds, so for_candidates
    // would pass it over at every sample.
    auto visit = [&](auto fn) {
        for (std::size_t i = 0; i < kept.size(); ++i) {
            const Triangle& t = kept[i];
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

} // namespace clvis
