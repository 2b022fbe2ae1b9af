/* Raster math of the raster path, shared by raster_setup.cl, raster_bin.cl, raster_fine.cl and the
   host tests: clip planes in camera space, 16.16 fixed-point snapping, edge functions with the
   top-left rule, the per-sample coverage and depth test, and the tile-overlap test of binning. */
#ifndef CLVIS_SHARED_RASTER_H
#define CLVIS_SHARED_RASTER_H

#include "shared/camera.h"
#include "shared/region.h"
#include "shared/samples.h"
#include "shared/types.h"
#include "shared/visibility.h"


/* The limits of raster space, all derived here from the largest accepted image side S and the
   fixed-point fraction F (docs/architecture.md "Raster-space limits" walks through them):
   - Sub-pixel precision: raster coordinates are snapped to 1 / 2^F px, F = 16.
   - Guard band: geometry farther than M = CLVIS_GUARD_MARGIN px beyond the image's edges is
     clipped away in camera space, so the band is W/2 + M px from the image centre in x and
     H/2 + M in y. Clipped vertices then sit as close to the centre as the image's own corners,
     and float32 gives them the same raster-space error (about max(W, H) 2^-24 px per operation).
   - Snapped vertices are clamped to CLVIS_GUARD_SLACK px past the band (the clipper's cuts may
     round past it; non-finite values never reach a float-to-int conversion). Raster coordinates
     then lie within S + M + slack < 2^(31 - F) px of the origin: int32 16.16 holds them
     (clvis_raster_projected).
   - Every point an edge function is evaluated at (two vertices, a pixel centre of the image or of
     a vector span at most 8 px past its right edge, 8 <= M) lies in the rectangle of sides
     L = S + 2 (M + slack) px around the image centre; an edge value is the doubled area of a
     triangle in it, each of its products at most L^2, so |value| <= L^2 2^(2F) < 2^63.
   host/raster_pipeline.cpp checks these inequalities at compile time. */
#define CLVIS_SUBPIXEL_BITS 16
#define CLVIS_SUBPIXEL_ONE ((clvis_i64)1 << CLVIS_SUBPIXEL_BITS) /* one pixel, fixed units */
#define CLVIS_SUBPIXEL_HALF (CLVIS_SUBPIXEL_ONE >> 1)           /* half a pixel: the sample offset */
#define CLVIS_MAX_IMAGE_LOG2 14
#define CLVIS_MAX_IMAGE_SIZE (1 << CLVIS_MAX_IMAGE_LOG2) /* S = 16384 px, width and height */
#define CLVIS_GUARD_MARGIN 64                            /* M px beyond each edge of the image */
#define CLVIS_GUARD_SLACK 64                             /* px past the band where snapping clamps */
/* L, the side of the square every edge-function point lies in (px). */
#define CLVIS_RASTER_SPAN (CLVIS_MAX_IMAGE_SIZE + 2 * (CLVIS_GUARD_MARGIN + CLVIS_GUARD_SLACK))

/* Clip planes: near and the guard band's four sides (clvis_clip_distance). */
#define CLVIS_CLIP_PLANES 5

/* A camera-space point as the clipper sees it: d = -z is the view depth. */
typedef struct { float x, y, d; } clvis_clip_vertex;

/* A triangle ready to rasterize (setup's output for triangles that are binned). Edge k is
   opposite vertex k; the value of edge k at the centre of pixel (i, j) is
   e0[k] + i * ex[k] + j * ey[k] (fixed units squared), minus one on edges that are not top or
   left, so that a sample is covered iff all three values are >= 0. */
typedef struct clvis_raster_tri {
    clvis_i64 e0[3];           /* at the centre of pixel (0, 0), top-left bias applied */
    clvis_i64 ex[3];           /* change per pixel to the right */
    clvis_i64 ey[3];           /* change per pixel downwards */
    float w[3];                /* per vertex: 1/d (perspective) or d (orthographic), over the doubled area */
    float wc;                  /* the top-left bias given back: sum of w[k] over biased edges */
    clvis_u32 id;              /* triangle id */
    clvis_i32 x0, y0, x1, y1;  /* pixels whose centres it may cover, inclusive, inside the image */
    float dnear;               /* no sample of it is nearer (view depth; 0: no bound known) */
} clvis_raster_tri;

