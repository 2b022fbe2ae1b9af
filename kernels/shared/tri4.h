/* The watertight triangle test of shared/ray.h on up to four triangles of a leaf at once, one
   triangle a lane of OpenCL's float4 (OpenCL C only), for ray_query.cl's single rays: the
   operations of the scalar clvis_project_triangle_scaled (k = 1), clvis_ray_trusted,
   clvis_triangle_tz and clvis_triangle_t lane by lane and in the same order (FP_CONTRACT OFF,
   shared/types.h), so each lane holds the bits the scalar test gives its triangle. A lane whose
   scalar test would take a fallback (an edge function 0: clvis_exact_edges; not trusted, or det
   or tz not finite: clvis_project_triangle_wide) is only flagged: the caller tests that triangle
   again with the scalar code. Without a fallback, the half-open test (edge functions all non-zero)
   and the edges-inclusive one agree, so one hit mask serves every query. */
#ifndef CLVIS_SHARED_TRI4_H
#define CLVIS_SHARED_TRI4_H

#include "shared/bvh.h"
#include "shared/ray.h"

/* Four triangles against one ray, as bit masks (bit k: lane k): the lanes hit without a fallback
   and the lanes that need the scalar test. */
typedef struct clvis_tri4 {
    int hits, redo;
} clvis_tri4;

/* clvis_min3f / clvis_max3f lane by lane (the same comparisons, so the same NaN and -0 choices). */
static inline float4 clvis_min3f4(float4 x, float4 y, float4 z)
{
    float4 m = select(y, x, x < y);
    return select(z, m, m < z);
}

static inline float4 clvis_max3f4(float4 x, float4 y, float4 z)
{
    float4 m = select(y, x, x > y);
    return select(z, m, m > z);
}

/* clvis_component with a lane-uniform axis. */
static inline float4 clvis_pick4(int k, float4 x, float4 y, float4 z) { return k == 0 ? x : (k == 1 ? y : z); }

/* clvis_finite lane by lane, from the bits. */
static inline int4 clvis_finite4(float4 v) { return (as_int4(v) & 0x7F800000) != (int4)(0x7F800000); }

static inline int clvis_mask4(int4 m) { return (m.s0 & 1) | (m.s1 & 2) | (m.s2 & 4) | (m.s3 & 8); }

/* clvis_ray_trusted lane by lane, from the vertices minus the origin in world axes. */
static inline CLVIS_ALWAYS_INLINE int4 clvis_ray_trusted4(float4 Ax, float4 Ay, float4 Az, float4 Bx, float4 By,
                                                          float4 Bz, float4 Cx, float4 Cy, float4 Cz)
{
    float4 lx = clvis_min3f4(Ax, Bx, Cx), hx = clvis_max3f4(Ax, Bx, Cx);
    float4 ly = clvis_min3f4(Ay, By, Cy), hy = clvis_max3f4(Ay, By, Cy);
    float4 lz = clvis_min3f4(Az, Bz, Cz), hz = clvis_max3f4(Az, Bz, Cz);
    float4 gap = clvis_max3f4(select(-hx, lx, lx > -hx), select(-hy, ly, ly > -hy), select(-hz, lz, lz > -hz));
    float4 m = clvis_max3f4(select(hx, -lx, -lx > hx), select(hy, -ly, -ly > hy), select(hz, -lz, -lz > hz));
    return m <= CLVIS_RAY_RANGE * gap;
}

/* Tests triangles tris[g .. g + m - 1] (m from 1 to 4; the lanes past m read tris[g] again and
   are masked off) against the ray s in [near_t, far_t], edges inclusive, both sides. A lane in
   `hits` is a hit of clvis_intersect_triangle with CLVIS_CULL_NONE (and of
   clvis_intersect_triangle_half_open); a lane in `redo` is undecided, and in neither a miss. Fields are read by name (the triangle record's layout may change). The
   result goes out by pointer (a returned struct: see clvis_project_triangle). */
