/* Raster path, stage 1 of 3: raster_setup_vertices projects every vertex once; raster_setup then
   takes every triangle (one work-item each), clips those that need it, rasterizes the ones that
   touch few pixel centres at once into the visibility buffer (64-bit atomic min), and lists the
   others for raster_bin.cl (binning) and raster_fine.cl (tile rasterization). Built with
   CLVIS_RASTER_OWNED (tile ownership, RasterAtomics::Off) it draws nothing and lists every
   triangle, and needs no 64-bit atomics. raster_setup_item_vertices and raster_setup_items do the
   same for a chunk of the items of a scene with instances (shared/scene_items.h): vertices read
   through each instance's matrix, with the expansion's bits, and ids as the expansion's. */
#ifndef CLVIS_RASTER_OWNED
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable
#endif
#include "shared/layers.h"
#include "shared/raster_rule.h"
#include "shared/scene_items.h"

/* Triangles whose pixel bounding box holds at most CLVIS_RASTER_SCALAR pixel centres are
   rasterized here sample by sample; those whose box is at most CLVIS_RASTER_SMALL_COLS pixels
   wide and CLVIS_RASTER_SMALL_ROWS rows tall, and takes draw_small at most
   CLVIS_RASTER_SMALL_PASSES passes of 16 pixels, here by draw_small; the rest are binned. */
#define CLVIS_RASTER_SCALAR 4       /* pixel centres */
#define CLVIS_RASTER_SMALL_COLS 16  /* columns: draw_small's 16 lanes */
#define CLVIS_RASTER_SMALL_ROWS 16  /* rows */
#define CLVIS_RASTER_SMALL_PASSES 6 /* passes of 16 pixels */

typedef struct {
    clvis_camera_gpu cam;
    int cull;
    volatile __global ulong* keys;
    __global clvis_raster_tri* tris;
    uint capacity;
    volatile __global uint* listed; /* 2 words: triangles listed, low and high 32 bits */
    clvis_region region;            /* keys hold this region of the image (shared/region.h) */
    /* Where the one triangle an unclipped work-item lists waits for list_group (null: listed at
       once, as the clipped fans' are), and whether it holds one. */
    clvis_raster_tri* pending;
    int* has_pending;
} raster_setup_out;

static clvis_clip_vertex load_camera_vertex(clvis_camera_gpu cam, __global const float* positions, uint v)
{
    size_t o = 3 * (size_t)v;
    return clvis_clip_vertex_of(cam, positions[o], positions[o + 1], positions[o + 2]);
}

#ifndef CLVIS_RASTER_OWNED
/* CLVIS_PEEK (PoCL's CPU device, Device::Impl::cpu_hints; little-endian): draw_key first reads
   the depth word (the key's high 32 bits) with a plain load and skips the atomic when the key there
   is already nearer by depth. Keys only ever decrease within a frame, so a depth word below key's
   stays below it; an equal depth takes the atomic (the id decides). A 32-bit load that no 64-bit
   write can tear returns a depth stored there, the newest or an older, larger one: skipping stays
   right. A locked compare-exchange serialises the CPU's memory accesses where a load does not, and
   in a scene with depth complexity most samples are behind what an earlier triangle drew. The
   read races with other work-items' atomics, which OpenCL leaves undefined and Oclgrind reports:
   it is made only where the hardware's answer is known. */
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
/* Depth layers (shared/layers.h): the lock-free cascade. The key goes into layer 0 by atomic min;
   the larger of it and the key that was there goes on to the next layer, and so on, until a
   layer was background (the key took an empty slot), held the key already, or the last layer is
   passed. Every layer's key only decreases and every key carried moves only to later layers, so
   however work-items interleave, each list ends sorted, holding the K smallest distinct keys
   drawn (a key meets any copy of itself on its way). CLVIS_PEEK tests the last layer first: a
   depth word below the key's there stays below it, and K keys nearer by depth leave no room; then
   each layer: where its depth word is below the key's, the atomic would keep that layer's key and
   carry this one on, which the carry does without it. */