/* The guard band of a camera and image on the screen (screen units: s.x = x / d, or x itself when
   orthographic): CLVIS_GUARD_MARGIN pixels beyond each edge of the image, whose centre need not
   be the optical axis (a shifted principal point). lo/hi: its planes; gx, gy: its half extents;
   kx = 1 / (2 (1 + max |lo_x|, |hi_x|)), ky likewise, scale clip distances so that they stay
   finite for every finite camera-space point; khi_x = kx hi_x and so on. */
typedef struct {
    float lo_x, hi_x, lo_y, hi_y, gx, gy, kx, ky, klo_x, khi_x, klo_y, khi_y;
} clvis_guard;

static inline float clvis_guard_absf(float v) { return v < 0.0f ? -v : v; }

/* A guard band from its four planes (screen units). */
static inline clvis_guard clvis_guard_make(float lo_x, float hi_x, float lo_y, float hi_y)
{
    clvis_guard g;
    float ax = clvis_guard_absf(lo_x) > clvis_guard_absf(hi_x) ? clvis_guard_absf(lo_x) : clvis_guard_absf(hi_x);
    float ay = clvis_guard_absf(lo_y) > clvis_guard_absf(hi_y) ? clvis_guard_absf(lo_y) : clvis_guard_absf(hi_y);
    g.lo_x = lo_x; g.hi_x = hi_x; g.lo_y = lo_y; g.hi_y = hi_y;
    g.gx = 0.5f * hi_x - 0.5f * lo_x;
    g.gy = 0.5f * hi_y - 0.5f * lo_y;
    g.kx = 0.5f / (1.0f + ax);
    g.ky = 0.5f / (1.0f + ay);
    g.klo_x = g.kx * lo_x; g.khi_x = g.kx * hi_x;
    g.klo_y = g.ky * lo_y; g.khi_y = g.ky * hi_y;
    return g;
}

static inline clvis_guard clvis_guard_of(clvis_camera_gpu cam)
{
    float mx = (0.5f * (float)cam.width - cam.cx) / cam.fx;
    float gx = (0.5f * (float)cam.width + (float)CLVIS_GUARD_MARGIN) / cam.fx;
    float my = (cam.cy - 0.5f * (float)cam.height) / cam.fy;
    float gy = (0.5f * (float)cam.height + (float)CLVIS_GUARD_MARGIN) / cam.fy;
    return clvis_guard_make(mx - gx, mx + gx, my - gy, my + gy);
}

/* Whether a camera-space point is finite (the camera transform of a finite world point beyond
   about 3.4e38 from the eye overflows). Bits, not isfinite: the same on every compiler. */
static inline int clvis_clip_vertex_finite(clvis_clip_vertex p)
{
    return (clvis_float_bits(p.x) & 0x7F800000u) != 0x7F800000u &&
           (clvis_float_bits(p.y) & 0x7F800000u) != 0x7F800000u &&
           (clvis_float_bits(p.d) & 0x7F800000u) != 0x7F800000u;
}

/* Signed distance-like value of a camera-space point to clip plane `plane` (>= 0: inside), scaled
   so that it stays finite, at most FLT_MAX / 2 in magnitude, for every finite point; NaN for a
   point that is not finite (outside every plane: the clipper drops it and cuts nothing towards
   it, so its triangle draws only the part its finite points span). 0: near; 1-4: the guard
   band's right, left, top and bottom planes. */
static inline float clvis_clip_distance(clvis_clip_vertex p, int plane, float near_d, clvis_guard g, int ortho)
{
    if (!clvis_clip_vertex_finite(p)) return clvis_bits_float(0x7FC00000u); /* a quiet NaN */
    float h = ortho ? 1.0f : p.d;
    switch (plane) {
    case 0: return 0.5f * p.d - 0.5f * near_d;
    case 1: return g.khi_x * h - g.kx * p.x;
    case 2: return g.kx * p.x - g.klo_x * h;
    case 3: return g.khi_y * h - g.ky * p.y;
    default: return g.ky * p.y - g.klo_y * h;
    }
}

