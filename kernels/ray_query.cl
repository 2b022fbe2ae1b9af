/* Answers ray queries for any batch of rays (closest hit, any hit, hit count, all hits; CONVENTIONS.md
   "Ray queries", "Depth layers"), a run of rays per work-item (CLVIS_QUERY_LANES of them walked interleaved;
   on PoCL's CPU device one lane in work-groups of one work-item, host/query/ray_query.cpp), through
   the wide BVH that ray_trace.cl reads (shared/bvh.h);
   ray_query_brute tests every triangle in id order instead, the reference the BVH walk must
   equal (shared/brute_scene.h: the expansion's arrays, or with CLVIS_SCENE_ITEMS the meshes once
   and a record per item). Rays and results live in buffers of either layout (shared/ray_query.h). Launched by
   host/query/ray_query.cpp, built once per query kind (CLVIS_QUERY), stack size (CLVIS_RAY_STACK) and
   lanes, on PoCL's CPU device with CLVIS_PREFETCH. The walk is the ray kernels' one
   (shared/bvh_walk.h). With CLVIS_INSTANCES (a scene with instances) it starts in the top level
   of the two-level BVH and enters instances (shared/instance.h: world boxes widened
   conservatively, world vertices computed on the fly with the expansion's bits), so every answer
   equals the expansion's; without it the walk is the flat tree's. The walk's order never changes
   an answer (ties go to the lower id whatever the order). No packet assumption: incoherent rays
   (ambient occlusion, shadows, random) walk on their own. A leaf's triangles are tested four at a
   time (shared/tri4.h), the scalar test's bits lane by lane; the SAH sizes leaves for it
   (host/ray/bvh_build.cpp, leaf_test_cost). */
#include "shared/brute_scene.h"
#include "shared/bvh.h"
#include "shared/bvh_boxes.h"
#include "shared/instance.h"
#include "shared/ray.h"
#include "shared/ray_query.h"
#include "shared/tri4.h"
#include "shared/visibility.h"

#ifndef CLVIS_QUERY
#error "CLVIS_QUERY must be defined (shared/ray_query.h)"
#endif
#if CLVIS_QUERY == CLVIS_QUERY_ALL
#ifndef CLVIS_MAX_HITS
#error "CLVIS_MAX_HITS must be defined for all hits (shared/ray_query.h)"
#endif
/* CLVIS_ALL_COUNTS: the number of all hits is asked for, so no hit may be pruned: the walk
   visits every box the ray meets in [tmin, tmax]. Without it the walk prunes against the K-th
   nearest hit once the list is full. */
#endif
/* CLVIS_RAY_STACK: entries, at least (CLVIS_BVH_WIDTH - 1) x the wide tree's depth + 1 (each
   visited node leaves at most that many children besides the one taken; shared/bvh_walk.h checks
   it is defined). */

#if CLVIS_QUERY == CLVIS_QUERY_ANY
typedef uchar out_t;
#else
typedef uint out_t;
#endif

/* The answer for one ray so far. */
typedef struct answer {
    float t;      /* closest: nearest hit; any, count: tmax */
    uint id;      /* closest: its id; any: 0 or 1 */
    float u, v;   /* closest: barycentrics */
    uint count;   /* count: crossings; all: hits (edges inclusive) */
#if CLVIS_QUERY == CLVIS_QUERY_ALL
    uint n, k;    /* hits kept, at most k (max_hits) */
    float ht[CLVIS_MAX_HITS], hu[CLVIS_MAX_HITS], hv[CLVIS_MAX_HITS]; /* kept in order of (t, id) */
    uint hid[CLVIS_MAX_HITS];
#endif
} answer;

static clvis_ray_rec load_ray(__global const float* rays, int layout, ulong stride, ulong i)
{
    /* The layout chosen once, outside the field loop: no load of the other layout's address. */
    ulong first = layout == CLVIS_LAYOUT_AOS ? i * CLVIS_RAY_FIELDS : i;
    ulong step = layout == CLVIS_LAYOUT_AOS ? 1 : stride;
    clvis_ray_rec r = {rays[first], rays[first + step], rays[first + 2 * step], rays[first + 3 * step],
                       rays[first + 4 * step], rays[first + 5 * step], rays[first + 6 * step], rays[first + 7 * step]};
    return r;
}

/* All hits: ray i's k hits at records i k .. i k + k - 1 (AoS only), misses after the hits kept;
   its count at counts[i] when asked (counts not null). */
