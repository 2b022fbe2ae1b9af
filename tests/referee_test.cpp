// The referee against hand-computed answers: samples on edges and vertices, depth ties, robust
// insides, triangles behind the eye and across the near plane, orthographic cameras, flat
// triangles and slivers; compare() and check() counting on hand-made buffers; and the referee's
// reference() against an independent double-precision ray cast on real meshes.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

using namespace clvis;

namespace {

Scene scene_of(std::vector<float> positions)
{
    Scene s;
    MeshData m;
    m.name = "hand-made";
    m.positions = std::move(positions);
    for (std::uint32_t i = 0; i < m.positions.size() / 3; ++i) m.indices.push_back(i);
    s.add_mesh(m);
    return s;
}

// Camera space equals world space; fov 90 on a 4x4 image: a point at z = -2 lands at raster
// (2 (x/2 + 1), 2 (1 - y/2)), so pixel centres x = 0.5 .. 3.5 see sx = -0.75, -0.25, 0.25, 0.75.
Camera axis_camera(double near = 0.1, double far = 100)
{
    return Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, near, far);
}

// Two triangles at z = -2 sharing the edge x = 0.5 (screen sx = 0.25, the centres of column 2):
// id 0 on the left, id 1 on the right.
Scene shared_edge()
{
    return scene_of({0.5f, -10, -2, 0.5f, 10, -2, -10, 0, -2, //
                     0.5f, -10, -2, 10, 0, -2, 0.5f, 10, -2});
}

// An orthographic camera whose raster position is the world (x, H - y): one world unit per
// pixel, view depth 10 - z.
Camera pixel_ortho(int w, int h)
{
    return Camera::orthographic({w / 2.0, h / 2.0, 10}, {w / 2.0, h / 2.0, 0}, {0, 1, 0}, h, 1, 100);
}

/// Möller-Trumbore in double: the view depth of the hit, or NaN; `margin` receives the smallest
/// barycentric.
double ray_hit(const Ray& ray, const float* v, double* margin)
{
    Vec3 p0{v[0], v[1], v[2]}, p1{v[3], v[4], v[5]}, p2{v[6], v[7], v[8]};
    Vec3 e1 = p1 - p0, e2 = p2 - p0;
    Vec3 pv = cross(ray.direction, e2);
    double det = dot(e1, pv);
    if (det == 0) return std::nan("");
    Vec3 tv = ray.origin - p0;
    double u = dot(tv, pv) / det;
    Vec3 qv = cross(tv, e1);
    double w = dot(ray.direction, qv) / det;
    *margin = std::fmin(std::fmin(u, w), 1 - u - w);
    return dot(e2, qv) / det;
}

} // namespace

TEST_CASE("a sample robustly inside is in, and its triangle is the only acceptable answer", "[referee]")
{
    Scene s = shared_edge();
    Referee ref(s, axis_camera(), 4, 4);
    bool ambiguous = true;
    double depth = 0;
    CHECK(ref.reference(1, 1, &ambiguous, &depth) == 0);
    CHECK_FALSE(ambiguous);
    CHECK(depth == Approx(2.0).epsilon(1e-12));
    CHECK(ref.classify(0, 1, 1).cls == SampleClass::In);
    CHECK(ref.judge(1, 1, 0).acceptable());

    PixelVerdict other = ref.judge(1, 1, 1); // sx = -0.25 is 0.5 screen units = 1 px left of x = 0.5
    CHECK(other.error == AnswerError::Coverage);
    CHECK(other.edge_distance == Approx(1.0).epsilon(1e-9));
    CHECK(other.nearest_id == 0);
    CHECK_THAT(other.describe(), Catch::Contains("pixel (1, 1)") && Catch::Contains("coverage") &&
                                     Catch::Contains("nearest covering: id 0"));

    PixelVerdict missed = ref.judge(1, 1, background_id);
    CHECK(missed.error == AnswerError::Missed);
    CHECK(ref.reference(3, 2) == 1);
}