/* Outcode bits of a camera-space point. The first six say which planes of the view volume it
   lies outside (a triangle whose three vertices share one is invisible: each plane bounds a
   half-space); CLVIS_OUT_CLIP says it lies outside near or the guard band, so that a triangle
   with such a vertex goes through the clipper. */
#define CLVIS_OUT_NEAR 1u
#define CLVIS_OUT_FAR 2u
#define CLVIS_OUT_RIGHT 4u
#define CLVIS_OUT_LEFT 8u
#define CLVIS_OUT_TOP 16u
#define CLVIS_OUT_BOTTOM 32u
#define CLVIS_OUT_VIEW 63u
#define CLVIS_OUT_CLIP 64u

static inline clvis_u32 clvis_outcode(clvis_camera_gpu cam, clvis_clip_vertex p)
{
    float h = cam.ortho ? 1.0f : p.d;
    clvis_guard g = clvis_guard_of(cam);
    /* The clip test is the clipper's own (clvis_clip_distance not >= 0 for some plane: a NaN, a
       point that is not finite, counts as outside), so that a vertex kept whole here is kept
       whole by the clipper of a neighbour that needs clipping. */
    int clip = !(clvis_clip_distance(p, 0, cam.near_d, g, cam.ortho) >= 0.0f) |
               !(clvis_clip_distance(p, 1, cam.near_d, g, cam.ortho) >= 0.0f) |
               !(clvis_clip_distance(p, 2, cam.near_d, g, cam.ortho) >= 0.0f) |
               !(clvis_clip_distance(p, 3, cam.near_d, g, cam.ortho) >= 0.0f) |
               !(clvis_clip_distance(p, 4, cam.near_d, g, cam.ortho) >= 0.0f);
    float right = clvis_window_right(cam), left = clvis_window_left(cam);
    float top = clvis_window_top(cam), bottom = clvis_window_bottom(cam);
    return (p.d < cam.near_d ? CLVIS_OUT_NEAR : 0u) | (p.d > cam.far_d ? CLVIS_OUT_FAR : 0u) |
           (p.x > right * h ? CLVIS_OUT_RIGHT : 0u) | (p.x < left * h ? CLVIS_OUT_LEFT : 0u) |
           (p.y > top * h ? CLVIS_OUT_TOP : 0u) | (p.y < bottom * h ? CLVIS_OUT_BOTTOM : 0u) |
           (clip ? CLVIS_OUT_CLIP : 0u);
}

/* Lexicographic order on (x, y, d): the clipper computes every cut from an edge's endpoints in
   this order, so two triangles that share an edge get bit-identical cut points on it. */
static inline int clvis_clip_vertex_less(clvis_clip_vertex a, clvis_clip_vertex b)
{
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.d < b.d;
}

static inline float clvis_absf32(float v) { return v < 0.0f ? -v : v; }

/* The point where segment ab crosses clip plane `plane`, on which a and b have distances da and db
   of opposite signs (clvis_clip_distance: finite, at most FLT_MAX / 2 in magnitude); symmetric in
   (a, da) and (b, db) to the bit. It is measured from the endpoint nearer the plane (ties: the
   lower in clvis_clip_vertex_less), so its error is relative to the distance from that endpoint,
   not to the other's size; the halved difference keeps huge finite endpoints from overflowing.
   Then the coordinate the plane fixes is set on the plane (d = near, x = +-gx h, y = +-gy h): an
   edge between two points near 3e38 has its cut's parameter rounded by far more than the view,
   but only along the plane, where it stays far outside the image. */
