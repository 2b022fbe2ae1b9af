/* Raster path, stage 3 of 3: rasterizes the binned triangles of raster_bin.cl tile by tile. A
   work-group covers one tile; each work-item owns a span of CLVIS_FINE_SPAN pixels of one row,
   walks the tile's bin testing the span with explicit vector code, then merges its nearest keys
   with what raster_setup.cl wrote for small triangles. */
#include "shared/raster.h"

/* Pixels per work-item: 8 (one vector span of clvis_raster_span8), or 4 on 4-pixel tiles, where
   the upper lanes stay empty. Explicit vectors rather than PoCL's packing of work-items: the bin
   walk branches per triangle (rows outside its box are skipped), which would keep PoCL from
   vectorizing across work-items. */
#ifndef CLVIS_FINE_SPAN
#define CLVIS_FINE_SPAN 8
#endif

__kernel void raster_fine(__global const clvis_raster_tri* tris, __global const uint* entries,
                          __global const uint* offsets, int tile_log2, int tiles_x, clvis_camera_gpu cam,
                          __global ulong* keys)
{
    int i0 = (int)get_global_id(0) * CLVIS_FINE_SPAN, j = (int)get_global_id(1);
    if (i0 >= cam.width || j >= cam.height) return;
    uint tile = (uint)(j >> tile_log2) * (uint)tiles_x + (uint)(i0 >> tile_log2);
    uint begin = offsets[tile], end = offsets[tile + 1];
    ulong8 best = (ulong8)(CLVIS_BACKGROUND_KEY);
    int count = min(CLVIS_FINE_SPAN, cam.width - i0);
    for (uint k = begin; k < end; ++k) {
        __global const clvis_raster_tri* t = &tris[entries[k]];
        if (j < t->y0 || j > t->y1 || i0 + CLVIS_FINE_SPAN - 1 < t->x0 || i0 > t->x1) continue;
        best = min(best, clvis_raster_span8(t->e0[0] + (long)i0 * t->ex[0] + (long)j * t->ey[0],
                                            t->e0[1] + (long)i0 * t->ex[1] + (long)j * t->ey[1],
                                            t->e0[2] + (long)i0 * t->ex[2] + (long)j * t->ey[2], t->ex[0], t->ex[1],
                                            t->ex[2], t->wc, t->w[0], t->w[1], t->w[2], t->id, count, cam.ortho,
                                            cam.near_d, cam.far_d));
    }
    if (all(best == (ulong8)(CLVIS_BACKGROUND_KEY))) return;
    __global ulong* row = keys + (size_t)j * (size_t)cam.width + (size_t)i0;
    if (count == 8) {
        vstore8(min(best, vload8(0, row)), 0, row);
    } else {
        ulong lane[8];
        vstore8(best, 0, lane);
        for (int l = 0; l < count; ++l) row[l] = min(row[l], lane[l]);
    }
}