TEST_CASE("a sample exactly on a shared edge is ambiguous for both triangles", "[referee]")
{
    Scene s = shared_edge();
    Referee ref(s, axis_camera(), 4, 4);
    for (int y = 0; y < 4; ++y) {
        CHECK(ref.classify(0, 2, y).cls == SampleClass::Ambiguous);
        CHECK(ref.classify(1, 2, y).cls == SampleClass::Ambiguous);
        bool ambiguous = false;
        CHECK(ref.reference(2, y, &ambiguous) == background_id); // nothing is robustly in
        CHECK(ambiguous);
        CHECK(ref.judge(2, y, 0).acceptable());
        CHECK(ref.judge(2, y, 1).acceptable());
        CHECK(ref.judge(2, y, background_id).acceptable());
    }
}

TEST_CASE("a sample exactly on a vertex is ambiguous, one EPS away it is decided", "[referee]")
{
    // Pixel (2, 1) samples sx = 0.25, sy = 0.25: the point (0.5, 0.5, -2).
    Scene s = scene_of({0.5f, 0.5f, -2, 4, 0.5f, -2, 0.5f, 4, -2,      // corner at the sample
                        0.5f, 0.5f, -2, 0.5f, 4, -2, -4, -4, -2});    // the neighbour across
    Referee ref(s, axis_camera(), 4, 4);
    CHECK(ref.classify(0, 2, 1).cls == SampleClass::Ambiguous);
    CHECK(ref.classify(1, 2, 1).cls == SampleClass::Ambiguous);
    CHECK(ref.judge(2, 1, 0).acceptable());
    CHECK(ref.judge(2, 1, 1).acceptable());
    CHECK(ref.judge(2, 1, background_id).acceptable());

    // Move the corner 0.002 world units inwards (0.001 screen units at z = -2, 2 px per screen
    // unit on this image: 0.002 px > EPS): now robustly in.
    Scene moved = scene_of({0.498f, 0.498f, -2, 4, 0.498f, -2, 0.498f, 4, -2});
    Referee ref2(moved, axis_camera(), 4, 4);
    CHECK(ref2.classify(0, 2, 1).cls == SampleClass::In);
    CHECK(ref2.judge(2, 1, background_id).error == AnswerError::Missed);
}

TEST_CASE("at an exact depth tie the lower id is the reference and both are acceptable", "[referee]")
{
    std::vector<float> tri = {-4, -4, -3, 4, -4, -3, 0, 4, -3};
    std::vector<float> both = tri;
    both.insert(both.end(), tri.begin(), tri.end());
    // id 2 a hair behind (1e-7 relative: within the tolerance), id 3 clearly behind (1e-5).
    for (float z : {-3.0000003f, -3.00003f}) both.insert(both.end(), {-4, -4, z, 4, -4, z, 0, 4, z});
    Scene s = scene_of(both);
    Referee ref(s, axis_camera(), 4, 4);
    bool ambiguous = false;
    CHECK(ref.reference(1, 2, &ambiguous) == 0);
    CHECK(ambiguous); // id 1 ties
    CHECK(ref.judge(1, 2, 1).acceptable());
    CHECK(ref.judge(1, 2, 2).acceptable());
    PixelVerdict hidden = ref.judge(1, 2, 3);
    CHECK(hidden.error == AnswerError::HiddenSurface);
    CHECK(hidden.depth_excess == Approx(double(3.00003f) / 3 - 1).epsilon(1e-6));
    CHECK_THAT(hidden.describe(), Catch::Contains("hidden surface"));
}

TEST_CASE("a triangle behind the eye is clipped, never covering", "[referee]")
{
    Scene s = scene_of({-10, -10, 2, 10, -10, 2, 0, 10, 2});
    Referee ref(s, axis_camera(), 4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            CHECK(ref.reference(x, y) == background_id);
            CHECK(ref.judge(x, y, 0).error == AnswerError::Clipped);
            CHECK(ref.judge(x, y, background_id).acceptable());
        }
}

