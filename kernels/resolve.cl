/* Resolves a visibility buffer into per-pixel attributes: barycentrics, world position, the
   geometric normal and the smooth (vertex-interpolated) normal, each written only when asked
   (`what`, bits of shared/resolve.h), normals in world or camera axes. Reads the keys and the
   resident scene; knows nothing of which path wrote the keys. Launched by host/render/resolve.cpp. */
#include "shared/camera.h"
#include "shared/resolve.h"
#include "shared/visibility.h"

static clvis_vec3 vertex(__global const float* p, uint v)
{
    clvis_vec3 r;
    r.x = p[3 * (size_t)v];
    r.y = p[3 * (size_t)v + 1];
    r.z = p[3 * (size_t)v + 2];
    return r;
}

static void store3(__global float* out, size_t pixel, float x, float y, float z)
{
    out[3 * pixel] = x;
    out[3 * pixel + 1] = y;
    out[3 * pixel + 2] = z;
}

/* x / |x| in the precision of shared/resolve.h; NaN for the zero vector. */
static void store_unit(__global float* out, size_t pixel, clvis_real x, clvis_real y, clvis_real z)
{
    clvis_real len = sqrt(x * x + y * y + z * z);
    if (len > (clvis_real)0) store3(out, pixel, (float)(x / len), (float)(y / len), (float)(z / len));
    else store3(out, pixel, NAN, NAN, NAN);
}

/* x / |x| in camera axes (r, u, -f) when `camera` (CLVIS_RESOLVE_CAMERA_SPACE), else as given. */
static void store_normal(__global float* out, size_t pixel, clvis_camera_gpu cam, int camera, clvis_real x,
                         clvis_real y, clvis_real z)
{
    if (!camera) {
        store_unit(out, pixel, x, y, z);
        return;
    }
    store_unit(out, pixel, x * cam.r_x + y * cam.r_y + z * cam.r_z, x * cam.u_x + y * cam.u_y + z * cam.u_z,
               -(x * cam.f_x + y * cam.f_y + z * cam.f_z));
}

__kernel void resolve(__global const ulong* keys, clvis_camera_gpu cam, __global const float* positions,
                      __global const uint* indices, __global const float* normals, int has_normals, uint triangle_count,
                      int what,
                      __global float* bary, __global float* position, __global float* normal,
                      __global float* smooth)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= cam.width || y >= cam.height) return;
    size_t pixel = (size_t)y * cam.width + x;
    uint id = clvis_key_id(keys[pixel]);
    if (id == CLVIS_BACKGROUND_ID || id >= triangle_count) {
        if (what & CLVIS_RESOLVE_BARY) vstore2((float2)(0.0f, 0.0f), pixel, bary);
        if (what & CLVIS_RESOLVE_POSITION) store3(position, pixel, NAN, NAN, NAN);
        if (what & CLVIS_RESOLVE_NORMAL) store3(normal, pixel, NAN, NAN, NAN);
        if (what & CLVIS_RESOLVE_SMOOTH_NORMAL) store3(smooth, pixel, NAN, NAN, NAN);
        return;
    }
    uint i0 = indices[3 * (size_t)id], i1 = indices[3 * (size_t)id + 1], i2 = indices[3 * (size_t)id + 2];
    clvis_vec3 a = vertex(positions, i0), b = vertex(positions, i1), c = vertex(positions, i2);
    clvis_vec3 o, d;
    clvis_primary_ray(cam, x + 0.5f, y + 0.5f, &o, &d);
    float u, v, t;
    clvis_plane_barycentrics(o, d, a, b, c, &u, &v, &t);
    if (what & CLVIS_RESOLVE_BARY) vstore2((float2)(u, v), pixel, bary);
    if (what & CLVIS_RESOLVE_POSITION) {
        clvis_vec3 p = clvis_barycentric_point(a, b, c, u, v);
        store3(position, pixel, p.x, p.y, p.z);
    }
    /* The geometric normal, cross(b - a, c - a): the right-hand rule in index order. */
    clvis_real e1x = (clvis_real)b.x - a.x, e1y = (clvis_real)b.y - a.y, e1z = (clvis_real)b.z - a.z;
    clvis_real e2x = (clvis_real)c.x - a.x, e2y = (clvis_real)c.y - a.y, e2z = (clvis_real)c.z - a.z;
    clvis_real gx = e1y * e2z - e1z * e2y, gy = e1z * e2x - e1x * e2z, gz = e1x * e2y - e1y * e2x;
    int camera = (what & CLVIS_RESOLVE_CAMERA_SPACE) != 0;
    if (what & CLVIS_RESOLVE_NORMAL) store_normal(normal, pixel, cam, camera, gx, gy, gz);
    if (what & CLVIS_RESOLVE_SMOOTH_NORMAL) {
        clvis_vec3 n = {0.0f, 0.0f, 0.0f};
        if (has_normals) n = clvis_barycentric_point(vertex(normals, i0), vertex(normals, i1), vertex(normals, i2), u, v);
        /* Zero where the mesh has no normals (host/render/renderer.cpp): the geometric one then. */
        if (n.x == 0.0f && n.y == 0.0f && n.z == 0.0f) store_normal(smooth, pixel, cam, camera, gx, gy, gz);
        else store_normal(smooth, pixel, cam, camera, n.x, n.y, n.z);
    }
}
