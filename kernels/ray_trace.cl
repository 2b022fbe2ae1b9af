/* Casts one primary ray per pixel centre through the BVH (shared/bvh.h) and writes the visibility
   key of every pixel; launched by host/ray/ray_pipeline.cpp. Each work-item traces a packet of 4x4
   pixels as the 16 lanes of OpenCL vectors (Wald et al., "Interactive rendering with coherent ray
   tracing", 2001): one walk of the 4-wide tree per packet, nearest child first, with a short
   stack; every box and triangle test runs on all 16 rays at once, the same operations as the
   scalar tests of shared/ray.h, so each ray gets the bits that ray_brute.cl computes for it. A
   child is skipped when no ray of the packet can meet it before its nearest hit so far. A
   perspective packet walks a flat tree by an interval test of the whole packet first (walk_span).
   Work-groups are screen tiles of packets. Built with CLVIS_RASTER_RULE (RenderOptions::coverage),
   each candidate triangle is judged by the raster path's predicate instead (packet_rule_leaf). */
#include "shared/ray_packet.h"
#include "shared/region.h"
#include "shared/visibility.h"
#ifdef CLVIS_RASTER_RULE
#include "shared/raster_rule.h"
#else
#include "shared/ray_packet_tri.h"
#endif

#define CLVIS_RAY_NONE 0xFFFFFFFFu

/* CLVIS_RAY_STACK (entries, at least 3 x the 4-wide tree's depth) is set by the host at build
   time. */
#ifndef CLVIS_RAY_STACK
#error "CLVIS_RAY_STACK must be defined"
#endif

#ifdef CLVIS_RASTER_RULE
/* Coverage by the raster path's rule (RenderOptions::coverage, CLVIS_RASTER_RULE): the packet
   keeps its 16 keys in private memory, every candidate triangle leaves at each pixel the key the
   raster path leaves there (shared/raster_rule.h: set up once per triangle for the whole packet),
   and a box is skipped only where no ray can find such a key in it: the ray misses the box
   widened by clvis_rule_box_of's margin, or every key in it would lie beyond the ray's nearest
   (its depth range starts past it) or before near. */
static lanes_i packet_hits_box_rule(const packet* p, clvis_camera_gpu cam, __global const clvis_bvh4_node* n, int k,
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
   ray's nearest key depth (or far). */
static void packet_rule_leaf(__global const clvis_bvh_tri* tris, uint first, uint count, __global const clvis_instance* xi,
                             clvis_camera_gpu cam, int faces, int x0, int y0, ulong* best, lanes_f* cull)
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
    for (int l = 0; l < CLVIS_PACKET; ++l) depth[l] = (uint)(best[l] >> 32);
    *cull = fmin((lanes_f)(cam.far_d), as_float16(vload16(0, depth)));
}
#endif

#ifndef CLVIS_RASTER_RULE
/* The children of node n that the walk enters (bit k: child k), entry[k] the bound of their entry
   distance: those that pass the interval test (packet_span_hits) and, among the leaves (or all
   of them where the rays' culls spread, some ray's nearest hit far before another's), that some
   ray meets by its own test (packet_hits_box), as its own cull goes. */
static int span_children(const packet* p, __global const clvis_bvh4_node* n, float near_t, lanes_f cull, float cull_max,
                         int spread, float entry[4])
{
    float4 enter;
    int bits = packet_span_hits(p, n, near_t, cull_max, &enter), exact = 0;
    vstore4(enter, 0, entry);
    for (int c = 0; c < 4; ++c)
        if (spread || n->count[c] > 0) exact |= bits & (1 << c);
    if (!exact) return bits;
    lanes_i lane_bits = (lanes_i)(0);
    for (int c = 0; c < 4; ++c)
        if (exact & (1 << c)) lane_bits |= packet_hits_box(p, n, c, 0, near_t, cull) & (1 << c);
    return (bits & ~exact) | or_lanes(lane_bits);
}

/* The walk of a flat tree for a packet with p->span: a node's four children tested against the
   whole packet at once (packet_span_hits), nearest entry first, each stack entry (node << 2 | slot)
   beside its entry bound, so that a pop is skipped by one comparison once every ray's cull lies
   before it; a leaf is opened only where some ray meets its box (packet_hits_box). The interval
   test only keeps more boxes than the rays' own tests, so every ray finds the same nearest key. */
