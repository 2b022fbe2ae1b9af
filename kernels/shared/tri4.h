/* The watertight triangle test of shared/ray.h on up to four triangles of a leaf at once, one
   triangle a lane of OpenCL's float4 (OpenCL C only), for ray_query.cl's single rays. Each lane
   runs the operations of the scalar test's float path in the same order (FP_CONTRACT OFF,
   shared/types.h): clvis_project_triangle_scaled with k = 1, clvis_ray_extent's trust check,
   clvis_triangle_tz and clvis_triangle_t, so a lane holds the bits the scalar test gives its
   triangle. Where the scalar test leaves the float path, a lane is decided only when the scalar
   test's answer is known without its fallbacks:
   - an edge function 0 (clvis_exact_edges would recompute them): undecided;
   - not trusted, or det or tz not finite (clvis_project_triangle_near): a miss where
     clvis_float_misses says the miss is certain (the same bounds, lane by lane), else undecided.
   Undecided lanes are flagged for the caller, which tests those triangles with the scalar code.
   On the float path every edge function is non-zero, so the edges-inclusive test
   (clvis_intersect_triangle, _plane) and the half-open one (clvis_intersect_triangle_half_open)
   agree: one hit mask serves every query. */
#ifndef CLVIS_SHARED_TRI4_H
#define CLVIS_SHARED_TRI4_H

#include "shared/bvh.h"
#include "shared/instance.h"
#include "shared/ray.h"

/* Four triangles against one ray: per lane the edge functions v (c->a) and w (a->b), det and the
   ray parameter t, and as bit masks (bit k: lane k) the lanes hit and the lanes the scalar test
   must decide. */
typedef struct clvis_tri4 {
    float4 v, w, det, t;
    int hits, redo;
} clvis_tri4;

/* clvis_min3f and clvis_max3f lane by lane (the same comparisons: the same NaN and -0 choices). */
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

/* Up to four triangles' world-space vertices, one triangle a lane, and their ids. */
typedef struct clvis_tri4_verts {
    float4 x0, y0, z0, x1, y1, z1, x2, y2, z2;
    uint4 id;
} clvis_tri4_verts;

/* Triangles tris[g .. g + m - 1] (m from 1 to 4; the lanes past m read tris[g] again, and the
   test masks them off). Fields are read by name (the triangle record's layout may change). */
static inline CLVIS_ALWAYS_INLINE void clvis_tri4_load(__global const clvis_bvh_tri* tris, uint g, uint m,
                                                       clvis_tri4_verts* q)
{
    __global const clvis_bvh_tri* t0 = tris + g;
    __global const clvis_bvh_tri* t1 = m > 1u ? t0 + 1 : t0;
    __global const clvis_bvh_tri* t2 = m > 2u ? t0 + 2 : t0;
    __global const clvis_bvh_tri* t3 = m > 3u ? t0 + 3 : t0;
    q->x0 = (float4)(t0->v0_x, t1->v0_x, t2->v0_x, t3->v0_x);
    q->y0 = (float4)(t0->v0_y, t1->v0_y, t2->v0_y, t3->v0_y);
    q->z0 = (float4)(t0->v0_z, t1->v0_z, t2->v0_z, t3->v0_z);
    q->x1 = (float4)(t0->v1_x, t1->v1_x, t2->v1_x, t3->v1_x);
    q->y1 = (float4)(t0->v1_y, t1->v1_y, t2->v1_y, t3->v1_y);
    q->z1 = (float4)(t0->v1_z, t1->v1_z, t2->v1_z, t3->v1_z);
    q->x2 = (float4)(t0->v2_x, t1->v2_x, t2->v2_x, t3->v2_x);
    q->y2 = (float4)(t0->v2_y, t1->v2_y, t2->v2_y, t3->v2_y);
    q->z2 = (float4)(t0->v2_z, t1->v2_z, t2->v2_z, t3->v2_z);
    q->id = (uint4)(t0->id, t1->id, t2->id, t3->id);
}

/* The same for the triangles of instance xi (none: the plain meshes), their world vertices and
   ids computed as the expansion's (clvis_instance_triangle). */
static inline CLVIS_ALWAYS_INLINE void clvis_tri4_load_instance(__global const clvis_bvh_tri* tris, uint g, uint m,
                                                                __global const clvis_instance* xi,
                                                                clvis_tri4_verts* q)
{
    float c[9][4];
    uint id[4];
    for (uint k = 0; k < 4u; ++k) {
        float v[9];
        if (k < m) {
            id[k] = clvis_instance_triangle(tris + g + k, xi, v);
        } else { /* the lanes past m repeat lane 0, transformed once */
            id[k] = id[0];
            for (int j = 0; j < 9; ++j) v[j] = c[j][0];
        }
        for (int j = 0; j < 9; ++j) c[j][k] = v[j];
    }
    q->x0 = vload4(0, c[0]); q->y0 = vload4(0, c[1]); q->z0 = vload4(0, c[2]);
    q->x1 = vload4(0, c[3]); q->y1 = vload4(0, c[4]); q->z1 = vload4(0, c[5]);
    q->x2 = vload4(0, c[6]); q->y2 = vload4(0, c[7]); q->z2 = vload4(0, c[8]);
    q->id = vload4(0, id);
}