static void draw_key_layers(volatile __global ulong* p, size_t plane, ulong key)
{
#ifdef CLVIS_PEEK
    if (((volatile __global const uint*)(p + (size_t)(CLVIS_LAYERS - 1) * plane))[1] < (uint)(key >> 32)) return;
#endif
    for (int k = 0; k < CLVIS_LAYERS; ++k) {
#ifdef CLVIS_PEEK
        if (((volatile __global const uint*)(p + (size_t)k * plane))[1] < (uint)(key >> 32)) continue;
#endif
        ulong old = atom_min(p + (size_t)k * plane, key);
        if (old == key || old == CLVIS_BACKGROUND_KEY) return;
        key = max(old, key);
    }
}
#define draw_key(p, key) draw_key_layers(p, plane, key)
#else
static void draw_key(volatile __global ulong* p, ulong key)
{
#ifdef CLVIS_PEEK
    if (((volatile __global const uint*)p)[1] < (uint)(key >> 32)) return;
#endif
    atom_min(p, key);
}
#endif

/* CLVIS_PREFETCH (PoCL's CPU device, Device::Impl::cpu_hints): the rows of keys a small
   triangle draws are fetched into the cache before its samples are computed, so that their misses
   overlap instead of each stalling a draw_key in turn (a row's first and last key: two of its
   lines, of at most three). A hint only: the same keys are drawn with or without it. */
static void prefetch_rows(const clvis_raster_tri* t, raster_setup_out out)
{
#ifdef CLVIS_PREFETCH
    int n_log2 = out.cam.sample_log2;
    size_t last = (size_t)(t->x1 - t->x0) << n_log2;
    for (int j = t->y0; j <= t->y1; ++j) {
        __global const ulong* row =
            (__global const ulong*)out.keys + (((size_t)j * (size_t)out.region.width + (size_t)t->x0) << n_log2);
        CLVIS_PREFETCH_LINE(row);
        CLVIS_PREFETCH_LINE(row + last);
    }
#endif
}

/* log2 of the columns of draw_small's passes for a box w pixels wide (1 .. 16): the fewest of
   1, 2, 4, 8, 16 that hold it. */
static inline int small_columns_log2(int w)
{
    return w > 8 ? 4 : w > 4 ? 3 : w > 2 ? 2 : w - 1;
}

/* The passes draw_small takes for a box of w by h pixels. */
static inline int small_passes(int w, int h)
{
    int rows_log2 = 4 - small_columns_log2(w);
    return (h + (1 << rows_log2) - 1) >> rows_log2;
}

/* The keys of the 16 lanes of draw_small's pass at row j (lane l: pixel (x0 + l % c, j + l / c),
   c = 2^c_log2 columns, rows past y1 read as row y1: their lanes are never covered), one sample
   per pixel and one layer; x0 + c must not pass the region's width. */
static inline CLVIS_ALWAYS_INLINE ulong16 held_keys(volatile __global ulong* keys, size_t width, int x0, int j, int y1,
                                                    int c_log2)
{
    __global const ulong* p = (__global const ulong*)keys + (size_t)x0;
#define CLVIS_ROW(k) (p + (size_t)min(j + (k), y1) * width)
    if (c_log2 == 4) return vload16(0, CLVIS_ROW(0));
    if (c_log2 == 3) return (ulong16)(vload8(0, CLVIS_ROW(0)), vload8(0, CLVIS_ROW(1)));
    if (c_log2 == 2)
        return (ulong16)(vload4(0, CLVIS_ROW(0)), vload4(0, CLVIS_ROW(1)), vload4(0, CLVIS_ROW(2)),
                         vload4(0, CLVIS_ROW(3)));
    if (c_log2 == 1)
        return (ulong16)(vload2(0, CLVIS_ROW(0)), vload2(0, CLVIS_ROW(1)), vload2(0, CLVIS_ROW(2)),
                         vload2(0, CLVIS_ROW(3)), vload2(0, CLVIS_ROW(4)), vload2(0, CLVIS_ROW(5)),
                         vload2(0, CLVIS_ROW(6)), vload2(0, CLVIS_ROW(7)));
    return (ulong16)(*CLVIS_ROW(0), *CLVIS_ROW(1), *CLVIS_ROW(2), *CLVIS_ROW(3), *CLVIS_ROW(4), *CLVIS_ROW(5),
                     *CLVIS_ROW(6), *CLVIS_ROW(7), *CLVIS_ROW(8), *CLVIS_ROW(9), *CLVIS_ROW(10), *CLVIS_ROW(11),
                     *CLVIS_ROW(12), *CLVIS_ROW(13), *CLVIS_ROW(14), *CLVIS_ROW(15));
#undef CLVIS_ROW
}