static void walk_span(const packet* p, clvis_camera_gpu cam, __global const clvis_bvh4_node* nodes,
                      __global const clvis_bvh_tri* tris, int faces, lanes_u* best_t, lanes_u* best_id, lanes_f* cull)
{
    uint stack[CLVIS_RAY_STACK];
    float stack_t[CLVIS_RAY_STACK];
    float cull_max = max_lanes(*cull);
    int spread = 0;
    uint sp = 0, node = 0;
    for (;;) {
        __global const clvis_bvh4_node* nd = 0;
        uint k = 0;
        if (node != CLVIS_RAY_NONE) {
            float entry[4], along[4];
            int bits = span_children(p, nodes + node, cam.near_d, *cull, cull_max, spread, entry);
            uint order[4], hits = 0;
            for (int c = 0; c < 4; ++c)
                if (bits & (1 << c)) clvis_insert_child(order, along, &hits, (uint)c, entry[c]);
            for (uint i = 0; i < hits; ++i) clvis_prefetch_child(nodes, tris, nodes + node, (int)order[i]);
            for (uint i = hits; i > 1; --i, ++sp) stack_t[sp] = along[i - 1], stack[sp] = node << 2 | order[i - 1];
            if (hits > 0) nd = nodes + node, k = order[0];
            node = CLVIS_RAY_NONE;
        }
        while (!nd && sp > 0)
            if (stack_t[--sp] <= cull_max &&
                or_lanes(packet_hits_box(p, nodes + (stack[sp] >> 2), stack[sp] & 3, 0, cam.near_d, *cull)) < 0)
                nd = nodes + (stack[sp] >> 2), k = stack[sp] & 3;
        if (!nd) break;
        if (nd->count[k] == 0) node = nd->child[k];
        else {
            packet_test_leaf(p, tris, nd->child[k], nd->count[k], 0, cam.near_d, cam.far_d, faces, best_t, best_id,
                             cull);
            cull_max = max_lanes(*cull);
            spread = min_lanes(*cull) * 1.25f < cull_max;
        }
    }
}
#endif

/* Traces the packet of pixels from (x0, y0) (in the image) and writes the keys of those inside
   `region` into its buffer (shared/region.h); `faces` is the cull mode (CLVIS_CULL_*). Stack
   entries name a child slot, (4-wide node << 2) | slot, so that a popped child is tested again
   against the hits found since it was pushed, with the instance it lies in (shared/instance.h:
   boxes and triangles tested in world space); `two_level` starts in the top level of `instances`.
   Always inlined: out of line it took the camera by value, a per-work-item copy on PoCL read back
   across its stores (docs/architecture.md, decision 5). */
