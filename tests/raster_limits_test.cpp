// The limits of raster space (kernels/shared/raster.h): the largest accepted images drawn to
// their borders in both directions, snapped coordinates clamped into what int32 and int64 hold
// whatever the camera-space point, the clipper on huge finite and non-finite points, the
// nearest-depth bound below every sample's depth, and scenes with coordinates near +-3e38 beside
// ordinary triangles on both paths.
#include "catch.hpp"

#include "shared/raster.h"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace clvis;

namespace {

Device& device()
{
    static Device d = Device::open();
    return d;
}

/// The float32 camera of an orthographic pixel camera (see pixel_camera below) for a w x h image.
clvis_camera_gpu gpu_camera(int w, int h, bool ortho)
{
    clvis_camera_gpu c{};
    c.near_d = 0.5f;
    c.far_d = 100.0f;
    c.r_x = 1;
    c.u_y = 1;
    c.f_z = -1;
    // Canvas half-height h/2 (ortho) or 0.5 (perspective): fx = fy = h/(2 top), centred.
    c.fx = c.fy = ortho ? 1.0f : float(h);
    c.cx = float(w) / 2;
    c.cy = float(h) / 2;
    c.width = w;
    c.height = h;
    c.ortho = ortho;
    return c;
}

/// Orthographic camera looking down -z whose world (x, y) is raster (x - w/2, h/2 - y): with
/// power-of-two sizes and vertices on a 1/64 px grid every step of both paths is exact.
Camera pixel_camera(int h, double near = 0.5, double far = 100)
{
    return Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, double(h), near, far);
}

MeshData triangles(const std::vector<float>& positions)
{
    MeshData m;
    m.positions = positions;
    for (std::uint32_t i = 0; i < positions.size() / 3; ++i) m.indices.push_back(i);
    return m;
}

/// Triangles reaching every border and corner of a w x h image (raster coordinates on a 1/64 px
/// grid, under pixel_camera): a backdrop far past the guard band, thin triangles along each
/// border with vertices just outside it, and triangles across each corner.
MeshData border_scene(int w, int h)
{
    std::vector<float> p;
    auto at = [&](double x, double y, double d) {
        x = std::round(x * 64) / 64;
        y = std::round(y * 64) / 64;
        p.insert(p.end(), {float(x - w / 2.0), float(h / 2.0 - y), float(-d)});
    };
    const double far_out = 3.0 * CLVIS_MAX_IMAGE_SIZE; // beyond every guard band
    at(-far_out, -far_out, 20), at(w + far_out, -far_out, 20), at(w + far_out, h + far_out, 20);
    at(-far_out, -far_out, 20), at(w + far_out, h + far_out, 20), at(-far_out, h + far_out, 20);
    // Along the left and right borders (x = 0 and x = w), 0.3 px wide and reaching 0.2 px out.
    for (double y0 = 0; y0 < h; y0 += std::fmax(1.0, h / 8.0)) {
        double y1 = std::fmin(h + 0.7, y0 + std::fmax(1.3, h / 11.0));
        at(-0.2, y0 - 0.1, 10), at(0.1, y1, 10), at(0.6, y0 + 0.2, 10);
        at(w + 0.2, y0 - 0.1, 10), at(w - 0.6, y0 + 0.2, 10), at(w - 0.1, y1, 10);
    }
    // Along the top and bottom borders.
    for (double x0 = 0; x0 < w; x0 += std::fmax(1.0, w / 8.0)) {
        double x1 = std::fmin(w + 0.7, x0 + std::fmax(1.3, w / 11.0));
        at(x0 - 0.1, -0.2, 10), at(x0 + 0.2, 0.6, 10), at(x1, 0.1, 10);
        at(x0 - 0.1, h + 0.2, 10), at(x1, h - 0.1, 10), at(x0 + 0.2, h - 0.6, 10);
    }
    // Across each corner, from 40 px outside (past the guard band's margin) to 3.3 px inside.
    for (double cx : {0.0, double(w)})
        for (double cy : {0.0, double(h)}) {
            double sx = cx == 0 ? 1 : -1, sy = cy == 0 ? 1 : -1;
            at(cx - 100 * sx, cy - 2 * sy, 5), at(cx + 3.3 * sx, cy - 2 * sy, 5), at(cx - 2 * sx, cy + 3.3 * sy, 5);
        }
    return triangles(p);
}