static inline clvis_clip_vertex clvis_clip_cut(clvis_clip_vertex a, float da, clvis_clip_vertex b, float db, int plane,
                                               float near_d, clvis_guard g, int ortho)
{
    float fa = da < 0.0f ? -da : da, fb = db < 0.0f ? -db : db;
    if (fb < fa || (fb == fa && clvis_clip_vertex_less(b, a))) {
        clvis_clip_vertex tv = a; a = b; b = tv;
        float td = da; da = db; db = td;
    }
    float t2 = (2.0f * da) / (da - db); /* twice the parameter, in [0, 1] */
    clvis_clip_vertex p;
    p.x = a.x + t2 * (0.5f * b.x - 0.5f * a.x);
    p.y = a.y + t2 * (0.5f * b.y - 0.5f * a.y);
    p.d = a.d + t2 * (0.5f * b.d - 0.5f * a.d);
    float h = ortho ? 1.0f : p.d;
    float on = plane == 0 ? near_d
             : plane == 1 ? g.hi_x * h : plane == 2 ? g.lo_x * h : plane == 3 ? g.hi_y * h : g.lo_y * h;
    if ((clvis_float_bits(on) & 0x7F800000u) != 0x7F800000u) { /* hi_x h may overflow: keep the cut */
        if (plane == 0) p.d = on;
        else if (plane <= 2) p.x = on;
        else p.y = on;
    }
    /* Each coordinate it interpolates is off by about 2^-22 (|a| + |p|) in that coordinate (a:
       the nearer endpoint); the one it sets is exact. Where that moves its screen position by more
       than the guard band and by more than 2^-8 of that position (an edge between points near
       3e38 whose cut near the eye is all rounding: camera-space coordinates that large carry
       about 2e31 of error under a rotated frame), the cut says nothing: it becomes a NaN point,
       which the next plane drops, so the triangle draws at most the part its trustworthy points
       span, never a part the rounding invented. */
    float ux = plane == 1 || plane == 2 ? 0.0f : 4.8e-7f * (0.5f * clvis_absf32(a.x) + 0.5f * clvis_absf32(p.x));
    float uy = plane == 3 || plane == 4 ? 0.0f : 4.8e-7f * (0.5f * clvis_absf32(a.y) + 0.5f * clvis_absf32(p.y));
    float ud = plane == 0 || ortho ? 0.0f : 4.8e-7f * (0.5f * clvis_absf32(a.d) + 0.5f * clvis_absf32(p.d));
    float hp = ortho ? 1.0f : clvis_absf32(p.d);
    float sx = clvis_absf32(p.x) / hp, sy = clvis_absf32(p.y) / hp, rd = ud / hp;
    float usx = ux / hp + sx * rd, usy = uy / hp + sy * rd;
    float us = usx > usy ? usx : usy, sp = sx > sy ? sx : sy;
    float gmin = g.gx < g.gy ? g.gx : g.gy;
    if (us > gmin && us > 0.00390625f * sp) p.x = clvis_bits_float(0x7FC00000u);
    return p;
}

/* Rounds to the nearest integer, ties to even, with plain arithmetic (vectorizable, unlike PoCL's
   rint and convert_long_rte): adding and removing 2^23 leaves no fraction bits, and floats of
   magnitude 2^23 or more are integers already. Host and device give the same bits. */
static inline float clvis_round_even(float v)
{
    float big = v < 0.0f ? -8388608.0f : 8388608.0f;
    float r = (v + big) - big;
    return (v < 8388608.0f && v > -8388608.0f) ? r : v;
}

/* Snaps a raster coordinate to fixed point, rounding to nearest even. */
static inline clvis_i64 clvis_snap(float v)
{
    return (clvis_i64)clvis_round_even(v * (float)CLVIS_SUBPIXEL_ONE);
}

/* floor(v / 2^CLVIS_SUBPIXEL_BITS) without relying on the shift of negative numbers. */
static inline clvis_i64 clvis_fixed_floor(clvis_i64 v)
{
    return v >= 0 ? v >> CLVIS_SUBPIXEL_BITS : -((-v + CLVIS_SUBPIXEL_ONE - 1) >> CLVIS_SUBPIXEL_BITS);
}

/* A projected, snapped vertex: fixed-point raster position and its depth attribute
   (1/d perspective, d orthographic). */
typedef struct { clvis_i64 x, y; float v; } clvis_raster_vertex;

/* A vertex as the vertex pass of raster_setup.cl leaves it for the triangle pass. */
typedef struct clvis_raster_projected {
    clvis_i32 x, y;  /* snapped raster position, fixed units (0 when code has CLVIS_OUT_CLIP) */
    float v;         /* 1/d (perspective) or d (orthographic) */
    clvis_u32 code;  /* clvis_outcode */
} clvis_raster_projected;

