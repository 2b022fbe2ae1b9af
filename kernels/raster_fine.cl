/* Raster path, stage 3 of 3: rasterizes the binned triangles of raster_bin.cl tile by tile. A
   work-group covers one tile; each work-item owns a span of CLVIS_FINE_SPAN pixels of one row,
   walks the tile's bin testing the span with explicit vector code, then merges its nearest keys
   with what raster_setup.cl wrote for small triangles. */
#include "shared/raster.h"

/* Pixels per work-item (the host passes 4 for 4-pixel tiles). Explicit vectors rather than
   PoCL's packing of work-items: the bin walk branches per triangle (rows outside its box are
   skipped), which would keep PoCL from vectorizing across work-items. */
#ifndef CLVIS_FINE_SPAN
#define CLVIS_FINE_SPAN 8
#endif

#define CLVIS_CAT_(a, b) a##b
#define CLVIS_CAT(a, b) CLVIS_CAT_(a, b)
#define longS CLVIS_CAT(long, CLVIS_FINE_SPAN)
#define ulongS CLVIS_CAT(ulong, CLVIS_FINE_SPAN)
#define floatS CLVIS_CAT(float, CLVIS_FINE_SPAN)
#define uintS CLVIS_CAT(uint, CLVIS_FINE_SPAN)
#define convert_floatS CLVIS_CAT(convert_float, CLVIS_FINE_SPAN)
#define convert_longS CLVIS_CAT(convert_long, CLVIS_FINE_SPAN)
#define convert_ulongS CLVIS_CAT(convert_ulong, CLVIS_FINE_SPAN)
#define as_uintS CLVIS_CAT(as_uint, CLVIS_FINE_SPAN)
#if CLVIS_FINE_SPAN == 8
#define CLVIS_LANES ((long8)(0, 1, 2, 3, 4, 5, 6, 7))
#elif CLVIS_FINE_SPAN == 4
#define CLVIS_LANES ((long4)(0, 1, 2, 3))
#else
#error "CLVIS_FINE_SPAN must be 4 or 8"
#endif

__kernel void raster_fine(__global const clvis_raster_tri* tris, __global const uint* entries,
                          __global const uint* offsets, int tile_log2, int tiles_x, clvis_camera_gpu cam,
                          __global ulong* keys)
{
    int i0 = (int)get_global_id(0) * CLVIS_FINE_SPAN, j = (int)get_global_id(1);
    if (i0 >= cam.width || j >= cam.height) return;
    uint tile = (uint)(j >> tile_log2) * (uint)tiles_x + (uint)(i0 >> tile_log2);
    uint begin = offsets[tile], end = offsets[tile + 1];
    ulongS best = (ulongS)(CLVIS_BACKGROUND_KEY);
    for (uint k = begin; k < end; ++k) {
        __global const clvis_raster_tri* t = &tris[entries[k]];
        if (j < t->y0 || j > t->y1 || i0 + CLVIS_FINE_SPAN - 1 < t->x0 || i0 > t->x1) continue;
        longS e0 = (longS)(t->e0[0] + (long)i0 * t->ex[0] + (long)j * t->ey[0]) + CLVIS_LANES * t->ex[0];
        longS e1 = (longS)(t->e0[1] + (long)i0 * t->ex[1] + (long)j * t->ey[1]) + CLVIS_LANES * t->ex[1];
        longS e2 = (longS)(t->e0[2] + (long)i0 * t->ex[2] + (long)j * t->ey[2]) + CLVIS_LANES * t->ex[2];
        longS inside = (e0 | e1 | e2) >= 0;
        if (!any(inside)) continue;
        /* The same operations, in the same order, as clvis_raster_depth. */
        floatS v = (floatS)(t->wc) + convert_floatS(e0) * t->w[0] + convert_floatS(e1) * t->w[1] +
                   convert_floatS(e2) * t->w[2];
        floatS d = cam.ortho ? v : 1.0f / v;
        longS hit = inside & convert_longS((d >= cam.near_d) & (d <= cam.far_d));
        ulongS key = (convert_ulongS(as_uintS(d)) << 32) | (ulongS)(t->id);
        best = select(best, min(best, key), hit);
    }
    if (all(best == (ulongS)(CLVIS_BACKGROUND_KEY))) return;
    __global ulong* row = keys + (size_t)j * (size_t)cam.width + (size_t)i0;
    if (i0 + CLVIS_FINE_SPAN <= cam.width) {
        CLVIS_CAT(vstore, CLVIS_FINE_SPAN)(min(best, CLVIS_CAT(vload, CLVIS_FINE_SPAN)(0, row)), 0, row);
    } else {
        ulong lanes[CLVIS_FINE_SPAN];
        CLVIS_CAT(vstore, CLVIS_FINE_SPAN)(best, 0, lanes);
        for (int l = 0; l < cam.width - i0; ++l) row[l] = min(row[l], lanes[l]);
    }
}
