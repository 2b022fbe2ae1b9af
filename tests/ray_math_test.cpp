// The ray tests of kernels/shared/ray.h on the host, where every case can be set up exactly: the
// watertight triangle test on shared edges and vertices, its near/far and degenerate cases, and
// the conservative slab test against flat boxes and axis-parallel rays. The kernels run these same
// operations (ray_test.cpp checks them on the device).
#include "catch.hpp"

#include "shared/ray.h"

#include <cmath>
#include <random>

namespace {

clvis_vec3 v3(float x, float y, float z) { return {x, y, z}; }

bool hits(clvis_vec3 o, clvis_vec3 d, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c, float near_t = 0.0f,
          float far_t = CLVIS_INFINITY, float* t_out = nullptr, int cull = CLVIS_CULL_NONE)
{
    float t = 0;
    bool h = clvis_intersect_triangle(clvis_make_shear(o, d), a, b, c, near_t, far_t, cull, &t) != 0;
    if (t_out) *t_out = t;
    return h;
}

bool hits_box(clvis_vec3 o, clvis_vec3 d, clvis_vec3 lo, clvis_vec3 hi, float near_t = 0.0f,
              float far_t = CLVIS_INFINITY)
{
    float entry = 0;
    return clvis_ray_hits_box(clvis_make_box_ray(o, d), lo, hi, near_t, far_t, &entry) != 0;
}

} // namespace

TEST_CASE("culling keeps the faces whose normal points against the ray, any ray axis", "[ray]")
{
    // A triangle around the point p, with normal n = cross(b - a, c - a) along each axis sign,
    // hit from the side n points to (front) and from behind (back).
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-0.3f, 0.3f);
    for (int axis = 0; axis < 3; ++axis) {
        for (float sign : {1.0f, -1.0f}) {
            float n[3] = {0, 0, 0};
            n[axis] = sign;
            clvis_vec3 e1 = v3(n[1] + n[2], n[2] + n[0], n[0] + n[1]); // perpendicular to n
            clvis_vec3 nn = v3(n[0], n[1], n[2]);
            clvis_vec3 e2 = v3(nn.y * e1.z - nn.z * e1.y, nn.z * e1.x - nn.x * e1.z, nn.x * e1.y - nn.y * e1.x);
            // (a, b, c) = (-e1 - e2, e1 - e2, e2): cross(b - a, c - a) = cross(2 e1, e1 + 2 e2) ~ +n
            clvis_vec3 a = v3(-e1.x - e2.x, -e1.y - e2.y, -e1.z - e2.z);
            clvis_vec3 b = v3(e1.x - e2.x, e1.y - e2.y, e1.z - e2.z);
            for (int trial = 0; trial < 50; ++trial) {
                clvis_vec3 o = v3(4 * nn.x + u(rng), 4 * nn.y + u(rng), 4 * nn.z + u(rng)); // in front
                clvis_vec3 d = v3(u(rng) / 3 - o.x, u(rng) / 3 - o.y, u(rng) / 3 - o.z); // to near the centre
                INFO("axis " << axis << " sign " << sign << " trial " << trial);
                CHECK(hits(o, d, a, b, e2, 0.0f, CLVIS_INFINITY, nullptr, CLVIS_CULL_BACK));
                CHECK(!hits(o, d, a, b, e2, 0.0f, CLVIS_INFINITY, nullptr, CLVIS_CULL_FRONT));
                CHECK(hits(o, d, a, b, e2, 0.0f, CLVIS_INFINITY, nullptr, CLVIS_CULL_NONE));
                clvis_vec3 ob = v3(-o.x, -o.y, -o.z), db = v3(-d.x, -d.y, -d.z); // from behind
                CHECK(!hits(ob, db, a, b, e2, 0.0f, CLVIS_INFINITY, nullptr, CLVIS_CULL_BACK));
                CHECK(hits(ob, db, a, b, e2, 0.0f, CLVIS_INFINITY, nullptr, CLVIS_CULL_FRONT));
                // the same triangle wound the other way swaps front and back
                CHECK(!hits(o, d, a, e2, b, 0.0f, CLVIS_INFINITY, nullptr, CLVIS_CULL_BACK));
            }
        }
    }
}