/* Rasterizes a triangle whose box is at most 16 pixels wide: its box's pixels go 16 to a pass, as
   c = 1, 2, 4, 8 or 16 columns (the fewest that hold its width) by 16 / c rows, so that a narrow
   triangle takes a pass per 16 / c rows, not one per row. Each lane's edge values are the same
   integers as clvis_raster_sample's (exact int64 sums at points within raster.h's square: at
   most 7 px past the image's right edge and 16 rows below the box), its depth the same float
   operations in the same order (clvis_raster_span8's), so each key is the same bits. Lanes outside the box, not
   covered, or outside [near, far] draw nothing. */
static inline CLVIS_ALWAYS_INLINE void draw_small(const clvis_raster_tri* t, raster_setup_out out)
{
    int n_log2 = out.cam.sample_log2;
    size_t sample = (size_t)out.cam.sample;
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    size_t plane = ((size_t)out.region.width * (size_t)out.region.height) << n_log2; /* keys per layer */
#endif
    int w = t->x1 - t->x0 + 1; /* 1 .. 16 */
    int c_log2 = small_columns_log2(w);
    int rows = 16 >> c_log2;
    const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    int16 di = lane & (int16)((1 << c_log2) - 1);
    int16 dj = lane >> (int16)(c_log2);
    long16 di64 = convert_long16(di), dj64 = convert_long16(dj);
    long16 o0 = di64 * t->ex[0] + dj64 * t->ey[0];
    long16 o1 = di64 * t->ex[1] + dj64 * t->ey[1];
    long16 o2 = di64 * t->ex[2] + dj64 * t->ey[2];
    long r0 = t->e0[0] + (long)t->x0 * t->ex[0] + (long)t->y0 * t->ey[0];
    long r1 = t->e0[1] + (long)t->x0 * t->ex[1] + (long)t->y0 * t->ey[1];
    long r2 = t->e0[2] + (long)t->x0 * t->ex[2] + (long)t->y0 * t->ey[2];
    long s0 = (long)rows * t->ey[0], s1 = (long)rows * t->ey[1], s2 = (long)rows * t->ey[2];
    int16 in_x = di < (int16)(w);
#if defined(CLVIS_PEEK) && !(defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1)
    const int16 weight = (int16)(1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768);
    int peek = n_log2 == 0 && t->x0 + (1 << c_log2) <= out.region.width;
#endif
    for (int j = t->y0; j <= t->y1; j += rows, r0 += s0, r1 += s1, r2 += s2) {
        long16 e0 = (long16)(r0) + o0;
        long16 e1 = (long16)(r1) + o1;
        long16 e2 = (long16)(r2) + o2;
        long16 inside = ((e0 | e1 | e2) >= 0) & convert_long16(in_x & (dj <= (int16)(t->y1 - j)));
        float16 v = (float16)(t->wc) + convert_float16(e0) * t->w[0] + convert_float16(e1) * t->w[1] +
                    convert_float16(e2) * t->w[2];
        float16 d = out.cam.ortho ? v : 1.0f / v;
        int16 take = convert_int16(inside) & ((d >= out.cam.near_d) & (d <= out.cam.far_d));
        ulong16 key = (convert_ulong16(as_uint16(d)) << 32) | (ulong16)(t->id);
        ulong keys[16];
#if defined(CLVIS_PEEK) && !(defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1)
        if (peek) {
            /* draw_key's test for the 16 keys at once (depth words compared): the lanes whose
               pixel is not already nearer take the atomic, found by a mask (the .lo | .hi folds
               crash Oclgrind 21.10's uninitialised-value check: PoCL's build only). */
            take &= convert_int16((key >> 32) <= (held_keys(out.keys, (size_t)out.region.width, t->x0, j, t->y1,
                                                            c_log2) >> 32));
            int16 bit = take & weight;
            int8 b8 = bit.lo | bit.hi;
            int4 b4 = b8.lo | b8.hi;
            int2 b2 = b4.lo | b4.hi;
            uint mask = (uint)(b2.lo | b2.hi);
            if (mask == 0u) continue;
            vstore16(key, 0, keys);
            for (; mask != 0u; mask &= mask - 1u) {
                int l = 31 - (int)clz(mask & (0u - mask));
                atom_min(out.keys + (size_t)(j + (l >> c_log2)) * (size_t)out.region.width +
                             (size_t)(t->x0 + (l & ((1 << c_log2) - 1))) + sample,
                         keys[l]);
            }
            continue;
        }
#endif
        int takes[16];
        vstore16(take, 0, takes);
        vstore16(key, 0, keys);
        for (int l = 0; l < 16; ++l) {
            if (!takes[l]) continue;
            size_t x = (size_t)(t->x0 + (l & ((1 << c_log2) - 1)));
            size_t y = (size_t)(j + (l >> c_log2));
            draw_key(out.keys + ((y * (size_t)out.region.width + x) << n_log2) + sample, keys[l]);
        }
    }
}
#endif

