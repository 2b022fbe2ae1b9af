/* Depth layers (RenderOptions::layers, CONVENTIONS.md "Depth layers"): a sample keeps its K
   nearest distinct keys, K = CLVIS_LAYERS (2 to 8; the kernels are built with -DCLVIS_LAYERS=K only
   when K > 1, so a one-layer build compiles none of this). A buffer of keys is layer-major: layer
   k of a frame's `plane` keys (width * height * samples of the region) starts at key k * plane,
   so layer 0 is the one-layer buffer, key for key. Each layer's list is sorted ascending (depth
   bits, then id), background keys last; a key already present is not inserted again (a key holds
   its triangle's id: equal keys are the same triangle at the same sample), so a triangle holds at
   most one layer of a sample.
   Two inserts, the same list: clvis_layers_insert for a list its caller owns (private memory, or
   keys no other work-item writes in this launch: the raster fine stage's squares and pixels, the
   ray kernels), and, in raster_setup.cl, the atomic cascade for keys other work-items draw at the
   same time. */
#ifndef CLVIS_SHARED_LAYERS_H
#define CLVIS_SHARED_LAYERS_H

#include "shared/visibility.h"

#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
#if CLVIS_LAYERS > 8
#error "CLVIS_LAYERS: 1 to 8 layers"
#endif

/* Sorted insert of `key` into the list list[0], list[stride], .. list[(K - 1) stride]: the key
   takes the first slot it is below, every key after moves on one slot, the last drops off. A
   background key inserts nothing; a key already held changes nothing. */
#define CLVIS_LAYERS_INSERT_BODY                                                                    \
    if (key == CLVIS_BACKGROUND_KEY) return;                                                         \
    for (int k = 0; k < CLVIS_LAYERS; ++k) {                                                         \
        clvis_u64 old = list[(size_t)k * stride];                                                    \
        if (key == old) return; /* held already (or the background: nothing to insert) */            \
        if (key < old) {                                                                             \
            list[(size_t)k * stride] = key;                                                          \
            if (old == CLVIS_BACKGROUND_KEY) return;                                                 \
            key = old;                                                                               \
        }                                                                                            \
    }

static inline void clvis_layers_insert(clvis_u64* list, size_t stride, clvis_u64 key) { CLVIS_LAYERS_INSERT_BODY }

#ifdef __OPENCL_C_VERSION__
static inline void clvis_layers_insert_global(__global ulong* list, size_t stride, ulong key) { CLVIS_LAYERS_INSERT_BODY }
#endif

#endif
#endif
