/* Casts one primary ray per pixel centre through the BVH (shared/bvh.h) and writes the visibility
   key of every pixel; launched by host/ray/ray_pipeline.cpp. Each work-item traces a packet of 4x4
   pixels as the 16 lanes of OpenCL vectors (Wald et al., "Interactive rendering with coherent ray
   tracing", 2001): one walk of the wide tree per packet (shared/bvh_walk.h), nearest child
   first; every box and triangle test runs on all 16 rays at once, the same operations as the
   scalar tests of shared/ray.h, so each ray gets the bits that ray_brute.cl computes for it. A
   child is skipped when no ray of the packet can meet it before its nearest hit so far. A
   perspective packet walks a flat tree by an interval test of the whole packet first (WALK_SPAN).
   Work-groups are screen tiles of packets. Built with CLVIS_RASTER_RULE (RenderOptions::coverage),
   each candidate triangle is judged by the raster path's predicate instead (packet_rule_leaf). */
#include "shared/ray_packet.h"
#include "shared/region.h"
#include "shared/visibility.h"
#ifdef CLVIS_RASTER_RULE
/* depth layers: a packet's keys are K layers of 16, layer k of lane l at best[k * 16 + l] */
#define CLVIS_RULE_LAYER_STRIDE CLVIS_PACKET
#include "shared/raster_rule.h"
#else
#include "shared/ray_packet_tri.h"
#endif

#ifdef CLVIS_RASTER_RULE
/* Coverage by the raster path's rule (RenderOptions::coverage, CLVIS_RASTER_RULE): the packet
   keeps its 16 keys in private memory, every candidate triangle leaves at each pixel the key the
   raster path leaves there (shared/raster_rule.h: set up once per triangle for the whole packet),
   and a box is skipped only where no ray can find such a key in it: the ray misses the box
   widened by clvis_rule_box_of's margin, or every key in it would lie beyond the ray's nearest
   (its depth range starts past it) or before near. */
static lanes_i packet_hits_box_rule(const packet* p, clvis_camera_gpu cam, __global const clvis_wide_node* n, int k,
                                    __global const clvis_instance* xi, lanes_f cull)
{
    float lo[3], hi[3];
    clvis_instance_child_box(n, k, xi, lo, hi);
    float lx = lo[0], ly = lo[1], lz = lo[2], hx = hi[0], hy = hi[1], hz = hi[2];
    if (!(lx <= hx && ly <= hy && lz <= hz)) return (lanes_i)(0); /* an unused slot */
    clvis_rule_box b = clvis_rule_box_of(cam, lx, ly, lz, hx, hy, hz);
    if (b.hi_d < cam.near_d) return (lanes_i)(0);
    float lo_d = b.lo_d == b.lo_d ? b.lo_d : -CLVIS_INFINITY; /* a NaN (overflow) skips nothing */
    lanes_f lox = (lanes_f)(lx - b.margin), loy = (lanes_f)(ly - b.margin), loz = (lanes_f)(lz - b.margin);
    lanes_f hix = (lanes_f)(hx + b.margin), hiy = (lanes_f)(hy + b.margin), hiz = (lanes_f)(hz + b.margin);
    /* from -inf and +inf, so that a NaN slab (an origin in a slab plane of an axis the ray runs
       parallel to: 0 * inf) is ignored on every axis, the first included */
    lanes_f t0 = raise(raise(raise((lanes_f)(-CLVIS_INFINITY), (select(lox, hix, p->nx) - p->ox) * p->ix),
                             (select(loy, hiy, p->ny) - p->oy) * p->iy),
                       (select(loz, hiz, p->nz) - p->oz) * p->iz);
    lanes_f t1 = lower(lower(lower((lanes_f)(CLVIS_INFINITY), (select(hix, lox, p->nx) - p->ox) * p->ix),
                             (select(hiy, loy, p->ny) - p->oy) * p->iy),
                       (select(hiz, loz, p->nz) - p->oz) * p->iz);
    /* the whole line, either side of its origin; the margin dwarfs the slab test's rounding */
    t0 = t0 - fabs(t0) * 9.5367431640625e-7f;
    t1 = t1 + fabs(t1) * 9.5367431640625e-7f;
    return (t0 <= t1) & ((lanes_f)(lo_d) <= cull);
}

/* The raster rule on every pixel of the packet for the triangles of a leaf; `cull` becomes each
   ray's nearest key depth (or far). Kept out of line, as packet_test_leaf. */