/* Reserves n slots of the list (n > 0) and returns the first. The count is 64 bits kept in two
   32-bit words (core atomics): a total past the capacity makes the host grow the list and run
   setup again (slots past 2^32 wrap, and what they overwrite is drawn again then). */
static uint reserve_slots(volatile __global uint* listed, uint n)
{
    uint first = atomic_add(&listed[0], n);
    if (first + n < first) atomic_inc(&listed[1]); /* the low word wrapped */
    return first;
}

/* Lists t for binning, or leaves it for list_group where the work-item's one triangle waits. */
static void list_triangle(const clvis_raster_tri* t, raster_setup_out out)
{
    if (out.pending) {
        *out.pending = *t;
        *out.has_pending = 1;
        return;
    }
    uint slot = reserve_slots(out.listed, 1u);
    if (slot < out.capacity) out.tris[slot] = *t;
}

/* Lists the work-group's waiting triangles (`has`: this work-item's, in *t) with one global
   atomic for the group: a global atomic per triangle made every listed triangle of a frame
   drawn by tile ownership (all of them) fight over one cache line, which on PoCL's CPU device with
   its workers on two cores took most of setup (a 65k-triangle frame: setup 1.7 ms or 5.6-9 ms
   with the line bouncing). Every work-item of the group calls it (barriers). The list's order
   changes nothing: the keys are minima. */
static void list_group(const clvis_raster_tri* t, int has, __global clvis_raster_tri* tris, uint capacity,
                       volatile __global uint* listed, __local uint* group)
{
    if (get_local_id(0) == 0) group[0] = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    uint mine = has ? atomic_inc(&group[0]) : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0) group[1] = group[0] ? reserve_slots(listed, group[0]) : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    uint slot = group[1] + mine;
    if (has && slot < capacity) tris[slot] = *t;
}

/* Rasterizes a small triangle on the spot (atomic mode), or lists it for binning: at the camera's
   sample (shared/samples.h), one launch per sample. Always inlined: out of line, its struct
   arguments were per-work-item copies on PoCL (docs/architecture.md, decision 5). */
