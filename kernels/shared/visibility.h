/* The visibility key: one 64-bit word per pixel, (as_uint(view depth) << 32) | triangle id.
   Non-negative floats order like their bit patterns, so one 64-bit atomic min keeps the nearest
   triangle and, at an exact depth tie, the lower id: the tie rule lives in the key, not in the
   order work-items run. Written by both paths; read by shading and by the host. */
#ifndef CLVIS_SHARED_VISIBILITY_H
#define CLVIS_SHARED_VISIBILITY_H

#include "shared/types.h"

#define CLVIS_BACKGROUND_ID 0xFFFFFFFFu
/* (as_uint(+inf) << 32) | background id: larger than every key of a finite depth. */
#define CLVIS_BACKGROUND_KEY ((((clvis_u64)0x7F800000u) << 32) | (clvis_u64)0xFFFFFFFFu)

static inline clvis_u64 clvis_make_key(float depth, clvis_u32 id)
{
    return ((clvis_u64)clvis_float_bits(depth) << 32) | (clvis_u64)id;
}
/* Face culling (RenderOptions::cull), the same on every path. A triangle (v0, v1, v2), its
   vertices in index order after the mesh's transform, is front-facing when it appears
   counter-clockwise on screen (raster y down: clockwise in raster coordinates), which is when the
   eye lies on the side its normal cross(v1 - v0, v2 - v0) points to (orthographic: the normal
   points towards the camera, against f). A mirroring transform therefore turns front faces into
   back faces. `orientation` is the sign of a path's own measure of it: the raster path's doubled
   area in snapped raster space, the ray path's watertight determinant. */
#define CLVIS_CULL_NONE 0
#define CLVIS_CULL_BACK 1
#define CLVIS_CULL_FRONT 2

static inline int clvis_cull_keeps(int cull, int front, int back)
{
    return cull == CLVIS_CULL_BACK ? front : (cull == CLVIS_CULL_FRONT ? back : 1);
}

static inline clvis_u32 clvis_key_id(clvis_u64 key) { return (clvis_u32)(key & 0xFFFFFFFFu); }
static inline float clvis_key_depth(clvis_u64 key) { return clvis_bits_float((clvis_u32)(key >> 32)); }

#endif
