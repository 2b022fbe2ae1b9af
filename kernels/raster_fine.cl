/* Raster path, stage 3 of 3: rasterizes the binned triangles of raster_bin.cl tile by tile. A
   work-item owns a square of up to CLVIS_FINE_SUB pixels a side inside one tile, walks the tile's
   bin, evaluates only the 8-pixel row spans each triangle's box touches (clvis_raster_span8),
   keeps the nearest keys in private memory, then merges them with what raster_setup.cl wrote
   (atomic mode) or, built with CLVIS_RASTER_OWNED (tile ownership: every triangle was binned),
   writes them, background included: each key of the buffer is written once, by its owner. */
#include "shared/raster.h"

#define CLVIS_FINE_SPANS (CLVIS_FINE_SUB / 8) /* 8-pixel spans per row of the square */

/* What a work-item leaves in a key it owns: its nearest key merged with what the small triangles
   of raster_setup.cl left there (atomic mode), or its nearest key alone (tile ownership). */
#ifdef CLVIS_RASTER_OWNED
#define CLVIS_FINE_MERGE(kept, stored) (kept)
#else
#define CLVIS_FINE_MERGE(kept, stored) min((kept), (stored))
#endif

__kernel void raster_fine(__global const clvis_raster_tri* tris, __global const uint* entries,
                          __global const uint* offsets, int tile_log2, int tiles_x, clvis_camera_gpu cam,
                          __global ulong* keys)
{
    int sub = min(1 << tile_log2, CLVIS_FINE_SUB);
    int px0 = (int)get_global_id(0) * sub, py0 = (int)get_global_id(1) * sub;
    if (px0 >= cam.width || py0 >= cam.height) return;
    int px1 = min(px0 + sub, cam.width) - 1, py1 = min(py0 + sub, cam.height) - 1;
    uint tile = (uint)(py0 >> tile_log2) * (uint)tiles_x + (uint)(px0 >> tile_log2);
    uint begin = offsets[tile], end = offsets[tile + 1];

    ulong8 best[CLVIS_FINE_SUB][CLVIS_FINE_SPANS];
    for (int r = 0; r < CLVIS_FINE_SUB; ++r)
        for (int s = 0; s < CLVIS_FINE_SPANS; ++s) best[r][s] = (ulong8)(CLVIS_BACKGROUND_KEY);

    for (uint k = begin; k < end; ++k) {
        __global const clvis_raster_tri* t = &tris[entries[k]];
        int ya = max(t->y0, py0), yb = min(t->y1, py1);
        int xa = max(t->x0, px0), xb = min(t->x1, px1);
        if (ya > yb || xa > xb) continue;
        long e0 = t->e0[0], e1 = t->e0[1], e2 = t->e0[2];
        long ex0 = t->ex[0], ex1 = t->ex[1], ex2 = t->ex[2];
        long ey0 = t->ey[0], ey1 = t->ey[1], ey2 = t->ey[2];
        float wc = t->wc, w0 = t->w[0], w1 = t->w[1], w2 = t->w[2];
        uint id = t->id;
        int s0 = (xa - px0) >> 3, s1 = (xb - px0) >> 3;
        for (int j = ya; j <= yb; ++j) {
            for (int s = s0; s <= s1; ++s) {
                int i0 = px0 + 8 * s;
                ulong8 key = clvis_raster_span8(e0 + (long)i0 * ex0 + (long)j * ey0, e1 + (long)i0 * ex1 + (long)j * ey1,
                                                e2 + (long)i0 * ex2 + (long)j * ey2, ex0, ex1, ex2, wc, w0, w1, w2, id,
                                                min(8, px1 - i0 + 1), cam.ortho, cam.near_d, cam.far_d);
                best[j - py0][s] = min(best[j - py0][s], key);
            }
        }
    }

    for (int j = py0; j <= py1; ++j) {
        for (int s = 0; 8 * s <= px1 - px0; ++s) {
            ulong8 b = best[j - py0][s];
            int i0 = px0 + 8 * s, count = min(8, px1 - i0 + 1);
            __global ulong* row = keys + (size_t)j * (size_t)cam.width + (size_t)i0;
#ifndef CLVIS_RASTER_OWNED
            if (all(b == (ulong8)(CLVIS_BACKGROUND_KEY))) continue; /* nothing to merge */
#endif
            if (count == 8) {
                vstore8(CLVIS_FINE_MERGE(b, vload8(0, row)), 0, row);
            } else {
                ulong lane[8];
                vstore8(b, 0, lane);
                for (int l = 0; l < count; ++l) row[l] = CLVIS_FINE_MERGE(lane[l], row[l]);
            }
        }
    }
}
