/* The visible set of a scene's triangles, on the device: visible_mark sets bit id of a mask for
   every id in a visibility buffer (views accumulate until the host clears the mask);
   visible_scan turns the mask words' bit counts into offsets (one work-group); visible_fill
   writes the set bits of each word at its offset, so the list comes out in ascending id order.
   Launched by host/render/visible_set.cpp. */
#include "shared/visibility.h"

__kernel void visible_clear(__global uint* mask, uint words)
{
    uint i = (uint)get_global_id(0);
    if (i < words) mask[i] = 0u;
}

__kernel void visible_mark(__global const ulong* keys, uint count, uint triangle_count, volatile __global uint* mask)
{
    uint i = (uint)get_global_id(0);
    if (i >= count) return;
    uint id = clvis_key_id(keys[i]);
    if (id == CLVIS_BACKGROUND_ID || id >= triangle_count) return;
    atomic_or(&mask[id >> 5], 1u << (id & 31u));
}

/* One work-group: each work-item sums the bit counts of a contiguous run of words, the group
   scans the sums in local memory (Hillis and Steele, log2(size) steps), then each work-item writes
   its run's offsets; offsets[words] receives the total. */
__kernel void visible_scan(__global const uint* mask, uint words, __global uint* offsets, __local uint* partial)
{
    uint lid = (uint)get_local_id(0), size = (uint)get_local_size(0);
    uint run = (words + size - 1) / size;
    uint begin = min(lid * run, words), end = min(begin + run, words);
    uint sum = 0;
    for (uint i = begin; i < end; ++i) sum += popcount(mask[i]);
    partial[lid] = sum;
    for (uint step = 1; step < size; step <<= 1) {
        barrier(CLK_LOCAL_MEM_FENCE);
        uint left = lid >= step ? partial[lid - step] : 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        partial[lid] += left;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == size - 1) offsets[words] = partial[lid];
    uint at = partial[lid] - sum; /* the inclusive scan less this run: where it starts */
    for (uint i = begin; i < end; ++i) {
        offsets[i] = at;
        at += popcount(mask[i]);
    }
}

__kernel void visible_fill(__global const uint* mask, uint words, __global const uint* offsets, __global uint* ids)
{
    uint i = (uint)get_global_id(0);
    if (i >= words) return;
    uint m = mask[i], at = offsets[i];
    while (m != 0u) {
        uint b = 31u - clz(m & (0u - m)); /* lowest set bit */
        ids[at++] = (i << 5) | b;
        m &= m - 1u;
    }
}