static CLVIS_NOINLINE void packet_rule_leaf(__global const clvis_bvh_tri* tris, uint first, uint count,
                                            __global const clvis_instance* xi, clvis_camera_gpu cam, int faces, int x0,
                                            int y0, ulong* best, lanes_f* cull)
{
    clvis_pixel_block blk = {x0, y0, min(CLVIS_PACKET_W, cam.width - x0), min(CLVIS_PACKET_H, cam.height - y0),
                             CLVIS_PACKET_W};
    for (uint k = first; k < first + count; ++k) {
        float v[9];
        uint id = clvis_instance_triangle(tris + k, xi, v);
        clvis_vec3 a = {v[0], v[1], v[2]}, b = {v[3], v[4], v[5]}, c = {v[6], v[7], v[8]};
        clvis_raster_rule_keys(cam, faces, a, b, c, id, blk, best);
    }
    uint depth[CLVIS_PACKET];
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    for (int l = 0; l < CLVIS_PACKET; ++l) depth[l] = (uint)(best[(CLVIS_LAYERS - 1) * CLVIS_PACKET + l] >> 32);
#else
    for (int l = 0; l < CLVIS_PACKET; ++l) depth[l] = (uint)(best[l] >> 32);
#endif
    *cull = fmin((lanes_f)(cam.far_d), as_float16(vload16(0, depth)));
}
#endif

#ifndef CLVIS_RASTER_RULE
/* The children of node n that the walk enters (bit k: child k), entry[k] the bound of their entry
   distance: those that pass the interval test (packet_span_hits) and, among the leaves (or all
   of them where the rays' culls spread, some ray's nearest hit far before another's), that some
   ray meets by its own test (packet_hits_box), as its own cull goes. */
static int span_children(const packet* p, __global const clvis_wide_node* n, float near_t, lanes_f cull, float cull_max,
                         int spread, float entry[CLVIS_BVH_WIDTH])
{
    clvis_wfloat enter;
    int bits = packet_span_hits(p, n, near_t, cull_max, &enter), exact = 0;
    clvis_vstore_w(enter, 0, entry);
    for (int c = 0; c < CLVIS_BVH_WIDTH; ++c)
        if (spread || n->count[c] > 0) exact |= bits & (1 << c);
    if (!exact) return bits;
    lanes_i lane_bits = (lanes_i)(0);
    for (int c = 0; c < CLVIS_BVH_WIDTH; ++c)
        if (exact & (1 << c)) lane_bits |= packet_hits_box(p, n, c, 0, near_t, cull) & (1 << c);
    return (bits & ~exact) | or_lanes(lane_bits);
}

#endif

/* The packet walk's context (CLVIS_WALK_CTX): what its tests read and the nearest keys they keep. */
typedef struct packet_walk {
    const packet* p;
    const clvis_camera_gpu* cam;
    int faces;
    lanes_f* cull;      /* each ray's far distance: its nearest key's depth, or far */
#ifdef CLVIS_RASTER_RULE
    int x0, y0;         /* the packet's corner */
    ulong* best;        /* the 16 keys */
#else
    lanes_u *best_t, *best_id;
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    ulong* lists;       /* depth layers: each lane's K nearest keys (shared/ray_packet_tri.h) */
#endif
    float cull_max;     /* WALK_SPAN: the largest cull */
    int spread;         /* WALK_SPAN: the culls spread (some ray's nearest hit far before another's) */
#endif
} packet_walk;

/* The walk's variants: WALK_LANES tests each child by every lane's own test and orders them by
   their box centres along a central ray, stack entries tested again when popped; WALK_SPAN
   (a flat tree, a packet with p->span) tests a node's children against the whole packet
   at once (span_children), nearest entry bound first, each stack entry beside its entry bound so
   that a pop is skipped by one comparison once every ray's cull lies before it. The interval test
   only keeps more boxes than the rays' own tests, so every ray finds the same nearest key. */
#define WALK_LANES 0
#define WALK_SPAN 1

#ifdef CLVIS_RASTER_RULE
#define PACKET_HITS_BOX(c, nd, k, xi) packet_hits_box_rule((c)->p, *(c)->cam, nd, k, xi, *(c)->cull)
#else
#define PACKET_HITS_BOX(c, nd, k, xi) packet_hits_box((c)->p, nd, k, xi, (c)->cam->near_d, *(c)->cull)
#endif

/* The node test: the children some ray meets (the children's masks as bits 0 .. CLVIS_BVH_WIDTH - 1
   of each lane, then one reduction for all), keyed by their box centres along a central ray. */
