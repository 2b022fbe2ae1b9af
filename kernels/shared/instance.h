/* Instances (CONVENTIONS.md "Instances"): the float32 transform that defines an instance's
   world-space vertices, shared by the host's expansion (Scene::world_positions) and the kernels
   that transform prototype vertices on the fly, so that both compute the same bits. The matrix is
   the instance's 4x4 transform rounded to float row by row (the last row, 0 0 0 1, dropped):
   x' = ((m0 * x + m1 * y) + m2 * z) + m3, and so on, in float32, in that order, without FMA
   (FP_CONTRACT off on both compilers). */
#ifndef CLVIS_SHARED_INSTANCE_H
#define CLVIS_SHARED_INSTANCE_H

#include "shared/bvh.h"
#include "shared/types.h"

/* One entry of the ray path's two-level BVH as the device reads it: 56 bytes. An instance's
   prototype tree sits in the shared node and triangle arrays from node `tree`, its triangles' ids
   local (0, 1, ...). The plain meshes of the scene form one more entry, `tree` marked with
   CLVIS_INSTANCE_PLAIN: their vertices are world-space and their ids global, so their tree is
   walked as a flat tree (no record, matrix and first_id unused). */
typedef struct clvis_instance {
    float m[12];              /* rows 0-2 of the transform, float32 */
    clvis_u32 first_id;       /* added to each triangle's stored id */
    clvis_u32 tree;           /* the tree's root (a wide node), | CLVIS_INSTANCE_PLAIN for the plain meshes */
} clvis_instance;

#define CLVIS_INSTANCE_PLAIN 0x80000000u

#ifdef __OPENCL_C_VERSION__
#define CLVIS_GLOBAL __global
#else
#define CLVIS_GLOBAL
#endif
#define CLVIS_INSTANCE_MATRIX CLVIS_GLOBAL const float*

static inline float clvis_instance_abs(float x) { return x < 0.0f ? -x : x; }

/* The world-space position of object-space (x, y, z) under matrix m (12 floats, row by row). */
static inline clvis_vec3 clvis_instance_point(CLVIS_INSTANCE_MATRIX m, float x, float y, float z)
{
    clvis_vec3 r;
    r.x = ((m[0] * x + m[1] * y) + m[2] * z) + m[3];
    r.y = ((m[4] * x + m[5] * y) + m[6] * z) + m[7];
    r.z = ((m[8] * x + m[9] * y) + m[10] * z) + m[11];
    return r;
}

/* A world-space box that holds clvis_instance_point of every point of the object-space box
   lo..hi (as computed in float32, roundings included): the exact image's box (centre and
   half-extent through |m|) widened by a margin far above the roundings of either computation
   (each a few units in the last place of the sum of magnitudes |m0 x| + |m1 y| + |m2 z| + |m3|).
   An empty box (lo > hi) stays empty. */
static inline void clvis_instance_box(CLVIS_INSTANCE_MATRIX m, const float lo[3], const float hi[3], float out_lo[3],
                                      float out_hi[3])
{
    if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2])) {
        for (int a = 0; a < 3; ++a) {
            out_lo[a] = lo[a];
            out_hi[a] = hi[a];
        }
        return;
    }
    float c[3], e[3], mag[3];
    for (int a = 0; a < 3; ++a) {
        c[a] = 0.5f * lo[a] + 0.5f * hi[a];
        e[a] = 0.5f * hi[a] - 0.5f * lo[a];
        mag[a] = clvis_instance_abs(lo[a]) > clvis_instance_abs(hi[a]) ? clvis_instance_abs(lo[a]) : clvis_instance_abs(hi[a]);
    }
    for (int r = 0; r < 3; ++r) {
        const float m0 = m[4 * r], m1 = m[4 * r + 1], m2 = m[4 * r + 2], m3 = m[4 * r + 3];
        float centre = ((m0 * c[0] + m1 * c[1]) + m2 * c[2]) + m3;
        float extent = (clvis_instance_abs(m0) * e[0] + clvis_instance_abs(m1) * e[1]) + clvis_instance_abs(m2) * e[2];
        float size = ((clvis_instance_abs(m0) * mag[0] + clvis_instance_abs(m1) * mag[1]) + clvis_instance_abs(m2) * mag[2]) + clvis_instance_abs(m3);
        /* 2^-19 of the magnitudes (about 32 ulps of them) plus the smallest normal */
        float margin = size * 1.9073486328125e-6f + extent * 1.9073486328125e-6f + 1.1754943508e-38f;
        out_lo[r] = (centre - extent) - margin;
        out_hi[r] = (centre + extent) + margin;
    }
}

/* The world-space vertices (v0, v1, v2) of leaf triangle t of instance xi (none: the flat BVH of
   a scene without instances, or the plain meshes' tree) and its id. */
static inline clvis_u32 clvis_instance_triangle(CLVIS_GLOBAL const clvis_bvh_tri* t, CLVIS_GLOBAL const clvis_instance* xi,
                                                float v[9])
{
    v[0] = t->v0_x; v[1] = t->v0_y; v[2] = t->v0_z;
    v[3] = t->v1_x; v[4] = t->v1_y; v[5] = t->v1_z;
    v[6] = t->v2_x; v[7] = t->v2_y; v[8] = t->v2_z;
    if (!xi) return t->id;
    for (int k = 0; k < 9; k += 3) {
        clvis_vec3 w = clvis_instance_point(xi->m, v[k], v[k + 1], v[k + 2]);
        v[k] = w.x; v[k + 1] = w.y; v[k + 2] = w.z;
    }
    return t->id + xi->first_id;
}

/* The world-space box of child k of wide node n in instance xi (none: the node's own box). */
static inline void clvis_instance_child_box(CLVIS_GLOBAL const clvis_wide_node* n, int k,
                                            CLVIS_GLOBAL const clvis_instance* xi, float lo[3], float hi[3])
{
    float l[3] = {n->lo_x[k], n->lo_y[k], n->lo_z[k]}, h[3] = {n->hi_x[k], n->hi_y[k], n->hi_z[k]};
    if (xi) {
        clvis_instance_box(xi->m, l, h, lo, hi);
        return;
    }
    for (int a = 0; a < 3; ++a) {
        lo[a] = l[a];
        hi[a] = h[a];
    }
}

#endif