static inline CLVIS_ALWAYS_INLINE void clvis_leaf_tri4(clvis_ray_shear s, __global const clvis_bvh_tri* tris, uint g,
                                                       uint m, float near_t, float far_t, clvis_tri4* out)
{
    __global const clvis_bvh_tri* t0 = tris + g;
    __global const clvis_bvh_tri* t1 = m > 1u ? t0 + 1 : t0;
    __global const clvis_bvh_tri* t2 = m > 2u ? t0 + 2 : t0;
    __global const clvis_bvh_tri* t3 = m > 3u ? t0 + 3 : t0;
    /* clvis_ray_translate with k = 1: p * 1 - origin * 1 */
    float4 ox = (float4)(s.origin.x * 1.0f), oy = (float4)(s.origin.y * 1.0f), oz = (float4)(s.origin.z * 1.0f);
    float4 Ax = (float4)(t0->v0_x, t1->v0_x, t2->v0_x, t3->v0_x) * 1.0f - ox;
    float4 Ay = (float4)(t0->v0_y, t1->v0_y, t2->v0_y, t3->v0_y) * 1.0f - oy;
    float4 Az = (float4)(t0->v0_z, t1->v0_z, t2->v0_z, t3->v0_z) * 1.0f - oz;
    float4 Bx = (float4)(t0->v1_x, t1->v1_x, t2->v1_x, t3->v1_x) * 1.0f - ox;
    float4 By = (float4)(t0->v1_y, t1->v1_y, t2->v1_y, t3->v1_y) * 1.0f - oy;
    float4 Bz = (float4)(t0->v1_z, t1->v1_z, t2->v1_z, t3->v1_z) * 1.0f - oz;
    float4 Cx = (float4)(t0->v2_x, t1->v2_x, t2->v2_x, t3->v2_x) * 1.0f - ox;
    float4 Cy = (float4)(t0->v2_y, t1->v2_y, t2->v2_y, t3->v2_y) * 1.0f - oy;
    float4 Cz = (float4)(t0->v2_z, t1->v2_z, t2->v2_z, t3->v2_z) * 1.0f - oz;
    float4 akz = clvis_pick4(s.kz, Ax, Ay, Az), bkz = clvis_pick4(s.kz, Bx, By, Bz);
    float4 ckz = clvis_pick4(s.kz, Cx, Cy, Cz);
    float4 ax = clvis_pick4(s.kx, Ax, Ay, Az) - s.sx * akz;
    float4 ay = clvis_pick4(s.ky, Ax, Ay, Az) - s.sy * akz;
    float4 bx = clvis_pick4(s.kx, Bx, By, Bz) - s.sx * bkz;
    float4 by = clvis_pick4(s.ky, Bx, By, Bz) - s.sy * bkz;
    float4 cx = clvis_pick4(s.kx, Cx, Cy, Cz) - s.sx * ckz;
    float4 cy = clvis_pick4(s.ky, Cx, Cy, Cz) - s.sy * ckz;
    float4 u = cx * by - cy * bx;
    float4 v = ax * cy - ay * cx;
    float4 w = bx * ay - by * ax;
    float4 det = u + v + w;
    float4 tz = u * (s.sz * akz) + v * (s.sz * bkz) + w * (s.sz * ckz);
    float4 t = tz / det * 1.0f; /* clvis_triangle_t: unscale = 1 / k = 1 */
    int4 active = (int4)(0, 1, 2, 3) < (int4)((int)m);
    int4 simple = active & (u != 0.0f) & (v != 0.0f) & (w != 0.0f) &
                  clvis_ray_trusted4(Ax, Ay, Az, Bx, By, Bz, Cx, Cy, Cz) & clvis_finite4(det) & clvis_finite4(tz);
    int4 inside = ((u >= 0.0f) & (v >= 0.0f) & (w >= 0.0f)) | ((u <= 0.0f) & (v <= 0.0f) & (w <= 0.0f));
    int4 hit = simple & inside & (det != 0.0f) & (t >= near_t) & (t <= far_t);
    out->hits = clvis_mask4(hit);
    out->redo = clvis_mask4(active) & ~clvis_mask4(simple);
}

#endif
