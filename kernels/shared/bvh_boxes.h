/* The slab test of all of a wide node's children at once (OpenCL C only: vector types), a child a
   lane of CLVIS_BVH_WIDTH: shared/ray.h's clvis_ray_hits_box, the same operations lane by lane,
   so each lane gets the bits the scalar test gives that child. ray_query.cl's node test and
   ray_trace_single.cl's (watertight) one; ray_trace.cl's packets test a child per 16 rays. */
#ifndef CLVIS_SHARED_BVH_BOXES_H
#define CLVIS_SHARED_BVH_BOXES_H

#include "shared/bvh.h"
#include "shared/instance.h"
#include "shared/ray.h"

/* The world boxes of node n's children in transformed instance xi, as the node stores them:
   lo x, y, z then hi x, y, z, CLVIS_BVH_WIDTH lanes each. */
static inline void clvis_world_boxes(__global const clvis_wide_node* n, __global const clvis_instance* xi,
                                     float w[6 * CLVIS_BVH_WIDTH])
{
    for (int k = 0; k < CLVIS_BVH_WIDTH; ++k) {
        float lo[3], hi[3];
        clvis_instance_child_box(n, k, xi, lo, hi);
        for (int c = 0; c < 3; ++c) {
            w[CLVIS_BVH_WIDTH * c + k] = lo[c];
            w[CLVIS_BVH_WIDTH * (3 + c) + k] = hi[c];
        }
    }
}

/* clvis_ray_hits_box(br, child k's box, near_t, far_t) in lane k: all bits set where the ray may
   meet the child, entry lane k its entry distance. Without an instance (xi null, at compile time
   in a flat build) each axis' near and far planes are read straight from the node (lo_x, hi_x,
   ... follow each other, a vector each, aligned to it: the plane a ray meets first is the row
   after lo when its direction is negative), so no select runs per node. */
static inline CLVIS_ALWAYS_INLINE clvis_wint clvis_hits_boxes(__global const clvis_wide_node* n,
                                                              __global const clvis_instance* xi, clvis_box_ray br,
                                                              float near_t, float far_t, clvis_wfloat* entry)
{
    clvis_wfloat nx, ny, nz, fx, fy, fz;
    if (xi) {
        float w[6 * CLVIS_BVH_WIDTH];
        clvis_world_boxes(n, xi, w);
        clvis_wfloat lox = clvis_vload_w(0, w), loy = clvis_vload_w(1, w), loz = clvis_vload_w(2, w);
        clvis_wfloat hix = clvis_vload_w(3, w), hiy = clvis_vload_w(4, w), hiz = clvis_vload_w(5, w);
        nx = ((br.neg_x ? hix : lox) - br.origin.x) * br.inv.x;
        ny = ((br.neg_y ? hiy : loy) - br.origin.y) * br.inv.y;
        nz = ((br.neg_z ? hiz : loz) - br.origin.z) * br.inv.z;
        fx = ((br.neg_x ? lox : hix) - br.origin.x) * br.inv.x;
        fy = ((br.neg_y ? loy : hiy) - br.origin.y) * br.inv.y;
        fz = ((br.neg_z ? loz : hiz) - br.origin.z) * br.inv.z;
    } else {
        __global const clvis_wfloat* rows = (__global const clvis_wfloat*)n->lo_x;
        nx = (rows[br.neg_x] - br.origin.x) * br.inv.x;
        ny = (rows[2 + br.neg_y] - br.origin.y) * br.inv.y;
        nz = (rows[4 + br.neg_z] - br.origin.z) * br.inv.z;
        fx = (rows[1 - br.neg_x] - br.origin.x) * br.inv.x;
        fy = (rows[3 - br.neg_y] - br.origin.y) * br.inv.y;
        fz = (rows[5 - br.neg_z] - br.origin.z) * br.inv.z;
    }
    /* clvis_raise / clvis_lower: a NaN (origin in a slab's plane, 0 * inf) constrains nothing */
    clvis_wfloat t0 = (clvis_wfloat)(near_t);
    t0 = select(t0, nx, nx > t0);
    t0 = select(t0, ny, ny > t0);
    t0 = select(t0, nz, nz > t0);
    clvis_wfloat t1 = (clvis_wfloat)(CLVIS_INFINITY);
    t1 = select(t1, fx, fx < t1);
    t1 = select(t1, fy, fy < t1);
    t1 = select(t1, fz, fz < t1);
    t1 = t1 * CLVIS_IZE_SCALE;
    *entry = t0;
    return (t0 <= t1) & (t0 <= (clvis_wfloat)(far_t * CLVIS_IZE_SCALE));
}

#endif