/// Every pixel of the raster and ray paths judged by the referee (with `tolerance`), and the
/// raster path's ids equal to the ray path's wherever the referee says the answer is unique.
void check_both_paths(const Scene& s, const Camera& cam, int w, int h, RefereeTolerance tolerance = {})
{
    Renderer r(device(), s);
    Referee ref(s, cam, w, h, {}, tolerance);
    HostVisibility raster = r.render(cam, w, h, Path::Raster).read();
    HostVisibility ray = r.render(cam, w, h, Path::Ray).read();
    CompareOptions o;
    o.max_reported = 5;
    for (const HostVisibility* v : {&raster, &ray}) {
        CompareReport rep = ref.check(*v, o);
        std::string first;
        for (const PixelVerdict& e : rep.first_errors) first += "\n  " + e.describe();
        INFO((v == &raster ? "raster" : "ray") << " path " << w << "x" << h << ": " << rep.errors << " errors"
                                                << first);
        CHECK(rep.errors == 0);
        std::size_t covered = 0;
        for (std::uint32_t id : v->ids) covered += id != background_id;
        CHECK(covered == v->ids.size()); // the backdrop covers every pixel
    }
    CHECK(ref.compare(raster, ray, o).errors == 0);
}

} // namespace

TEST_CASE("snapped raster coordinates stay in the clamp range for any camera-space point", "[raster]")
{
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const clvis_i64 slack = clvis_i64(CLVIS_GUARD_MARGIN + CLVIS_GUARD_SLACK) << CLVIS_SUBPIXEL_BITS;
    for (bool ortho : {false, true})
        for (auto [w, h] : {std::pair{CLVIS_MAX_IMAGE_SIZE, CLVIS_MAX_IMAGE_SIZE}, {16383, 37}, {1, 1}}) {
            clvis_camera_gpu cam = gpu_camera(w, h, ortho);
            for (float x : {0.0f, 1e4f, -1e9f, 3e38f, -3e38f, inf, -inf, nan})
                for (float d : {1e-30f, 0.5f, 7.0f, 3e38f, inf, nan}) {
                    INFO("w " << w << " h " << h << " ortho " << ortho << " x " << x << " d " << d);
                    clvis_raster_vertex v = clvis_raster_vertex_from(cam, clvis_clip_vertex{x, -x, d});
                    CHECK(v.x >= -slack);
                    CHECK(v.x <= (clvis_i64(w) << CLVIS_SUBPIXEL_BITS) + slack);
                    CHECK(v.y >= -slack);
                    CHECK(v.y <= (clvis_i64(h) << CLVIS_SUBPIXEL_BITS) + slack);
                    CHECK(v.x < (clvis_i64(1) << 31));
                }
        }
}

TEST_CASE("edge functions over the largest image and its whole clamp range are exact", "[raster]")
{
    // Vertices at the extremes of the clamp range; the edge values at the image's corners and at
    // the last vector span past its right edge, against 128-bit arithmetic.
    const int s = CLVIS_MAX_IMAGE_SIZE;
    const clvis_i64 lo = -(clvis_i64(CLVIS_GUARD_MARGIN + CLVIS_GUARD_SLACK) << CLVIS_SUBPIXEL_BITS);
    const clvis_i64 hi = (clvis_i64(s) << CLVIS_SUBPIXEL_BITS) - lo;
    const clvis_raster_vertex corners[4] = {{lo, lo, 1}, {hi, lo, 1}, {hi, hi, 1}, {lo, hi, 1}};
    int checked = 0;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
            for (int c = 0; c < 4; ++c) {
                if (a == b || b == c || a == c) continue;
                clvis_raster_tri t;
                if (!clvis_raster_setup(corners[a], corners[b], corners[c], 0, s, s, CLVIS_CULL_NONE, &t)) continue;
                for (int i : {0, s - 1, s + 7})
                    for (int j : {0, s - 1}) {
                        for (int k = 0; k < 3; ++k) {
                            __int128 exact = __int128(t.e0[k]) + __int128(i) * t.ex[k] + __int128(j) * t.ey[k];
                            clvis_i64 got = t.e0[k] + clvis_i64(i) * t.ex[k] + clvis_i64(j) * t.ey[k];
                            CHECK(__int128(got) == exact);
                            CHECK(exact < (__int128(1) << 62));
                            CHECK(exact > -(__int128(1) << 62));
                        }
                        ++checked;
                    }
            }
    CHECK(checked > 0);
}

