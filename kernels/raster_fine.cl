/* Raster path, stage 3 of 3: rasterizes the binned triangles of raster_bin.cl tile by tile. A
   work-group covers one tile (or a band of it), one work-item per pixel, walks the tile's bin
   keeping the pixel's nearest key, then merges it with what raster_setup.cl wrote. */
#include "shared/raster.h"

__kernel void raster_fine(__global const clvis_raster_tri* tris, __global const uint* entries,
                          __global const uint* offsets, int tile_log2, int tiles_x, clvis_camera_gpu cam,
                          __global ulong* keys)
{
    int i = (int)get_global_id(0), j = (int)get_global_id(1);
    uint tile = (uint)(j >> tile_log2) * (uint)tiles_x + (uint)(i >> tile_log2);
    uint begin = offsets[tile], end = offsets[tile + 1];
    ulong best = CLVIS_BACKGROUND_KEY;
    for (uint k = begin; k < end; ++k) {
        /* Every work-item of the group walks the same bin: the barrier splits the loop body into
           a region that PoCL runs as one vectorized loop over the group's pixels. */
        barrier(CLK_LOCAL_MEM_FENCE);
        clvis_raster_tri t = tris[entries[k]];
        ulong key = clvis_raster_sample(&t, i, j, cam.ortho, cam.near_d, cam.far_d);
        best = key < best ? key : best;
    }
    if (i < cam.width && j < cam.height && best != CLVIS_BACKGROUND_KEY) {
        size_t p = (size_t)j * (size_t)cam.width + (size_t)i;
        ulong old = keys[p];
        keys[p] = best < old ? best : old;
    }
}
