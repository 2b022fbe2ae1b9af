/* Clears a visibility buffer to the background key before a path writes it; consumed by
   raster_* (atomic min) and read back by the host. */
#include "shared/visibility.h"
#include "shared/raster_stream.h"

/* The raster path's clear: work-item k writes keys CLVIS_CLEAR_RUN k .. CLVIS_CLEAR_RUN (k + 1) - 1
   (those below `count`) a cache line at a time. With `stream` (the host asks for it where the
   keys are large against the cache) on a build with CLVIS_STREAM (shared/raster_stream.h), the
   lines go past the cache: the clear then neither reads the lines it writes (16 MB of keys at
   1080p) nor evicts what the frame's stages fetch. The same keys either way. */
__kernel void visibility_clear_lines(__global ulong* keys, ulong count, int stream)
{
    ulong begin = (ulong)get_global_id(0) * CLVIS_CLEAR_RUN;
    if (begin < count) {
        ulong end = min(begin + CLVIS_CLEAR_RUN, count);
        ulong i = begin;
        if (clvis_stream_aligned(keys + i))
            for (; i + 8 <= end; i += 8) clvis_stream_line(keys + i, (ulong8)(CLVIS_BACKGROUND_KEY), stream);
        for (; i < end; ++i) keys[i] = CLVIS_BACKGROUND_KEY;
    }
    /* One fence per work-group, once every work-item's lines are out: a fence per work-item
       would wait for each 2 KB to reach memory in turn. */
    barrier(CLK_GLOBAL_MEM_FENCE);
    if (stream && get_local_id(0) == 0) clvis_stream_fence();
}