TEST_CASE("no sample of a triangle is nearer than its nearest-depth bound", "[raster]")
{
    // Random triangles over a 32x32 image, vertex depths spread over six orders of magnitude, both
    // projections: every covered sample's depth (clvis_raster_sample, the kernels' formula) lies
    // at or behind clvis_raster_set_nearest's bound, and the bound is within 2^-9 of the nearest
    // vertex's depth.
    std::mt19937 rng(11);
    std::uniform_int_distribution<clvis_i64> coord(-(clvis_i64(8) << CLVIS_SUBPIXEL_BITS),
                                                   clvis_i64(40) << CLVIS_SUBPIXEL_BITS);
    std::uniform_real_distribution<float> exponent(-3.0f, 3.0f);
    int covered = 0;
    for (int round = 0; round < 2000; ++round) {
        const int ortho = round & 1;
        clvis_raster_vertex v[3];
        float nearest = std::numeric_limits<float>::infinity();
        for (auto& p : v) {
            float d = std::pow(10.0f, exponent(rng));
            nearest = std::min(nearest, d);
            p = {coord(rng), coord(rng), ortho ? d : 1.0f / d};
        }
        clvis_raster_tri t;
        if (!clvis_raster_setup(v[0], v[1], v[2], 7, 32, 32, CLVIS_CULL_NONE, &t)) continue;
        clvis_raster_set_nearest(v[0], v[1], v[2], ortho, &t);
        CHECK(t.dnear <= nearest);
        CHECK(t.dnear >= nearest * (1.0f - 0x1p-9f));
        for (int j = t.y0; j <= t.y1; ++j)
            for (int i = t.x0; i <= t.x1; ++i) {
                clvis_u64 key = clvis_raster_sample(&t, i, j, ortho, 0.0f, std::numeric_limits<float>::max());
                if (key == CLVIS_BACKGROUND_KEY) continue;
                CHECK(clvis_key_depth(key) >= t.dnear);
                ++covered;
            }
    }
    CHECK(covered > 10000);
}

TEST_CASE("the clipper cuts huge finite edges on the plane and drops points that are not finite", "[raster]")
{
    clvis_camera_gpu cam = gpu_camera(CLVIS_MAX_IMAGE_SIZE, 64, false);
    clvis_guard g = clvis_guard_of(cam);
    // From a huge point to an ordinary one, and between two huge ones on either side.
    const clvis_clip_vertex pairs[][2] = {{{-3e38f, 0, 50}, {3e38f, 1, 50}},
                                          {{2, 0.5f, 50}, {3.3e38f, -3e38f, 3e38f}},
                                          {{-3.4e38f, 3.4e38f, 3.4e38f}, {3.4e38f, -3.4e38f, 1}}};
    for (const auto& pr : pairs)
        for (int plane = 0; plane < CLVIS_CLIP_PLANES; ++plane) {
            float da = clvis_clip_distance(pr[0], plane, cam.near_d, g, 0);
            float db = clvis_clip_distance(pr[1], plane, cam.near_d, g, 0);
            REQUIRE(std::isfinite(da));
            REQUIRE(std::isfinite(db));
            if ((da >= 0) == (db >= 0)) continue;
            clvis_clip_vertex p = clvis_clip_cut(pr[0], da, pr[1], db, plane, cam.near_d, g, 0);
            INFO("plane " << plane << " cut (" << p.x << ", " << p.y << ", " << p.d << ")");
            REQUIRE(clvis_clip_vertex_finite(p));
            // On the plane: its distance is tiny next to the endpoints'.
            double scale = std::fmax(std::fabs(double(da)), std::fabs(double(db)));
            CHECK(std::fabs(double(clvis_clip_distance(p, plane, cam.near_d, g, 0))) <= 1e-6 * scale);
        }
    const float inf = std::numeric_limits<float>::infinity();
    for (clvis_clip_vertex p : {clvis_clip_vertex{inf, 0, 5}, clvis_clip_vertex{0, -inf, 5},
                                clvis_clip_vertex{0, 0, inf}, clvis_clip_vertex{std::nanf(""), 0, 5}}) {
        CHECK((clvis_outcode(cam, p) & CLVIS_OUT_CLIP) != 0);
        for (int plane = 0; plane < CLVIS_CLIP_PLANES; ++plane)
            CHECK(!(clvis_clip_distance(p, plane, cam.near_d, g, 0) >= 0));
    }
}

TEST_CASE("the largest accepted images are drawn exactly to their borders, both ways",
          "[device][raster][limits][rusticl][rusticl_long]")
{
    // Power-of-two sizes under the pixel camera: every float32 step is exact, so the referee's
    // own EPS applies. On main before the guard band followed the image, the backdrop's clipped
    // corners stopped 8000 px from the centre and the outer 192 px of a 16384 px side were empty.
    for (auto [w, h] : {std::pair{CLVIS_MAX_IMAGE_SIZE, 64}, {64, CLVIS_MAX_IMAGE_SIZE}, {8192, 128}}) {
        Scene s;
        s.add_mesh(border_scene(w, h));
        check_both_paths(s, pixel_camera(h), w, h);
    }
}

TEST_CASE("sizes past the raster path's limit are refused by name", "[device][raster][limits]")
{
    Scene s;
    s.add_mesh(border_scene(64, 64));
    Renderer r(device(), s);
    for (auto [w, h] : {std::pair{CLVIS_MAX_IMAGE_SIZE + 1, 4}, {4, CLVIS_MAX_IMAGE_SIZE + 1}}) {
        try {
            r.render(pixel_camera(h), w, h, Path::Raster);
            FAIL("accepted " << w << "x" << h);
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::Limit);
            CHECK(std::string(e.what()).find(std::to_string(CLVIS_MAX_IMAGE_SIZE)) != std::string::npos);
        }
    }
}

