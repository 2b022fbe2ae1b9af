/* Turns a visibility buffer into an RGBA8 image: Lambert with a directional light (smooth where
   the scene has vertex normals), view depth, or a false colour per triangle id. Reads only the
   keys and the scene; knows nothing of which path wrote the keys. */
#include "shared/camera.h"
#include "shared/visibility.h"

#define CLVIS_SHADE_LAMBERT 0
#define CLVIS_SHADE_DEPTH 1
#define CLVIS_SHADE_IDS 2

static float3 load_position(__global const float* p, uint v) { return vload3(v, p); }

static uchar4 rgba(float3 c)
{
    c = clamp(c, 0.0f, 1.0f);
    return (uchar4)((uchar)(c.x * 255.0f + 0.5f), (uchar)(c.y * 255.0f + 0.5f), (uchar)(c.z * 255.0f + 0.5f), 255);
}

static float3 id_colour(uint id)
{
    /* a 32-bit integer hash (lowbias32) spread over hue-like channels */
    uint h = id;
    h ^= h >> 16; h *= 0x7feb352du; h ^= h >> 15; h *= 0x846ca68bu; h ^= h >> 16;
    return (float3)((h & 255u) / 255.0f, ((h >> 8) & 255u) / 255.0f, ((h >> 16) & 255u) / 255.0f) * 0.8f + 0.2f;
}

__kernel void shade(__global const ulong* keys, __global uchar4* out, clvis_camera_gpu cam,
                    __global const float* positions, __global const uint* indices,
                    __global const float* normals, int has_normals, uint triangle_count,
                    int mode, float light_x, float light_y, float light_z)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= cam.width || y >= cam.height) return;
    size_t pixel = (size_t)y * cam.width + x;
    ulong key = keys[pixel];
    uint id = clvis_key_id(key);
    if (id == CLVIS_BACKGROUND_ID || id >= triangle_count) {
        out[pixel] = (uchar4)(24, 24, 28, 255);
        return;
    }
    float depth = clvis_key_depth(key);
    if (mode == CLVIS_SHADE_IDS) {
        out[pixel] = rgba(id_colour(id));
        return;
    }
    if (mode == CLVIS_SHADE_DEPTH) {
        float g = 1.0f - (depth - cam.near_d) / (cam.far_d - cam.near_d);
        out[pixel] = rgba((float3)(g, g, g));
        return;
    }
    uint i0 = indices[3 * id], i1 = indices[3 * id + 1], i2 = indices[3 * id + 2];
    float3 v0 = load_position(positions, i0), v1 = load_position(positions, i1), v2 = load_position(positions, i2);
    clvis_vec3 o, d;
    clvis_primary_ray(cam, x + 0.5f, y + 0.5f, &o, &d);
    float3 dir = normalize((float3)(d.x, d.y, d.z));
    float3 n = cross(v1 - v0, v2 - v0);
    float area2 = length(n);
    n = area2 > 0.0f ? n / area2 : -dir;
    if (has_normals && area2 > 0.0f) {
        /* barycentrics of the hit point in the triangle's plane */
        float3 p = (float3)(o.x, o.y, o.z) + (float3)(d.x, d.y, d.z) * depth;
        float3 c0 = cross(v2 - v1, p - v1), c1 = cross(v0 - v2, p - v2);
        float b0 = dot(c0, n) / area2, b1 = dot(c1, n) / area2, b2 = 1.0f - b0 - b1;
        float3 s = load_position(normals, i0) * b0 + load_position(normals, i1) * b1 + load_position(normals, i2) * b2;
        if (dot(s, s) > 0.0f) n = normalize(s);
    }
    if (dot(n, dir) > 0.0f) n = -n; /* two-sided: face the viewer */
    float3 light = normalize((float3)(light_x, light_y, light_z));
    float lambert = fmax(dot(n, -light), 0.0f);
    float facing = fmax(dot(n, -dir), 0.0f);
    float3 albedo = (float3)(0.85f, 0.80f, 0.72f);
    out[pixel] = rgba(albedo * (0.10f + 0.65f * lambert + 0.25f * facing));
}
