/* Ray queries (CONVENTIONS.md "Ray queries"): the layouts of rays and hits in device buffers, the
   query kinds, and what makes a ray invalid. Shared by ray_query.cl, ray_query_brute.cl,
   ray_generate.cl and host/query/ray_query.cpp, so the host checks the layouts the kernels read. */
#ifndef CLVIS_SHARED_RAY_QUERY_H
#define CLVIS_SHARED_RAY_QUERY_H

#include "shared/types.h"

/* Query kinds (the kernels' CLVIS_QUERY). */
#define CLVIS_QUERY_CLOSEST 0 /* t, id, u, v per ray */
#define CLVIS_QUERY_ANY 1     /* one uchar per ray: 1 when any hit lies in [tmin, tmax] */
#define CLVIS_QUERY_COUNT 2   /* one uint per ray: crossings in [tmin, tmax], half-open */
#define CLVIS_QUERY_ALL 3     /* max_hits hits per ray (t, id, u, v), nearest first; optionally the
                                 number of all hits per ray (uint, edges inclusive) */

/* All hits: max_hits lies in [1, CLVIS_MAX_ALL_HITS]; a kernel keeps a list of CLVIS_MAX_HITS
   entries (the power of two at or above max_hits, built per power) in private memory. */
#define CLVIS_MAX_ALL_HITS 64

/* Buffer layouts. AoS: ray i is 8 floats at 8 i (ox, oy, oz, tmin, dx, dy, dz, tmax), hit i is
   4 words at 4 i (t, id, u, v). SoA: field k of record i at k * stride + i (stride >= records). */
#define CLVIS_LAYOUT_AOS 0
#define CLVIS_LAYOUT_SOA 1
#define CLVIS_RAY_FIELDS 8
#define CLVIS_HIT_FIELDS 4

/* A ray as 8 floats (one record of either layout). */
typedef struct clvis_ray_rec {
    float ox, oy, oz, tmin; /* origin (world units), start of the interval (>= 0) */
    float dx, dy, dz, tmax; /* direction (any length, not zero), end of the interval */
} clvis_ray_rec;

/* A closest hit: t = +inf, id = 0xFFFFFFFF, u = v = 0 for a miss. */
typedef struct clvis_hit_rec {
    float t;
    clvis_u32 id;
    float u, v; /* weights of v1 and v2 */
} clvis_hit_rec;

static inline int clvis_is_finite(float x) { return (clvis_float_bits(x) & 0x7F800000u) != 0x7F800000u; }
static inline int clvis_is_nan(float x) { return (clvis_float_bits(x) & 0x7FFFFFFFu) > 0x7F800000u; }

/* A ray the queries answer: origin, direction and tmin finite, tmax finite or +inf (an
   unbounded ray), 0 <= tmin <= tmax, direction not zero. Any other ray is a miss, and counted. */
static inline int clvis_ray_valid(clvis_ray_rec r)
{
    int finite = clvis_is_finite(r.ox) && clvis_is_finite(r.oy) && clvis_is_finite(r.oz) && clvis_is_finite(r.tmin) &&
                 clvis_is_finite(r.dx) && clvis_is_finite(r.dy) && clvis_is_finite(r.dz) && !clvis_is_nan(r.tmax);
    return finite && r.tmin >= 0.0f && r.tmin <= r.tmax && (r.dx != 0.0f || r.dy != 0.0f || r.dz != 0.0f);
}

#endif
