// The float test's certain misses (kernels/shared/ray.h, clvis_float_misses): a triangle that the
// float test cannot be trusted with (clvis_ray_trusted) skips the wide retest only where both would
// miss. Rays start on and near triangles (the ray's own triangle and its neighbours fail the trust
// check, as AO and shadow rays do), at several scales and far from the coordinates' origin; every
// certain miss is a miss of the wide retest, closed and half-open, and the three triangle tests
// answer as clvis_project_triangle (always the wide retest there) does, hit for hit, t bit for bit.
#include "catch.hpp"

#include "shared/ray.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

namespace {

clvis_vec3 v3(float x, float y, float z) { return {x, y, z}; }

std::uint32_t bits(float f)
{
    std::uint32_t b;
    std::memcpy(&b, &f, 4);
    return b;
}

/// The closed test with clvis_project_triangle (the wide retest wherever the float test is not
/// trusted), as clvis_intersect_triangle computed before certain misses were taken.
bool closed_reference(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c, float near_t, float far_t, float* t)
{
    clvis_tri_2d p;
    clvis_project_triangle(s, a, b, c, &p);
    bool inside = (p.u >= 0.0f && p.v >= 0.0f && p.w >= 0.0f) || (p.u <= 0.0f && p.v <= 0.0f && p.w <= 0.0f);
    float det = p.u + p.v + p.w;
    *t = clvis_triangle_t(s, p, det);
    return inside && det != 0.0f && *t >= near_t && *t <= far_t;
}

/// The half-open test with clvis_project_triangle.
bool half_open_reference(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c, float near_t, float far_t,
                         float* t)
{
    clvis_tri_2d p;
    clvis_project_triangle(s, a, b, c, &p);
    int su = clvis_edge_side(p.u, p.bx, p.by, p.cx, p.cy);
    int sv = clvis_edge_side(p.v, p.cx, p.cy, p.ax, p.ay);
    int sw = clvis_edge_side(p.w, p.ax, p.ay, p.bx, p.by);
    float det = p.u + p.v + p.w;
    *t = clvis_triangle_t(s, p, det);
    return su != 0 && su == sv && su == sw && det != 0.0f && *t >= near_t && *t <= far_t;
}

struct Tally {
    long untrusted = 0, certain = 0, cases = 0;
};

/// One ray against one triangle: the certain miss is a miss of the wide retest, and the tests
/// answer as the references do.
void check(clvis_vec3 o, clvis_vec3 d, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c, float near_t, float far_t, Tally& n)
{
    clvis_ray_shear s = clvis_make_shear(o, d);
    ++n.cases;
    clvis_tri_2d f;
    clvis_project_triangle_scaled(s, a, b, c, 1.0f, &f);
    if (f.wide) ++n.untrusted;
    if (f.wide && clvis_float_misses(s, a, b, c, &f, near_t)) {
        ++n.certain;
        clvis_tri_2d w = clvis_project_triangle_wide(s, a, b, c);
        bool inside = (w.u >= 0.0f && w.v >= 0.0f && w.w >= 0.0f) || (w.u <= 0.0f && w.v <= 0.0f && w.w <= 0.0f);
        float det = w.u + w.v + w.w;
        bool in_range = w.t >= near_t; // any far: the miss must not depend on it
        INFO("wide u " << w.u << " v " << w.v << " w " << w.w << " t " << w.t << " near " << near_t);
        REQUIRE_FALSE((inside && det != 0.0f && in_range));
        int su = clvis_edge_side(w.u, w.bx, w.by, w.cx, w.cy), sv = clvis_edge_side(w.v, w.cx, w.cy, w.ax, w.ay);
        int sw = clvis_edge_side(w.w, w.ax, w.ay, w.bx, w.by);
        REQUIRE_FALSE((su != 0 && su == sv && su == sw && det != 0.0f && in_range));
    }
    float t0 = 0, t1 = 0;
    bool want = closed_reference(s, a, b, c, near_t, far_t, &t0);
    REQUIRE((clvis_intersect_triangle(s, a, b, c, near_t, far_t, CLVIS_CULL_NONE, &t1) != 0) == want);
    if (want) REQUIRE(bits(t0) == bits(t1));
    clvis_tri_2d p;
    float det = 0;
    t1 = 0;
    REQUIRE((clvis_intersect_triangle_plane(s, a, b, c, near_t, far_t, &t1, &p, &det) != 0) == want);
    if (want) REQUIRE(bits(t0) == bits(t1));
    want = half_open_reference(s, a, b, c, near_t, far_t, &t0);
    REQUIRE((clvis_intersect_triangle_half_open(s, a, b, c, near_t, far_t, &t1) != 0) == want);
    if (want) REQUIRE(bits(t0) == bits(t1));
}

clvis_vec3 add(clvis_vec3 p, clvis_vec3 q) { return v3(p.x + q.x, p.y + q.y, p.z + q.z); }
clvis_vec3 scale(clvis_vec3 p, float k) { return v3(p.x * k, p.y * k, p.z * k); }

} // namespace

