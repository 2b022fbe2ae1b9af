/* Raster path, stage 1 of 3: raster_setup_vertices projects every vertex once; raster_setup then
   takes every triangle (one work-item each), clips those that need it, rasterizes the ones that
   touch few pixel centres at once into the visibility buffer (64-bit atomic min), and lists the
   others for raster_bin.cl (binning) and raster_fine.cl (tile rasterization). Built with
   CLVIS_RASTER_OWNED (tile ownership, RasterAtomics::Off) it draws nothing and lists every
   triangle, and needs no 64-bit atomics. */
#ifndef CLVIS_RASTER_OWNED
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable
#endif
#include "shared/raster_rule.h"

/* Triangles whose pixel bounding box holds at most CLVIS_RASTER_SCALAR pixel centres are
   rasterized here sample by sample; those whose box is at most 8 pixels wide (one vector span)
   and CLVIS_RASTER_SMALL_ROWS rows tall, here row by row; the rest are binned. */
#define CLVIS_RASTER_SCALAR 4     /* pixel centres */
#define CLVIS_RASTER_SMALL_ROWS 8 /* rows */

typedef struct {
    clvis_camera_gpu cam;
    int cull;
    volatile __global ulong* keys;
    __global clvis_raster_tri* tris;
    uint capacity;
    volatile __global uint* listed; /* 2 words: triangles listed, low and high 32 bits */
    clvis_region region;            /* keys hold this region of the image (shared/region.h) */
} raster_setup_out;

static clvis_clip_vertex load_camera_vertex(clvis_camera_gpu cam, __global const float* positions, uint v)
{
    size_t o = 3 * (size_t)v;
    return clvis_clip_vertex_of(cam, positions[o], positions[o + 1], positions[o + 2]);
}

/* Lists t for binning. The count is 64 bits kept in two 32-bit words (core atomics): a total
   past the capacity makes the host grow the list and run setup again. */
static void list_triangle(const clvis_raster_tri* t, raster_setup_out out)
{
    uint slot = atomic_inc(&out.listed[0]);
    if (slot == 0xFFFFFFFFu) atomic_inc(&out.listed[1]);
    if (slot < out.capacity) out.tris[slot] = *t;
}

/* Rasterizes a small triangle on the spot (atomic mode), or lists it for binning: at the camera's
   sample (shared/samples.h), one launch per sample. */
static void emit_triangle(clvis_raster_vertex a, clvis_raster_vertex b, clvis_raster_vertex c, uint id,
                          raster_setup_out out)
{
    clvis_raster_tri t;
    if (!clvis_raster_setup_region(clvis_raster_vertex_at_sample(a, out.cam), clvis_raster_vertex_at_sample(b, out.cam),
                                   clvis_raster_vertex_at_sample(c, out.cam), id, out.region, out.cull, &t))
        return;
    /* Key of the camera's sample of region pixel p: the samples of a pixel are adjacent. */
    int n_log2 = out.cam.sample_log2;
    size_t sample = (size_t)out.cam.sample;
#ifndef CLVIS_RASTER_OWNED
    if ((t.x1 - t.x0 + 1) * (t.y1 - t.y0 + 1) <= CLVIS_RASTER_SCALAR) {
        for (int j = t.y0; j <= t.y1; ++j) {
            for (int i = t.x0; i <= t.x1; ++i) {
                ulong key = clvis_raster_sample(&t, i, j, out.cam.ortho, out.cam.near_d, out.cam.far_d);
                if (key != CLVIS_BACKGROUND_KEY)
                    atom_min(&out.keys[(((size_t)j * out.region.width + i) << n_log2) + sample], key);
            }
        }
        return;
    }
    if (t.x1 - t.x0 < 8 && t.y1 - t.y0 < CLVIS_RASTER_SMALL_ROWS) {
        long r0 = t.e0[0] + (long)t.x0 * t.ex[0] + (long)t.y0 * t.ey[0];
        long r1 = t.e0[1] + (long)t.x0 * t.ex[1] + (long)t.y0 * t.ey[1];
        long r2 = t.e0[2] + (long)t.x0 * t.ex[2] + (long)t.y0 * t.ey[2];
        for (int j = t.y0; j <= t.y1; ++j, r0 += t.ey[0], r1 += t.ey[1], r2 += t.ey[2]) {
            ulong8 key = clvis_raster_span8(r0, r1, r2, t.ex[0], t.ex[1], t.ex[2], t.wc, t.w[0], t.w[1], t.w[2], t.id,
                                            t.x1 - t.x0 + 1, out.cam.ortho, out.cam.near_d, out.cam.far_d);
            if (all(key == (ulong8)(CLVIS_BACKGROUND_KEY))) continue;
            ulong lane[8];
            vstore8(key, 0, lane);
            volatile __global ulong* row =
                out.keys + (((size_t)j * (size_t)out.region.width + (size_t)t.x0) << n_log2) + sample;
            for (int l = 0; l < 8; ++l)
                if (lane[l] != CLVIS_BACKGROUND_KEY) atom_min(&row[(size_t)l << n_log2], lane[l]);
        }
        return;
    }
#endif
    list_triangle(&t, out);
}

