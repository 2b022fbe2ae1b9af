/* Ray casting shared by the ray kernels (ray_trace.cl, ray_brute.cl, ray_query*.cl) and the host
   tests: the watertight ray/triangle test of Woop, Benthin and Wald (JCGT 2013), its half-open
   form for hit counts, and the conservative slab test of Ize ("Robust BVH Ray Traversal", JCGT
   2013), so that float rounding never culls a box that a ray touches. ray_trace.cl runs the
   same operations on 16 rays at once (OpenCL vectors); these scalar forms
   define the bits and are what host tests check. */
#ifndef CLVIS_SHARED_RAY_H
#define CLVIS_SHARED_RAY_H

#include "shared/types.h"
#include "shared/visibility.h"

#ifdef __OPENCL_C_VERSION__
#define CLVIS_INFINITY INFINITY
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define CLVIS_HAVE_DOUBLE 1
#endif
#else
#include <limits>
#define CLVIS_INFINITY (std::numeric_limits<float>::infinity())
#define CLVIS_HAVE_DOUBLE 1
#endif
#include "shared/exact.h"

/* The exact a b - c d of the edge functions' fallback (shared/exact.h): in double where the
   device has it, float-only (integers) without cl_khr_fp64 or where the host builds the kernels
   with CLVIS_EXACT_FLOAT (the environment variable CLVIS_EXACT_FLOAT=1); the same bits either way. */
static inline float clvis_exact_dp(float a, float b, float c, float d)
{
#if defined(CLVIS_HAVE_DOUBLE) && !defined(CLVIS_EXACT_FLOAT)
    return clvis_exact_dp_double(a, b, c, d);
#else
    return clvis_exact_dp_int(a, b, c, d);
#endif
}

/* Ize's factor 1 + 2 gamma(3), gamma(n) = n u / (1 - n u), u = 2^-24: the far distance of a slab
   test scaled by it bounds the rounding of (plane - origin) * (1 / direction). */
#define CLVIS_IZE_SCALE (1.0f + 2.0f * (3.0f * 5.9604645e-8f) / (1.0f - 3.0f * 5.9604645e-8f))

static inline float clvis_component(clvis_vec3 v, clvis_i32 k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }
static inline float clvis_absf(float x) { return x < 0.0f ? -x : x; }

/* A ray prepared for the watertight test: the axis kz where the direction is largest, the
   other two (kx, ky) swapped where that keeps the winding, and the shear that maps the
   direction to (0, 0, 1). */
typedef struct clvis_ray_shear {
    clvis_vec3 origin;          /* world units */
    float sx, sy, sz;           /* d[kx] / d[kz], d[ky] / d[kz], 1 / d[kz] */
    clvis_i32 kx, ky, kz;       /* axis permutation, 0..2 */
} clvis_ray_shear;

static inline clvis_ray_shear clvis_make_shear(clvis_vec3 origin, clvis_vec3 dir)
{
    clvis_ray_shear s;
    float ax = clvis_absf(dir.x), ay = clvis_absf(dir.y), az = clvis_absf(dir.z);
    s.kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    s.kx = s.kz == 2 ? 0 : s.kz + 1;
    s.ky = s.kx == 2 ? 0 : s.kx + 1;
    float dz = clvis_component(dir, s.kz);
    if (dz < 0.0f) {
        clvis_i32 k = s.kx;
        s.kx = s.ky;
        s.ky = k;
    }
    s.sx = clvis_component(dir, s.kx) / dz;
    s.sy = clvis_component(dir, s.ky) / dz;
    s.sz = 1.0f / dz;
    s.origin = origin;
    return s;
}

/* Whether a float is finite, from its bits (the same on every compiler and device). */
static inline int clvis_finite(float v) { return (clvis_float_bits(v) & 0x7F800000u) != 0x7F800000u; }

/* The power of two 2^(30 - e) that brings the largest magnitude m (exponent e > 30) down to
   [2^30, 2^31): then tz, a product of three sheared coordinates, stays below 2^100. Multiplying
   by it is exact (barring underflow below 2^-156 m), so the edge functions' signs, and with them
   watertightness, do not change. 1 when m is below 2^31 (nothing can overflow then). */
static inline float clvis_ray_scale(float m)
{
    clvis_i32 e = (clvis_i32)((clvis_float_bits(m) >> 23) & 0xFFu) - 127;
    return e > 30 ? clvis_bits_float((clvis_u32)(157 - e) << 23) : 1.0f;
}

