/* Clears a visibility buffer to the background key before a path writes it; consumed by
   raster_* (atomic min) and read back by the host. */
#include "shared/visibility.h"

__kernel void visibility_clear(__global ulong* keys, uint count)
{
    uint i = get_global_id(0);
    if (i < count) keys[i] = CLVIS_BACKGROUND_KEY;
}
