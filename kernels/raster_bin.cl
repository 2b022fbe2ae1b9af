/* Raster path, stage 2 of 3: bins the triangles that raster_setup.cl listed into screen tiles.
   raster_bin_count counts the triangles touching each tile, raster_bin_scan turns the counts
   into bin offsets, raster_bin_fill writes each bin (the entries its capacity holds: the host
   reads the total back at the end of the frame and redraws it with larger bins when they
   overflowed); raster_fine.cl walks the bins. raster_bin_small does all three in one launch for
   small frames on PoCL's CPU device. Only 32-bit atomics: it builds on devices without 64-bit ones. */
#include "shared/raster.h"

/* Calls BODY(tile) for every tile of `tile_log2` whose pixel centres triangle t may cover. Most
   triangles lie in one tile: that tile, without the loops or the edge test (a triangle whose box
   holds no sample it covers costs the fine stage a test, never a pixel). */
#define CLVIS_FOR_EACH_TILE(t, tile_log2, tiles_x, BODY)                                          \
    if (((t).x0 >> (tile_log2)) == ((t).x1 >> (tile_log2)) &&                                      \
        ((t).y0 >> (tile_log2)) == ((t).y1 >> (tile_log2))) {                                      \
        uint tile = (uint)((t).y0 >> (tile_log2)) * (uint)(tiles_x) + (uint)((t).x0 >> (tile_log2)); \
        BODY;                                                                                      \
    } else                                                                                         \
        for (int ty = (t).y0 >> (tile_log2); ty <= (t).y1 >> (tile_log2); ++ty) {                  \
            int j0 = max(ty << (tile_log2), (t).y0), j1 = min(((ty + 1) << (tile_log2)) - 1, (t).y1); \
            for (int tx = (t).x0 >> (tile_log2); tx <= (t).x1 >> (tile_log2); ++tx) {              \
                int i0 = max(tx << (tile_log2), (t).x0);                                           \
                int i1 = min(((tx + 1) << (tile_log2)) - 1, (t).x1);                               \
                if (clvis_raster_overlaps(&(t), i0, j0, i1, j1)) {                                 \
                    uint tile = (uint)ty * (uint)(tiles_x) + (uint)tx;                             \
                    BODY;                                                                          \
                }                                                                                  \
            }                                                                                      \
        }

/* Zeroes `count` words: the counters before raster_setup.cl lists triangles, the tile counts
   before raster_bin_count when a frame stopped before raster_bin_scan zeroed them. */
__kernel void raster_bin_zero(__global uint* words, uint count)
{
    uint i = (uint)get_global_id(0);
    if (i < count) words[i] = 0;
}

/* The triangles raster_setup.cl stored: those it listed (`listed`, two words), at most `capacity`.
   Read on the device, so the host launches the bins over the list's capacity without waiting. */
static uint listed_count(__global const uint* listed, uint capacity)
{
    return listed[1] != 0u ? capacity : min(listed[0], capacity);
}

__kernel void raster_bin_count(__global const clvis_raster_tri* tris, __global const uint* listed, uint capacity,
                               int tile_log2, int tiles_x, volatile __global uint* tile_counts)
{
    uint k = (uint)get_global_id(0);
    if (k >= listed_count(listed, capacity)) return;
    clvis_raster_tri t = tris[k];
    CLVIS_FOR_EACH_TILE(t, tile_log2, tiles_x, atomic_inc(&tile_counts[tile]))
}

/* One work-group: each work-item sums a contiguous run of tiles, work-item 0 scans the sums, then
   each writes its run's offsets. offsets[tile_count] and counters[1] receive the total (64-bit:
   the host refuses totals that 32-bit offsets cannot hold), counters[2] the longest bin (the host
   splits raster_fine.cl's launches by it where a device caps loops). Each work-item zeroes the
   counts of its run once read, so the next raster_bin_count needs no zeroing launch. */
__kernel void raster_bin_scan(__global uint* tile_counts, uint tile_count, __global uint* offsets,
                              __global uint* cursors, __global ulong* counters, __local ulong* partial)
{
    uint lid = (uint)get_local_id(0), size = (uint)get_local_size(0);
    uint run = (tile_count + size - 1) / size;
    uint begin = min(lid * run, tile_count), end = min(begin + run, tile_count);
    ulong sum = 0;
    for (uint i = begin; i < end; ++i) sum += tile_counts[i];
    partial[lid] = sum;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        ulong total = 0;
        for (uint i = 0; i < size; ++i) {
            ulong s = partial[i];
            partial[i] = total;
            total += s;
        }
        counters[1] = total;
        offsets[tile_count] = (uint)total;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    ulong offset = partial[lid], peak = 0;
    for (uint i = begin; i < end; ++i) {
        offsets[i] = (uint)offset;
        cursors[i] = (uint)offset;
        uint n = tile_counts[i];
        offset += n;
        peak = max(peak, (ulong)n);
        tile_counts[i] = 0u; /* zero for the next raster_bin_count */
    }
    barrier(CLK_LOCAL_MEM_FENCE); /* every offset read before the partials are reused */
    partial[lid] = peak;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        for (uint i = 1; i < size; ++i) peak = max(peak, partial[i]);
        counters[2] = peak;
    }
}

__kernel void raster_bin_fill(__global const clvis_raster_tri* tris, __global const uint* listed, uint tri_capacity,
                              int tile_log2, int tiles_x, volatile __global uint* cursors, __global uint* entries,
                              uint capacity)
{
    uint k = (uint)get_global_id(0);
    if (k >= listed_count(listed, tri_capacity)) return;
    clvis_raster_tri t = tris[k];
    CLVIS_FOR_EACH_TILE(t, tile_log2, tiles_x, {
        uint slot = atomic_inc(&cursors[tile]);
        if (slot < capacity) entries[slot] = k;
    })
}

/* The three kernels above in one work-group, for a short list over few tiles (the host's
   bin_listed: PoCL's CPU device, where each launch of a small frame costs more than the binning
   itself): the tiles' counts and cursors in local memory (`cursor`, tile_count words), then the
   same offsets, counters and entries as raster_bin_scan and raster_bin_fill write (a bin's
   entries in another order: raster_fine.cl keeps the least key whatever the order). Neither
   tile_counts nor cursors is touched. */
__kernel void raster_bin_small(__global const clvis_raster_tri* tris, __global const uint* listed, uint tri_capacity,
                               int tile_log2, int tiles_x, uint tile_count, __global uint* offsets,
                               __global ulong* counters, __global uint* entries, uint capacity,
                               volatile __local uint* cursor)
{
    uint lid = (uint)get_local_id(0), size = (uint)get_local_size(0);
    uint n = listed_count(listed, tri_capacity);
    for (uint i = lid; i < tile_count; i += size) cursor[i] = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint k = lid; k < n; k += size) {
        clvis_raster_tri t = tris[k];
        CLVIS_FOR_EACH_TILE(t, tile_log2, tiles_x, atomic_inc(&cursor[tile]))
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        ulong total = 0, peak = 0;
        for (uint i = 0; i < tile_count; ++i) {
            uint c = cursor[i];
            offsets[i] = (uint)total;
            cursor[i] = (uint)total;
            total += c;
            peak = max(peak, (ulong)c);
        }
        offsets[tile_count] = (uint)total;
        counters[1] = total;
        counters[2] = peak;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint k = lid; k < n; k += size) {
        clvis_raster_tri t = tris[k];
        CLVIS_FOR_EACH_TILE(t, tile_log2, tiles_x, {
            uint slot = atomic_inc(&cursor[tile]);
            if (slot < capacity) entries[slot] = k;
        })
    }
}
