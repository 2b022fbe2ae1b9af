/* The BVH as host/ray/bvh_build.cpp builds it and as the ray kernels read it (shared/bvh_walk.h
   walks it). The build makes a binary tree of 32-byte nodes in depth-first order (an interior
   node's left child follows it, the right child is named); the kernels read it collapsed to
   wide nodes of CLVIS_BVH_WIDTH (8) children, 256 bytes (each holds its children's boxes, SoA,
   so one visit tests eight boxes in one vector). The triangles of each leaf are copied contiguously with their ids, the vertices
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

/* The width of the nodes the kernels walk, one constant for the host's collapse and every
   kernel (issue 37: 8 children tested in one 8-lane vector, so a ray visits fewer nodes). 4 or 8;
   CLVIS_BVH_SLOT_BITS names a slot in a stack entry (shared/bvh_walk.h). */
#define CLVIS_BVH_WIDTH 8
#define CLVIS_BVH_SLOT_BITS 3
#if (1 << CLVIS_BVH_SLOT_BITS) != CLVIS_BVH_WIDTH
#error "CLVIS_BVH_SLOT_BITS must be log2(CLVIS_BVH_WIDTH)"
#endif

/* A wide node: child k's box is (lo_x[k], lo_y[k], lo_z[k]) - (hi_x[k], ...). An unused slot
   has an empty box (lo = +inf, hi = -inf), which no ray meets. 32 bytes a child (256 bytes at
   width 8); each row of boxes is aligned to its vector (float8 at width 8). */
typedef struct clvis_wide_node {
    float lo_x[CLVIS_BVH_WIDTH], hi_x[CLVIS_BVH_WIDTH]; /* world units */
    float lo_y[CLVIS_BVH_WIDTH], hi_y[CLVIS_BVH_WIDTH];
    float lo_z[CLVIS_BVH_WIDTH], hi_z[CLVIS_BVH_WIDTH];
    clvis_u32 child[CLVIS_BVH_WIDTH]; /* a wide node's index (count 0) or a leaf's first triangle slot */
    clvis_u32 count[CLVIS_BVH_WIDTH]; /* 0: child is a node; > 0: a leaf of that many triangles */
} clvis_wide_node;

#ifdef __OPENCL_C_VERSION__
/* The vectors of one row of a node's boxes (a child a lane), and the bits of a lane mask. */
#define CLVIS_PASTE_(a, b) a##b
#define CLVIS_PASTE(a, b) CLVIS_PASTE_(a, b)
typedef CLVIS_PASTE(float, CLVIS_BVH_WIDTH) clvis_wfloat;
typedef CLVIS_PASTE(int, CLVIS_BVH_WIDTH) clvis_wint;
#define clvis_vload_w CLVIS_PASTE(vload, CLVIS_BVH_WIDTH)
#define clvis_vstore_w CLVIS_PASTE(vstore, CLVIS_BVH_WIDTH)

/* Bit k set where lane k of a comparison's mask is (all bits set there). On x86 with AVX (PoCL's
   CPU device) the eight lanes' sign bits in one instruction: PoCL compiled the lanes ORed one by
   one into an extract and a test of each lane where the walk tests the slots, and the walk waited
   on those chains (issue 37, docs/architecture.md). Elsewhere, and at width 4, the lanes ORed. */
static inline int clvis_wmask_bits(clvis_wint m)
{
#if CLVIS_BVH_WIDTH == 8 && defined(__AVX__)
    return __builtin_ia32_movmskps256(as_float8(m));
#elif CLVIS_BVH_WIDTH == 8
    return (m.s0 & 1) | (m.s1 & 2) | (m.s2 & 4) | (m.s3 & 8) | (m.s4 & 16) | (m.s5 & 32) | (m.s6 & 64) |
           (m.s7 & 128);
#else
    return (m.s0 & 1) | (m.s1 & 2) | (m.s2 & 4) | (m.s3 & 8);
#endif
}
#endif

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