static void store_answer(__global out_t* out, int layout, ulong stride, ulong i, const answer* a,
                         __global uint* counts)
{
#if CLVIS_QUERY == CLVIS_QUERY_ALL
    (void)layout;
    (void)stride;
    __global uint* o = out + i * a->k * CLVIS_HIT_FIELDS;
    for (uint j = 0; j < a->k; ++j, o += CLVIS_HIT_FIELDS) {
        int kept = j < a->n;
        o[0] = as_uint(kept ? a->ht[j] : CLVIS_INFINITY);
        o[1] = kept ? a->hid[j] : CLVIS_BACKGROUND_ID;
        o[2] = as_uint(kept ? a->hu[j] : 0.0f);
        o[3] = as_uint(kept ? a->hv[j] : 0.0f);
    }
    if (counts) counts[i] = a->count;
#elif CLVIS_QUERY == CLVIS_QUERY_CLOSEST
    (void)counts;
#if CLVIS_HIT_FIELDS != 4
#error "a hit record is four words (shared/ray_query.h)"
#endif
    /* a record in one store (the field loop cost 36 instructions a ray, callgrind) */
    uint4 w = (uint4)(as_uint(a->t), a->id, as_uint(a->u), as_uint(a->v));
    if (layout == CLVIS_LAYOUT_AOS) {
        vstore4(w, i, out);
    } else {
        out[i] = w.s0;
        out[stride + i] = w.s1;
        out[2 * stride + i] = w.s2;
        out[3 * stride + i] = w.s3;
    }
#elif CLVIS_QUERY == CLVIS_QUERY_ANY
    (void)counts;
    out[i] = (uchar)a->id;
#else
    (void)counts;
    out[i] = a->count;
#endif
}

static void start_answer(clvis_ray_rec r, uint max_hits, answer* a)
{
    a->t = CLVIS_INFINITY;
    a->id = CLVIS_BACKGROUND_ID;
    a->u = a->v = 0.0f;
    a->count = 0u;
#if CLVIS_QUERY == CLVIS_QUERY_ALL
    a->n = 0u;
    a->k = max_hits;
#else
    (void)max_hits;
#endif
#if CLVIS_QUERY == CLVIS_QUERY_ANY || CLVIS_QUERY == CLVIS_QUERY_COUNT
    a->t = r.tmax;
    a->id = 0u;
#endif
}

#if CLVIS_QUERY == CLVIS_QUERY_ALL
/* Whether hit (t, id) comes after entry j of the list: keys order by t, then id. */
static inline int after_entry(const answer* a, uint j, float t, uint id)
{
    return t > a->ht[j] || (t == a->ht[j] && id > a->hid[j]);
}

/* Inserts hit (t, id) in order, the farthest dropped when the list is full. */
static void insert_hit(answer* a, float t, uint id, clvis_tri_2d p, float det)
{
    uint n = a->n;
    if (n == a->k) {
        if (after_entry(a, n - 1u, t, id)) return;
        --n;
    }
    uint j = n;
    for (; j > 0u && !after_entry(a, j - 1u, t, id); --j) {
        a->ht[j] = a->ht[j - 1u];
        a->hid[j] = a->hid[j - 1u];
        a->hu[j] = a->hu[j - 1u];
        a->hv[j] = a->hv[j - 1u];
    }
    a->ht[j] = t;
    a->hid[j] = id;
    a->hu[j] = p.v / det;
    a->hv[j] = p.w / det;
    a->n = n + 1u;
}
#endif

/* Tests one triangle; returns 1 when an any-hit query is answered. */
static int test_triangle(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c, uint id, float tmin,
                         float tmax, answer* ans)
{
    float t;
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST
    /* A ray outside the triangle pays no division, one farther than the nearest hit no barycentrics. */
    clvis_tri_2d p;
    float det;
    if (!clvis_intersect_triangle_plane(s, a, b, c, tmin, tmax, &t, &p, &det)) return 0;
    t = t + 0.0f; /* -0 becomes +0: the key orders by bits */
    if (t < ans->t || (t == ans->t && id < ans->id)) {
        ans->t = t;
        ans->id = id;
        ans->u = p.v / det;
        ans->v = p.w / det;
    }
    return 0;
#elif CLVIS_QUERY == CLVIS_QUERY_ALL
    /* Edges inclusive, the closest hit's test, u and v: with max_hits 1 the closest hit's bits. */
    clvis_tri_2d p;
    float det;
    if (!clvis_intersect_triangle_plane(s, a, b, c, tmin, tmax, &t, &p, &det)) return 0;
    ans->count += 1u;
    insert_hit(ans, t + 0.0f, id, p, det);
    return 0;
#elif CLVIS_QUERY == CLVIS_QUERY_ANY
    if (clvis_intersect_triangle(s, a, b, c, tmin, tmax, CLVIS_CULL_NONE, &t)) {
        ans->id = 1u;
        return 1;
    }
    return 0;
#else
    ans->count += (uint)clvis_intersect_triangle_half_open(s, a, b, c, tmin, tmax, &t);
    return 0;
#endif
}

