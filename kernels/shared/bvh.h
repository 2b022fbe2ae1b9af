/* The BVH as the ray kernels read it, written by host/bvh_build.cpp: binary nodes of 32 bytes in
   depth-first order (an interior node's left child follows it, the right child is named), and
   the triangles of each leaf copied contiguously with their ids, the vertices unchanged so the
   watertight test (shared/ray.h) sees the scene's own float32 positions. */
#ifndef CLVIS_SHARED_BVH_H
#define CLVIS_SHARED_BVH_H

#include "shared/types.h"

typedef struct clvis_bvh_node {
    float lo_x, lo_y, lo_z;   /* box minimum, world units */
    clvis_u32 first;          /* leaf: first slot in the triangle array; interior: right child */
    float hi_x, hi_y, hi_z;   /* box maximum, world units; an empty box has lo > hi */
    clvis_u32 count;          /* leaf: triangles (> 0); interior: 0, left child = this + 1 */
} clvis_bvh_node;

/* One triangle of a leaf: its vertices as in the scene (v0, v1, v2 in index order), its id. */
typedef struct clvis_bvh_tri {
    float v0_x, v0_y, v0_z;
    clvis_u32 id;             /* triangle id (CONVENTIONS.md) */
    float v1_x, v1_y, v1_z;
    clvis_u32 pad0;
    float v2_x, v2_y, v2_z;
    clvis_u32 pad1;
} clvis_bvh_tri;

#endif
