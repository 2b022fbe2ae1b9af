/* A region: the rectangle of a full image's pixels that one launch renders, into a buffer of the
   region's size (row 0 = the region's top row). Every kernel still computes in the full image's
   raster space (the camera keeps the full width and height), so a region's keys are the bits of
   the same pixels of the full render; the host splits images into regions for several devices
   and MPI ranks. */
#ifndef CLVIS_SHARED_REGION_H
#define CLVIS_SHARED_REGION_H

#include "shared/types.h"

typedef struct clvis_region {
    clvis_i32 x, y;          /* the region's top-left pixel in the full image */
    clvis_i32 width, height; /* pixels; the buffer holds width * height keys */
} clvis_region;

#endif
