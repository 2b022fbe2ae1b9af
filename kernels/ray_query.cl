/* Answers ray queries for any batch of rays (closest hit, any hit, hit count; CONVENTIONS.md "Ray
   queries"), a run of rays per work-item (CLVIS_QUERY_LANES of them walked interleaved), through
   the 4-wide BVH that ray_trace.cl reads (shared/bvh.h);
   ray_query_brute tests every triangle in id order instead, the reference the BVH walk must
   equal. Rays and results live in buffers of either layout (shared/ray_query.h). Launched by
   host/ray/ray_query.cpp, built once per query kind (CLVIS_QUERY), stack size (CLVIS_RAY_STACK) and
   lanes, on PoCL's CPU device with CLVIS_PREFETCH. With CLVIS_INSTANCES (a scene with instances) the walk
   starts in the top level of the two-level BVH and enters instances as ray_trace.cl does
   (shared/instance.h: world boxes widened conservatively, world vertices computed on the fly with
   the expansion's bits), so every answer equals the expansion's; without it the walk is the flat
   tree's. The walk's order never changes an answer (ties go to the lower id whatever the order).
   No packet assumption: incoherent rays (ambient occlusion, shadows, random) walk on their own. */
#include "shared/bvh.h"
#include "shared/instance.h"
#include "shared/ray.h"
#include "shared/ray_query.h"
#include "shared/visibility.h"

#ifndef CLVIS_QUERY
#error "CLVIS_QUERY must be defined (shared/ray_query.h)"
#endif
/* CLVIS_RAY_STACK: entries, at least 3 x the 4-wide tree's depth + 1 (each visited node leaves
   at most three children besides the one taken). */
#ifndef CLVIS_RAY_STACK
#error "CLVIS_RAY_STACK must be defined"
#endif

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
    uint count;   /* count: crossings */
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

static void store_answer(__global out_t* out, int layout, ulong stride, ulong i, answer a)
{
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST
    uint w[CLVIS_HIT_FIELDS] = {as_uint(a.t), a.id, as_uint(a.u), as_uint(a.v)};
    for (int k = 0; k < CLVIS_HIT_FIELDS; ++k) {
        if (layout == CLVIS_LAYOUT_AOS) out[i * CLVIS_HIT_FIELDS + (ulong)k] = w[k];
        else out[(ulong)k * stride + i] = w[k];
    }
#elif CLVIS_QUERY == CLVIS_QUERY_ANY
    out[i] = (uchar)a.id;
#else
    out[i] = a.count;
#endif
}

static answer start_answer(clvis_ray_rec r)
{
    answer a = {CLVIS_INFINITY, CLVIS_BACKGROUND_ID, 0.0f, 0.0f, 0u};
#if CLVIS_QUERY != CLVIS_QUERY_CLOSEST
    a.t = r.tmax;
    a.id = 0u;
#endif
    return a;
}

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

/* The far end of the interval that a box must reach: the nearest hit so far for closest. */
static float query_far(clvis_ray_rec r, const answer* a)
{
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST
    return a->t < r.tmax ? a->t : r.tmax;
#else
    return r.tmax;
#endif
}

/* Tests the n triangles of a leaf from `first`, those of instance xi (none: world-space already). */
static int leaf(__global const clvis_bvh_tri* tris, uint first, uint n, __global const clvis_instance* xi,
                clvis_ray_shear s, clvis_ray_rec r, answer* a)
{
    for (uint k = first; k < first + n; ++k) {
        __global const clvis_bvh_tri* tr = tris + k;
#ifdef CLVIS_INSTANCES
        float v[9];
        uint id = clvis_instance_triangle(tr, xi, v);
        clvis_vec3 v0 = {v[0], v[1], v[2]}, v1 = {v[3], v[4], v[5]}, v2 = {v[6], v[7], v[8]};
        if (test_triangle(s, v0, v1, v2, id, r.tmin, query_far(r, a), a)) return 1;
#else
        clvis_vec3 v0 = {tr->v0_x, tr->v0_y, tr->v0_z}, v1 = {tr->v1_x, tr->v1_y, tr->v1_z};
        clvis_vec3 v2 = {tr->v2_x, tr->v2_y, tr->v2_z};
        if (test_triangle(s, v0, v1, v2, tr->id, r.tmin, query_far(r, a), a)) return 1;
#endif
    }
    return 0;
}

#ifdef CLVIS_INSTANCES
/* The world boxes of node n's four children in transformed instance xi, as the node stores them:
   lo x, y, z then hi x, y, z, four lanes each. */
static void world_boxes(__global const clvis_bvh4_node* n, __global const clvis_instance* xi, float w[24])
{
    for (int k = 0; k < 4; ++k) {
        float lo[3], hi[3];
        clvis_instance_child_box(n, k, xi, lo, hi);
        for (int c = 0; c < 3; ++c) {
            w[4 * c + k] = lo[c];
            w[12 + 4 * c + k] = hi[c];
        }
    }
}
#endif