static inline CLVIS_ALWAYS_INLINE void
emit_triangle(clvis_raster_vertex a, clvis_raster_vertex b, clvis_raster_vertex c, uint id, raster_setup_out out)
{
    clvis_raster_tri t;
    if (!clvis_raster_setup_region(clvis_raster_vertex_at_sample(a, out.cam), clvis_raster_vertex_at_sample(b, out.cam),
                                   clvis_raster_vertex_at_sample(c, out.cam), id, out.region, out.cull, &t))
        return;
    /* Key of the camera's sample of region pixel p: the samples of a pixel are adjacent. */
    int n_log2 = out.cam.sample_log2;
    size_t sample = (size_t)out.cam.sample;
#ifndef CLVIS_RASTER_OWNED
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    size_t plane = ((size_t)out.region.width * (size_t)out.region.height) << n_log2; /* keys per layer */
#endif
    int small = t.x1 - t.x0 < CLVIS_RASTER_SMALL_COLS && t.y1 - t.y0 < CLVIS_RASTER_SMALL_ROWS &&
                small_passes(t.x1 - t.x0 + 1, t.y1 - t.y0 + 1) <= CLVIS_RASTER_SMALL_PASSES;
    if (small) prefetch_rows(&t, out);
    if ((t.x1 - t.x0 + 1) * (t.y1 - t.y0 + 1) <= CLVIS_RASTER_SCALAR) {
        for (int j = t.y0; j <= t.y1; ++j) {
            for (int i = t.x0; i <= t.x1; ++i) {
                ulong key = clvis_raster_sample(&t, i, j, out.cam.ortho, out.cam.near_d, out.cam.far_d);
                if (key != CLVIS_BACKGROUND_KEY)
                    draw_key(&out.keys[(((size_t)j * out.region.width + i) << n_log2) + sample], key);
            }
        }
        return;
    }
    if (small) {
        draw_small(&t, out);
        return;
    }
#endif
    clvis_raster_set_nearest(a, b, c, out.cam.ortho, &t); /* raster_fine.cl's occlusion test */
    list_triangle(&t, out);
}

/* Clips the triangle against near and the guard band and fans the polygon into triangles. */
static void clip_and_emit(clvis_clip_vertex p0, clvis_clip_vertex p1, clvis_clip_vertex p2, uint id, clvis_guard g,
                          raster_setup_out out)
{
    clvis_clip_vertex poly[CLVIS_CLIP_CAPACITY];
    int n = clvis_clip_polygon(p0, p1, p2, out.cam, g, poly); /* shared/raster_rule.h */
    if (n < 3) return;
    int s = clvis_fan_start(poly, n);
    clvis_raster_vertex first = clvis_raster_vertex_from(out.cam, poly[s]);
    clvis_raster_vertex prev = clvis_raster_vertex_from(out.cam, poly[s + 1 < n ? s + 1 : s + 1 - n]);
    for (int k = 2; k < n; ++k) {
        clvis_raster_vertex cur = clvis_raster_vertex_from(out.cam, poly[s + k < n ? s + k : s + k - n]);
        emit_triangle(first, prev, cur, id, out);
        prev = cur;
    }
}

static clvis_raster_projected project(clvis_camera_gpu cam, clvis_clip_vertex p)
{
    clvis_u32 code = clvis_outcode(cam, p);
    clvis_raster_vertex r = clvis_raster_vertex_from(cam, p);
    int keep = (code & CLVIS_OUT_CLIP) == 0u;
    clvis_raster_projected out = {keep ? (int)r.x : 0, keep ? (int)r.y : 0, r.v, code};
    return out;
}

/* Straight-line code, one work-item per vertex: PoCL runs it as a vector loop. */
__kernel void raster_setup_vertices(clvis_camera_gpu cam, __global const float* positions, uint vertex_count,
                                    __global clvis_raster_projected* projected)
{
    uint v = (uint)get_global_id(0);
    if (v >= vertex_count) return;
    projected[v] = project(cam, load_camera_vertex(cam, positions, v));
}

static clvis_raster_vertex widen(clvis_raster_projected p)
{
    clvis_raster_vertex v = {p.x, p.y, p.v};
    return v;
}

/* Emits a triangle that needs no clipping and returns 0, or returns 1 for one that needs it
   (nothing for one wholly outside a side of the view). */
static int emit_unclipped(clvis_raster_projected pa, clvis_raster_projected pb, clvis_raster_projected pc, uint id,
                          raster_setup_out out)
{
    if (pa.code & pb.code & pc.code & CLVIS_OUT_VIEW) return 0;
    if ((pa.code | pb.code | pc.code) & CLVIS_OUT_CLIP) return 1;
    emit_triangle(widen(pa), widen(pb), widen(pc), id, out);
    return 0;
}