/* Clamps a raster coordinate of a `size`-pixel axis to CLVIS_GUARD_SLACK px past the guard band;
   a NaN goes to the low end (only vertices that are clipped away are ever NaN here). */
static inline float clvis_clamp_raster(float v, int size)
{
    float lo = -(float)(CLVIS_GUARD_MARGIN + CLVIS_GUARD_SLACK);
    float hi = (float)size + (float)(CLVIS_GUARD_MARGIN + CLVIS_GUARD_SLACK);
    return v >= lo ? (v <= hi ? v : hi) : lo;
}

/* The raster vertex of a camera-space point, through the shared projection. */
static inline clvis_raster_vertex clvis_raster_vertex_from(clvis_camera_gpu cam, clvis_clip_vertex p)
{
    clvis_vec3 c;
    c.x = p.x;
    c.y = p.y;
    c.z = -p.d;
    clvis_vec2 r = clvis_raster_from_screen(cam, clvis_screen_from_camera(cam, c));
    clvis_raster_vertex v;
    v.x = clvis_snap(clvis_clamp_raster(r.x, cam.width));
    v.y = clvis_snap(clvis_clamp_raster(r.y, cam.height));
    v.v = cam.ortho ? p.d : 1.0f / p.d;
    return v;
}

/* The vertex moved by minus the offset of the camera's sample (shared/samples.h): the edge
   functions of the moved triangle at pixel centres are the original's at that sample, with the
   same snapping and top-left rule (they are translation invariant). Offsets are multiples of
   1/16 px, 2^(CLVIS_SUBPIXEL_BITS - 4) fixed units: exact. One sample: v itself. */
static inline clvis_raster_vertex clvis_raster_vertex_at_sample(clvis_raster_vertex v, clvis_camera_gpu cam)
{
    v.x -= (clvis_i64)clvis_sample_offset(cam.sample_log2, cam.sample, 0) * (CLVIS_SUBPIXEL_ONE / 16);
    v.y -= (clvis_i64)clvis_sample_offset(cam.sample_log2, cam.sample, 1) * (CLVIS_SUBPIXEL_ONE / 16);
    return v;
}

static inline int clvis_raster_vertex_less(clvis_raster_vertex a, clvis_raster_vertex b)
{
    return a.x < b.x || (a.x == b.x && a.y < b.y);
}

/* Edge k's coefficients for the edge from a to b: E(p) = A px + B py + C, positive inside a
   triangle of positive doubled area. Top-left (y down): the inward normal (A, B) points right, or
   straight down on a horizontal edge. Decided from integers only, so the two triangles beside a
   shared edge (whose coefficients are exact negatives) never both own it. */
static inline void clvis_raster_edge(clvis_raster_vertex a, clvis_raster_vertex b, clvis_i64* e0, clvis_i64* ex,
                                     clvis_i64* ey, int* top_left)
{
    clvis_i64 A = b.y - a.y;
    clvis_i64 B = a.x - b.x;
    *top_left = A > 0 || (A == 0 && B > 0);
    *ex = A * CLVIS_SUBPIXEL_ONE;
    *ey = B * CLVIS_SUBPIXEL_ONE;
    *e0 = A * (CLVIS_SUBPIXEL_HALF - a.x) + B * (CLVIS_SUBPIXEL_HALF - a.y) - (*top_left ? 0 : 1);
}

/* Sets up triangle (v0, v1, v2) for a width x height image. Returns 0 when it covers no sample:
   zero doubled area after snapping, culled by `cull`, or no pixel centre in its bounding box. */