/* clvis_ray_hits_box on the four children of a node at once: the same operations lane by lane.
   The flat tree reads each axis' near and far planes straight from the node (lo_x, hi_x, ...
   follow each other: the plane a ray meets first is the row after lo when its direction is
   negative), so no select runs per node. */
static int4 hits_boxes(__global const clvis_bvh4_node* n, __global const clvis_instance* xi, clvis_box_ray br,
                       float near_t, float far_t, float4* entry)
{
#ifdef CLVIS_INSTANCES
    float4 lox = vload4(0, n->lo_x), hix = vload4(0, n->hi_x);
    float4 loy = vload4(0, n->lo_y), hiy = vload4(0, n->hi_y);
    float4 loz = vload4(0, n->lo_z), hiz = vload4(0, n->hi_z);
    if (xi) {
        float w[24];
        world_boxes(n, xi, w);
        lox = vload4(0, w), loy = vload4(1, w), loz = vload4(2, w);
        hix = vload4(3, w), hiy = vload4(4, w), hiz = vload4(5, w);
    }
    float4 nx = ((br.neg_x ? hix : lox) - br.origin.x) * br.inv.x;
    float4 ny = ((br.neg_y ? hiy : loy) - br.origin.y) * br.inv.y;
    float4 nz = ((br.neg_z ? hiz : loz) - br.origin.z) * br.inv.z;
    float4 fx = ((br.neg_x ? lox : hix) - br.origin.x) * br.inv.x;
    float4 fy = ((br.neg_y ? loy : hiy) - br.origin.y) * br.inv.y;
    float4 fz = ((br.neg_z ? loz : hiz) - br.origin.z) * br.inv.z;
#else
    /* lo_x, hi_x, lo_y, hi_y, lo_z, hi_z: four floats each, 16-byte aligned in a 128-byte node (one
       aligned load per row, where vload4 of a float pointer is split in two) */
    __global const float4* rows = (__global const float4*)n->lo_x;
    float4 nx = (rows[br.neg_x] - br.origin.x) * br.inv.x;
    float4 ny = (rows[2 + br.neg_y] - br.origin.y) * br.inv.y;
    float4 nz = (rows[4 + br.neg_z] - br.origin.z) * br.inv.z;
    float4 fx = (rows[1 - br.neg_x] - br.origin.x) * br.inv.x;
    float4 fy = (rows[3 - br.neg_y] - br.origin.y) * br.inv.y;
    float4 fz = (rows[5 - br.neg_z] - br.origin.z) * br.inv.z;
#endif
    /* clvis_raise / clvis_lower: a NaN (origin in a slab's plane, 0 * inf) constrains nothing */
    float4 t0 = (float4)(near_t);
    t0 = select(t0, nx, nx > t0);
    t0 = select(t0, ny, ny > t0);
    t0 = select(t0, nz, nz > t0);
    float4 t1 = (float4)(CLVIS_INFINITY);
    t1 = select(t1, fx, fx < t1);
    t1 = select(t1, fy, fy < t1);
    t1 = select(t1, fz, fz < t1);
    t1 = t1 * CLVIS_IZE_SCALE;
    *entry = t0;
    return (t0 <= t1) & (t0 <= (float4)(far_t * CLVIS_IZE_SCALE));
}

/* One ray's walk, advanced a node at a time (walk_step) so that a work-item can interleave the
   walks of CLVIS_QUERY_LANES rays: while one lane waits for the node it popped, the others' loads
   are in flight. Of the children that the ray meets, the nearest is visited next; the others are
   pushed far to near (by entry distance) as (child, count) with their entry distance, and popped
   while they may still hold a hit before the nearest so far (closest) or in [tmin, tmax]. With
   CLVIS_INSTANCES each entry also remembers its instance (or the top level, or the plain meshes'
   flat tree), a top-level leaf enters its instances (the first at once, the others pushed as
   CLVIS_ENTER_INSTANCE entries at the leaf's entry distance), and boxes and triangles of an
   instance are tested in world space. */
typedef struct walker {
    clvis_ray_rec r;
    clvis_ray_shear s;
    clvis_box_ray br;
    answer a;
    uint ray;   /* its index in the batch */
    uint node;  /* the node it visits next; CLVIS_BACKGROUND_ID once answered */
    uint sp;    /* stack entries */
#ifdef CLVIS_INSTANCES
    uint inst;  /* the level it walks: an instance, CLVIS_INST_TOP or CLVIS_INST_FLAT */
#endif
} walker;