/* The far end of the interval that a box must reach: the nearest hit so far for closest, the
   K-th kept one for all hits once K are kept (unless all are counted). Inclusive: a hit at that t
   with a lower id still enters. */
static float query_far(clvis_ray_rec r, const answer* a)
{
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST
    return a->t < r.tmax ? a->t : r.tmax;
#elif CLVIS_QUERY == CLVIS_QUERY_ALL && !defined(CLVIS_ALL_COUNTS)
    float kth = a->n == a->k ? a->ht[a->k - 1u] : CLVIS_INFINITY;
    return kth < r.tmax ? kth : r.tmax;
#else
    return r.tmax;
#endif
}

/* Tests the n triangles of a leaf from `first`, those of instance xi (none: world-space already),
   four at a time (shared/tri4.h); the scalar test decides the lanes that need its fallbacks. Each
   query's answer is order-independent (closest: the least (t, id); all: the K least, inserted in
   order; any, count), so it is the one the triangles tested one by one give. */
static int leaf(__global const clvis_bvh_tri* tris, uint first, uint n, __global const clvis_instance* xi,
                clvis_ray_shear s, clvis_ray_rec r, answer* a)
{
    for (uint g = first; g < first + n; g += 4u) {
        uint m = min(first + n - g, 4u);
        clvis_tri4_verts vq;
#ifdef CLVIS_INSTANCES
        clvis_tri4_load_instance(tris, g, m, xi, &vq);
#else
        (void)xi;
        clvis_tri4_load(tris, g, m, &vq);
#endif
        clvis_tri4 q;
        clvis_tri4_test(s, &vq, m, r.tmin, query_far(r, a), &q);
#if CLVIS_QUERY == CLVIS_QUERY_ANY
        if (q.hits) {
            a->id = 1u;
            return 1;
        }
#elif CLVIS_QUERY == CLVIS_QUERY_COUNT
        a->count += (uint)popcount(q.hits);
#else
        if (q.hits) {
            float t[4], v[4], w[4], det[4];
            uint id[4];
            vstore4(q.t, 0, t), vstore4(q.v, 0, v), vstore4(q.w, 0, w), vstore4(q.det, 0, det);
            vstore4(vq.id, 0, id);
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST
            /* the least (t, id) of the hits and the answer so far; one division for the winner */
            int best = -1;
            float bt = a->t;
            uint bid = a->id;
            for (int k = 0; k < 4; ++k) {
                float tk = t[k] + 0.0f; /* -0 becomes +0: the key orders by bits */
                if ((q.hits & (1 << k)) && (tk < bt || (tk == bt && id[k] < bid))) {
                    bt = tk;
                    bid = id[k];
                    best = k;
                }
            }
            if (best >= 0) {
                a->t = bt;
                a->id = bid;
                a->u = v[best] / det[best];
                a->v = w[best] / det[best];
            }
#else
            for (int k = 0; k < 4; ++k) {
                if (!(q.hits & (1 << k))) continue;
                float tk = t[k] + 0.0f; /* -0 becomes +0: the key orders by bits */
                clvis_tri_2d p;
                p.v = v[k];
                p.w = w[k];
                a->count += 1u;
                insert_hit(a, tk, id[k], p, det[k]);
            }
#endif
        }
#endif
        for (int k = 0; q.redo >> k; ++k) {
            if (!(q.redo & (1 << k))) continue;
#ifdef CLVIS_INSTANCES
            float v[9];
            uint id = clvis_instance_triangle(tris + g + (uint)k, xi, v);
            clvis_vec3 v0 = {v[0], v[1], v[2]}, v1 = {v[3], v[4], v[5]}, v2 = {v[6], v[7], v[8]};
#else
            __global const clvis_bvh_tri* tr = tris + g + (uint)k;
            clvis_vec3 v0 = {tr->v0_x, tr->v0_y, tr->v0_z}, v1 = {tr->v1_x, tr->v1_y, tr->v1_z};
            clvis_vec3 v2 = {tr->v2_x, tr->v2_y, tr->v2_z};
            uint id = tr->id;
#endif
            if (test_triangle(s, v0, v1, v2, id, r.tmin, query_far(r, a), a)) return 1;
        }
    }
    return 0;
}