static inline CLVIS_ALWAYS_INLINE int packet_children(packet_walk* c, int variant, __global const clvis_wide_node* nd,
                                                      __global const clvis_instance* xi,
                                                      float keys[CLVIS_BVH_WIDTH])
{
#ifndef CLVIS_RASTER_RULE
    if (variant == WALK_SPAN) return span_children(c->p, nd, c->cam->near_d, *c->cull, c->cull_max, c->spread, keys);
#endif
    const packet* p = c->p;
    lanes_i lane_bits = (lanes_i)(0);
#pragma unroll
    for (int k = 0; k < CLVIS_BVH_WIDTH; ++k) lane_bits |= PACKET_HITS_BOX(c, nd, k, xi) & (1 << k);
    int bits = or_lanes(lane_bits);
    for (int k = 0; k < CLVIS_BVH_WIDTH; ++k)
        if (bits & (1 << k))
            keys[k] = (nd->lo_x[k] + nd->hi_x[k]) * p->cx + (nd->lo_y[k] + nd->hi_y[k]) * p->cy +
                      (nd->lo_z[k] + nd->hi_z[k]) * p->cz;
    return bits;
}

/* The leaf test on every lane; WALK_SPAN follows its culls' largest and spread. */
static inline CLVIS_ALWAYS_INLINE int packet_leaf(packet_walk* c, int variant, __global const clvis_bvh_tri* tris,
                                                  uint first, uint count, __global const clvis_instance* xi)
{
#ifdef CLVIS_RASTER_RULE
    packet_rule_leaf(tris, first, count, xi, *c->cam, c->faces, c->x0, c->y0, c->best, c->cull);
#else
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    packet_test_leaf(c->p, tris, first, count, xi, c->cam->near_d, c->cam->far_d, c->faces, c->best_t, c->best_id,
                     c->cull, c->lists);
#else
    packet_test_leaf(c->p, tris, first, count, xi, c->cam->near_d, c->cam->far_d, c->faces, c->best_t, c->best_id,
                     c->cull);
#endif
    if (variant == WALK_SPAN) {
        c->cull_max = max_lanes(*c->cull);
        c->spread = min_lanes(*c->cull) * 1.25f < c->cull_max;
    }
#endif
    return 0;
}

#define CLVIS_WALK_CTX packet_walk
#define CLVIS_WALK_CHILDREN(c, v, nd, xi, keys) packet_children(c, v, nd, xi, keys)
#ifdef CLVIS_RASTER_RULE
#define CLVIS_WALK_KEY_SKIP(c, v, key) 0
#else
#define CLVIS_WALK_KEY_SKIP(c, v, key) ((v) == WALK_SPAN && !((key) <= (c)->cull_max))
#endif
/* popped: no lane set, no ray can still meet the child */
#define CLVIS_WALK_BOX_SKIP(c, v, nd, k, xi) (!any_lane(PACKET_HITS_BOX(c, nd, k, xi)))
#define CLVIS_WALK_LEAF(c, v, tris, first, count, xi) packet_leaf(c, v, tris, first, count, xi)
#include "shared/bvh_walk.h"

/* Traces the packet of pixels from (x0, y0) (in the image) and writes the keys of those inside
   `region` into its buffer (shared/region.h); `faces` is the cull mode (CLVIS_CULL_*). Stack
   entries name a child slot, so that a popped child is tested again against the hits found since
   it was pushed, with the instance it lies in (shared/instance.h: boxes and triangles tested in
   world space); `two_level` starts in the top level of `instances`. Always inlined: out of line it
   took the camera by value, a per-work-item copy on PoCL read back across its stores
   (docs/architecture.md, decision 5). */