static inline CLVIS_ALWAYS_INLINE void
trace_packet(clvis_camera_gpu cam, clvis_region region, int x0, int y0, __global const clvis_bvh4_node* nodes,
             uint node_count, __global const clvis_bvh_tri* tris, __global const clvis_instance* instances,
             int two_level, int faces, __global ulong* keys)
{
    int x_end = region.x + region.width, y_end = region.y + region.height;
    packet p;
    make_packet(cam, x0, y0, &p);
#ifdef CLVIS_RASTER_RULE
    ulong best[CLVIS_PACKET];
    for (int l = 0; l < CLVIS_PACKET; ++l) best[l] = CLVIS_BACKGROUND_KEY;
    lanes_f cull = (lanes_f)(cam.far_d); /* each ray's nearest key depth, or far */
#define CLVIS_HITS_BOX(nd, k) packet_hits_box_rule(&p, cam, nd, k, xi, cull)
#define CLVIS_TEST_LEAF(nd, k) packet_rule_leaf(tris, nd->child[k], nd->count[k], xi, cam, faces, x0, y0, best, &cull)
#else
    lanes_u best_t = (lanes_u)(clvis_float_bits(CLVIS_INFINITY)), best_id = (lanes_u)(CLVIS_BACKGROUND_ID);
    /* each ray's far distance (far, or its nearest hit), scaled for the conservative slab test */
    lanes_f cull = (lanes_f)(cam.far_d * CLVIS_IZE_SCALE);
#define CLVIS_HITS_BOX(nd, k) packet_hits_box(&p, nd, k, xi, cam.near_d, cull)
#define CLVIS_TEST_LEAF(nd, k) \
    packet_test_leaf(&p, tris, nd->child[k], nd->count[k], xi, cam.near_d, cam.far_d, faces, &best_t, &best_id, &cull)
#endif
#define CLVIS_OPEN_LEAF(nd, k)                                                                            \
    if (inst == CLVIS_INST_TOP)                                                                           \
        node = clvis_enter_instances(nd->child[k], nd->count[k], instances, stack, stack_inst, &sp, &inst, &xi); \
    else CLVIS_TEST_LEAF(nd, k)

    uint stack[CLVIS_RAY_STACK], stack_inst[CLVIS_RAY_STACK];
    uint sp = 0, node = node_count > 0 ? 0u : CLVIS_RAY_NONE;
    uint inst = two_level ? CLVIS_INST_TOP : CLVIS_INST_FLAT;
    __global const clvis_instance* xi = 0; /* instance `inst`, or none at the top level and in the flat tree */
#ifndef CLVIS_RASTER_RULE
    if (node == 0 && p.span && !two_level) { /* then the loop below has nothing left to walk */
        walk_span(&p, cam, nodes, tris, faces, &best_t, &best_id, &cull);
        node = CLVIS_RAY_NONE;
    }
#endif
    for (;;) {
        if (node != CLVIS_RAY_NONE) {
            __global const clvis_bvh4_node* nd = nodes + node;
            /* The children some ray meets, nearest first by their box centres along a central ray. */
            uint order[4];
            float along[4];
            uint hits = 0;
            /* the four children's masks as bits 0-3 of each lane, then one reduction for all */
            int child_bits = or_lanes((CLVIS_HITS_BOX(nd, 0) & 1) | (CLVIS_HITS_BOX(nd, 1) & 2) |
                                      (CLVIS_HITS_BOX(nd, 2) & 4) | (CLVIS_HITS_BOX(nd, 3) & 8));
            for (int k = 0; k < 4; ++k) {
                if (!(child_bits & (1 << k))) continue;
                float d = (nd->lo_x[k] + nd->hi_x[k]) * p.cx + (nd->lo_y[k] + nd->hi_y[k]) * p.cy +
                          (nd->lo_z[k] + nd->hi_z[k]) * p.cz;
                clvis_insert_child(order, along, &hits, (uint)k, d);
            }
            node = CLVIS_RAY_NONE;
            if (hits > 0) {
                for (uint i = 0; i < hits && inst != CLVIS_INST_TOP; ++i) /* the top level's leaves: instances */
                    clvis_prefetch_child(nodes, tris, nd, (int)order[i]);
                for (uint i = hits - 1; i > 0; --i, ++sp)
                    stack_inst[sp] = inst, stack[sp] = (uint)(nd - nodes) << 2 | order[i];
                uint k = order[0];
                if (nd->count[k] > 0) { CLVIS_OPEN_LEAF(nd, k); }
                else node = nd->child[k];
            }
        }
        /* Pop the next child that some ray may still reach before its nearest hit. */
        while (node == CLVIS_RAY_NONE && sp > 0) {
            uint e = stack[--sp];
            inst = stack_inst[sp];
            xi = inst < CLVIS_INST_TOP ? instances + inst : 0;
            if (e == CLVIS_ENTER_INSTANCE) { node = clvis_enter_instance(instances, inst, &inst, &xi); break; }
            __global const clvis_bvh4_node* nd = nodes + (e >> 2);
            uint k = e & 3;
            if (or_lanes(CLVIS_HITS_BOX(nd, (int)k)) >= 0) continue; /* no lane's sign bit */
            if (nd->count[k] > 0) { CLVIS_OPEN_LEAF(nd, k); }
            else node = nd->child[k];
        }
        if (node == CLVIS_RAY_NONE) break;
    }

#undef CLVIS_HITS_BOX
#undef CLVIS_TEST_LEAF
#undef CLVIS_OPEN_LEAF
#ifndef CLVIS_RASTER_RULE
    uint t_bits[CLVIS_PACKET], ids[CLVIS_PACKET];
    vstore16(best_t, 0, t_bits);
    vstore16(best_id, 0, ids);
    ulong best[CLVIS_PACKET];
    for (int l = 0; l < CLVIS_PACKET; ++l) best[l] = ((ulong)t_bits[l] << 32) | ids[l];
#endif
    /* Row by row, one address per row: the packet's corner lies in the region (the launch). */
    int w = min(CLVIS_PACKET_W, x_end - x0), h = min(CLVIS_PACKET_H, y_end - y0);
    for (int j = 0; j < h; ++j) {
        __global ulong* row =
            keys + ((((size_t)(y0 + j - region.y) * region.width + (x0 - region.x)) << cam.sample_log2) + cam.sample);
        if (w == CLVIS_PACKET_W && cam.sample_log2 == 0) /* one vector store, not a scatter */
            vstore4(vload4(0, best + j * CLVIS_PACKET_W), 0, row);
        else
            for (int i = 0; i < w; ++i) row[(size_t)i << cam.sample_log2] = best[j * CLVIS_PACKET_W + i];
    }
}

__kernel void ray_trace(clvis_camera_gpu cam, __global const clvis_bvh4_node* nodes, uint node_count,
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
__kernel void ray_trace_views(__global const clvis_camera_gpu* cams, __global const clvis_bvh4_node* nodes,
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