/* Whether the interval shrinks as hits are found (the walk orders children and drops far ones). */
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST || (CLVIS_QUERY == CLVIS_QUERY_ALL && !defined(CLVIS_ALL_COUNTS))
#define QUERY_PRUNES 1
#else
#define QUERY_PRUNES 0
#endif

/* One ray and its answer so far: the walk's context (CLVIS_WALK_CTX). */
typedef struct walker {
    clvis_ray_rec r;
    clvis_ray_shear s;
    clvis_box_ray br;
    answer a;
    uint ray;   /* its index in the batch */
} walker;

/* The node test: the children the ray meets within its interval. Closest hits (and all hits
   without counts) order them by entry distance (and drop a popped one that starts past the
   nearest hit so far, the K-th); any hit and counts keep slot order (keys 0): their interval never
   shrinks, and any hit ends the walk at once. */
static inline CLVIS_ALWAYS_INLINE int query_children(walker* w, __global const clvis_wide_node* nd,
                                                     __global const clvis_instance* xi, float keys[CLVIS_BVH_WIDTH])
{
    clvis_wfloat e;
    clvis_wint hit = clvis_hits_boxes(nd, xi, w->br, w->r.tmin, query_far(w->r, &w->a), &e);
#if QUERY_PRUNES
    clvis_vstore_w(e, 0, keys);
#else
    clvis_vstore_w((clvis_wfloat)(0.0f), 0, keys);
#endif
    return clvis_wmask_bits(hit);
}

#define CLVIS_WALK_CTX walker
#define CLVIS_WALK_CHILDREN(w, v, nd, xi, keys) query_children(w, nd, xi, keys)
#if QUERY_PRUNES
#define CLVIS_WALK_KEY_SKIP(w, v, key) ((key) > query_far((w)->r, &(w)->a) * CLVIS_IZE_SCALE)
#else
#define CLVIS_WALK_KEY_SKIP(w, v, key) 0
#endif
#define CLVIS_WALK_BOX_SKIP(w, v, nd, k, xi) 0
#define CLVIS_WALK_LEAF(w, v, tris, first, count, xi) leaf(tris, first, count, xi, (w)->s, (w)->r, &(w)->a)
#include "shared/bvh_walk.h"

#ifdef CLVIS_INSTANCES
#define QUERY_TWO_LEVEL 1
#else
#define QUERY_TWO_LEVEL 0
#endif

/* Starts ray i's walk in a lane (at once answered when invalid or the tree is empty). */
static void walk_start(__global const float* rays, int layout, ulong stride, ulong offset, uint i, uint node_count,
                       __global uint* invalid, uint max_hits, walker* w, clvis_walk* walk)
{
    w->r = load_ray(rays, layout, stride, offset + i);
    start_answer(w->r, max_hits, &w->a);
    w->ray = i;
    int valid = clvis_ray_valid(w->r);
    if (!valid) atomic_inc(invalid);
    clvis_walk_start(walk, valid ? node_count : 0u, QUERY_TWO_LEVEL);
    clvis_vec3 o = {w->r.ox, w->r.oy, w->r.oz}, d = {w->r.dx, w->r.dy, w->r.dz};
    w->s = clvis_make_shear(o, d);
    w->br = clvis_make_box_ray(o, d);
}

/* CLVIS_QUERY_LANES: rays a work-item walks interleaved (1, the default, walks them one after the
   other). */
#ifndef CLVIS_QUERY_LANES
#define CLVIS_QUERY_LANES 1
#endif

/* Both kernels' last arguments, all hits only: max_hits (the list's length, 1 .. CLVIS_MAX_HITS) and
   counts (null: not asked). The other queries take neither: QUERY_ALL_DEFAULTS, first in each
   kernel's body, gives them max_hits 1 and no counts. */
#if CLVIS_QUERY == CLVIS_QUERY_ALL
#define QUERY_ALL_ARGS , uint max_hits, __global uint* counts
#define QUERY_ALL_DEFAULTS
#else
#define QUERY_ALL_ARGS
#define QUERY_ALL_DEFAULTS const uint max_hits = 1u; __global uint* counts = 0;
#endif

/* Work-item g answers rays [g * per_item, (g + 1) * per_item) of the batch, CLVIS_QUERY_LANES at a
   time: a lane whose ray is answered stores it and takes the next. `instances` only with
   CLVIS_INSTANCES: the flat build's arguments (and code) are as before. */
