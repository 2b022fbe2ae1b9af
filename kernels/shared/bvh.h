/* The BVH as host/ray/bvh_build.cpp builds it and as the ray kernels read it (shared/bvh_walk.h
   walks it). The build makes a binary tree of 32-byte nodes in depth-first order (an interior
   node's left child follows it, the right child is named); the kernels read it collapsed to
   4-wide nodes of 128 bytes (each holds its up to four children's boxes, SoA, so one visit tests
   four boxes). The triangles of each leaf are copied contiguously with their ids, the vertices
   unchanged so the watertight test (shared/ray.h) sees the scene's own float32 positions. */
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

/* One triangle of a leaf: its vertices as in the scene (v0, v1, v2 in index order), its id. 40
   bytes, no padding (issue 37's memory): a triangle is only 4-byte aligned, so it is read field
   by field, never through a float4 (or a vload4 that assumes 16-byte alignment). */
typedef struct clvis_bvh_tri {
    float v0_x, v0_y, v0_z;
    clvis_u32 id;             /* triangle id (CONVENTIONS.md) */
    float v1_x, v1_y, v1_z;
    float v2_x, v2_y, v2_z;
} clvis_bvh_tri;

#endif