TEST_CASE("a triangle crossing the near plane is judged by its visible part", "[referee]")
{
    // Vertex C is behind the eye; the plane -6y + 4z + 2 = 0 meets the ray (sx, sy, -1) at
    // t = 2 / (6 sy + 4). Pixel (1, 1) (sx = -0.25, sy = 0.25) hits it at t = 4 / 11, inside.
    Scene s = scene_of({-1, -1, -2, 1, -1, -2, 0, 1, 1});
    Referee ref(s, axis_camera(0.1), 4, 4);
    TriangleAtSample in = ref.classify(0, 1, 1);
    CHECK(in.cls == SampleClass::In);
    CHECK(in.depth == Approx(4.0 / 11).epsilon(1e-12));
    CHECK(ref.reference(1, 1) == 0);
    // Row 3 (sy = -0.75) meets the plane behind the eye (t = -4): not acceptable there.
    CHECK_FALSE(ref.judge(1, 3, 0).acceptable());

    // The same sample with near beyond the hit: clipped.
    Referee clipped(s, axis_camera(0.5), 4, 4);
    CHECK(clipped.judge(1, 1, 0).error == AnswerError::Clipped);
    CHECK(clipped.reference(1, 1) == background_id);

    // Against an independent ray cast on a fine image: robust hits are in at the same depth,
    // robust misses are out.
    const int n = 64;
    Camera cam = axis_camera(0.1);
    Referee fine(s, cam, n, n);
    float v[9];
    s.triangle(0, v);
    int ins = 0, outs = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            double margin = 0;
            double t = ray_hit(cam.primary_ray(x + 0.5, y + 0.5, n, n), v, &margin);
            TriangleAtSample c = fine.classify(0, x, y);
            if (c.cls == SampleClass::In) {
                ++ins;
                CHECK(margin >= 0);
                CHECK(t == Approx(c.depth).epsilon(1e-9));
            }
            bool robust_hit = margin > 1e-3 && t > 0.1 * 1.01 && t < 100;
            bool robust_miss = margin < -1e-3 || t < 0.1 * 0.99;
            if (robust_hit) CHECK(c.cls == SampleClass::In);
            if (robust_miss) {
                ++outs;
                CHECK(c.cls == SampleClass::Out);
            }
        }
    CHECK(ins > 100);
    CHECK(outs > 100);
}

TEST_CASE("near an almost edge-on triangle, the depth is its nearest visible point's", "[referee]")
{
    // The plane 4x + z = 0.004 passes 1e-3 beside the eye; the triangle projects to a sliver at
    // sx in [0.25 + 0.001/6, 0.25 + 0.001/2], 3.3e-4 px right of column 2's centres, whose rays
    // run parallel to the plane: its depth along them is infinite, not out of range.
    Scene s = scene_of({0.501f, -4, -2, 0.501f, 4, -2, 1.501f, 0, -6});
    Referee ref(s, axis_camera(), 4, 4);
    TriangleAtSample c = ref.classify(0, 2, 1);
    CHECK(c.cls == SampleClass::Ambiguous);
    CHECK(c.depth >= 2);
    CHECK(c.depth <= 6);
    CHECK(ref.judge(2, 1, 0).acceptable());
    CHECK(ref.reference(2, 1) == background_id);
    CHECK(ref.judge(3, 1, 0).error == AnswerError::Coverage);
}

TEST_CASE("orthographic cameras judge edges and the plane's depth along the ray", "[referee]")
{
    // The shared edge x = 4.5 runs through the centres of column 4.
    Scene s = scene_of({4.5f, -20, 2, 4.5f, 20, 2, -20, 0, 2,   // left, depth 8
                        4.5f, -20, 1, 20, 0, 5, 4.5f, 20, 1});  // right, tilted
    Referee ref(s, pixel_ortho(8, 8), 8, 8);
    TriangleAtSample left = ref.classify(0, 2, 3);
    CHECK(left.cls == SampleClass::In);
    CHECK(left.depth == Approx(8.0).epsilon(1e-12));
    CHECK(ref.classify(0, 4, 3).cls == SampleClass::Ambiguous);
    CHECK(ref.classify(1, 4, 3).cls == SampleClass::Ambiguous);
    // id 1 lies in the plane z = 1 + (x - 4.5) * 4 / 15.5; pixel (6, 4) samples x = 6.5.
    TriangleAtSample right = ref.classify(1, 6, 4);
    CHECK(right.cls == SampleClass::In);
    CHECK(right.depth == Approx(10 - (1 + 2.0 * 4 / 15.5)).epsilon(1e-9));
    CHECK(ref.judge(2, 3, 1).error == AnswerError::Coverage);
    CHECK(ref.judge(2, 3, 1).edge_distance == Approx(2.0).epsilon(1e-9));
}

