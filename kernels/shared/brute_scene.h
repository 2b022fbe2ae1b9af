/* The triangles that the brute-force kernels (ray_brute.cl, ray_query.cl's ray_query_brute) test,
   one after the other in id order. A plain scene: the expansion's world positions and indices
   (3 per triangle, in id order). Built with CLVIS_SCENE_ITEMS (a scene with instances,
   host/frame/instanced_scene.hpp): the meshes once and a record per item (shared/scene_items.h),
   each vertex through clvis_item_point, so that every triangle has the expansion's bits and the
   answers are the expansion's, with no array of the expansion's size on the device. */
#ifndef CLVIS_SHARED_BRUTE_SCENE_H
#define CLVIS_SHARED_BRUTE_SCENE_H

#include "shared/scene_items.h"

/* The scene a brute-force kernel reads, and where its walk through the ids has got to. */
typedef struct clvis_brute_scene {
    __global const float* positions; /* plain: world, per expanded vertex; items: per mesh vertex */
    __global const uint* indices;    /* plain: 3 per triangle, global; items: 3 per mesh triangle, local */
    __global const clvis_item_mesh* meshes; /* items only */
    __global const clvis_item* items;       /* items only: item_count records in id order */
    uint item_count;
    uint item;    /* the item of the triangle fetched last */
    uint next_id; /* the first id of the item after it (0xFFFFFFFF: none) */
} clvis_brute_scene;

static inline clvis_brute_scene clvis_brute_start(__global const float* positions, __global const uint* indices,
                                                  __global const clvis_item_mesh* meshes,
                                                  __global const clvis_item* items, uint item_count)
{
    clvis_brute_scene s = {positions, indices, meshes, items, item_count, 0u, 0xFFFFFFFFu};
#ifdef CLVIS_SCENE_ITEMS
    s.next_id = item_count > 1u ? items[1].first_id : 0xFFFFFFFFu;
#endif
    return s;
}

static inline clvis_vec3 clvis_brute_vertex(__global const float* positions, uint v)
{
    clvis_vec3 p = {positions[3 * (size_t)v], positions[3 * (size_t)v + 1], positions[3 * (size_t)v + 2]};
    return p;
}

/* The world-space corners of triangle `id`; ids must come in increasing order (each item's
   triangles are consecutive ids, so the walk only moves forward). */
static inline void clvis_brute_triangle(clvis_brute_scene* s, uint id, clvis_vec3* a, clvis_vec3* b, clvis_vec3* c)
{
#ifdef CLVIS_SCENE_ITEMS
    while (id >= s->next_id) {
        s->item += 1u;
        s->next_id = s->item + 1u < s->item_count ? s->items[s->item + 1u].first_id : 0xFFFFFFFFu;
    }
    __global const clvis_item* item = s->items + s->item;
    __global const clvis_item_mesh* mesh = s->meshes + (item->mesh & ~CLVIS_ITEM_TRANSFORMED);
    __global const uint* tri = s->indices + 3 * ((size_t)mesh->first_triangle + (id - item->first_id));
    *a = clvis_item_point(item, s->meshes, s->positions, tri[0]);
    *b = clvis_item_point(item, s->meshes, s->positions, tri[1]);
    *c = clvis_item_point(item, s->meshes, s->positions, tri[2]);
#else
    size_t i = 3 * (size_t)id;
    *a = clvis_brute_vertex(s->positions, s->indices[i]);
    *b = clvis_brute_vertex(s->positions, s->indices[i + 1]);
    *c = clvis_brute_vertex(s->positions, s->indices[i + 2]);
#endif
}

#endif
