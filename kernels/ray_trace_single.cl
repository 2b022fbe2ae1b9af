/* Casts one primary ray per work-item and writes its pixel's visibility key: the ray path's
   mapping for GPUs (RayMapping::Single; ray_trace.cl is the packet mapping for CPUs). A work-group
   is a tile of pixels, sized by host/ray/ray_pipeline.cpp from the kernel's grant. Same kernel
   interfaces as ray_trace.cl, same keys bit for bit: the ray is clvis_primary_ray's (the packet's
   lanes compute the same operations), every candidate triangle gets the scalar test of
   shared/ray.h (or, with CLVIS_RASTER_RULE, the raster path's predicate of shared/raster_rule.h),
   and the walk only prunes boxes that the packet's walk would prune for this ray, so the nearest
   key is the same. The walk (shared/bvh_walk.h): the wide BVH (shared/bvh.h), or from the top
   level of the instances (shared/instance.h), children met pushed with their entry distance,
   nearest taken first, a popped entry skipped when it lies beyond the nearest key so far. */
#include "shared/bvh.h"
#include "shared/bvh_boxes.h"
#include "shared/camera.h"
#include "shared/instance.h"
#include "shared/layers.h"
#include "shared/ray.h"
#include "shared/region.h"
#include "shared/visibility.h"
#ifdef CLVIS_RASTER_RULE
#include "shared/raster_rule.h"
#endif

/* One pixel's ray and its nearest key so far. */
typedef struct single_ray {
    clvis_ray_shear shear; /* the watertight test's */
    clvis_box_ray box;     /* the slab test's */
    int x, y;              /* the pixel, in the image */
    ulong best;            /* the nearest key (with depth layers: the last layer's, what pruning reads) */
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    ulong list[CLVIS_LAYERS]; /* depth layers (shared/layers.h): the nearest keys, sorted */
#endif
} single_ray;

#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
/* A box is pruned against the K-th nearest key: the background until K keys are found. */
#define SINGLE_KEPT(r) ((r)->best = (r)->list[CLVIS_LAYERS - 1])
#else
#define SINGLE_KEPT(r) ((void)0)
#endif

static single_ray make_ray(clvis_camera_gpu cam, int x, int y)
{
    single_ray r;
    clvis_vec3 origin, dir;
    clvis_vec2 f = clvis_camera_sample(cam);
    clvis_primary_ray(cam, (float)x + f.x, (float)y + f.y, &origin, &dir);
    r.shear = clvis_make_shear(origin, dir);
    r.box = clvis_make_box_ray(origin, dir);
    r.x = x;
    r.y = y;
    r.best = CLVIS_BACKGROUND_KEY;
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    for (int k = 0; k < CLVIS_LAYERS; ++k) r.list[k] = CLVIS_BACKGROUND_KEY;
#endif
    return r;
}

#ifdef CLVIS_RASTER_RULE
/* A box's key is beyond reach when its depth range starts past the ray's nearest key (or far). */
static float reach(const single_ray* r, clvis_camera_gpu cam) { return fmin(cam.far_d, clvis_key_depth(r->best)); }

/* ray_trace.cl's packet_hits_box_rule for this ray: whether the ray's line meets child k's box
   widened by clvis_rule_box_of's margin, slabs bounded by rounding, a NaN (the line in a slab's
   plane) constraining nothing. *enter gets the box's depth range's start, what pruning compares. */
static int child_hits(const single_ray* r, clvis_camera_gpu cam, __global const clvis_wide_node* n, int k,
                      __global const clvis_instance* xi, float* enter)
{
    float lo[3], hi[3];
    clvis_instance_child_box(n, k, xi, lo, hi);
    if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2])) return 0; /* an unused slot */
    clvis_rule_box b = clvis_rule_box_of(cam, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    if (b.hi_d < cam.near_d) return 0;
    *enter = b.lo_d == b.lo_d ? b.lo_d : -CLVIS_INFINITY; /* a NaN (overflow) skips nothing */
    clvis_box_ray q = r->box;
    float t0 = -CLVIS_INFINITY, t1 = CLVIS_INFINITY;
    for (int a = 0; a < 3; ++a) {
        float o = a == 0 ? q.origin.x : (a == 1 ? q.origin.y : q.origin.z);
        float inv = a == 0 ? q.inv.x : (a == 1 ? q.inv.y : q.inv.z);
        int neg = a == 0 ? q.neg_x : (a == 1 ? q.neg_y : q.neg_z);
        float l = lo[a] - b.margin, h = hi[a] + b.margin;
        t0 = clvis_raise(t0, ((neg ? h : l) - o) * inv);
        t1 = clvis_lower(t1, ((neg ? l : h) - o) * inv);
    }
    t0 = t0 - fabs(t0) * 9.5367431640625e-7f;
    t1 = t1 + fabs(t1) * 9.5367431640625e-7f;
    return t0 <= t1 && *enter <= reach(r, cam);
}