/* Tests the first m lanes of q (m from 1 to 4) against the ray s in [near_t, far_t], both
   sides. The result goes out by pointer (a returned struct: see clvis_project_triangle). */
static inline CLVIS_ALWAYS_INLINE void clvis_tri4_test(clvis_ray_shear s, const clvis_tri4_verts* q, uint m,
                                                       float near_t, float far_t, clvis_tri4* out)
{
    /* clvis_ray_translate with k = 1: p * 1 - origin * 1 */
    float4 ox = (float4)(s.origin.x * 1.0f), oy = (float4)(s.origin.y * 1.0f), oz = (float4)(s.origin.z * 1.0f);
    float4 Ax = q->x0 * 1.0f - ox, Ay = q->y0 * 1.0f - oy, Az = q->z0 * 1.0f - oz;
    float4 Bx = q->x1 * 1.0f - ox, By = q->y1 * 1.0f - oy, Bz = q->z1 * 1.0f - oz;
    float4 Cx = q->x2 * 1.0f - ox, Cy = q->y2 * 1.0f - oy, Cz = q->z2 * 1.0f - oz;
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
    /* clvis_ray_extent: M and the gap d, and the trust check M <= CLVIS_RAY_RANGE d */
    float4 lx = clvis_min3f4(Ax, Bx, Cx), hx = clvis_max3f4(Ax, Bx, Cx);
    float4 ly = clvis_min3f4(Ay, By, Cy), hy = clvis_max3f4(Ay, By, Cy);
    float4 lz = clvis_min3f4(Az, Bz, Cz), hz = clvis_max3f4(Az, Bz, Cz);
    float4 gap = clvis_max3f4(select(-hx, lx, lx > -hx), select(-hy, ly, ly > -hy), select(-hz, lz, lz > -hz));
    float4 mm = clvis_max3f4(select(hx, -lx, -lx > hx), select(hy, -ly, -ly > hy), select(hz, -lz, -lz > hz));
    float4 det = u + v + w;
    /* lane by lane: written (int4)(0, 1, 2, 3) < (int4)(m), Oclgrind 21.10 took lanes past m as
       active (tests/oclgrind_test.cpp: extra crossings counted; PoCL gave the right ones) */
    int4 active = (int4)(-1, m > 1u ? -1 : 0, m > 2u ? -1 : 0, m > 3u ? -1 : 0);
    int4 edges = (u != 0.0f) & (v != 0.0f) & (w != 0.0f);
    int4 trusted = mm <= CLVIS_RAY_RANGE * gap;
    int4 inside = ((u >= 0.0f) & (v >= 0.0f) & (w >= 0.0f)) | ((u <= 0.0f) & (v <= 0.0f) & (w <= 0.0f));
    float z = clvis_absf(s.sz);
    /* Lanes on the float path (tz finite where det is: clvis_float_finite) that the ray passes
       outside: misses without tz. Where every lane is one, nothing else is computed. */
    int4 small = (mm <= 0x1p24f) & (int4)(z <= 0x1p24f ? -1 : 0);
    int4 det_finite = clvis_finite4(det);
    int4 plain_miss = edges & trusted & det_finite & small & ~inside;
    if (!clvis_mask4(active & ~plain_miss)) {
        out->hits = out->redo = 0;
        return;
    }
    float4 tz = u * (s.sz * akz) + v * (s.sz * bkz) + w * (s.sz * ckz);
    float4 t = tz / det * 1.0f; /* clvis_triangle_t: unscale = 1 / k = 1 */
    int4 finite = det_finite & clvis_finite4(tz);
    int4 simple = edges & trusted & finite;
    /* clvis_float_misses lane by lane: a certain miss needs no retest */
    int4 miss = (int4)(0);
#if defined(CLVIS_HAVE_DOUBLE)
    if (z >= 0x1p-24f && z <= 0x1p24f) {
        float4 e = mm * mm * 0x1p-16f;
        int4 bounded = finite & (mm >= 0x1p-24f) & (mm <= 0x1p24f);
        int4 outside = (clvis_max3f4(u, v, w) > 2.0f * e) & (clvis_min3f4(u, v, w) < -2.0f * e);
        int4 behind = (int4)(0);
        if (near_t >= 0.0f) {
            /* fabs where clvis_absf keeps a -0: only compared, a zero's sign changes nothing */
            float4 sum = fabs(u) + fabs(v) + fabs(w);
            float4 et = z * mm * (4.0f * e + 0x1p-21f * sum), ed = 4.0f * e + 0x1p-22f * sum;
            behind = (fabs(tz) > 2.0f * et) & (fabs(det) > 2.0f * ed) & ((tz < 0.0f) != (det < 0.0f));
        }
        miss = bounded & (outside | behind);
    }
#endif
    int4 hit = simple & inside & (det != 0.0f) & (t >= near_t) & (t <= far_t);
    out->v = v;
    out->w = w;
    out->det = det;
    out->t = t;
    out->hits = clvis_mask4(active & hit);
    out->redo = clvis_mask4(active & ~simple & ~(edges & miss));
}

#endif
