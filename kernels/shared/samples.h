/* Samples per pixel (CONVENTIONS.md "Samples per pixel"), shared by the raster kernels, the ray
   kernels and the host (referee, tests): N = 2^log2n in {1, 2, 4, 8, 16} samples per pixel, and
   sample k of pixel (i, j) at (i + 0.5 + dx_k / 16, j + 0.5 + dy_k / 16), y down, with (dx, dy)
   the standard sample locations of Vulkan and Direct3D in their order. The offsets, in
   [-8, 7], are packed as 4-bit two's complement nibbles (sample k in bits 4k .. 4k + 3), one
   64-bit word per axis and sample count. A buffer of N samples holds width x height x N keys,
   the N samples of a pixel adjacent: key (pixel << log2n) + k. */
#ifndef CLVIS_SHARED_SAMPLES_H
#define CLVIS_SHARED_SAMPLES_H

#include "shared/types.h"

#define CLVIS_MAX_SAMPLES_LOG2 4 /* 16 samples per pixel at most */

/* dx_k (axis 0) or dy_k (axis 1), in 1/16 px, of sample k of 2^log2n. */
static inline int clvis_sample_offset(int log2n, int k, int axis)
{
    clvis_u64 x, y;
    switch (log2n) {
    case 1: x = 0xC4ull; y = 0xC4ull; break;                                        /* (4,4) (-4,-4) */
    case 2: x = 0x2A6Eull; y = 0x62EAull; break;                                    /* (-2,-6) (6,-2) (-6,2) (2,6) */
    case 3: x = 0x739BD5F1ull; y = 0x97F5B13Dull; break;
    case 4: x = 0x9678AC0E352B4DF1ull; y = 0x87C04A96B35EF2D1ull; break;
    default: x = 0; y = 0; break;                                                   /* one sample at the centre */
    }
    clvis_u64 word = axis == 0 ? x : y;
    int nibble = (int)((word >> (4 * k)) & 15u);
    return nibble >= 8 ? nibble - 16 : nibble;
}

/* Where sample k of 2^log2n lies inside its pixel along an axis, px from the pixel's left (top)
   edge: 0.5 + d / 16, exact in float32; the raster position of the sample of pixel i is
   (float)i + this, exact for |i| < 2^18, and (float)i + 0.5f for one sample, bit for bit. */
static inline float clvis_sample_fraction(int log2n, int k, int axis)
{
    return 0.5f + (float)clvis_sample_offset(log2n, k, axis) * 0.0625f;
}

#endif
