/* Raster path, stage 3 of 3: rasterizes the binned triangles of raster_bin.cl tile by tile. A
   work-item owns a square of up to CLVIS_FINE_SUB pixels a side inside one tile, walks the tile's
   bin (or a `chunk` of it from `first`: the host splits long bins over launches for devices that
   cap loops; a square whose bin ran past the bins' `capacity` writes nothing, the host redraws
   the frame with larger bins), skips triangles wholly behind the keys it holds, evaluates only the
   8-pixel row spans each triangle's box touches (clvis_raster_span8), keeps the nearest keys in
   private memory, then stores them: merged with what is there when `merge` (the small triangles
   raster_setup.cl drew with atomics, or an earlier chunk), or as they are, background included
   (tile ownership's first launch: every key of the buffer written once, by its owner, with no
   clear and no atomics). */
#include "shared/layers.h"
#include "shared/raster.h"
#include "shared/raster_stream.h"

#define CLVIS_FINE_AHEAD 4 /* bin entries: how far ahead a triangle is prefetched (CLVIS_PREFETCH) */

/* Both fine kernels' bin range (depth layers or not): the entries [*begin, *end) that a launch
   walks for the square or group whose first pixel is (px0, py0), the `chunk` of its tile's bin
   from `first`. 0 when the bins ran past `capacity`: then nothing is written, the host redraws
   the frame with larger bins. */
static inline CLVIS_ALWAYS_INLINE int fine_bin(__global const uint* offsets, int tile_log2, int tiles_x, int px0,
                                               int py0, uint first, uint chunk, uint capacity, uint* begin, uint* end)
{
    uint tile = (uint)(py0 >> tile_log2) * (uint)tiles_x + (uint)(px0 >> tile_log2);
    uint b = offsets[tile], e = offsets[tile + 1];
    if (e > capacity) return 0;
    b = first < e - b ? b + first : e;
    *begin = b;
    *end = chunk < e - b ? b + chunk : e;
    return 1;
}

#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
/* Depth layers (shared/layers.h): raster_fine's walk of its square (px0..px1, py0..py1) over
   the bin entries [begin, end), each covered sample's key inserted into the sample's sorted
   list of CLVIS_LAYERS keys in the buffer itself. The work-item owns its square's keys for the
   launch (setup's atomics finished before it), so the insert needs no atomics, under tile
   ownership or not; without `merge` it first writes the background into every layer of the
   square. No occlusion bound: the K-th key rises slowly. */
static inline CLVIS_ALWAYS_INLINE void
raster_fine_layers(__global const clvis_raster_tri* tris, __global const uint* entries, clvis_camera_gpu cam,
                   __global ulong* keys, clvis_region region, int px0, int py0, int px1, int py1, uint begin,
                   uint end, int merge)
{
    int n_log2 = cam.sample_log2;
    size_t plane = ((size_t)region.width * (size_t)region.height) << n_log2; /* keys per layer */
    if (!merge)
        for (int j = py0; j <= py1; ++j)
            for (int i = px0; i <= px1; ++i) {
                __global ulong* list = keys + (((size_t)j * (size_t)region.width + (size_t)i) << n_log2) + (size_t)cam.sample;
                for (int k = 0; k < CLVIS_LAYERS; ++k) list[(size_t)k * plane] = CLVIS_BACKGROUND_KEY;
            }
    for (uint e = begin; e < end; ++e) {
        __global const clvis_raster_tri* t = &tris[entries[e]];
        int ya = max(t->y0, py0), yb = min(t->y1, py1);
        int xa = max(t->x0, px0), xb = min(t->x1, px1);
        if (ya > yb || xa > xb) continue;
        long ex0 = t->ex[0], ex1 = t->ex[1], ex2 = t->ex[2];
        long ey0 = t->ey[0], ey1 = t->ey[1], ey2 = t->ey[2];
        float wc = t->wc, w0 = t->w[0], w1 = t->w[1], w2 = t->w[2];
        uint id = t->id;
        int s0 = (xa - px0) >> 3, s1 = (xb - px0) >> 3;
        int i0 = px0 + 8 * s0;
        long r0 = t->e0[0] + (long)i0 * ex0 + (long)ya * ey0;
        long r1 = t->e0[1] + (long)i0 * ex1 + (long)ya * ey1;
        long r2 = t->e0[2] + (long)i0 * ex2 + (long)ya * ey2;
        for (int j = ya; j <= yb; ++j, r0 += ey0, r1 += ey1, r2 += ey2) {
            long q0 = r0, q1 = r1, q2 = r2;
            for (int s = s0; s <= s1; ++s, q0 += 8 * ex0, q1 += 8 * ex1, q2 += 8 * ex2) {
                int x = px0 + 8 * s, count = min(8, px1 - x + 1);
                ulong8 key = clvis_raster_span8(q0, q1, q2, ex0, ex1, ex2, wc, w0, w1, w2, id, count, cam.ortho,
                                                cam.near_d, cam.far_d, 0);
                if (all(key == (ulong8)(CLVIS_BACKGROUND_KEY))) continue;
                ulong lane[8];
                vstore8(key, 0, lane);
                __global ulong* row = keys + (((size_t)j * (size_t)region.width + (size_t)x) << n_log2) + (size_t)cam.sample;
                for (int l = 0; l < count; ++l)
                    if (lane[l] != CLVIS_BACKGROUND_KEY) clvis_layers_insert_global(row + ((size_t)l << n_log2), plane, lane[l]);
            }
        }
    }
}
#endif