static inline int clvis_raster_setup(clvis_raster_vertex a, clvis_raster_vertex b, clvis_raster_vertex c,
                                     clvis_u32 id, int width, int height, int cull, clvis_raster_tri* t)
{
    /* Reordered below in copies of its own, never in its parameters: Mesa 22.3's Rusticl let
       assignments to struct parameters reach the caller's variables (raster_setup.cl's fan). */
    clvis_raster_vertex v0 = a, v1 = b, v2 = c;
    /* The box first: most triangles of a dense mesh hold no pixel centre and stop here. */
    clvis_i64 xmin = v0.x < v1.x ? (v0.x < v2.x ? v0.x : v2.x) : (v1.x < v2.x ? v1.x : v2.x);
    clvis_i64 xmax = v0.x > v1.x ? (v0.x > v2.x ? v0.x : v2.x) : (v1.x > v2.x ? v1.x : v2.x);
    clvis_i64 ymin = v0.y < v1.y ? (v0.y < v2.y ? v0.y : v2.y) : (v1.y < v2.y ? v1.y : v2.y);
    clvis_i64 ymax = v0.y > v1.y ? (v0.y > v2.y ? v0.y : v2.y) : (v1.y > v2.y ? v1.y : v2.y);
    /* Pixel i's centre lies at i + 1/2: the first centre at or after min, the last at or before max. */
    clvis_i64 i0 = -clvis_fixed_floor(CLVIS_SUBPIXEL_HALF - xmin);
    clvis_i64 i1 = clvis_fixed_floor(xmax - CLVIS_SUBPIXEL_HALF);
    clvis_i64 j0 = -clvis_fixed_floor(CLVIS_SUBPIXEL_HALF - ymin);
    clvis_i64 j1 = clvis_fixed_floor(ymax - CLVIS_SUBPIXEL_HALF);
    if (i0 < 0) i0 = 0;
    if (j0 < 0) j0 = 0;
    if (i1 > width - 1) i1 = width - 1;
    if (j1 > height - 1) j1 = height - 1;
    if (i0 > i1 || j0 > j1) return 0;

    /* Doubled signed area; > 0 for a triangle counter-clockwise on screen (raster y points down). */
    clvis_i64 area = (v0.x - v1.x) * (v2.y - v1.y) - (v0.y - v1.y) * (v2.x - v1.x);
    if (area == 0) return 0;
    if (!clvis_cull_keeps(cull, area > 0, area < 0)) return 0; /* shared/visibility.h */
    if (area < 0) { /* one orientation for the edge functions; the id does not depend on it */
        clvis_raster_vertex tv = v1; v1 = v2; v2 = tv;
        area = -area;
    }
    /* Start at the lowest vertex in (x, y) order: the same three vertices in any order then give
       the same bits everywhere below, so coincident triangles tie exactly (lower id wins). */
    if (clvis_raster_vertex_less(v1, v0) && clvis_raster_vertex_less(v1, v2)) {
        clvis_raster_vertex tv = v0; v0 = v1; v1 = v2; v2 = tv;
    } else if (clvis_raster_vertex_less(v2, v0) && clvis_raster_vertex_less(v2, v1)) {
        clvis_raster_vertex tv = v0; v0 = v2; v2 = v1; v1 = tv;
    }
    t->x0 = (clvis_i32)i0;
    t->y0 = (clvis_i32)j0;
    t->x1 = (clvis_i32)i1;
    t->y1 = (clvis_i32)j1;

    int tl0, tl1, tl2;
    clvis_raster_edge(v1, v2, &t->e0[0], &t->ex[0], &t->ey[0], &tl0);
    clvis_raster_edge(v2, v0, &t->e0[1], &t->ex[1], &t->ey[1], &tl1);
    clvis_raster_edge(v0, v1, &t->e0[2], &t->ex[2], &t->ey[2], &tl2);
    float fa = (float)area;
    t->w[0] = v0.v / fa;
    t->w[1] = v1.v / fa;
    t->w[2] = v2.v / fa;
    t->wc = (tl0 ? 0.0f : t->w[0]) + (tl1 ? 0.0f : t->w[1]) + (tl2 ? 0.0f : t->w[2]);
    t->id = id;
    t->dnear = 0.0f; /* clvis_raster_set_nearest gives the bound */
    return 1;
}

