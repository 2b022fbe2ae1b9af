/* The raster path's coverage and depth for one triangle given by its world vertices, the whole of
   what raster_setup.cl, raster_bin.cl and raster_fine.cl decide for it at a pixel centre: the
   camera transform, the outcodes, the clipper against near and the guard band and its fan, the
   16.16 snapping, the edge functions with the top-left rule, culling by the snapped area, and the
   depth formula. raster_setup.cl clips with clvis_clip_polygon; the ray kernels' coverage mode
   CLVIS_RASTER_RULE (RenderOptions::coverage) calls clvis_raster_rule_keys for each candidate
   triangle, so both paths leave bit-identical keys. Compiled by OpenCL C and C++ alike. */
#ifndef CLVIS_SHARED_RASTER_RULE_H
#define CLVIS_SHARED_RASTER_RULE_H

#include "shared/layers.h"
#include "shared/raster.h"

#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1 && !defined(CLVIS_RULE_LAYER_STRIDE)
#define CLVIS_RULE_LAYER_STRIDE 1 /* a pixel block of one pixel: its layers adjacent */
#endif

/* Worst case of Sutherland-Hodgman: a polygon of n vertices, I of them inside, comes out with
   I + (sign changes) <= I + 2 min(I, n - I) <= 1.5 n vertices. Exact clipping keeps a triangle
   convex (at most 3 + 5 = 8), but rounded cuts need not: 3 -> 4 -> 6 -> 9 -> 13 -> 19. */
#define CLVIS_CLIP_CAPACITY 19

/* The camera-space point of a world position, as the raster path's vertex pass loads it. */
static inline clvis_clip_vertex clvis_clip_vertex_of(clvis_camera_gpu cam, float x, float y, float z)
{
    clvis_vec3 c = clvis_camera_from_world(cam, x, y, z);
    clvis_clip_vertex p;
    p.x = c.x;
    p.y = c.y;
    p.d = -c.z;
    return p;
}

/* Clips triangle (p0, p1, p2) against near and the guard band into poly (CLVIS_CLIP_CAPACITY
   points). Returns the polygon's vertex count, or 0 when fewer than three remain. */
static inline int clvis_clip_polygon(clvis_clip_vertex p0, clvis_clip_vertex p1, clvis_clip_vertex p2,
                                     clvis_camera_gpu cam, clvis_guard g, clvis_clip_vertex* poly)
{
    clvis_clip_vertex next[CLVIS_CLIP_CAPACITY];
    poly[0] = p0;
    poly[1] = p1;
    poly[2] = p2;
    int n = 3;
    for (int plane = 0; plane < CLVIS_CLIP_PLANES; ++plane) {
        int m = 0;
        for (int k = 0; k < n; ++k) {
            clvis_clip_vertex a = poly[k], b = poly[k + 1 == n ? 0 : k + 1];
            float da = clvis_clip_distance(a, plane, cam.near_d, g, cam.ortho);
            float db = clvis_clip_distance(b, plane, cam.near_d, g, cam.ortho);
            if (da >= 0.0f) next[m++] = a;
            /* No cut towards a point that is not finite (NaN distance): it is dropped whole. */
            if (da == da && db == db && (da >= 0.0f) != (db >= 0.0f))
                next[m++] = clvis_clip_cut(a, da, b, db, plane, cam.near_d, g, cam.ortho);
        }
        if (m < 3) return 0;
        for (int k = 0; k < m; ++k) poly[k] = next[k];
        n = m;
    }
    return n;
}

/* Where the fan of a clipped polygon starts: its lowest vertex, so that the same polygon walked
   from anywhere, either way round, gives the same triangles (coincident triangles then tie
   exactly). Triangle k (k = 2 .. n-1) of the fan is (s, s + k - 1, s + k), indices mod n. */
static inline int clvis_fan_start(const clvis_clip_vertex* poly, int n)
{
    int s = 0;
    for (int k = 1; k < n; ++k) s = clvis_clip_vertex_less(poly[k], poly[s]) ? k : s;
    return s;
}

/* A block of pixels: pw x ph from (x0, y0); pixel (x0 + i, y0 + j) keeps its key in
   best[j * stride + i]. */