/* The stacks of one lane. */
typedef struct walk_stack {
    uint ref[CLVIS_RAY_STACK];   /* a child: a node's index or a leaf's first triangle slot */
    uint count[CLVIS_RAY_STACK]; /* 0: a node; > 0: the leaf's triangles */
    float enter[CLVIS_RAY_STACK];
#ifdef CLVIS_INSTANCES
    uint inst[CLVIS_RAY_STACK];
#endif
} walk_stack;

/* Visits w->node, then pops entries (testing leaves) until the next node to visit; w->node is
   CLVIS_BACKGROUND_ID once the ray is answered. */
static void walk_step(__global const clvis_bvh4_node* nodes, __global const clvis_bvh_tri* tris,
                      __global const clvis_instance* instances, walker* w, walk_stack* st)
{
    __global const clvis_bvh4_node* n = nodes + w->node;
    /* instance w->inst's record, none in the top level and the flat tree */
#ifdef CLVIS_INSTANCES
    __global const clvis_instance* xi = w->inst < CLVIS_INST_TOP ? instances + w->inst : 0;
#else
    __global const clvis_instance* xi = 0;
#endif
    float4 e4;
    int4 hit4 = hits_boxes(n, xi, w->br, w->r.tmin, query_far(w->r, &w->a), &e4);
    float e[4];
    int h[4];
    vstore4(e4, 0, e);
    vstore4(hit4, 0, h);
    uint first = w->sp, sp = w->sp;
    /* The nearest child the ray meets (closest; the first otherwise) is visited next without a
       trip through the stack; the others are pushed far to near (closest) as (child, count). */
    int next = -1;
    float next_e = 0.0f;
    /* Unrolled, so that the four children's hits and entries stay in registers instead of going
       through e[] and h[] in memory. (A loop over the set bits of a hit mask instead, with clz,
       crashes Oclgrind 21.10's uninitialised-value checker, and was no faster on PoCL; ranks from
       comparisons in registers that put every met child on the stack without a branch per child
       measured 10-20 % slower.) */
#pragma unroll
    for (uint k = 0; k < 4; ++k) {
        if (!h[k]) continue;
        clvis_prefetch_child(nodes, tris, n, (int)k);
        if (next < 0) {
            next = (int)k;
            next_e = e[k];
            continue;
        }
        uint push = k;
        float push_e = e[k];
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST
        if (push_e < next_e) {
            push = (uint)next;
            push_e = next_e;
            next = (int)k;
            next_e = e[k];
        }
#endif
        uint i = sp++;
#if CLVIS_QUERY == CLVIS_QUERY_CLOSEST
        for (; i > first && st->enter[i - 1] < push_e; --i) {
            st->ref[i] = st->ref[i - 1];
            st->count[i] = st->count[i - 1];
            st->enter[i] = st->enter[i - 1];
        }
#endif
        st->ref[i] = n->child[push];
        st->count[i] = n->count[push];
        st->enter[i] = push_e;
    }
#ifdef CLVIS_INSTANCES
    for (uint j = first; j < sp; ++j) st->inst[j] = w->inst; /* all of this node */
#endif
    w->node = CLVIS_BACKGROUND_ID;
    /* the entry at hand: child `ref` (a node when cnt is 0, else a leaf of cnt), met at `at` */
    uint ref = 0, cnt = 0;
    float at = next_e;
    if (next >= 0) {
        ref = n->child[next];
        cnt = n->count[next];
    }
    for (;;) {
        if (next < 0) {
            if (sp == 0) break;
            --sp;
            at = st->enter[sp];
            if (at > query_far(w->r, &w->a) * CLVIS_IZE_SCALE) continue;
            ref = st->ref[sp];
            cnt = st->count[sp];
#ifdef CLVIS_INSTANCES
            w->inst = st->inst[sp];
            xi = w->inst < CLVIS_INST_TOP ? instances + w->inst : 0;
            if (ref == CLVIS_ENTER_INSTANCE) {
                w->node = clvis_enter_instance(instances, w->inst, &w->inst, &xi);
                break;
            }
#endif
        }
        next = -1;
        if (cnt == 0) {
            w->node = ref;
            break;
        }
#ifdef CLVIS_INSTANCES
        if (w->inst == CLVIS_INST_TOP) {
            uint pushed = sp;
            w->node = clvis_enter_instances(ref, cnt, instances, st->ref, st->inst, &sp, &w->inst, &xi);
            for (; pushed < sp; ++pushed) {
                st->enter[pushed] = at; /* the leaf's entry distance */
                st->count[pushed] = 0u;
            }
            break;
        }
#endif
        if (leaf(tris, ref, cnt, xi, w->s, w->r, &w->a)) break; /* answered: node stays none */
    }
    w->sp = sp;
}