/* Clips the triangle against near and the guard band and fans the polygon into triangles. */
static void clip_and_emit(clvis_clip_vertex p0, clvis_clip_vertex p1, clvis_clip_vertex p2, uint id, clvis_guard g,
                          raster_setup_out out)
{
    clvis_clip_vertex poly[CLVIS_CLIP_CAPACITY];
    int n = clvis_clip_polygon(p0, p1, p2, out.cam, g, poly); /* shared/raster_rule.h */
    if (n < 3) return;
    int s = clvis_fan_start(poly, n);
    clvis_raster_vertex first = clvis_raster_vertex_from(out.cam, poly[s]);
    clvis_raster_vertex prev = clvis_raster_vertex_from(out.cam, poly[s + 1 < n ? s + 1 : s + 1 - n]);
    for (int k = 2; k < n; ++k) {
        clvis_raster_vertex cur = clvis_raster_vertex_from(out.cam, poly[s + k < n ? s + k : s + k - n]);
        emit_triangle(first, prev, cur, id, out);
        prev = cur;
    }
}

/* Straight-line code, one work-item per vertex: PoCL runs it as a vector loop. */
__kernel void raster_setup_vertices(clvis_camera_gpu cam, __global const float* positions, uint vertex_count,
                                    __global clvis_raster_projected* projected)
{
    uint v = (uint)get_global_id(0);
    if (v >= vertex_count) return;
    clvis_clip_vertex p = load_camera_vertex(cam, positions, v);
    clvis_u32 code = clvis_outcode(cam, p);
    clvis_raster_vertex r = clvis_raster_vertex_from(cam, p);
    int keep = (code & CLVIS_OUT_CLIP) == 0u;
    clvis_raster_projected out = {keep ? (int)r.x : 0, keep ? (int)r.y : 0, r.v, code};
    projected[v] = out;
}

static clvis_raster_vertex widen(clvis_raster_projected p)
{
    clvis_raster_vertex v = {p.x, p.y, p.v};
    return v;
}

__kernel void raster_setup(clvis_camera_gpu cam, __global const float* positions, __global const uint* indices,
                           uint triangle_count, __global const clvis_raster_projected* projected, int cull,
                           volatile __global ulong* keys, __global clvis_raster_tri* tris, uint capacity,
                           volatile __global uint* listed, clvis_region region)
{
    uint id = (uint)get_global_id(0);
    if (id >= triangle_count) return;
    size_t i = 3 * (size_t)id;
    uint a = indices[i], b = indices[i + 1], c = indices[i + 2];
    clvis_raster_projected pa = projected[a], pb = projected[b], pc = projected[c];
    if (pa.code & pb.code & pc.code & CLVIS_OUT_VIEW) return;
    raster_setup_out out = {cam, cull, keys, tris, capacity, listed, region};
    if ((pa.code | pb.code | pc.code) & CLVIS_OUT_CLIP) {
        clip_and_emit(load_camera_vertex(cam, positions, a), load_camera_vertex(cam, positions, b),
                      load_camera_vertex(cam, positions, c), id, clvis_guard_of(cam), out);
        return;
    }
    emit_triangle(widen(pa), widen(pb), widen(pc), id, out);
}