namespace {

/// Counts of unacceptable answers in a frame of a scene whose triangles from `first_huge` on have
/// coordinates near +-3e38.
struct HugeVerdicts {
    std::size_t stray = 0;  ///< a huge triangle answered wrongly, or a coverage/clip/id error
    std::size_t missed = 0; ///< a huge triangle robustly covers the sample and was not answered
    std::size_t other = 0;  ///< anything else: the ordinary triangles judged exactly
    std::size_t huge_px = 0;
};

HugeVerdicts judge_huge(const Referee& ref, const HostVisibility& v, std::uint32_t first_huge)
{
    HugeVerdicts h;
    for (float d : v.depth) CHECK((std::isfinite(d) || d == std::numeric_limits<float>::infinity()));
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x) {
            std::uint32_t id = v.id(x, y);
            h.huge_px += id != background_id && id >= first_huge;
            PixelVerdict e = ref.judge(x, y, id);
            if (e.acceptable()) continue;
            if (e.error == AnswerError::Coverage || e.error == AnswerError::Clipped ||
                e.error == AnswerError::InvalidId || (id != background_id && id >= first_huge)) {
                if (h.stray < 3) UNSCOPED_INFO(e.describe());
                ++h.stray;
            }
            else if (e.nearest_id != background_id && e.nearest_id >= first_huge)
                ++h.missed;
            else
                ++h.other;
        }
    return h;
}

} // namespace

TEST_CASE("coordinates near +-3e38 beside ordinary triangles draw no stray coverage", "[device][raster][limits]")
{
    // An ordinary sphere, then huge triangles: a backdrop whose vertices are near +-3e38, ones the
    // referee (double precision) says cover nothing (beyond far, behind the eye, off to the side,
    // above with coordinates at FLT_MAX), and one with a single vertex at 1e30 behind the eye,
    // crossing near. Looking down -z from the origin the float32 camera transform of all of them
    // is exact, so both paths must draw them exactly (on main the clipper's cuts overflowed to
    // NaN and the ray path's products to inf); under a rotated frame the FLT_MAX
    // vertices overflow float32 (dropped by the clipper) and the backdrop's depth is uncertain
    // by 3e38 2^-24 (CONVENTIONS.md's precision paragraph), so that scene leaves it out.
    const float big = 3e38f, max = std::numeric_limits<float>::max();
    auto scene = [&](bool backdrop) {
        Scene s;
        Mat4 move;
        move(2, 3) = -6;
        s.add_mesh(make_uv_sphere(200), move);
        if (backdrop) s.add_mesh(triangles({-big, -big, -50, big, -big, -50, 0, big, -50}));
        s.add_mesh(triangles({-big, -big, -1e38f, big, -big, -1e38f, 0, big, -1e38f})); // beyond far
        s.add_mesh(triangles({-big, -big, 5, big, -big, 5, 0, big, 5}));                // behind the eye
        s.add_mesh(triangles({big, -1, -5, max, 1, -5, big, 0, -max}));                 // off to the side
        s.add_mesh(triangles({max, max, max, -max, max, max, 0, max, -max}));           // above
        s.add_mesh(triangles({1e30f, 1e30f, 1e30f, 2, 0, -4, 0, 2, -4}));               // across near
        return s;
    };
    const std::uint32_t first_huge = std::uint32_t(make_uv_sphere(200).triangle_count());
    Camera straight = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 0.5, 100);
    Camera rotated = Camera::perspective({0, 0, 0}, {0.13, -0.07, -1}, {0.1, 1, 0}, 50, 0.5, 100);
    for (bool backdrop : {true, false}) {
        Scene s = scene(backdrop);
        Camera cam = backdrop ? straight : rotated;
        Renderer r(device(), s);
        for (auto [w, h] : {std::pair{96, 64}, {151, 97}}) {
            Referee ref(s, cam, w, h);
            for (Path p : {Path::Raster, Path::Ray}) {
                HugeVerdicts v = judge_huge(ref, r.render(cam, w, h, p).read(), first_huge);
                INFO(to_string(p) << " path " << w << "x" << h << (backdrop ? " with" : " without")
                                  << " the backdrop: " << v.stray << " stray, " << v.missed
                                  << " huge triangles missed, " << v.other << " other errors");
                CHECK(v.stray == 0);
                CHECK(v.other == 0);
                CHECK(v.missed == 0);
                CHECK(v.huge_px > 0);
            }
        }
    }
}