TEST_CASE("a zero-area triangle is never in, ambiguous on its segment, out elsewhere", "[referee]")
{
    // Collinear through pixel centre (3.5, 4.5) in the pixel-unit orthographic frame (y = 8 - 4.5).
    Scene s = scene_of({1.5f, 3.5f, 0, 3.5f, 3.5f, 0, 6.5f, 3.5f, 0});
    Referee ref(s, pixel_ortho(8, 8), 8, 8);
    CHECK(ref.classify(0, 3, 4).cls == SampleClass::Ambiguous);
    CHECK(ref.classify(0, 3, 4).depth == Approx(10.0));
    CHECK(ref.classify(0, 3, 3).cls == SampleClass::Out);
    CHECK(ref.judge(3, 3, 0).edge_distance == Approx(1.0).epsilon(1e-9));
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) CHECK(ref.classify(0, x, y).cls != SampleClass::In);
    CHECK(ref.reference(3, 4) == background_id);
}

TEST_CASE("a sample beyond a sliver's tip is out, though within EPS of both edge lines", "[referee]")
{
    // Tip at raster (3.0, 4.5); the sample (3.5, 4.5) lies on the sliver's axis 0.5 px beyond it.
    Scene s = scene_of({-100, 3.5001f, 0, 3, 3.5f, 0, -100, 3.4999f, 0});
    Referee ref(s, pixel_ortho(8, 8), 8, 8);
    TriangleAtSample c = ref.classify(0, 3, 4);
    CHECK(c.cls == SampleClass::Out);
    CHECK(c.outside == Approx(0.5).epsilon(1e-6));
    // Inside, 2 px from the tip, the sliver is 3e-6 px wide: ambiguous, never in.
    CHECK(ref.classify(0, 1, 4).cls == SampleClass::Ambiguous);
}

TEST_CASE("compare counts equal, explained and erroneous pixels of hand-made buffers", "[referee]")
{
    Scene s = shared_edge();
    Referee ref(s, axis_camera(), 4, 4);
    HostVisibility a, b;
    a.width = b.width = 4;
    a.height = b.height = 4;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            a.ids.push_back(x <= 2 ? 0 : 1); // the shared edge (column 2) to the left triangle
            b.ids.push_back(x <= 1 ? 0 : 1); // ... and to the right one: explained
        }
    a.ids[0] = 7;                       // (0, 0): not a triangle of the scene
    b.ids[3 * 4 + 3] = 0;               // (3, 3): the left triangle, 1 px outside
    a.ids[1] = b.ids[1] = background_id; // (1, 0): both miss, the same wrong answer

    CompareReport r = ref.compare(a, b); // every pixel judged
    CHECK(r.pixels == 16);
    CHECK(r.judged == 16);
    CHECK(r.equal == 9);
    CHECK(r.explained == 4);
    CHECK(r.errors == 3);
    CHECK(r.equal + r.explained + r.errors == r.pixels);
    CHECK(r.errors_a == 2);
    CHECK(r.errors_b == 2);
    REQUIRE(r.first_errors.size() == 3);
    CHECK(r.first_errors[0].error == AnswerError::InvalidId);
    CHECK(r.first_errors[0].source == 0);
    CHECK_THAT(r.first_errors[0].describe(), Catch::Contains("invalid id") && Catch::Contains("id 7"));
    CHECK(r.first_errors[1].error == AnswerError::Missed);
    CHECK(r.first_errors[1].source == 2);
    CHECK(r.first_errors[2].error == AnswerError::Coverage);
    CHECK(r.first_errors[2].x == 3);
    CHECK(r.first_errors[2].y == 3);
    CHECK(r.first_errors[2].source == 1);

    CompareOptions differing;
    differing.differing_only = true;
    differing.max_reported = 1;
    CompareReport rd = ref.compare(a, b, differing);
    CHECK(rd.judged == 6);
    CHECK(rd.equal == 10); // counted equal without being judged: (1, 0) passes
    CHECK(rd.explained == 4);
    CHECK(rd.errors == 2);
    CHECK(rd.equal + rd.explained + rd.errors == rd.pixels);
    CHECK(rd.errors_a == 1);
    CHECK(rd.errors_b == 1);
    REQUIRE(rd.first_errors.size() == 1); // capped, raster order
    CHECK(rd.first_errors[0].error == AnswerError::InvalidId);

    CompareReport ca = ref.check(a);
    CHECK(ca.pixels == 16);
    CHECK(ca.errors == 2);
    CHECK(ca.equal == 10); // column 2 is background in reference(), ambiguous
    CHECK(ca.explained == 4);

    HostVisibility small = a;
    small.width = 2;
    small.ids.resize(8);
    CHECK_THROWS_AS(ref.compare(a, small), Error);
    CHECK_THROWS_AS(ref.judge(4, 0, 0), Error);
    CHECK(ref.judge(0, 0, 2).error == AnswerError::InvalidId);
}