/* Starts ray i's walk in a lane (at once answered when invalid or the tree is empty). */
static void walk_start(__global const float* rays, int layout, ulong stride, ulong offset, uint i, uint node_count,
                       __global uint* invalid, walker* w)
{
    w->r = load_ray(rays, layout, stride, offset + i);
    w->a = start_answer(w->r);
    w->ray = i;
    w->sp = 0;
#ifdef CLVIS_INSTANCES
    w->inst = CLVIS_INST_TOP;
#endif
    int valid = clvis_ray_valid(w->r);
    if (!valid) atomic_inc(invalid);
    w->node = valid && node_count > 0 ? 0u : CLVIS_BACKGROUND_ID;
    clvis_vec3 o = {w->r.ox, w->r.oy, w->r.oz}, d = {w->r.dx, w->r.dy, w->r.dz};
    w->s = clvis_make_shear(o, d);
    w->br = clvis_make_box_ray(o, d);
}

/* CLVIS_QUERY_LANES: rays a work-item walks interleaved (1, the default, walks them one after the
   other). */
#ifndef CLVIS_QUERY_LANES
#define CLVIS_QUERY_LANES 1
#endif

/* Work-item g answers rays [g * per_item, (g + 1) * per_item) of the batch, CLVIS_QUERY_LANES at a
   time: a lane whose ray is answered stores it and takes the next. `instances` only with
   CLVIS_INSTANCES: the flat build's arguments (and code) are as before. */
__kernel void ray_query(__global const clvis_bvh4_node* nodes, uint node_count, __global const clvis_bvh_tri* tris,
#ifdef CLVIS_INSTANCES
                        __global const clvis_instance* instances,
#endif
                        __global const float* rays, int ray_layout, ulong ray_stride, ulong ray_offset, uint count,
                        uint per_item, __global out_t* out, int out_layout, ulong out_stride, ulong out_offset,
                        __global uint* invalid)
{
#ifndef CLVIS_INSTANCES
    __global const clvis_instance* instances = 0;
#endif
    ulong begin = (ulong)get_global_id(0) * per_item;
    if (begin >= count) return;
    uint next = (uint)begin, end = (ulong)count - begin < per_item ? count : (uint)begin + per_item;
    walker w[CLVIS_QUERY_LANES];
    walk_stack st[CLVIS_QUERY_LANES];
    uint busy = 0; /* lanes holding a ray */
    for (int j = 0; j < CLVIS_QUERY_LANES; ++j) {
        w[j].node = CLVIS_BACKGROUND_ID;
        w[j].ray = end; /* none */
        if (next < end) {
            walk_start(rays, ray_layout, ray_stride, ray_offset, next++, node_count, invalid, &w[j]);
            ++busy;
        }
    }
    while (busy > 0) {
        for (int j = 0; j < CLVIS_QUERY_LANES; ++j) {
            if (w[j].ray == end) continue;
            if (w[j].node != CLVIS_BACKGROUND_ID) walk_step(nodes, tris, instances, &w[j], &st[j]);
            if (w[j].node != CLVIS_BACKGROUND_ID) continue;
            store_answer(out, out_layout, out_stride, out_offset + w[j].ray, w[j].a);
            if (next < end) {
                walk_start(rays, ray_layout, ray_stride, ray_offset, next++, node_count, invalid, &w[j]);
            } else {
                w[j].ray = end;
                --busy;
            }
        }
    }
}

static clvis_vec3 load_vertex(__global const float* positions, uint v)
{
    clvis_vec3 p = {positions[3 * (size_t)v], positions[3 * (size_t)v + 1], positions[3 * (size_t)v + 2]};
    return p;
}

__kernel void ray_query_brute(__global const float* positions, __global const uint* indices, uint triangle_count,
                              __global const float* rays, int ray_layout, ulong ray_stride, ulong ray_offset,
                              uint count, __global out_t* out, int out_layout, ulong out_stride, ulong out_offset,
                              __global uint* invalid)
{
    uint i = (uint)get_global_id(0);
    if (i >= count) return;
    clvis_ray_rec r = load_ray(rays, ray_layout, ray_stride, ray_offset + i);
    answer a = start_answer(r);
    if (!clvis_ray_valid(r)) {
        atomic_inc(invalid);
    } else {
        clvis_vec3 o = {r.ox, r.oy, r.oz}, d = {r.dx, r.dy, r.dz};
        clvis_ray_shear s = clvis_make_shear(o, d);
        for (uint id = 0; id < triangle_count; ++id) {
            size_t j = 3 * (size_t)id;
            if (test_triangle(s, load_vertex(positions, indices[j]), load_vertex(positions, indices[j + 1]),
                              load_vertex(positions, indices[j + 2]), id, r.tmin, r.tmax, &a))
                break;
        }
    }
    store_answer(out, out_layout, out_stride, out_offset + i, a);
}