/* raster_fine's work-item: its square, from its bin to its keys. */
static inline CLVIS_ALWAYS_INLINE void
raster_fine_square(__global const clvis_raster_tri* tris, __global const uint* entries, __global const uint* offsets,
                   int tile_log2, int tiles_x, clvis_camera_gpu cam, __global ulong* keys, clvis_region region,
                   uint first, uint chunk, int merge, uint capacity, int stream)
{
    int sub = min(1 << tile_log2, CLVIS_FINE_SUB);
    int px0 = (int)get_global_id(0) * sub, py0 = (int)get_global_id(1) * sub;
    if (px0 >= region.width || py0 >= region.height) return; /* region pixels, shared/region.h */
    int px1 = min(px0 + sub, region.width) - 1, py1 = min(py0 + sub, region.height) - 1;
    uint begin, end;
    if (!fine_bin(offsets, tile_log2, tiles_x, px0, py0, first, chunk, capacity, &begin, &end))
        return; /* the bins overflowed: the host redraws the frame */
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    raster_fine_layers(tris, entries, cam, keys, region, px0, py0, px1, py1, begin, end, merge);
    return;
#endif
    int n_log2 = cam.sample_log2;
    /* Every key of the square written as it is (tile ownership's first launch), a line at a time:
       streamed past the cache when the host asks (`stream`: keys large against the cache, a
       CLVIS_STREAM build, shared/raster_stream.h), as the atomic depth test's clear does. */
    int lines = !merge && n_log2 == 0;
    stream = stream && lines;
    if (begin == end) { /* an empty bin (or chunk): nothing to merge, or the background to write */
        if (merge) return;
        for (int j = py0; j <= py1; ++j) {
            __global ulong* row = keys + (((size_t)j * (size_t)region.width + (size_t)px0) << n_log2) + (size_t)cam.sample;
            int i = 0;
            if (lines && clvis_stream_aligned(row))
                for (; i + 8 <= px1 - px0 + 1; i += 8) clvis_stream_line(row + i, (ulong8)(CLVIS_BACKGROUND_KEY), stream);
            for (; i <= px1 - px0; ++i) row[(size_t)i << n_log2] = CLVIS_BACKGROUND_KEY;
        }
        return;
    }

#ifdef CLVIS_PREFETCH
    /* The keys this square merges with at the end are fetched into the cache now (PoCL's CPU
       device, Device::Impl::cpu_hints), their misses overlapping the bin's walk. A hint only. */
    if (merge)
        for (int j = py0; j <= py1; ++j) {
            __global const ulong* row = keys + (((size_t)j * (size_t)region.width + (size_t)px0) << n_log2);
            CLVIS_PREFETCH_LINE(row);
            CLVIS_PREFETCH_LINE(row + ((size_t)(px1 - px0) << n_log2));
        }
#endif
    ulong8 best[CLVIS_FINE_SUB][CLVIS_FINE_SPANS];
    for (int r = 0; r < CLVIS_FINE_SUB; ++r)
        for (int s = 0; s < CLVIS_FINE_SPANS; ++s) best[r][s] = (ulong8)(CLVIS_BACKGROUND_KEY);

    /* Occlusion: keys only decrease, so `bound`, the largest key of the square when it was last
       taken (the background until then), bounds every key from above; a triangle whose nearest
       possible key (clvis_raster_tri::dnear, its id) exceeds it changes none and is skipped. Taking
       it costs about a span's evaluation per span of the square: it is retaken once the square's
       worth of spans has been evaluated since. Squares the image's edge cuts keep background
       keys in their unused rows and lanes, and skip nothing. */
    ulong bound = CLVIS_BACKGROUND_KEY;
    int evaluated = 0;
    for (uint k = begin; k < end; ++k) {
#ifdef CLVIS_PREFETCH
        /* the triangle CLVIS_FINE_AHEAD entries on (its three lines at most): the list is in
           setup's order, the bins' entries scattered over it */
        if (k + CLVIS_FINE_AHEAD < end) {
            __global const char* ahead = (__global const char*)&tris[entries[k + CLVIS_FINE_AHEAD]];
            CLVIS_PREFETCH_LINE(ahead);
            CLVIS_PREFETCH_LINE(ahead + 64);
            CLVIS_PREFETCH_LINE(ahead + sizeof(clvis_raster_tri) - 1);
        }
#endif
        __global const clvis_raster_tri* t = &tris[entries[k]];
        int ya = max(t->y0, py0), yb = min(t->y1, py1);
        int xa = max(t->x0, px0), xb = min(t->x1, px1);
        if (ya > yb || xa > xb || clvis_make_key(t->dnear, t->id) > bound) continue;
        long ex0 = t->ex[0], ex1 = t->ex[1], ex2 = t->ex[2];
        long ey0 = t->ey[0], ey1 = t->ey[1], ey2 = t->ey[2];
        float wc = t->wc, w0 = t->w[0], w1 = t->w[1], w2 = t->w[2];
        uint id = t->id;
        int s0 = (xa - px0) >> 3, s1 = (xb - px0) >> 3;
        /* Edge values at the first pixel of span s0 on row ya, stepped a row (ey) or a span (8 ex)
           at a time: the same integers as e0 + i ex + j ey at every pixel evaluated. */
        int i0 = px0 + 8 * s0;
        long r0 = t->e0[0] + (long)i0 * ex0 + (long)ya * ey0;
        long r1 = t->e0[1] + (long)i0 * ex1 + (long)ya * ey1;
        long r2 = t->e0[2] + (long)i0 * ex2 + (long)ya * ey2;
        for (int j = ya; j <= yb; ++j, r0 += ey0, r1 += ey1, r2 += ey2) {
            long q0 = r0, q1 = r1, q2 = r2;
            for (int s = s0; s <= s1; ++s, q0 += 8 * ex0, q1 += 8 * ex1, q2 += 8 * ex2) {
                ulong8 key = clvis_raster_span8(q0, q1, q2, ex0, ex1, ex2, wc, w0, w1, w2, id,
                                                min(8, px1 - (px0 + 8 * s) + 1), cam.ortho, cam.near_d, cam.far_d, 0);
                best[j - py0][s] = min(best[j - py0][s], key);
            }
        }
        evaluated += (yb - ya + 1) * (s1 - s0 + 1);
        if (evaluated >= CLVIS_FINE_SUB * CLVIS_FINE_SPANS) {
            ulong8 m = best[0][0];
            for (int q = 1; q < CLVIS_FINE_SUB * CLVIS_FINE_SPANS; ++q)
                m = max(m, best[q / CLVIS_FINE_SPANS][q % CLVIS_FINE_SPANS]);
            ulong4 m4 = max(m.lo, m.hi);
            ulong2 m2 = max(m4.lo, m4.hi);
            bound = max(m2.lo, m2.hi);
            evaluated = 0;
        }
    }

    for (int j = py0; j <= py1; ++j) {
        for (int s = 0; 8 * s <= px1 - px0; ++s) {
            ulong8 b = best[j - py0][s];
            int i0 = px0 + 8 * s, count = min(8, px1 - i0 + 1);
            /* the camera's sample of each pixel: samples of a pixel are adjacent (shared/samples.h) */
            __global ulong* row = keys + (((size_t)j * (size_t)region.width + (size_t)i0) << n_log2) + (size_t)cam.sample;
            if (merge && all(b == (ulong8)(CLVIS_BACKGROUND_KEY))) continue; /* nothing to merge */
            if (count == 8 && lines && clvis_stream_aligned(row)) {
                clvis_stream_line(row, b, stream);
            } else if (count == 8 && n_log2 == 0) {
                vstore8(merge ? min(b, vload8(0, row)) : b, 0, row);
            } else {
                ulong lane[8];
                vstore8(b, 0, lane);
                for (int l = 0; l < count; ++l) {
                    size_t o = (size_t)l << n_log2;
                    row[o] = merge ? min(row[o], lane[l]) : lane[l];
                }
            }
        }
    }
}