static inline CLVIS_ALWAYS_INLINE void
trace_packet(clvis_camera_gpu cam, clvis_region region, int x0, int y0, __global const clvis_wide_node* nodes,
             uint node_count, __global const clvis_bvh_tri* tris, __global const clvis_instance* instances,
             int two_level, int faces, __global ulong* keys)
{
    int x_end = region.x + region.width, y_end = region.y + region.height;
    packet p;
    make_packet(cam, x0, y0, &p);
    packet_walk c;
    c.p = &p;
    c.cam = &cam;
    c.faces = faces;
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
#define PACKET_KEYS (CLVIS_LAYERS * CLVIS_PACKET) /* depth layers: K layers of the 16 lanes */
#else
#define PACKET_KEYS CLVIS_PACKET
#endif
#ifdef CLVIS_RASTER_RULE
    ulong best[PACKET_KEYS];
    for (int l = 0; l < PACKET_KEYS; ++l) best[l] = CLVIS_BACKGROUND_KEY;
    lanes_f cull = (lanes_f)(cam.far_d); /* each ray's nearest key depth, or far */
    c.x0 = x0;
    c.y0 = y0;
    c.best = best;
#else
    lanes_u best_t = (lanes_u)(clvis_float_bits(CLVIS_INFINITY)), best_id = (lanes_u)(CLVIS_BACKGROUND_ID);
    /* each ray's far distance (far, or its nearest hit), scaled for the conservative slab test */
    lanes_f cull = (lanes_f)(cam.far_d * CLVIS_IZE_SCALE);
    c.best_t = &best_t;
    c.best_id = &best_id;
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    ulong lists[PACKET_KEYS];
    for (int l = 0; l < PACKET_KEYS; ++l) lists[l] = CLVIS_BACKGROUND_KEY;
    c.lists = lists;
#endif
#endif
    c.cull = &cull;
    clvis_walk walk;
    clvis_walk_stack st;
    clvis_walk_start(&walk, node_count, two_level);
#ifndef CLVIS_RASTER_RULE
    if (walk.node == 0 && p.span && !two_level) { /* then the walk below has nothing left to walk */
        c.cull_max = max_lanes(cull);
        c.spread = 0;
        while (walk.node != CLVIS_WALK_DONE) clvis_walk_step(&c, WALK_SPAN, 0, nodes, tris, instances, &walk, &st);
    }
#endif
    while (walk.node != CLVIS_WALK_DONE) clvis_walk_step(&c, WALK_LANES, 1, nodes, tris, instances, &walk, &st);

#if !defined(CLVIS_RASTER_RULE) && defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    ulong* best = lists;
#elif !defined(CLVIS_RASTER_RULE)
    uint t_bits[CLVIS_PACKET], ids[CLVIS_PACKET];
    vstore16(best_t, 0, t_bits);
    vstore16(best_id, 0, ids);
    ulong best[CLVIS_PACKET];
    for (int l = 0; l < CLVIS_PACKET; ++l) best[l] = ((ulong)t_bits[l] << 32) | ids[l];
#endif
    /* Row by row, one address per row: the packet's corner lies in the region (the launch). */
    int w = min(CLVIS_PACKET_W, x_end - x0), h = min(CLVIS_PACKET_H, y_end - y0);
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    /* depth layers: layer k's keys `plane` keys after layer k - 1's (shared/layers.h); `keys`
       holds the region (a batch of views is refused with layers) */
    size_t plane = ((size_t)region.width * (size_t)region.height) << cam.sample_log2;
    for (int k = 0; k < CLVIS_LAYERS; ++k)
        for (int j = 0; j < h; ++j) {
            __global ulong* row = keys + (size_t)k * plane +
                                  ((((size_t)(y0 + j - region.y) * region.width + (x0 - region.x)) << cam.sample_log2) +
                                   cam.sample);
            for (int i = 0; i < w; ++i) row[(size_t)i << cam.sample_log2] = best[k * CLVIS_PACKET + j * CLVIS_PACKET_W + i];
        }
    return;
#endif
    for (int j = 0; j < h; ++j) {
        __global ulong* row =
            keys + ((((size_t)(y0 + j - region.y) * region.width + (x0 - region.x)) << cam.sample_log2) + cam.sample);
        if (w == CLVIS_PACKET_W && cam.sample_log2 == 0) /* one vector store, not a scatter */
            vstore4(vload4(0, best + j * CLVIS_PACKET_W), 0, row);
        else
            for (int i = 0; i < w; ++i) row[(size_t)i << cam.sample_log2] = best[j * CLVIS_PACKET_W + i];
    }
}

__kernel void ray_trace(clvis_camera_gpu cam, __global const clvis_wide_node* nodes, uint node_count,
                        __global const clvis_bvh_tri* tris, int faces, __global ulong* keys, clvis_region region,
                        __global const clvis_instance* instances, int two_level)
{
    /* Packets start at the region's corner; each lane's ray is its own pixel's. */
    int x0 = region.x + (int)get_global_id(0) * CLVIS_PACKET_W, y0 = region.y + (int)get_global_id(1) * CLVIS_PACKET_H;
    if (x0 >= region.x + region.width || y0 >= region.y + region.height) return; /* the launch is rounded up */
    trace_packet(cam, region, x0, y0, nodes, node_count, tris, instances, two_level, faces, keys);
}

/* Many views in one launch: the third dimension is the view, whose keys start `stride` keys after
   the previous view's. Each view gets the bits ray_trace gives it alone (the same function). */
__kernel void ray_trace_views(__global const clvis_camera_gpu* cams, __global const clvis_wide_node* nodes,
                              uint node_count, __global const clvis_bvh_tri* tris, int faces, __global ulong* keys,
                              ulong stride, __global const clvis_instance* instances, int two_level)
{
    size_t view = get_global_id(2);
    clvis_camera_gpu cam = cams[view];
    int x0 = (int)get_global_id(0) * CLVIS_PACKET_W, y0 = (int)get_global_id(1) * CLVIS_PACKET_H;
    if (x0 >= cam.width || y0 >= cam.height) return;
    clvis_region whole = {0, 0, cam.width, cam.height};
    trace_packet(cam, whole, x0, y0, nodes, node_count, tris, instances, two_level, faces, keys + view * stride);
}