/* Sets t->dnear for the triangle of vertices a, b, c that clvis_raster_setup set up: the depth
   attribute at a sample is a convex combination of the vertices' (1/d, or d when orthographic), so
   no depth lies nearer than the nearest vertex's, less the float rounding of clvis_raster_depth
   (about ten ulps, far below the 2^-10 taken off). Weights too small to stay normal floats in its
   products, or attributes large enough to overflow its sums, could round by more: such a triangle
   gets no bound (0). */
static inline void clvis_raster_set_nearest(clvis_raster_vertex a, clvis_raster_vertex b, clvis_raster_vertex c,
                                            int ortho, clvis_raster_tri* t)
{
    float lo = a.v < b.v ? a.v : b.v, hi = a.v > b.v ? a.v : b.v;
    lo = lo < c.v ? lo : c.v;
    hi = hi > c.v ? hi : c.v;
    if (!(t->w[0] >= 0x1p-100f && t->w[1] >= 0x1p-100f && t->w[2] >= 0x1p-100f && hi <= 0x1p100f)) return;
    float d = (ortho ? lo : 1.0f / hi) * 0x1.ff8p-1f; /* 1 - 2^-10 */
    t->dnear = d > 0.0f ? d : 0.0f;
}

/* The depth attribute at a covered sample from its three (biased) edge values: the barycentric
   combination of the vertices' 1/d (perspective) or d (orthographic), all weights >= 0. */
static inline float clvis_raster_depth(float wc, float w0, float w1, float w2, clvis_i64 e0, clvis_i64 e1,
                                       clvis_i64 e2, int ortho)
{
    float v = wc + (float)e0 * w0 + (float)e1 * w1 + (float)e2 * w2;
    return ortho ? v : 1.0f / v;
}

/* The key triangle t leaves at the centre of pixel (i, j), or the background key when it does
   not cover it or its depth there lies outside [near, far]. */
static inline clvis_u64 clvis_raster_sample(const clvis_raster_tri* t, int i, int j, int ortho, float near_d,
                                            float far_d)
{
    clvis_i64 e0 = t->e0[0] + (clvis_i64)i * t->ex[0] + (clvis_i64)j * t->ey[0];
    clvis_i64 e1 = t->e0[1] + (clvis_i64)i * t->ex[1] + (clvis_i64)j * t->ey[1];
    clvis_i64 e2 = t->e0[2] + (clvis_i64)i * t->ex[2] + (clvis_i64)j * t->ey[2];
    if ((e0 | e1 | e2) < 0) return CLVIS_BACKGROUND_KEY; /* before the division: most samples miss */
    float d = clvis_raster_depth(t->wc, t->w[0], t->w[1], t->w[2], e0, e1, e2, ortho);
    if (!(d >= near_d && d <= far_d)) return CLVIS_BACKGROUND_KEY;
    return clvis_make_key(d, t->id);
}

#ifdef __OPENCL_C_VERSION__
/* The vector form of clvis_raster_sample for the 8 pixels (i, j) .. (i + 7, j) whose edge values
   at (i, j) are r0, r1, r2: the same operations in the same order, so the same bits. Lanes that
   are not covered, out of [near, far], or at or past `count` hold the background key, so a min
   over spans needs no mask. `skip` (a constant where it is inlined) returns early when no lane
   is covered (setup's small triangles); raster_fine.cl's tile walk runs branch-free: its spans
   are covered and missed in no pattern a branch predictor learns, and PoCL's any() reduces lane
   by lane, a branch per lane (that walk took about 30% longer with it). The same keys. */
static inline CLVIS_ALWAYS_INLINE ulong8 clvis_raster_span8(long r0, long r1, long r2, long ex0, long ex1, long ex2,
                                                            float wc, float w0, float w1, float w2, uint id, int count,
                                                            int ortho, float near_d, float far_d, int skip)
{
    const long8 lanes = (long8)(0, 1, 2, 3, 4, 5, 6, 7);
    long8 e0 = (long8)(r0) + lanes * ex0;
    long8 e1 = (long8)(r1) + lanes * ex1;
    long8 e2 = (long8)(r2) + lanes * ex2;
    /* A lane is inside iff its three edge values and the lane's place before `count` are all
       non-negative: the sign of their bitwise or. */
    long8 inside = (e0 | e1 | e2 | ((long8)(count - 1) - lanes)) >= 0;
    if (skip && !any(inside)) return (ulong8)(CLVIS_BACKGROUND_KEY);
    float8 v = (float8)(wc) + convert_float8(e0) * w0 + convert_float8(e1) * w1 + convert_float8(e2) * w2;
    float8 d = ortho ? v : 1.0f / v;
    long8 hit = inside & convert_long8((d >= near_d) & (d <= far_d));
    ulong8 key = (convert_ulong8(as_uint8(d)) << 32) | (ulong8)(id);
    return select((ulong8)(CLVIS_BACKGROUND_KEY), key, hit);
}
#endif

