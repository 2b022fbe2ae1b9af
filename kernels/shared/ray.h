/* Ray casting shared by the ray kernels (ray_trace.cl, ray_brute.cl) and the host tests: the
   watertight ray/triangle test of Woop, Benthin and Wald (JCGT 2013) and the conservative slab
   test of Ize ("Robust BVH Ray Traversal", JCGT 2013), so that float rounding never culls a box
   that a ray touches. ray_trace.cl runs the same operations on 16 rays at once (OpenCL vectors);
   these scalar forms define the bits and are what host tests check. */
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

/* The watertight test of the ray against triangle (a, b, c), both sides, edges inclusive: rays
   through an edge or vertex shared by two triangles hit at least one of them, whatever the order
   of the vertices. A degenerate triangle (zero area seen along the ray) never hits. Returns 1
   and the ray parameter in *t when the hit lies in [near, far] and `cull` (CLVIS_CULL_*) keeps the
   triangle: the determinant is positive where the triangle is front-facing (its normal
   cross(b - a, c - a) points against the ray, shared/visibility.h). The same float operations on
   host and device (no contraction: shared/types.h), so host tests check what kernels compute. */
static inline int clvis_intersect_triangle(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c,
                                           float near_t, float far_t, int cull, float* t)
{
    clvis_vec3 A, B, C;
    A.x = a.x - s.origin.x; A.y = a.y - s.origin.y; A.z = a.z - s.origin.z;
    B.x = b.x - s.origin.x; B.y = b.y - s.origin.y; B.z = b.z - s.origin.z;
    C.x = c.x - s.origin.x; C.y = c.y - s.origin.y; C.z = c.z - s.origin.z;
    float akz = clvis_component(A, s.kz), bkz = clvis_component(B, s.kz), ckz = clvis_component(C, s.kz);
    float ax = clvis_component(A, s.kx) - s.sx * akz;
    float ay = clvis_component(A, s.ky) - s.sy * akz;
    float bx = clvis_component(B, s.kx) - s.sx * bkz;
    float by = clvis_component(B, s.ky) - s.sy * bkz;
    float cx = clvis_component(C, s.kx) - s.sx * ckz;
    float cy = clvis_component(C, s.ky) - s.sy * ckz;
    /* Edge functions: each edge is evaluated with the same operations in both triangles that
       share it (only the sign flips), so no ray passes between them. */
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
#ifdef CLVIS_HAVE_DOUBLE
    /* An edge function that rounds to zero may have cancelled a non-zero value (a ray in the
       plane of a triangle seen edge-on): recompute all three in double, where products of floats
       are exact and the sign of their difference is right (Woop et al., section 3). */
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = (float)((double)cx * (double)by - (double)cy * (double)bx);
        v = (float)((double)ax * (double)cy - (double)ay * (double)cx);
        w = (float)((double)bx * (double)ay - (double)by * (double)ax);
    }
#endif
    int inside = (u >= 0.0f && v >= 0.0f && w >= 0.0f) || (u <= 0.0f && v <= 0.0f && w <= 0.0f);
    float det = u + v + w;
    float tz = u * (s.sz * akz) + v * (s.sz * bkz) + w * (s.sz * ckz);
    float tt = tz / det;
    *t = tt;
    return inside && det != 0.0f && tt >= near_t && tt <= far_t && clvis_cull_keeps(cull, det > 0.0f, det < 0.0f);
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