/* The raster path's keys of the leaf's triangles at this pixel. */
static void test_leaf(single_ray* r, clvis_camera_gpu cam, int faces, __global const clvis_bvh_tri* tris, uint first,
                      uint count, __global const clvis_instance* xi)
{
    clvis_pixel_block blk = {r->x, r->y, 1, 1, 1};
    for (uint k = first; k < first + count; ++k) {
        float v[9];
        uint id = clvis_instance_triangle(tris + k, xi, v);
        clvis_vec3 a = {v[0], v[1], v[2]}, b = {v[3], v[4], v[5]}, c = {v[6], v[7], v[8]};
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
        clvis_raster_rule_keys(cam, faces, a, b, c, id, blk, r->list);
        SINGLE_KEPT(r);
#else
        clvis_raster_rule_keys(cam, faces, a, b, c, id, blk, &r->best);
#endif
    }
}
#else
/* A box is beyond reach when the ray enters it past its nearest hit (or far), scaled as the
   conservative slab test scales it (clvis_ray_hits_box). */
static float reach(const single_ray* r, clvis_camera_gpu cam)
{
    return fmin(cam.far_d, clvis_key_depth(r->best)) * CLVIS_IZE_SCALE;
}

/* The watertight test on the leaf's triangles, keeping the nearest key (depth bits, then id). */
static void test_leaf(single_ray* r, clvis_camera_gpu cam, int faces, __global const clvis_bvh_tri* tris, uint first,
                      uint count, __global const clvis_instance* xi)
{
    for (uint k = first; k < first + count; ++k) {
        float v[9], t;
        uint id = clvis_instance_triangle(tris + k, xi, v);
        clvis_vec3 a = {v[0], v[1], v[2]}, b = {v[3], v[4], v[5]}, c = {v[6], v[7], v[8]};
        if (!clvis_intersect_triangle(r->shear, a, b, c, cam.near_d, cam.far_d, faces, &t)) continue;
        ulong key = clvis_make_key(t, id);
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
        clvis_layers_insert(r->list, 1, key);
        SINGLE_KEPT(r);
#else
        r->best = key < r->best ? key : r->best;
#endif
    }
}
#endif

/* The walk's context (CLVIS_WALK_CTX): the ray and what its tests read. */
typedef struct single_walk {
    single_ray* r;
    const clvis_camera_gpu* cam;
    int faces;
} single_walk;

/* The node test: the children the ray meets, keyed by their entry distance: watertight, every
   child at once (shared/bvh_boxes.h: clvis_ray_hits_box on each child's world box, ray_trace.cl's
   packet_hits_box on one lane); with the raster rule, child_hits on each. */
static inline CLVIS_ALWAYS_INLINE int single_children(single_walk* c, __global const clvis_wide_node* nd,
                                                      __global const clvis_instance* xi,
                                                      float keys[CLVIS_BVH_WIDTH])
{
#ifdef CLVIS_RASTER_RULE
    int bits = 0;
    for (int k = 0; k < CLVIS_BVH_WIDTH; ++k) {
        float e;
        if (child_hits(c->r, *c->cam, nd, k, xi, &e)) {
            bits |= 1 << k;
            keys[k] = e;
        }
    }
    return bits;
#else
    clvis_wfloat e;
    clvis_wint hit = clvis_hits_boxes(nd, xi, c->r->box, c->cam->near_d,
                                      fmin(c->cam->far_d, clvis_key_depth(c->r->best)), &e);
    clvis_vstore_w(e, 0, keys);
    return clvis_wmask_bits(hit);
#endif
}

#define CLVIS_WALK_CTX single_walk
#define CLVIS_WALK_CHILDREN(c, v, nd, xi, keys) single_children(c, nd, xi, keys)
/* a popped entry that can no longer hold a nearer key */
#define CLVIS_WALK_KEY_SKIP(c, v, key) ((key) > reach((c)->r, *(c)->cam))
#define CLVIS_WALK_BOX_SKIP(c, v, nd, k, xi) 0
#define CLVIS_WALK_LEAF(c, v, tris, first, count, xi) \
    (test_leaf((c)->r, *(c)->cam, (c)->faces, tris, first, count, xi), 0)