/* p - origin, both scaled by k (a power of two: exact; k = 1 gives p - origin's own bits). */
static inline clvis_vec3 clvis_ray_translate(clvis_vec3 p, clvis_vec3 origin, float k)
{
    clvis_vec3 r;
    r.x = p.x * k - origin.x * k;
    r.y = p.y * k - origin.y * k;
    r.z = p.z * k - origin.z * k;
    return r;
}

static inline float clvis_max_abs3(clvis_vec3 p)
{
    float m = clvis_absf(p.x) > clvis_absf(p.y) ? clvis_absf(p.x) : clvis_absf(p.y);
    return m > clvis_absf(p.z) ? m : clvis_absf(p.z);
}

/* How far the float test's rounding may move what it sees, relative to the distance: every
   coordinate of a vertex minus the origin rounds by up to 2^-24 of it, and the shear adds the
   same again, so an edge near which the ray passes at distance d moves by about 2^-22 M / d
   radians as seen from the origin, M the largest magnitude of the three vertices' coordinates
   minus the origin's; the hit distance, a sum of products of that size, moves as much relative
   to it. Where d is at least M / CLVIS_RAY_RANGE (2^-17 radians at most) the float test is as
   good as the 2^-24 of the coordinates themselves; nearer (vertices far beyond the hit: huge
   coordinates beside an ordinary mesh, a triangle's plane through the eye's neighbourhood) its
   answers can be anything, and clvis_project_triangle_wide decides. d is bounded below by the
   distance from the origin to the triangle's bounding box along the axis that separates them
   best (0 where the origin lies inside the box's slab on every axis). */
#define CLVIS_RAY_RANGE 32.0f

static inline float clvis_min3f(float x, float y, float z) { float m = x < y ? x : y; return m < z ? m : z; }
static inline float clvis_max3f(float x, float y, float z) { float m = x > y ? x : y; return m > z ? m : z; }

/* Whether the float test can be trusted on a triangle whose vertices minus the ray's origin are
   A, B and C: M <= CLVIS_RAY_RANGE d as above (false where a coordinate is not finite or NaN).
   clvis_ray_extent returns M (the largest magnitude of A's, B's and C's coordinates, where they
   are finite) and sets *gap to d. */
static inline float clvis_ray_extent(clvis_vec3 A, clvis_vec3 B, clvis_vec3 C, float* gap)
{
    float lx = clvis_min3f(A.x, B.x, C.x), hx = clvis_max3f(A.x, B.x, C.x);
    float ly = clvis_min3f(A.y, B.y, C.y), hy = clvis_max3f(A.y, B.y, C.y);
    float lz = clvis_min3f(A.z, B.z, C.z), hz = clvis_max3f(A.z, B.z, C.z);
    *gap = clvis_max3f(lx > -hx ? lx : -hx, ly > -hy ? ly : -hy, lz > -hz ? lz : -hz);
    return clvis_max3f(-lx > hx ? -lx : hx, -ly > hy ? -ly : hy, -lz > hz ? -lz : hz);
}

static inline int clvis_ray_trusted(clvis_vec3 A, clvis_vec3 B, clvis_vec3 C)
{
    float gap, m = clvis_ray_extent(A, B, C, &gap);
    return m <= CLVIS_RAY_RANGE * gap;
}

/* Triangle (a, b, c) in the sheared frame of a ray, which sits at the 2D origin: the vertices'
   2D positions, their depths along kz, and the edge functions u (edge b->c), v (c->a), w (a->b),
   which are the barycentric weights of a, b and c times det = u + v + w. Each edge is evaluated
   with the same operations in both triangles that share it (only the sign flips), so no ray
   passes between them. Coordinates may be scaled by a power of two (clvis_project_triangle_scaled):
   `unscale` takes a distance back to world units. Where the float test cannot be trusted
   (clvis_project_triangle), `wide` is set and `t` holds the plane's ray parameter. */
