/* A scene with instances as the raster path reads it without the expansion (CONVENTIONS.md
   "Instances", host/frame/instanced_scene.cpp): every mesh stored once (prototypes in object
   space, plain meshes in world space, as the expansion holds them) and a 64-byte record per item
   in id order. An item's world-space vertices are clvis_instance_point of its mesh's (the
   expansion's formula, shared/instance.h), or its mesh's own bits when it is not transformed
   (a plain mesh, or an instance whose transform is the identity: the expansion copies those). */
#ifndef CLVIS_SHARED_SCENE_ITEMS_H
#define CLVIS_SHARED_SCENE_ITEMS_H

#include "shared/instance.h"

/* One mesh stored once: its vertices (3 floats each) from first_vertex of the meshes' positions,
   its triangles' indices (3 each, local: 0 .. vertex_count - 1) from 3 * first_triangle. */
typedef struct clvis_item_mesh {
    clvis_u32 first_vertex, vertex_count, first_triangle, triangle_count;
} clvis_item_mesh;

/* `mesh` of an item whose vertices go through its matrix. */
#define CLVIS_ITEM_TRANSFORMED 0x80000000u

/* One item (a plain mesh or an instance) with at least one triangle, in id order. */
typedef struct clvis_item {
    float m[12];         /* rows 0-2 of its transform, float32 (shared/instance.h) */
    clvis_u32 first_id;  /* id of its first triangle */
    clvis_u32 mesh;      /* index of its clvis_item_mesh, | CLVIS_ITEM_TRANSFORMED */
    clvis_u32 vertex_lo; /* its first vertex counted over the items before it (64 bits) */
    clvis_u32 vertex_hi;
} clvis_item;

static inline clvis_u64 clvis_item_first_vertex(CLVIS_GLOBAL const clvis_item* item)
{
    return (clvis_u64)item->vertex_lo | ((clvis_u64)item->vertex_hi << 32);
}

/* The item of items[lo .. hi) (hi > lo) that holds triangle `id`: the last whose first_id <= id. */
static inline clvis_u32 clvis_item_of_triangle(CLVIS_GLOBAL const clvis_item* items, clvis_u32 lo, clvis_u32 hi,
                                               clvis_u32 id)
{
    while (hi - lo > 1) {
        clvis_u32 mid = lo + (hi - lo) / 2;
        if (items[mid].first_id <= id) lo = mid;
        else hi = mid;
    }
    return lo;
}

/* The item of items[lo .. hi) (hi > lo) that holds vertex v (counted as vertex_lo/hi count). */
static inline clvis_u32 clvis_item_of_vertex(CLVIS_GLOBAL const clvis_item* items, clvis_u32 lo, clvis_u32 hi,
                                             clvis_u64 v)
{
    while (hi - lo > 1) {
        clvis_u32 mid = lo + (hi - lo) / 2;
        if (clvis_item_first_vertex(items + mid) <= v) lo = mid;
        else hi = mid;
    }
    return lo;
}

/* The world-space position of local vertex v of item `item`: the expansion's bits. */
static inline clvis_vec3 clvis_item_point(CLVIS_GLOBAL const clvis_item* item, CLVIS_GLOBAL const clvis_item_mesh* meshes,
                                          CLVIS_GLOBAL const float* positions, clvis_u32 v)
{
    clvis_u32 mesh = item->mesh & ~CLVIS_ITEM_TRANSFORMED;
    CLVIS_GLOBAL const float* p = positions + 3 * ((clvis_u64)meshes[mesh].first_vertex + v);
    if (item->mesh & CLVIS_ITEM_TRANSFORMED) return clvis_instance_point(item->m, p[0], p[1], p[2]);
    clvis_vec3 r;
    r.x = p[0];
    r.y = p[1];
    r.z = p[2];
    return r;
}

#endif