typedef struct { int x0, y0, pw, ph, stride; } clvis_pixel_block;

/* One snapped triangle's keys at a block of pixels (at the camera's sample, shared/samples.h), kept where nearer: the (depth bits, id)
   minimum, the raster path's atomic min. Only pixel centres inside its box are evaluated (the
   others are outside the triangle, or outside the image). */
static inline void clvis_raster_rule_block(clvis_raster_vertex v0, clvis_raster_vertex v1, clvis_raster_vertex v2,
                                           clvis_u32 id, clvis_camera_gpu cam, int cull, clvis_pixel_block b,
                                           clvis_u64* best)
{
    clvis_raster_tri t;
    if (!clvis_raster_setup(clvis_raster_vertex_at_sample(v0, cam), clvis_raster_vertex_at_sample(v1, cam),
                            clvis_raster_vertex_at_sample(v2, cam), id, cam.width, cam.height, cull, &t))
        return;
    int i0 = t.x0 > b.x0 ? t.x0 : b.x0, i1 = t.x1 < b.x0 + b.pw - 1 ? t.x1 : b.x0 + b.pw - 1;
    int j0 = t.y0 > b.y0 ? t.y0 : b.y0, j1 = t.y1 < b.y0 + b.ph - 1 ? t.y1 : b.y0 + b.ph - 1;
    for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
            clvis_u64 key = clvis_raster_sample(&t, i, j, cam.ortho, cam.near_d, cam.far_d);
            clvis_u64* slot = best + (j - b.y0) * b.stride + (i - b.x0);
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
            /* depth layers: `best` holds CLVIS_LAYERS lists, layer k of a pixel
               CLVIS_RULE_LAYER_STRIDE keys after layer k - 1 (shared/layers.h) */
            clvis_layers_insert(slot, CLVIS_RULE_LAYER_STRIDE, key);
#else
            *slot = key < *slot ? key : *slot;
#endif
        }
    }
}

/* The raster path's keys of triangle `id`, world vertices a, b, c in index order, at a block of
   pixels (clvis_raster_rule_block): rejected when its three vertices lie outside one plane of
   the view volume, clipped and fanned when a vertex lies outside near or the guard band, else
   snapped as projected. `cull` is CLVIS_CULL_*. */
static inline void clvis_raster_rule_keys(clvis_camera_gpu cam, int cull, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c,
                                          clvis_u32 id, clvis_pixel_block blk, clvis_u64* best)
{
    clvis_clip_vertex pa = clvis_clip_vertex_of(cam, a.x, a.y, a.z);
    clvis_clip_vertex pb = clvis_clip_vertex_of(cam, b.x, b.y, b.z);
    clvis_clip_vertex pc = clvis_clip_vertex_of(cam, c.x, c.y, c.z);
    clvis_u32 ca = clvis_outcode(cam, pa), cb = clvis_outcode(cam, pb), cc = clvis_outcode(cam, pc);
    if (ca & cb & cc & CLVIS_OUT_VIEW) return;
    if (!((ca | cb | cc) & CLVIS_OUT_CLIP)) {
        clvis_raster_rule_block(clvis_raster_vertex_from(cam, pa), clvis_raster_vertex_from(cam, pb),
                                clvis_raster_vertex_from(cam, pc), id, cam, cull, blk, best);
        return;
    }
    clvis_clip_vertex poly[CLVIS_CLIP_CAPACITY];
    int n = clvis_clip_polygon(pa, pb, pc, cam, clvis_guard_of(cam), poly);
    if (n < 3) return;
    int s = clvis_fan_start(poly, n);
    clvis_raster_vertex first = clvis_raster_vertex_from(cam, poly[s]);
    clvis_raster_vertex prev = clvis_raster_vertex_from(cam, poly[s + 1 < n ? s + 1 : s + 1 - n]);
    for (int k = 2; k < n; ++k) {
        clvis_raster_vertex cur = clvis_raster_vertex_from(cam, poly[s + k < n ? s + k : s + k - n]);
        clvis_raster_rule_block(first, prev, cur, id, cam, cull, blk, best);
        prev = cur;
    }
}