typedef struct clvis_tri_2d {
    float ax, ay, bx, by, cx, cy;   /* sheared 2D positions, world units times 1 / unscale */
    float akz, bkz, ckz;            /* vertex minus origin along the axis kz */
    float u, v, w;                  /* edge functions of b->c, c->a, a->b */
    float unscale;                  /* 1 / the scale applied to every coordinate */
    float t;                        /* wide: the ray parameter of the plane (else unused) */
    float m;                        /* scale 1: clvis_ray_extent's M of the vertices minus the origin */
    clvis_i32 wide;                 /* computed by clvis_project_triangle_wide */
} clvis_tri_2d;

/* The three edge functions of clvis_tri_2d exactly rounded (the fallback where one rounded to 0). */
static inline void clvis_exact_edges(float* u, float* v, float* w, float ax, float ay, float bx, float by, float cx,
                                     float cy)
{
    *u = clvis_exact_dp(cx, by, cy, bx);
    *v = clvis_exact_dp(ax, cy, ay, cx);
    *w = clvis_exact_dp(bx, ay, by, ax);
}

static inline CLVIS_ALWAYS_INLINE void clvis_project_triangle_scaled(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b,
                                                                     clvis_vec3 c, float k, clvis_tri_2d* out)
{
    clvis_tri_2d p;
    clvis_vec3 A = clvis_ray_translate(a, s.origin, k), B = clvis_ray_translate(b, s.origin, k);
    clvis_vec3 C = clvis_ray_translate(c, s.origin, k);
    p.akz = clvis_component(A, s.kz); p.bkz = clvis_component(B, s.kz); p.ckz = clvis_component(C, s.kz);
    p.ax = clvis_component(A, s.kx) - s.sx * p.akz;
    p.ay = clvis_component(A, s.ky) - s.sy * p.akz;
    p.bx = clvis_component(B, s.kx) - s.sx * p.bkz;
    p.by = clvis_component(B, s.ky) - s.sy * p.bkz;
    p.cx = clvis_component(C, s.kx) - s.sx * p.ckz;
    p.cy = clvis_component(C, s.ky) - s.sy * p.ckz;
    p.u = p.cx * p.by - p.cy * p.bx;
    p.v = p.ax * p.cy - p.ay * p.cx;
    p.w = p.bx * p.ay - p.by * p.ax;
    /* An edge function that rounds to zero may have cancelled a non-zero value (a ray in the
       plane of a triangle seen edge-on): recompute all three exactly rounded (Woop et al.,
       section 3, do it in double; clvis_exact_dp gives the same bits with or without it). A
       float difference of rounded products never has the wrong sign, only a false zero, so every
       edge function now has the sign of its exact value. */
    if (p.u == 0.0f || p.v == 0.0f || p.w == 0.0f)
        clvis_exact_edges(&p.u, &p.v, &p.w, p.ax, p.ay, p.bx, p.by, p.cx, p.cy);
    p.unscale = 1.0f / k;
    p.t = 0.0f;
    p.wide = 0;
    p.m = 0.0f;
    /* Whether the float test can be trusted (clvis_ray_trusted) on the translated vertices */
    if (k == 1.0f) {
        float gap;
        p.m = clvis_ray_extent(A, B, C, &gap);
        if (!(p.m <= CLVIS_RAY_RANGE * gap)) p.wide = 1;
    }
    *out = p;
}

/* The hit distance times det, in the scaled units of p. */
static inline CLVIS_ALWAYS_INLINE float clvis_triangle_tz(clvis_ray_shear s, clvis_tri_2d p)
{
    return p.u * (s.sz * p.akz) + p.v * (s.sz * p.bkz) + p.w * (s.sz * p.ckz);
}

/* the wide retest (clvis_project_triangle_wide), in a file of its own */
#include "shared/ray_wide.h"

/* The triangle in the ray's frame. Where the float test cannot be trusted (clvis_ray_trusted, or
   det or tz not finite: huge finite coordinates overflow), it is computed again in wider
   arithmetic (clvis_project_triangle_wide). Always inlined into the tests below (and they into
   their callers where hot): out of line, the ray, the vertices and the result went through
   private memory per triangle. The result goes out by pointer, not returned: a returned struct
   is a noalias (sret) argument, and inlining one emits llvm.experimental.noalias.scope.decl,
   which Oclgrind 21.10's interpreter cannot run. */
/* Whether det and tz of a triangle projected with scale 1 are finite: tz is where det is and M (p->m)
   and |sz| are at most 2^24 (|u|, |v|, |w| <= 8 M^2, |sz akz| <= |sz| M: |tz| < 2^101), so the
   float test's triangles compute tz only once they are known to be inside. */