/* Whether t may cover a centre of the pixels [i0, i1] x [j0, j1]: each edge value is linear, so
   its largest value over those centres is at the corner its gradient points to. Exact. */
static inline int clvis_raster_overlaps(const clvis_raster_tri* t, int i0, int j0, int i1, int j1)
{
    for (int k = 0; k < 3; ++k) {
        clvis_i64 i = t->ex[k] > 0 ? i1 : i0;
        clvis_i64 j = t->ey[k] > 0 ? j1 : j0;
        if (t->e0[k] + i * t->ex[k] + j * t->ey[k] < 0) return 0;
    }
    return 1;
}

/* clvis_raster_setup for the pixels of `r` only, with t's box and edge values moved to the region's
   own coordinates (pixel (r.x, r.y) of the image is the region's (0, 0)): the edge values are the
   same integers at the same pixels, so every sample gives the bits of the full image's render. */
static inline int clvis_raster_setup_region(clvis_raster_vertex v0, clvis_raster_vertex v1, clvis_raster_vertex v2,
                                            clvis_u32 id, clvis_region r, int cull, clvis_raster_tri* t)
{
    if (!clvis_raster_setup(v0, v1, v2, id, r.x + r.width, r.y + r.height, cull, t)) return 0;
    if (t->x0 < r.x) t->x0 = r.x;
    if (t->y0 < r.y) t->y0 = r.y;
    if (t->x0 > t->x1 || t->y0 > t->y1) return 0;
    for (int k = 0; k < 3; ++k) t->e0[k] += (clvis_i64)r.x * t->ex[k] + (clvis_i64)r.y * t->ey[k];
    t->x0 -= r.x;
    t->x1 -= r.x;
    t->y0 -= r.y;
    t->y1 -= r.y;
    return 1;
}

/* Edge of the square a work-item of raster_fine.cl owns, in pixels (tiles smaller than this make
   the square the tile); a multiple of the span of clvis_raster_span8. The host sizes the launch
   from it. */
#define CLVIS_FINE_SUB 16
#define CLVIS_FINE_SPANS (CLVIS_FINE_SUB / 8) /* 8-pixel spans per row of the square */
/* Passes through loop headers of one work-item of raster_fine.cl, at most (a loop of n iterations
   counts n + 1, the pass that leaves it included, as Mesa's llvmpipe counts them): per bin entry
   (the entry; each row; each span; the occlusion bound's pass over the square's spans), and for
   the rest (clearing, then storing, the square's spans, a span's lanes stored one by one: a partial
   span, or strided samples). The host splits the bins into launches that stay within half a
   device's loop limit (Device::Impl::loop_limit). */
#define CLVIS_FINE_TRIPS_PER_ENTRY \
    (2 + CLVIS_FINE_SUB * (2 + CLVIS_FINE_SPANS) + CLVIS_FINE_SUB * CLVIS_FINE_SPANS)
#define CLVIS_FINE_TRIPS_FIXED (2 * (1 + CLVIS_FINE_SUB * (2 + CLVIS_FINE_SPANS)) + 9 * CLVIS_FINE_SUB * CLVIS_FINE_SPANS + 9)
/* The same for raster_fine_pixel, whose batches hold at least one entry: per entry (the batch
   loop's pass, the triangle loop's pass and its exit), and the rest (the batch loop's exit). */
#define CLVIS_FINE_PIXEL_TRIPS_PER_ENTRY 3
#define CLVIS_FINE_PIXEL_TRIPS_FIXED 4

#endif
