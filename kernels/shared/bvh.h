/* The BVH as host/ray/bvh_build.cpp builds it and as ray_trace.cl reads it. The build makes a binary
   tree of 32-byte nodes in depth-first order (an interior node's left child follows it, the right
   child is named); the kernel reads it collapsed to 4-wide nodes of 128 bytes (each holds its up
   to four children's boxes, SoA, so one visit tests four boxes). The triangles of each leaf are
   copied contiguously with their ids, the vertices unchanged so the watertight test
   (shared/ray.h) sees the scene's own float32 positions. */
#ifndef CLVIS_SHARED_BVH_H
#define CLVIS_SHARED_BVH_H

#include "shared/types.h"

typedef struct clvis_bvh_node {
    float lo_x, lo_y, lo_z;   /* box minimum, world units */
    clvis_u32 first;          /* leaf: first slot in the triangle array; interior: right child */
    float hi_x, hi_y, hi_z;   /* box maximum, world units; an empty box has lo > hi */
    clvis_u32 count;          /* leaf: triangles (> 0); interior: 0, left child = this + 1 */
} clvis_bvh_node;

/* A 4-wide node: child k's box is (lo_x[k], lo_y[k], lo_z[k]) - (hi_x[k], ...). An unused slot
   has an empty box (lo = +inf, hi = -inf), which no ray meets. */
typedef struct clvis_bvh4_node {
    float lo_x[4], hi_x[4], lo_y[4], hi_y[4], lo_z[4], hi_z[4]; /* world units */
    clvis_u32 child[4];       /* a 4-wide node's index (count 0) or a leaf's first triangle slot */
    clvis_u32 count[4];       /* 0: child is a node; > 0: a leaf of that many triangles */
} clvis_bvh4_node;

/* One triangle of a leaf: its vertices as in the scene (v0, v1, v2 in index order), its id. */
typedef struct clvis_bvh_tri {
    float v0_x, v0_y, v0_z;
    clvis_u32 id;             /* triangle id (CONVENTIONS.md) */
    float v1_x, v1_y, v1_z;
    clvis_u32 pad0;
    float v2_x, v2_y, v2_z;
    clvis_u32 pad1;
} clvis_bvh_tri;

/* Inserts child k, met at distance d along a ray, among the `*hits` children of a node kept
   nearest first in order[] and along[] (a tie keeps slot order): the ray kernels' walk order. */
static inline void clvis_insert_child(clvis_u32 order[4], float along[4], clvis_u32* hits, clvis_u32 k, float d)
{
    clvis_u32 i = (*hits)++;
    for (; i > 0 && along[i - 1] > d; --i) {
        order[i] = order[i - 1];
        along[i] = along[i - 1];
    }
    order[i] = k;
    along[i] = d;
}

#ifdef __OPENCL_C_VERSION__
/* CLVIS_PREFETCH (PoCL's CPU device, Device::Impl::cpu_hints): the ray kernels fetch every child
   a walk meets (the one visited next and those pushed) into the cache as the node is visited, so
   that the (up to four) misses of one node's children overlap instead of each stalling the walk
   when it is reached. A hint only: the walk reads the same values with or without it. */
static inline void clvis_prefetch_child(__global const clvis_bvh4_node* nodes, __global const clvis_bvh_tri* tris,
                                        __global const clvis_bvh4_node* n, int k)
{
#ifdef CLVIS_PREFETCH
    /* a node's first two cache lines, or a leaf's first triangles (past the end: no fault) */
    __global const char* p = n->count[k] == 0 ? (__global const char*)(nodes + n->child[k])
                                              : (__global const char*)(tris + n->child[k]);
    CLVIS_PREFETCH_LINE(p);
    CLVIS_PREFETCH_LINE(p + 64);
#endif
}
#endif

#endif