static inline CLVIS_ALWAYS_INLINE int clvis_float_finite(clvis_ray_shear s, const clvis_tri_2d* p)
{
    if (!clvis_finite(p->u + p->v + p->w)) return 0;
    return (p->m <= 0x1p24f && clvis_absf(s.sz) <= 0x1p24f) || clvis_finite(clvis_triangle_tz(s, *p));
}

static inline CLVIS_ALWAYS_INLINE void clvis_project_triangle(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b,
                                                              clvis_vec3 c, clvis_tri_2d* p)
{
    clvis_project_triangle_scaled(s, a, b, c, 1.0f, p);
    if (!p->wide && clvis_float_finite(s, p)) return;
    *p = clvis_project_triangle_wide_from(s, a, b, c, *p);
}

/* Whether a triangle that the float test cannot be trusted with is missed for certain, so that
   the wide retest, which would say so too, need not run (a miss either way: the same answer; on
   AO rays the triangle a ray starts on and its neighbours fail the trust check, and most of them
   are missed this way). p is the triangle projected with scale 1. Forward error bounds of the
   float operations, with M the largest magnitude of the vertices minus the origin (p->m; each
   coordinate rounded once, |sx|, |sy| <= 1: a sheared coordinate is off by at most 5 u M,
   u = 2^-24): each edge function lies within e = 256 u M^2 of its exact value (at most 81 u M^2,
   the float form's and clvis_exact_edges' alike), det within 4 e + 4 u S and tz within
   |sz| M (4 e + 8 u S), S = |u| + |v| + |w|. A value more than twice its bound from 0 has its
   exact value's sign and at least its bound's magnitude: over 2^30 times the double retest's own
   error on the same quantity, over 5 times a float retest's (with scale 1, required there), so
   the retest sees that sign too. Certain misses: two edge functions of opposite signs (the ray
   passes outside: the closed and the half-open test miss), or tz and det of opposite signs with
   near_t >= 0 (the plane lies behind the origin: the retest's t is negative, at least 2^-67 in
   magnitude). Only where M and |sz| lie in [2^-24, 2^24] (nothing overflows; what underflows
   stays far below the bounds) and det and tz are finite; elsewhere 0, and the retest decides. */
static inline CLVIS_ALWAYS_INLINE int clvis_float_misses(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c,
                                                         const clvis_tri_2d* p, float near_t)
{
    float det = p->u + p->v + p->w, tz = clvis_triangle_tz(s, *p);
    if (!clvis_finite(det) || !clvis_finite(tz)) return 0;
    float m = p->m, z = clvis_absf(s.sz); /* finite coordinates (det is): their largest magnitude */
    if (!(m >= 0x1p-24f && m <= 0x1p24f && z >= 0x1p-24f && z <= 0x1p24f)) return 0;
#if !defined(CLVIS_HAVE_DOUBLE)
    if (clvis_wide_scale(s, a, b, c) != 1.0f) return 0; /* a float retest's scaled products may underflow */
#else
    (void)a;
    (void)b;
    (void)c;
#endif
    float e = m * m * 0x1p-16f;
    if (clvis_max3f(p->u, p->v, p->w) > 2.0f * e && clvis_min3f(p->u, p->v, p->w) < -2.0f * e) return 1;
    if (!(near_t >= 0.0f)) return 0;
    float sum = clvis_absf(p->u) + clvis_absf(p->v) + clvis_absf(p->w);
    float et = z * m * (4.0f * e + 0x1p-21f * sum), ed = 4.0f * e + 0x1p-22f * sum;
    return clvis_absf(tz) > 2.0f * et && clvis_absf(det) > 2.0f * ed && (tz < 0.0f) != (det < 0.0f);
}

/* clvis_project_triangle for a test over [near_t, ...]: 0 where the triangle is missed for certain
   without the wide retest (clvis_float_misses; *p then holds the float projection), else 1 and
   clvis_project_triangle's result. */
static inline CLVIS_ALWAYS_INLINE int clvis_project_triangle_near(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b,
                                                                  clvis_vec3 c, float near_t, clvis_tri_2d* p)
{
    clvis_project_triangle_scaled(s, a, b, c, 1.0f, p);
    if (!p->wide && clvis_float_finite(s, p)) return 1;
    if (clvis_float_misses(s, a, b, c, p, near_t)) return 0;
    *p = clvis_project_triangle_wide_from(s, a, b, c, *p);
    return 1;
}

