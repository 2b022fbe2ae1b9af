/* Object ids and named corner attributes of a visibility buffer (CONVENTIONS.md "Vertex
   attributes", "Object ids"). resolve_objects finds each sample's item by a binary search over
   the items' first triangle ids; resolve_exact_barycentrics computes the sample's barycentrics in
   double where the device has it (the primary ray from the double-precision camera, sent as float
   pairs), once for every attribute; resolve_corners interpolates one attribute's corner values,
   (1 - u - v) a0 + u a1 + v a2. Launched by host/render/resolve_corners.cpp. */
#include "shared/resolve.h"
#include "shared/visibility.h"

/* The item holding triangle `id`: the last of first[0 .. count) with first[k] <= id (items
   without triangles share their successor's first id and are passed over). */
static uint item_of(__global const uint* first, uint count, uint id)
{
    uint lo = 0, hi = count;
    while (hi - lo > 1) {
        uint mid = lo + (hi - lo) / 2;
        if (first[mid] <= id) lo = mid;
        else hi = mid;
    }
    return lo;
}

__kernel void resolve_objects(__global const ulong* keys, int width, int height, uint triangle_count,
                              __global const uint* first, uint item_count, __global uint* objects)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    size_t pixel = (size_t)y * width + x;
    uint id = clvis_key_id(keys[pixel]);
    objects[pixel] = id < triangle_count && item_count > 0 ? item_of(first, item_count, id) : CLVIS_BACKGROUND_ID;
}

/* Camera parameter k: the float pair (hi, lo) summed in the precision of shared/resolve.h. */
static clvis_real param(__global const float* cam, int k)
{
    return (clvis_real)cam[2 * k] + (clvis_real)cam[2 * k + 1];
}

/* The exact barycentrics (u, v) of each sample: the primary ray of CONVENTIONS.md through the pixel
   centre, as clvis::Camera makes it, meeting the plane of its triangle, in double where the device
   has it. Stored as float: their rounding moves an attribute by 1e-7 of its corners at most,
   while the float32 ray's error would move it by far more on a triangle of a pixel or two.
   cam: eye (0-2), r (3-5), u (6-8), f (9-11), fx, fy, cx, cy (12-15), each as a float pair.
   sample_keys: renumbered into positions/indices (host/render/sample_scene.cpp). */
__kernel void resolve_exact_barycentrics(__global const ulong* sample_keys, __global const float* cam, int ortho,
                                         int width, int height, __global const float* positions,
                                         __global const uint* indices, uint triangle_count, __global float* bary)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    size_t pixel = (size_t)y * width + x;
    uint sid = clvis_key_id(sample_keys[pixel]);
    if (sid >= triangle_count) {
        vstore2((float2)(0.0f, 0.0f), pixel, bary);
        return;
    }
    clvis_real sx = ((clvis_real)x + (clvis_real)0.5 - param(cam, 14)) / param(cam, 12);
    clvis_real sy = (param(cam, 15) - ((clvis_real)y + (clvis_real)0.5)) / param(cam, 13);
    clvis_real o[3], d[3];
    for (int k = 0; k < 3; ++k) {
        clvis_real r = param(cam, 3 + k), u = param(cam, 6 + k), f = param(cam, 9 + k), e = param(cam, k);
        o[k] = ortho ? e + sx * r + sy * u : e;
        d[k] = ortho ? f : sx * r + sy * u + f;
    }
    uint i0 = indices[3 * (size_t)sid], i1 = indices[3 * (size_t)sid + 1], i2 = indices[3 * (size_t)sid + 2];
    clvis_real a[3], e1[3], e2[3], s[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = positions[3 * (size_t)i0 + k];
        e1[k] = (clvis_real)positions[3 * (size_t)i1 + k] - a[k];
        e2[k] = (clvis_real)positions[3 * (size_t)i2 + k] - a[k];
        s[k] = o[k] - a[k];
    }
    /* Moeller and Trumbore's solve against the plane (the ray need not hit the triangle). */
    clvis_real px = d[1] * e2[2] - d[2] * e2[1], py = d[2] * e2[0] - d[0] * e2[2], pz = d[0] * e2[1] - d[1] * e2[0];
    clvis_real det = e1[0] * px + e1[1] * py + e1[2] * pz;
    clvis_real u = 0, v = 0;
    if (det != (clvis_real)0) {
        clvis_real qx = s[1] * e1[2] - s[2] * e1[1], qy = s[2] * e1[0] - s[0] * e1[2], qz = s[0] * e1[1] - s[1] * e1[0];
        u = (s[0] * px + s[1] * py + s[2] * pz) / det;
        v = (d[0] * qx + d[1] * qy + d[2] * qz) / det;
    }
    vstore2((float2)((float)u, (float)v), pixel, bary);
}

/* One attribute at every sample: (1 - u - v) a0 + u a1 + v a2 of its triangle's corners, NaN on the
   background and on an item without it. keys: the buffer's own; objects: resolve_objects'; bary:
   resolve_exact_barycentrics'. first: each item's first id; base: where its corner values start in
   `values` (floats), ~0 for an item without the attribute. */
__kernel void resolve_corners(__global const ulong* keys, __global const uint* objects, __global const float* bary,
                              int width, int height, __global const uint* first, __global const ulong* base,
                              int components, __global const float* values, __global float* out)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    size_t pixel = (size_t)y * width + x;
    uint item = objects[pixel];
    ulong at = item == CLVIS_BACKGROUND_ID ? ~(ulong)0 : base[item];
    if (at == ~(ulong)0) {
        for (int j = 0; j < components; ++j) out[(size_t)components * pixel + j] = NAN;
        return;
    }
    float2 uv = vload2(pixel, bary);
    clvis_real u = uv.x, v = uv.y, w = (clvis_real)1 - u - v;
    uint tri = clvis_key_id(keys[pixel]) - first[item];
    __global const float* c = values + at + (size_t)3 * components * tri;
    for (int j = 0; j < components; ++j)
        out[(size_t)components * pixel + j] =
            (float)(w * c[j] + u * c[components + j] + v * c[2 * components + j]);
}