/* A BVH box as the raster rule needs it tested (world units): widened by `margin` on every side
   so that no triangle whose snapped, clipped projection covers a sample of a ray is lost, and
   the range [lo_d, hi_d] that the view depths of its triangles' keys cannot leave. */
typedef struct {
    float margin;     /* world units added on every side */
    float lo_d, hi_d; /* view depths, widened */
} clvis_rule_box;

/* The sub-pixel distance, px, by which the raster path's coverage may differ from the exact
   triangle's: snapping moves a vertex by at most 2^-17 px, and float32 raster coordinates (up to
   CLVIS_RASTER_SPAN px) round by about 2^-9 px per operation; 1/16 px bounds both many times. */
#define CLVIS_RULE_SLACK_PX 0.0625f

/* The widening of box [lo, hi] for camera cam. A sample covered by the raster path lies within
   CLVIS_RULE_SLACK_PX of the exact projection of the triangle: at view depth d that is
   CLVIS_RULE_SLACK_PX d / min(fx, fy) world units across the view (perspective; orthographic:
   without d), and d is at most R, the box's farthest reach from the eye along any axis summed
   (R >= the Euclidean distance). float32's camera transform, clip cuts and the packet's ray
   rounding add a few 2^-24 of the coordinates' magnitudes: 2^-16 of them is the absolute part.
   A key's depth is a convex combination of its vertices' (1/d interpolated, or d), each a
   camera-space depth off by a few 2^-24 of R: 2^-12 R widens the depth range. */
static inline clvis_rule_box clvis_rule_box_of(clvis_camera_gpu cam, float lo_x, float lo_y, float lo_z, float hi_x,
                                               float hi_y, float hi_z)
{
    float ax = clvis_absf32(lo_x - cam.eye_x), bx = clvis_absf32(hi_x - cam.eye_x);
    float ay = clvis_absf32(lo_y - cam.eye_y), by = clvis_absf32(hi_y - cam.eye_y);
    float az = clvis_absf32(lo_z - cam.eye_z), bz = clvis_absf32(hi_z - cam.eye_z);
    float rx = ax > bx ? ax : bx, ry = ay > by ? ay : by, rz = az > bz ? az : bz;
    float reach = rx + ry + rz;
    float mag = clvis_absf32(cam.eye_x) + clvis_absf32(cam.eye_y) + clvis_absf32(cam.eye_z) +
                (clvis_absf32(lo_x) > clvis_absf32(hi_x) ? clvis_absf32(lo_x) : clvis_absf32(hi_x)) +
                (clvis_absf32(lo_y) > clvis_absf32(hi_y) ? clvis_absf32(lo_y) : clvis_absf32(hi_y)) +
                (clvis_absf32(lo_z) > clvis_absf32(hi_z) ? clvis_absf32(lo_z) : clvis_absf32(hi_z));
    float f = cam.fx < cam.fy ? cam.fx : cam.fy;
    clvis_rule_box r;
    r.margin = CLVIS_RULE_SLACK_PX / f * (cam.ortho ? 1.0f : reach) + 1.52587890625e-5f * (reach + mag);
    /* depth = (p - eye) . f, its extremes at the box's corners */
    float dx0 = (lo_x - cam.eye_x) * cam.f_x, dx1 = (hi_x - cam.eye_x) * cam.f_x;
    float dy0 = (lo_y - cam.eye_y) * cam.f_y, dy1 = (hi_y - cam.eye_y) * cam.f_y;
    float dz0 = (lo_z - cam.eye_z) * cam.f_z, dz1 = (hi_z - cam.eye_z) * cam.f_z;
    float slack = 2.44140625e-4f * reach + r.margin * 2.0f;
    r.lo_d = (dx0 < dx1 ? dx0 : dx1) + (dy0 < dy1 ? dy0 : dy1) + (dz0 < dz1 ? dz0 : dz1) - slack;
    r.hi_d = (dx0 > dx1 ? dx0 : dx1) + (dy0 > dy1 ? dy0 : dy1) + (dz0 > dz1 ? dz0 : dz1) + slack;
    return r;
}

#endif