TEST_CASE("rays through shared edges and vertices of a fan hit at least one triangle", "[ray]")
{
    // A fan of 7 triangles around a centre, in a tilted plane; rays aimed at the centre, at points
    // along each shared edge, from many origins and in both vertex orders.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const int spokes = 7;
    clvis_vec3 centre = v3(0.3f, -0.2f, -4.0f);
    std::vector<clvis_vec3> rim;
    for (int k = 0; k < spokes; ++k) {
        double a = 6.283185307179586 * k / spokes;
        rim.push_back(v3(centre.x + float(std::cos(a)), centre.y + float(std::sin(a)), centre.z + 0.3f * float(std::cos(a))));
    }
    int misses = 0, tries = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        clvis_vec3 o = v3(u(rng) * 3, u(rng) * 3, 2.0f + u(rng));
        // the target: the centre, or a point on a spoke at a float parameter
        int spoke = trial % (spokes + 1);
        clvis_vec3 p = centre;
        if (spoke < spokes) {
            float s = (trial % 13 + 1) / 14.0f;
            p = v3(centre.x + s * (rim[spoke].x - centre.x), centre.y + s * (rim[spoke].y - centre.y),
                   centre.z + s * (rim[spoke].z - centre.z));
        }
        clvis_vec3 d = v3(p.x - o.x, p.y - o.y, p.z - o.z);
        bool any = false;
        for (int k = 0; k < spokes; ++k) {
            clvis_vec3 a = rim[k], b = rim[(k + 1) % spokes];
            any |= trial % 2 ? hits(o, d, centre, a, b) : hits(o, d, b, a, centre);
        }
        misses += !any;
        ++tries;
    }
    CHECK(tries == 2000);
    CHECK(misses == 0);
}

TEST_CASE("a hit is accepted exactly at near and at far and not beyond", "[ray]")
{
    clvis_vec3 o = v3(0, 0, 0), d = v3(0.125f, -0.25f, -1.0f);
    clvis_vec3 a = v3(-5, -5, -2), b = v3(5, -5, -2), c = v3(0, 5, -2);
    float t = 0;
    REQUIRE(hits(o, d, a, b, c, 0.5f, 10.0f, &t));
    CHECK(t == 2.0f); // t is the view depth: the direction's forward component is 1
    CHECK(hits(o, d, a, b, c, 2.0f, 10.0f));
    CHECK(hits(o, d, a, b, c, 0.5f, 2.0f));
    CHECK_FALSE(hits(o, d, a, b, c, std::nextafter(2.0f, 3.0f), 10.0f));
    CHECK_FALSE(hits(o, d, a, b, c, 0.5f, std::nextafter(2.0f, 1.0f)));
}

TEST_CASE("triangles behind the ray and degenerate triangles are never hit", "[ray]")
{
    clvis_vec3 o = v3(0, 0, 0), d = v3(0, 0, -1);
    CHECK_FALSE(hits(o, d, v3(-1, -1, 2), v3(1, -1, 2), v3(0, 1, 2), 0.1f));
    // zero area: a repeated vertex, three collinear vertices through the ray, all in one point
    CHECK_FALSE(hits(o, d, v3(-1, -1, -2), v3(-1, -1, -2), v3(1, 1, -2), 0.1f));
    CHECK_FALSE(hits(o, d, v3(-1, -1, -2), v3(0, 0, -2), v3(1, 1, -2), 0.1f));
    CHECK_FALSE(hits(o, d, v3(0, 0, -2), v3(0, 0, -2), v3(0, 0, -2), 0.1f));
    // a triangle seen edge-on, containing the ray
    CHECK_FALSE(hits(o, d, v3(0, -1, -1), v3(0, 1, -1), v3(0, 0, -5), 0.1f));
}

TEST_CASE("both sides of a triangle are hit at the same distance", "[ray]")
{
    clvis_vec3 a = v3(-1, -1, 0), b = v3(1, -1, 0.5f), c = v3(0, 1, -0.25f);
    float t1 = 0, t2 = 0;
    REQUIRE(hits(v3(0.1f, 0, 3), v3(0, 0, -1), a, b, c, 0, 100, &t1));
    REQUIRE(hits(v3(0.1f, 0, 3), v3(0, 0, -1), a, c, b, 0, 100, &t2));
    CHECK(t1 == t2);
    REQUIRE(hits(v3(0.1f, 0, -3), v3(0, 0, 1), a, b, c, 0, 100, &t1));
    CHECK(t1 > 2.0f);
}