/* The ray parameter of the projected triangle's plane (det = u + v + w, non-zero). */
static inline float clvis_triangle_t(clvis_ray_shear s, clvis_tri_2d p, float det)
{
    return p.wide ? p.t : clvis_triangle_tz(s, p) / det * p.unscale;
}

/* The watertight test of the ray against triangle (a, b, c), both sides, edges inclusive: rays
   through an edge or vertex shared by two triangles hit at least one of them, whatever the order
   of the vertices. A degenerate triangle (zero area seen along the ray) never hits, nor does a
   ray in the triangle's plane. Returns 1 and the ray parameter in *t when the hit lies in
   [near, far] and `cull` (CLVIS_CULL_*) keeps the triangle: the determinant is positive where
   the triangle is front-facing (its normal cross(b - a, c - a) points against the ray,
   shared/visibility.h). The same float operations on host and device (no contraction:
   shared/types.h), so host tests check what kernels compute. */
static inline CLVIS_ALWAYS_INLINE int clvis_intersect_triangle(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b,
                                                               clvis_vec3 c, float near_t, float far_t, int cull,
                                                               float* t)
{
    clvis_tri_2d p;
    if (!clvis_project_triangle_near(s, a, b, c, near_t, &p)) {
        *t = near_t;
        return 0;
    }
    int inside = (p.u >= 0.0f && p.v >= 0.0f && p.w >= 0.0f) || (p.u <= 0.0f && p.v <= 0.0f && p.w <= 0.0f);
    float det = p.u + p.v + p.w;
    float tt = clvis_triangle_t(s, p, det);
    *t = tt;
    return inside && det != 0.0f && tt >= near_t && tt <= far_t && clvis_cull_keeps(cull, det > 0.0f, det < 0.0f);
}

/* The same test (no culling), dividing only for a ray inside the triangle, and leaving the
   projected triangle and its determinant in *p and *det: the barycentrics of a hit (CONVENTIONS.md:
   the weights of b and c, the hit point (1 - u - v) a + u b + v c) are p->v / det and p->w / det,
   which a caller computes only for a hit it keeps. */
static inline CLVIS_ALWAYS_INLINE int clvis_intersect_triangle_plane(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b,
                                                                     clvis_vec3 c, float near_t, float far_t, float* t,
                                                                     clvis_tri_2d* p, float* det)
{
    if (!clvis_project_triangle_near(s, a, b, c, near_t, p)) return 0;
    int inside = (p->u >= 0.0f && p->v >= 0.0f && p->w >= 0.0f) || (p->u <= 0.0f && p->v <= 0.0f && p->w <= 0.0f);
    *det = p->u + p->v + p->w;
    if (!inside || *det == 0.0f) return 0;
    *t = clvis_triangle_t(s, *p, *det);
    return *t >= near_t && *t <= far_t;
}

/* The side of edge p->q on which the ray lies, as -1, 0 or +1, with an edge function e that is
   exactly zero (the ray meets the edge's line) decided as if the ray were moved by (eps, eps^2)
   in the sheared plane, eps -> 0+: by the sign of e's gradient with respect to the ray's
   position, (qy - py, px - qx), first component first. This is simulation of simplicity: every
   triangle tested against one ray sees the same moved ray, and a shared edge flips the gradient
   with the edge function, so a ray through an edge or a vertex of a closed mesh lies inside
   exactly the triangles that the moved ray crosses. 0 only for an edge of zero length. */
static inline int clvis_edge_side(float e, float px, float py, float qx, float qy)
{
    if (e != 0.0f) return e > 0.0f ? 1 : -1;
    float gx = qy - py; /* a float difference has the exact sign of the real one */
    if (gx != 0.0f) return gx > 0.0f ? 1 : -1;
    float gy = px - qx;
    return gy > 0.0f ? 1 : (gy < 0.0f ? -1 : 0);
}

/* The half-open watertight test for hit counts: edges and vertices belong to exactly one of the
   triangles that share them (clvis_edge_side), so a ray crossing a closed mesh through an edge or
   a vertex counts one crossing, and a ray grazing a silhouette edge counts none or two. A ray in
   the triangle's plane or a degenerate triangle never hits. */
