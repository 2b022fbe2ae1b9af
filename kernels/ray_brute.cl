/* Casts one primary ray per pixel centre (or per sample: one launch per sample) against every triangle of the scene, in id order, with
   the same watertight test as ray_trace.cl but no BVH: the reference the BVH path must equal,
   and the brute path of host/ray/ray_pipeline.cpp for small scenes. Built with CLVIS_RASTER_RULE
   (RenderOptions::coverage), each triangle covers the pixel and gives it the depth the raster path
   would (shared/raster_rule.h) instead. The triangles come from shared/brute_scene.h: the
   expansion's arrays, or with CLVIS_SCENE_ITEMS the meshes once and a record per item. */
#include "shared/brute_scene.h"
#include "shared/camera.h"
#include "shared/layers.h"
#ifdef CLVIS_RASTER_RULE
#include "shared/raster_rule.h"
#endif
#include "shared/ray.h"
#include "shared/region.h"
#include "shared/visibility.h"

__kernel void ray_brute(clvis_camera_gpu cam, __global const float* positions, __global const uint* indices,
                        uint triangle_count, int cull, __global ulong* keys, clvis_region region,
                        __global const clvis_item_mesh* meshes, __global const clvis_item* items, uint item_count)
{
    int lx = (int)get_global_id(0), ly = (int)get_global_id(1); /* in the region (shared/region.h) */
    if (lx >= region.width || ly >= region.height) return;
    int px = region.x + lx, py = region.y + ly;
    ulong best = CLVIS_BACKGROUND_KEY;
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    ulong list[CLVIS_LAYERS]; /* depth layers (shared/layers.h): the nearest keys, sorted */
    for (int k = 0; k < CLVIS_LAYERS; ++k) list[k] = CLVIS_BACKGROUND_KEY;
#define BRUTE_KEEP(key) clvis_layers_insert(list, 1, key)
#define BRUTE_KEYS list
#else
#define BRUTE_KEEP(key) (best = (key) < best ? (key) : best)
#define BRUTE_KEYS (&best)
#endif
    clvis_brute_scene scene = clvis_brute_start(positions, indices, meshes, items, item_count);
    clvis_vec3 a, b, c;
#ifdef CLVIS_RASTER_RULE
    clvis_pixel_block blk = {px, py, 1, 1, 1};
    for (uint id = 0; id < triangle_count; ++id) {
        clvis_brute_triangle(&scene, id, &a, &b, &c);
        clvis_raster_rule_keys(cam, cull, a, b, c, id, blk, BRUTE_KEYS);
    }
#else
    clvis_vec3 origin, dir;
    clvis_vec2 f = clvis_camera_sample(cam); /* (0.5f, 0.5f): one sample */
    clvis_primary_ray(cam, (float)px + f.x, (float)py + f.y, &origin, &dir);
    clvis_ray_shear ray = clvis_make_shear(origin, dir);
    for (uint id = 0; id < triangle_count; ++id) {
        float t;
        clvis_brute_triangle(&scene, id, &a, &b, &c);
        int hit = clvis_intersect_triangle(ray, a, b, c, cam.near_d, cam.far_d, cull, &t);
        ulong key = clvis_make_key(t, id);
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
        if (hit) BRUTE_KEEP(key);
#else
        best = hit && key < best ? key : best;
#endif
    }
#endif
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    {
        size_t plane = ((size_t)region.width * (size_t)region.height) << cam.sample_log2;
        __global ulong* out = keys + (((size_t)ly * (size_t)region.width + (size_t)lx) << cam.sample_log2) + (size_t)cam.sample;
        for (int k = 0; k < CLVIS_LAYERS; ++k) out[(size_t)k * plane] = list[k];
        return;
    }
#endif
    keys[(((size_t)ly * (size_t)region.width + (size_t)lx) << cam.sample_log2) + (size_t)cam.sample] = best;
}