TEST_CASE("reference() matches an independent ray cast on real meshes and random cameras", "[referee]")
{
    Scene s;
    s.add_mesh(load_mesh(CLVIS_SOURCE_DIR "/scenes/suzanne.obj"));
    s.add_mesh(make_uv_sphere(600));
    Bounds b = s.bounds();
    std::mt19937_64 rng(6);
    std::uniform_real_distribution<double> uni(-1, 1);
    const int w = 48, h = 36;
    // The nearest hit of a ray through raster (x, y) by brute force in double, and the second.
    auto cast = [&](const Camera& cam, double x, double y, double* best, double* second) {
        Ray ray = cam.primary_ray(x, y, w, h);
        *best = *second = 1e300;
        std::uint32_t best_id = background_id;
        for (std::uint32_t id = 0; id < s.triangle_count(); ++id) {
            float v[9];
            s.triangle(id, v);
            double margin = 0, t = ray_hit(ray, v, &margin);
            if (!(t >= cam.near && t <= cam.far) || margin < 0) continue;
            if (t < *best) {
                *second = *best;
                *best = t;
                best_id = id;
            } else {
                *second = std::fmin(*second, t);
            }
        }
        return best_id;
    };
    std::size_t robust = 0, covered = 0;
    for (int k = 0; k < 6; ++k) {
        Vec3 c = b.center();
        double r = length(b.extent()) / 2;
        Vec3 eye = c + Vec3{uni(rng), uni(rng), uni(rng)} * (1.5 * r);
        Camera cam = k % 2 ? Camera::orthographic(eye, c, {0, 1, 0}, 2 * r, 0.01, 10 * r)
                           : Camera::perspective(eye, c, {0, 1, 0}, 60, 0.01, 10 * r);
        Referee ref(s, cam, w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double best = 0, second = 0, b2 = 0, s2 = 0;
                std::uint32_t id = cast(cam, x + 0.5, y + 0.5, &best, &second);
                // Robust: the same answer 2 EPS away along both axes (one of the four moves
                // crosses any edge within EPS), and no second surface within 1e-5 in depth.
                bool same = id == background_id || second > best * (1 + 1e-5);
                const double step = 2 * referee_edge_eps;
                for (auto [dx, dy] : {std::pair{step, 0.0}, {-step, 0.0}, {0.0, step}, {0.0, -step}})
                    same = same && cast(cam, x + 0.5 + dx, y + 0.5 + dy, &b2, &s2) == id;
                if (!same) continue;
                ++robust;
                covered += id != background_id;
                double d = 0;
                INFO("camera " << k << " pixel " << x << "," << y);
                CHECK(ref.reference(x, y, nullptr, &d) == id);
                if (id != background_id) CHECK(d == Approx(best).epsilon(1e-9));
            }
    }
    CHECK(robust > 6 * w * h * 8 / 10);
    CHECK(covered > 6 * w * h / 10);
}