static inline CLVIS_ALWAYS_INLINE int clvis_intersect_triangle_half_open(clvis_ray_shear s, clvis_vec3 a,
                                                                         clvis_vec3 b, clvis_vec3 c, float near_t,
                                                                         float far_t, float* t)
{
    clvis_tri_2d p;
    if (!clvis_project_triangle_near(s, a, b, c, near_t, &p)) {
        *t = near_t;
        return 0;
    }
    int su = clvis_edge_side(p.u, p.bx, p.by, p.cx, p.cy);
    int sv = clvis_edge_side(p.v, p.cx, p.cy, p.ax, p.ay);
    int sw = clvis_edge_side(p.w, p.ax, p.ay, p.bx, p.by);
    float det = p.u + p.v + p.w;
    float tt = clvis_triangle_t(s, p, det);
    *t = tt;
    return su != 0 && su == sv && su == sw && det != 0.0f && tt >= near_t && tt <= far_t;
}

/* A ray prepared for the slab test: 1 / direction per axis (+-inf where a component is +-0) and
   which box plane it meets first on each axis (the hi plane where 1 / direction is negative, so
   a -0 component counts as negative). */
typedef struct clvis_box_ray {
    clvis_vec3 origin;           /* world units */
    clvis_vec3 inv;              /* 1 / direction */
    clvis_i32 neg_x, neg_y, neg_z;
} clvis_box_ray;

static inline clvis_box_ray clvis_make_box_ray(clvis_vec3 origin, clvis_vec3 dir)
{
    clvis_box_ray r;
    r.origin = origin;
    r.inv.x = 1.0f / dir.x;
    r.inv.y = 1.0f / dir.y;
    r.inv.z = 1.0f / dir.z;
    r.neg_x = r.inv.x < 0.0f;
    r.neg_y = r.inv.y < 0.0f;
    r.neg_z = r.inv.z < 0.0f;
    return r;
}

/* Keeps acc unless v is beyond it: a NaN v (0 * inf, a ray in a slab's plane) constrains nothing. */
static inline float clvis_raise(float acc, float v) { return v > acc ? v : acc; }
static inline float clvis_lower(float acc, float v) { return v < acc ? v : acc; }

/* The conservative slab test (Ize 2013): whether the ray may meet the box [lo, hi] at a distance
   in [near_t, far_t]; *entry gets the distance where it enters (at least near_t). The exit
   distance and far_t are scaled by 1 + 2 gamma(3), which bounds the rounding of
   (plane - origin) * (1 / direction): a box that the exact ray meets is never culled. Flat boxes
   (lo == hi) and rays parallel to an axis (a NaN where the origin lies in a plane) work. */
static inline int clvis_ray_hits_box(clvis_box_ray r, clvis_vec3 lo, clvis_vec3 hi, float near_t, float far_t,
                                     float* entry)
{
    float nx = ((r.neg_x ? hi.x : lo.x) - r.origin.x) * r.inv.x;
    float ny = ((r.neg_y ? hi.y : lo.y) - r.origin.y) * r.inv.y;
    float nz = ((r.neg_z ? hi.z : lo.z) - r.origin.z) * r.inv.z;
    float fx = ((r.neg_x ? lo.x : hi.x) - r.origin.x) * r.inv.x;
    float fy = ((r.neg_y ? lo.y : hi.y) - r.origin.y) * r.inv.y;
    float fz = ((r.neg_z ? lo.z : hi.z) - r.origin.z) * r.inv.z;
    float t0 = clvis_raise(clvis_raise(clvis_raise(near_t, nx), ny), nz);
    float t1 = clvis_lower(clvis_lower(clvis_lower(CLVIS_INFINITY, fx), fy), fz) * CLVIS_IZE_SCALE;
    *entry = t0;
    return t0 <= t1 && t0 <= far_t * CLVIS_IZE_SCALE;
}

/* The packet a work-item of ray_trace.cl traces: CLVIS_PACKET_W x CLVIS_PACKET_H pixels, one
   ray per lane of its 16-wide vectors. The host sizes the launch from it. */
#define CLVIS_PACKET_W 4                                /* pixels */
#define CLVIS_PACKET_H 4                                /* pixels */
#define CLVIS_PACKET (CLVIS_PACKET_W * CLVIS_PACKET_H)  /* rays: the lanes of float16 */

#endif