__kernel void raster_setup(clvis_camera_gpu cam, __global const float* positions, __global const uint* indices,
                           uint triangle_count, __global const clvis_raster_projected* projected, int cull,
                           volatile __global ulong* keys, __global clvis_raster_tri* tris, uint capacity,
                           volatile __global uint* listed, clvis_region region)
{
    __local uint group[2];
    clvis_raster_tri pending;
    int has = 0;
    uint id = (uint)get_global_id(0);
    if (id < triangle_count) {
        size_t i = 3 * (size_t)id;
        uint a = indices[i], b = indices[i + 1], c = indices[i + 2];
        raster_setup_out out = {cam, cull, keys, tris, capacity, listed, region, &pending, &has};
        if (emit_unclipped(projected[a], projected[b], projected[c], id, out)) {
            out.pending = 0; /* a clipped fan lists its triangles at once */
            clip_and_emit(load_camera_vertex(cam, positions, a), load_camera_vertex(cam, positions, b),
                          load_camera_vertex(cam, positions, c), id, clvis_guard_of(cam), out);
        }
    }
    list_group(&pending, has, tris, capacity, listed, group);
}

/* Where items read their vertices (shared/scene_items.h). */
typedef struct {
    __global const float* positions;
    __global const clvis_item_mesh* meshes;
    __global const clvis_item* items;
} item_chunk;

static clvis_clip_vertex item_camera_vertex(clvis_camera_gpu cam, item_chunk k, uint item, uint v)
{
    clvis_vec3 p = clvis_item_point(k.items + item, k.meshes, k.positions, v);
    return clvis_clip_vertex_of(cam, p.x, p.y, p.z);
}

/* raster_setup_vertices for the vertex_count vertices of a chunk's items, item after item. */
__kernel void raster_setup_item_vertices(clvis_camera_gpu cam, __global const float* positions,
                                         __global const clvis_item_mesh* meshes, __global const clvis_item* items,
                                         uint first_item, uint end_item, uint vertex_count,
                                         __global clvis_raster_projected* projected)
{
    uint v = (uint)get_global_id(0);
    if (v >= vertex_count) return;
    ulong first = clvis_item_first_vertex(items + first_item) + v;
    uint item = clvis_item_of_vertex(items, first_item, end_item, first);
    item_chunk k = {positions, meshes, items};
    projected[v] = project(cam, item_camera_vertex(cam, k, item, (uint)(first - clvis_item_first_vertex(items + item))));
}

/* raster_setup for the triangle_count triangles of a chunk's items (ids as the expansion's);
   `projected` holds raster_setup_item_vertices' vertices of the same chunk. */
__kernel void raster_setup_items(clvis_camera_gpu cam, __global const float* positions, __global const uint* indices,
                                 __global const clvis_item_mesh* meshes, __global const clvis_item* items,
                                 uint first_item, uint end_item, uint triangle_count,
                                 __global const clvis_raster_projected* projected, int cull,
                                 volatile __global ulong* keys, __global clvis_raster_tri* tris, uint capacity,
                                 volatile __global uint* listed, clvis_region region)
{
    __local uint group[2];
    clvis_raster_tri pending;
    int has = 0;
    uint t = (uint)get_global_id(0);
    if (t < triangle_count) {
        uint id = items[first_item].first_id + t;
        uint item = clvis_item_of_triangle(items, first_item, end_item, id);
        clvis_item_mesh mesh = meshes[items[item].mesh & ~CLVIS_ITEM_TRANSFORMED];
        size_t i = 3 * ((size_t)mesh.first_triangle + (id - items[item].first_id));
        uint a = indices[i], b = indices[i + 1], c = indices[i + 2];
        __global const clvis_raster_projected* own =
            projected + (size_t)(clvis_item_first_vertex(items + item) - clvis_item_first_vertex(items + first_item));
        raster_setup_out out = {cam, cull, keys, tris, capacity, listed, region, &pending, &has};
        item_chunk k = {positions, meshes, items};
        if (emit_unclipped(own[a], own[b], own[c], id, out)) {
            out.pending = 0; /* a clipped fan lists its triangles at once */
            clip_and_emit(item_camera_vertex(cam, k, item, a), item_camera_vertex(cam, k, item, b),
                          item_camera_vertex(cam, k, item, c), id, clvis_guard_of(cam), out);
        }
    }
    list_group(&pending, has, tris, capacity, listed, group);
}