TEST_CASE("screen-filling layers are judged without binning them, ties to the lower id", "[referee]")
{
    // 300 triangles larger than the view at depths 2 .. 3, nearest last, the nearest twice.
    std::vector<float> v;
    for (int k = 0; k < 300; ++k) {
        float z = -3 + float(k) / 300;
        v.insert(v.end(), {-50, -50, z, 50, -50, z, 0, 50, z});
    }
    v.insert(v.end(), v.end() - 9, v.end());
    Scene s = scene_of(v);
    Referee ref(s, axis_camera(), 320, 240);
    HostVisibility vis;
    vis.width = 320;
    vis.height = 240;
    vis.ids.assign(320 * 240, 299);
    vis.ids[5] = 300; // the duplicate of the nearest: acceptable, not the reference
    vis.ids[6] = 298; // a layer 1/300 behind: hidden
    CompareReport r = ref.check(vis);
    CHECK(r.equal == 320 * 240 - 2);
    CHECK(r.explained == 1);
    CHECK(r.errors == 1);
    REQUIRE(r.first_errors.size() == 1);
    CHECK(r.first_errors[0].error == AnswerError::HiddenSurface);
    CHECK(r.first_errors[0].nearest_id == 299);
}

TEST_CASE("the referee judges a 1920x1080 frame of a 70k-triangle mesh in a few seconds", "[referee][slow]")
{
    Scene s;
    s.add_mesh(load_mesh(CLVIS_SOURCE_DIR "/scenes/stanford-bunny.obj"));
    REQUIRE(s.triangle_count() > 60000);
    Camera cam = Camera::framing(s.bounds());
    auto t0 = std::chrono::steady_clock::now();
    Referee ref(s, cam, 1920, 1080);
    HostVisibility v;
    v.width = 1920;
    v.height = 1080;
    v.ids.assign(1920 * 1080, background_id);
    CompareReport r = ref.check(v);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("referee: bunny 1920x1080: set-up and check in %.2f s, %zu pixels covered\n", seconds, r.errors);
    CHECK(r.errors > 100000);       // the bunny covers a good part of the frame: all missed
    CHECK(r.errors == r.errors_a);
    CHECK(seconds < 10);
}

TEST_CASE("triangles near 3e38 and with one vertex at 1e30 are judged by their true planes", "[referee]")
{
    // A backdrop at depth 50 whose vertices are near +-3e38: its plane passes 50 from the eye,
    // 1e-37 of its vertices' size, and is not edge-on. One vertex at 1e30 behind the eye with two
    // ordinary ones: the edge vectors lose the ordinary coordinates in double, the normal must not.
    const float big = 3e38f;
    Scene s = scene_of({-big, -big, -50, big, -big, -50, 0, big, -50, //
                        1e30f, 1e30f, 1e30f, 2, 0, -4, 0, 2, -4});
    Camera cam = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 0.5, 100);
    Referee ref(s, cam, 96, 64);
    for (int y : {0, 31, 63})
        for (int x : {0, 47, 95}) {
            TriangleAtSample t = ref.classify(0, x, y);
            CHECK(t.cls == SampleClass::In);
            CHECK(t.depth == Approx(50.0).epsilon(1e-12));
        }
    // The second triangle's visible part runs from its ordinary edge (screen x + y = 0.5) towards
    // the near-plane cut far up and to the right; pixel (51, 0) lies inside it at screen
    // (0.051, 0.459), pixel (40, 40) below its ordinary edge.
    CHECK(ref.classify(1, 51, 0).cls == SampleClass::In);
    CHECK(ref.classify(1, 40, 40).cls == SampleClass::Out);
}

TEST_CASE("a looser tolerance widens the ambiguous band; a tighter one is refused", "[referee]")
{
    Scene s = shared_edge();
    Referee strict(s, axis_camera(), 4, 4);
    // Pixel column 1 lies 1 px from the shared edge, which runs through column 2's centres.
    CHECK(strict.classify(1, 1, 1).cls == SampleClass::Out);
    RefereeTolerance loose;
    loose.edge_eps = 1.25;
    Referee wide(s, axis_camera(), 4, 4, {}, loose);
    CHECK(wide.classify(1, 1, 1).cls == SampleClass::Ambiguous);
    CHECK(wide.judge(1, 1, 1).acceptable());
    for (RefereeTolerance bad : {RefereeTolerance{1e-4, 1e-6}, RefereeTolerance{1e-3, 1e-7},
                                 RefereeTolerance{std::nan(""), 1e-6}, RefereeTolerance{1e-3, INFINITY}})
        CHECK_THROWS_AS(Referee(s, axis_camera(), 4, 4, {}, bad), Error);
}