#include "shared/bvh_walk.h"

/* The whole walk of ray r (cast with camera cam); `two_level` starts in the top level of
   `instances`. */
static void walk_single(single_ray* r, const clvis_camera_gpu* cam, __global const clvis_wide_node* nodes,
                        uint node_count, __global const clvis_bvh_tri* tris, __global const clvis_instance* instances,
                        int two_level, int faces)
{
    single_walk c = {r, cam, faces};
    clvis_walk walk;
    clvis_walk_stack st;
    clvis_walk_start(&walk, node_count, two_level);
    while (walk.node != CLVIS_WALK_DONE) clvis_walk_step(&c, 0, 1, nodes, tris, instances, &walk, &st);
}

#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
/* Depth layers: the K nearest keys of the ray of pixel (x, y) into out[0], out[plane], .. */
static void trace_single_layers(clvis_camera_gpu cam, int x, int y, __global const clvis_wide_node* nodes,
                                uint node_count, __global const clvis_bvh_tri* tris,
                                __global const clvis_instance* instances, int two_level, int faces,
                                __global ulong* out, size_t plane)
{
    single_ray r = make_ray(cam, x, y);
    walk_single(&r, &cam, nodes, node_count, tris, instances, two_level, faces);
    for (int k = 0; k < CLVIS_LAYERS; ++k) out[(size_t)k * plane] = r.list[k];
}
#endif

/* The nearest key of the ray of pixel (x, y); `two_level` starts in the top level of `instances`. */
static ulong trace_single(clvis_camera_gpu cam, int x, int y, __global const clvis_wide_node* nodes, uint node_count,
                          __global const clvis_bvh_tri* tris, __global const clvis_instance* instances, int two_level,
                          int faces)
{
    single_ray r = make_ray(cam, x, y);
    walk_single(&r, &cam, nodes, node_count, tris, instances, two_level, faces);
    return r.best;
}

__kernel void ray_trace_single(clvis_camera_gpu cam, __global const clvis_wide_node* nodes, uint node_count,
                               __global const clvis_bvh_tri* tris, int faces, __global ulong* keys, clvis_region region,
                               __global const clvis_instance* instances, int two_level)
{
    int lx = (int)get_global_id(0), ly = (int)get_global_id(1); /* in the region (shared/region.h) */
    if (lx >= region.width || ly >= region.height) return;  /* the launch is rounded up to whole groups */
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    trace_single_layers(cam, region.x + lx, region.y + ly, nodes, node_count, tris, instances, two_level, faces,
                        keys + (((size_t)ly * (size_t)region.width + (size_t)lx) << cam.sample_log2) + (size_t)cam.sample,
                        ((size_t)region.width * (size_t)region.height) << cam.sample_log2);
    return;
#endif
    ulong key = trace_single(cam, region.x + lx, region.y + ly, nodes, node_count, tris, instances, two_level, faces);
    keys[(((size_t)ly * (size_t)region.width + (size_t)lx) << cam.sample_log2) + (size_t)cam.sample] = key;
}

/* Many views in one launch (ray_trace_views' interface): the third dimension is the view, whose
   keys start `stride` keys after the previous view's. */
__kernel void ray_trace_single_views(__global const clvis_camera_gpu* cams, __global const clvis_wide_node* nodes,
                                     uint node_count, __global const clvis_bvh_tri* tris, int faces,
                                     __global ulong* keys, ulong stride, __global const clvis_instance* instances,
                                     int two_level)
{
    size_t view = get_global_id(2);
    clvis_camera_gpu cam = cams[view];
    int x = (int)get_global_id(0), y = (int)get_global_id(1);
    if (x >= cam.width || y >= cam.height) return;
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    /* a view's layers (the host makes `stride` hold them all) */
    trace_single_layers(cam, x, y, nodes, node_count, tris, instances, two_level, faces,
                        keys + view * stride + ((((size_t)y * (size_t)cam.width + (size_t)x) << cam.sample_log2) +
                                                (size_t)cam.sample),
                        ((size_t)cam.width * (size_t)cam.height) << cam.sample_log2);
    return;
#endif
    ulong key = trace_single(cam, x, y, nodes, node_count, tris, instances, two_level, faces);
    keys[view * stride + ((((size_t)y * (size_t)cam.width + (size_t)x) << cam.sample_log2) + (size_t)cam.sample)] = key;
}