TEST_CASE("a certain miss of the float test is a miss of the wide retest; answers unchanged", "[ray]")
{
    std::mt19937 rng(37);
    std::uniform_real_distribution<float> u(0, 1), sgn(-1, 1);
    Tally n;
    const float centres[] = {0.0f, 1.0f, 1000.0f, -3.0e5f};
    const float sizes[] = {1e-3f, 0.1f, 10.0f};
    const float offsets[] = {0.0f, 1e-7f, 1e-5f, 1e-4f, 1e-2f, -1e-5f};
    for (int i = 0; i < 6000; ++i) {
        float centre = centres[i % 4], size = sizes[(i / 4) % 3];
        clvis_vec3 base = v3(centre + size * sgn(rng), centre + size * sgn(rng), centre + size * sgn(rng));
        // a fan of four triangles around the base's vertex q (neighbours share edges)
        clvis_vec3 q = base, r[4];
        for (clvis_vec3& x : r) x = add(base, v3(size * sgn(rng), size * sgn(rng), size * 0.2f * sgn(rng)));
        clvis_vec3 tris[4][3] = {{q, r[0], r[1]}, {q, r[1], r[2]}, {q, r[2], r[3]}, {q, r[3], r[0]}};
        // the ray starts on the first triangle (inside, on an edge, at a vertex), moved along its normal
        float w0 = u(rng), w1 = u(rng);
        if (w0 + w1 > 1) w0 = 1 - w0, w1 = 1 - w1;
        int where = i % 5;
        if (where == 3) w1 = 0;             // on edge q r0
        if (where == 4) w0 = w1 = 0;        // at the shared vertex q
        clvis_vec3 e1 = add(r[0], scale(q, -1)), e2 = add(r[1], scale(q, -1));
        clvis_vec3 nrm = v3(e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x);
        float len = std::sqrt(nrm.x * nrm.x + nrm.y * nrm.y + nrm.z * nrm.z);
        if (!(len > 0)) continue;
        nrm = scale(nrm, 1 / len);
        clvis_vec3 o = add(add(q, scale(e1, w0)), scale(e2, w1));
        o = add(o, scale(nrm, offsets[(i / 12) % 6] * size));
        // directions: the normal's hemisphere (AO), the other one, and grazing ones
        clvis_vec3 d = v3(sgn(rng), sgn(rng), sgn(rng));
        float dn = d.x * nrm.x + d.y * nrm.y + d.z * nrm.z;
        int kind = (i / 72) % 3;
        if (kind == 0 && dn < 0) d = add(d, scale(nrm, -2 * dn));
        if (kind == 2) d = add(d, scale(nrm, -dn * (1 - 1e-4f)));
        d = scale(d, size * 4);
        const float nears[] = {0.0f, -0.0f, 1e-4f, -1e-3f};
        float near_t = nears[(i / 216) % 4], far_t = (i & 1) ? CLVIS_INFINITY : 1.0f;
        for (auto& t : tris) check(o, d, t[0], t[1], t[2], near_t, far_t, n);
    }
    INFO("cases " << n.cases << " untrusted " << n.untrusted << " certain misses " << n.certain);
    CHECK(n.untrusted > n.cases / 4);
    CHECK(n.certain > n.untrusted / 3); // the shortcut is taken (AO-like rays: most of the untrusted)
}

TEST_CASE("certain misses are not claimed outside the bounds' range", "[ray]")
{
    // vertices minus the origin beyond 2^24, below 2^-24, and a direction whose |1 / d[kz]| is out
    // of range: no certain miss, the wide retest decides (and the answers stay the reference's)
    Tally n;
    clvis_vec3 a = v3(-1, -1, 0), b = v3(1, -1, 0), c = v3(0, 1, 0);
    for (float k : {1e-9f, 1e9f}) {
        clvis_vec3 o = v3(0.3f * k, 0.2f * k, 1e-9f * k), d = v3(0.1f, 0.05f, 1.0f);
        clvis_ray_shear s = clvis_make_shear(o, d);
        clvis_tri_2d f;
        clvis_project_triangle_scaled(s, scale(a, k), scale(b, k), scale(c, k), 1.0f, &f);
        REQUIRE(clvis_float_misses(s, scale(a, k), scale(b, k), scale(c, k), &f, 0.0f) == 0);
        check(o, d, scale(a, k), scale(b, k), scale(c, k), 0.0f, CLVIS_INFINITY, n);
    }
    clvis_vec3 o = v3(5, 0, 1e-6f), d = v3(0, 0, 1e-30f);
    clvis_ray_shear s = clvis_make_shear(o, d);
    clvis_tri_2d f;
    clvis_project_triangle_scaled(s, a, b, c, 1.0f, &f);
    REQUIRE(clvis_float_misses(s, a, b, c, &f, 0.0f) == 0);
    check(o, d, a, b, c, 0.0f, CLVIS_INFINITY, n);
}