__kernel void raster_fine(__global const clvis_raster_tri* tris, __global const uint* entries,
                          __global const uint* offsets, int tile_log2, int tiles_x, clvis_camera_gpu cam,
                          __global ulong* keys, clvis_region region, uint first, uint chunk, int merge,
                          uint capacity, int stream)
{
    raster_fine_square(tris, entries, offsets, tile_log2, tiles_x, cam, keys, region, first, chunk, merge, capacity,
                       stream);
#ifdef CLVIS_STREAM
    /* Streamed lines: one fence per work-group once every work-item's lines are out, as in
       visibility_clear.cl (a fence per work-item waits for each square's lines in turn). */
    barrier(CLK_GLOBAL_MEM_FENCE);
    if (stream && get_local_id(0) == 0 && get_local_id(1) == 0) clvis_stream_fence();
#endif
}

/* The same stage mapped for GPUs (RasterMapping::Pixel): a work-group owns a square of
   get_local_size pixels inside one tile (the host makes its edge divide the tile's), a work-item
   one pixel. The group walks the tile's bin (or its chunk) together: each batch of up to a
   group's worth of triangles is copied into `batch` (local memory, a triangle per work-item),
   then every work-item tests its pixel against the whole batch. The pixel's nearest key stays in
   private memory and is stored once, merged or not as raster_fine does: the same
   clvis_raster_sample bits as clvis_raster_span8's lanes, so the same keys. */