TEST_CASE("the slab test never culls a box a ray meets, flat boxes and parallel rays too", "[ray]")
{
    // Rays parallel to axes (zero components, +0 and -0) against flat and thick boxes, with the
    // origin inside, outside and exactly in a face plane.
    clvis_vec3 lo = v3(-1, -1, -3), hi = v3(1, 1, -3); // flat in z
    CHECK(hits_box(v3(0, 0, 0), v3(0, 0, -1), lo, hi));
    CHECK(hits_box(v3(0, 0, 0), v3(-0.0f, 0.0f, -1), lo, hi));
    CHECK(hits_box(v3(1, 1, 0), v3(0, 0, -1), lo, hi));        // along the box's edge
    CHECK(hits_box(v3(-1, 1, 0), v3(-0.0f, -0.0f, -1), lo, hi));
    CHECK_FALSE(hits_box(v3(1.5f, 0, 0), v3(0, 0, -1), lo, hi));
    CHECK_FALSE(hits_box(v3(0, 0, 0), v3(0, 0, 1), lo, hi));   // behind
    CHECK_FALSE(hits_box(v3(0, 0, 0), v3(0, 0, -1), lo, hi, 0.0f, 2.5f)); // beyond far
    CHECK(hits_box(v3(0, 0, 0), v3(0, 0, -1), lo, hi, 0.0f, 3.0f));
    CHECK(hits_box(v3(0, 0, 0), v3(0, 0, -1), lo, hi, 3.0f, 10.0f));
    // a ray inside the plane of a flat box, parallel to it: it lies in the box
    CHECK(hits_box(v3(-5, 0, -3), v3(1, 0, 0), lo, hi));
    CHECK(hits_box(v3(-5, 1, -3), v3(1, 0, -0.0f), lo, hi));
    CHECK_FALSE(hits_box(v3(-5, 0, -2.5f), v3(1, 0, 0), lo, hi));
    // a box flat in two axes (a segment) and a point box
    CHECK(hits_box(v3(0, 0, 0), v3(0, 0, -1), v3(0, 0, -3), v3(0, 0, -2)));
    CHECK(hits_box(v3(0, 0, 0), v3(0, 0, -1), v3(0, 0, -3), v3(0, 0, -3)));

    // Random rays that hit a random triangle: its box is never culled.
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int culled = 0;
    for (int i = 0; i < 100000; ++i) {
        float scale = std::ldexp(1.0f, int(rng() % 40) - 20);
        clvis_vec3 a = v3(u(rng) * scale, u(rng) * scale, u(rng) * scale);
        clvis_vec3 b = v3(a.x + u(rng) * scale, a.y + u(rng) * scale, i % 3 ? a.z : a.z + u(rng) * scale);
        clvis_vec3 c = v3(a.x + u(rng) * scale, i % 5 ? a.y + u(rng) * scale : a.y, a.z + u(rng) * scale);
        clvis_vec3 o = v3(u(rng) * 4 * scale, u(rng) * 4 * scale, u(rng) * 4 * scale);
        // aim at a vertex, an edge point or an inner point; zero some components
        float wa = float(rng() % 3) / 2, wb = (1 - wa) * float(rng() % 3) / 2, wc = 1 - wa - wb;
        clvis_vec3 p = v3(wa * a.x + wb * b.x + wc * c.x, wa * a.y + wb * b.y + wc * c.y, wa * a.z + wb * b.z + wc * c.z);
        clvis_vec3 d = v3(p.x - o.x, p.y - o.y, p.z - o.z);
        if (i % 7 == 0) d.x = 0, o.x = p.x;
        float t = 0;
        if (!hits(o, d, a, b, c, 0.0f, CLVIS_INFINITY, &t)) continue;
        clvis_vec3 lo2 = v3(std::fmin(a.x, std::fmin(b.x, c.x)), std::fmin(a.y, std::fmin(b.y, c.y)), std::fmin(a.z, std::fmin(b.z, c.z)));
        clvis_vec3 hi2 = v3(std::fmax(a.x, std::fmax(b.x, c.x)), std::fmax(a.y, std::fmax(b.y, c.y)), std::fmax(a.z, std::fmax(b.z, c.z)));
        culled += !hits_box(o, d, lo2, hi2, 0.0f, t);
    }
    CHECK(culled == 0);
}