__kernel void ray_query(__global const clvis_wide_node* nodes, uint node_count, __global const clvis_bvh_tri* tris,
#ifdef CLVIS_INSTANCES
                        __global const clvis_instance* instances,
#endif
                        __global const float* rays, int ray_layout, ulong ray_stride, ulong ray_offset, uint count,
                        uint per_item, __global out_t* out, int out_layout, ulong out_stride, ulong out_offset,
                        __global uint* invalid QUERY_ALL_ARGS)
{
    QUERY_ALL_DEFAULTS
#ifndef CLVIS_INSTANCES
    __global const clvis_instance* instances = 0;
#endif
    ulong begin = (ulong)get_global_id(0) * per_item;
    if (begin >= count) return;
    uint next = (uint)begin, end = (ulong)count - begin < per_item ? count : (uint)begin + per_item;
#if CLVIS_QUERY_LANES == 1
    /* One lane: the rays one after the other, each walk in a loop of its own, so that the
       compiler keeps the ray (origin, 1 / direction, the box planes it meets first) in
       registers across the walk's steps; the lanes' loop below kept them in memory and reloaded
       them at every node (AO rays through the bunny: 10 % fewer instructions, callgrind). */
    for (; next < end; ++next) {
        walker one;
        clvis_walk walk1;
        clvis_walk_stack st1;
        walk_start(rays, ray_layout, ray_stride, ray_offset, next, node_count, invalid, max_hits, &one, &walk1);
        while (walk1.node != CLVIS_WALK_DONE)
            clvis_walk_step(&one, 0, QUERY_TWO_LEVEL, nodes, tris, instances, &walk1, &st1);
        store_answer(out, out_layout, out_stride, out_offset + next, &one.a, counts);
    }
#else
    /* CLVIS_QUERY_LANES walks interleaved a step (a node) at a time: while one lane waits for the
       node it popped, the others' loads are in flight */
    walker w[CLVIS_QUERY_LANES];
    clvis_walk walk[CLVIS_QUERY_LANES];
    clvis_walk_stack st[CLVIS_QUERY_LANES];
    uint busy = 0; /* lanes holding a ray */
    for (int j = 0; j < CLVIS_QUERY_LANES; ++j) {
        walk[j].node = CLVIS_WALK_DONE;
        w[j].ray = end; /* none */
        if (next < end) {
            walk_start(rays, ray_layout, ray_stride, ray_offset, next++, node_count, invalid, max_hits, &w[j], &walk[j]);
            ++busy;
        }
    }
    while (busy > 0) {
        for (int j = 0; j < CLVIS_QUERY_LANES; ++j) {
            if (w[j].ray == end) continue;
            if (walk[j].node != CLVIS_WALK_DONE)
                clvis_walk_step(&w[j], 0, QUERY_TWO_LEVEL, nodes, tris, instances, &walk[j], &st[j]);
            if (walk[j].node != CLVIS_WALK_DONE) continue;
            store_answer(out, out_layout, out_stride, out_offset + w[j].ray, &w[j].a, counts);
            if (next < end) {
                walk_start(rays, ray_layout, ray_stride, ray_offset, next++, node_count, invalid, max_hits, &w[j], &walk[j]);
            } else {
                w[j].ray = end;
                --busy;
            }
        }
    }
#endif
}

__kernel void ray_query_brute(__global const float* positions, __global const uint* indices, uint triangle_count,
                              __global const clvis_item_mesh* meshes, __global const clvis_item* items, uint item_count,
                              __global const float* rays, int ray_layout, ulong ray_stride, ulong ray_offset,
                              uint count, __global out_t* out, int out_layout, ulong out_stride, ulong out_offset,
                              __global uint* invalid QUERY_ALL_ARGS)
{
    QUERY_ALL_DEFAULTS
    uint i = (uint)get_global_id(0);
    if (i >= count) return;
    clvis_ray_rec r = load_ray(rays, ray_layout, ray_stride, ray_offset + i);
    answer a;
    start_answer(r, max_hits, &a);
    if (!clvis_ray_valid(r)) {
        atomic_inc(invalid);
    } else {
        clvis_vec3 o = {r.ox, r.oy, r.oz}, d = {r.dx, r.dy, r.dz};
        clvis_ray_shear s = clvis_make_shear(o, d);
        clvis_brute_scene scene = clvis_brute_start(positions, indices, meshes, items, item_count);
        for (uint id = 0; id < triangle_count; ++id) {
            clvis_vec3 v0, v1, v2;
            clvis_brute_triangle(&scene, id, &v0, &v1, &v2);
            if (test_triangle(s, v0, v1, v2, id, r.tmin, r.tmax, &a)) break;
        }
    }
    store_answer(out, out_layout, out_stride, out_offset + i, &a, counts);
}