__kernel void raster_fine_pixel(__global const clvis_raster_tri* tris, __global const uint* entries,
                                __global const uint* offsets, int tile_log2, int tiles_x, clvis_camera_gpu cam,
                                __global ulong* keys, clvis_region region, uint first, uint chunk, int merge,
                                uint capacity, __local clvis_raster_tri* batch)
{
    int gw = (int)get_local_size(0), gh = (int)get_local_size(1);
    int px0 = (int)get_group_id(0) * gw, py0 = (int)get_group_id(1) * gh;
    if (px0 >= region.width || py0 >= region.height) return; /* the whole group: no barrier skipped */
    int i = px0 + (int)get_local_id(0), j = py0 + (int)get_local_id(1);
    int lid = (int)get_local_id(1) * gw + (int)get_local_id(0), items = gw * gh;
    int inside = i < region.width && j < region.height;
    uint begin, end;
    if (!fine_bin(offsets, tile_log2, tiles_x, px0, py0, first, chunk, capacity, &begin, &end))
        return; /* the bins overflowed (the whole group): the host redraws the frame */

#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    ulong list[CLVIS_LAYERS]; /* the pixel's layers (shared/layers.h), merged into the buffer at the end */
    for (int k = 0; k < CLVIS_LAYERS; ++k) list[k] = CLVIS_BACKGROUND_KEY;
#endif
    ulong best = CLVIS_BACKGROUND_KEY;
    for (uint base = begin; base < end; base += (uint)items) {
        uint count = min((uint)items, end - base);
        barrier(CLK_LOCAL_MEM_FENCE); /* the previous batch read by every work-item */
        if ((uint)lid < count) batch[lid] = tris[entries[base + (uint)lid]];
        barrier(CLK_LOCAL_MEM_FENCE);
        for (uint b = 0; b < count; ++b) {
            if (!inside || j < batch[b].y0 || j > batch[b].y1 || i < batch[b].x0 || i > batch[b].x1) continue;
            clvis_raster_tri t = batch[b];
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
            clvis_layers_insert(list, 1, clvis_raster_sample(&t, i, j, cam.ortho, cam.near_d, cam.far_d));
#else
            best = min(best, clvis_raster_sample(&t, i, j, cam.ortho, cam.near_d, cam.far_d));
#endif
        }
    }
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    if (!inside) return;
    {
        size_t plane = ((size_t)region.width * (size_t)region.height) << cam.sample_log2;
        __global ulong* out = keys + (((size_t)j * (size_t)region.width + (size_t)i) << cam.sample_log2) + (size_t)cam.sample;
        for (int k = 0; k < CLVIS_LAYERS; ++k) {
            if (merge) {
                if (list[k] == CLVIS_BACKGROUND_KEY) break;
                clvis_layers_insert_global(out, plane, list[k]);
            } else {
                out[(size_t)k * plane] = list[k];
            }
        }
    }
    return;
#endif
    if (!inside || (merge && best == CLVIS_BACKGROUND_KEY)) return;
    /* the camera's sample of the pixel: samples of a pixel are adjacent (shared/samples.h) */
    __global ulong* key = keys + (((size_t)j * (size_t)region.width + (size_t)i) << cam.sample_log2) + (size_t)cam.sample;
    *key = merge ? min(*key, best) : best;
}
