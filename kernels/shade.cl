/* Turns a visibility buffer into an RGBA8 image: Lambert with a directional light (smooth where
   the scene has vertex normals), view depth, or a false colour per triangle id. Reads only the
   keys and the scene; knows nothing of which path wrote the keys. Scalar vector math throughout:
   Oclgrind 21.10's uninitialised-value checker crashes on float3 shuffles. */
#include "shared/camera.h"
#include "shared/shade.h"
#include "shared/visibility.h"

static clvis_vec3 v3(float x, float y, float z) { clvis_vec3 r; r.x = x; r.y = y; r.z = z; return r; }
static clvis_vec3 load3(__global const float* p, uint v) { return v3(p[3 * v], p[3 * v + 1], p[3 * v + 2]); }
static clvis_vec3 sub3(clvis_vec3 a, clvis_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static clvis_vec3 scale3(clvis_vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static clvis_vec3 add3(clvis_vec3 a, clvis_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static float dot3(clvis_vec3 a, clvis_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static clvis_vec3 cross3(clvis_vec3 a, clvis_vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static clvis_vec3 unit3(clvis_vec3 a)
{
    float len = sqrt(dot3(a, a));
    return len > 0.0f ? scale3(a, 1.0f / len) : a;
}

static uchar4 rgba(float r, float g, float b)
{
    r = clamp(r, 0.0f, 1.0f);
    g = clamp(g, 0.0f, 1.0f);
    b = clamp(b, 0.0f, 1.0f);
    return (uchar4)((uchar)(r * 255.0f + 0.5f), (uchar)(g * 255.0f + 0.5f), (uchar)(b * 255.0f + 0.5f), 255);
}

static clvis_vec3 id_colour(uint id)
{
    /* a 32-bit integer hash (lowbias32), one byte per channel */
    uint h = id;
    h ^= h >> 16; h *= 0x7feb352du; h ^= h >> 15; h *= 0x846ca68bu; h ^= h >> 16;
    return v3(0.2f + 0.8f * (h & 255u) / 255.0f, 0.2f + 0.8f * ((h >> 8) & 255u) / 255.0f,
                0.2f + 0.8f * ((h >> 16) & 255u) / 255.0f);
}

/* The colour of one sample (each channel in [0, 1]) whose key is `key`, the ray through raster
   position (rx, ry). */
static clvis_vec3 shade_sample(ulong key, float rx, float ry, clvis_camera_gpu cam, __global const float* positions,
                               __global const uint* indices, __global const float* normals, int has_normals,
                               uint triangle_count, int mode, clvis_vec3 light)
{
    uint id = clvis_key_id(key);
    if (id == CLVIS_BACKGROUND_ID || id >= triangle_count) return v3(24.0f / 255.0f, 24.0f / 255.0f, 28.0f / 255.0f);
    float depth = clvis_key_depth(key);
    if (mode == CLVIS_SHADE_IDS) return id_colour(id);
    if (mode == CLVIS_SHADE_DEPTH) {
        float g = clamp(1.0f - (depth - cam.near_d) / (cam.far_d - cam.near_d), 0.0f, 1.0f);
        return v3(g, g, g);
    }
    uint i0 = indices[3 * id], i1 = indices[3 * id + 1], i2 = indices[3 * id + 2];
    clvis_vec3 p0 = load3(positions, i0), p1 = load3(positions, i1), p2 = load3(positions, i2);
    clvis_vec3 o, d;
    clvis_primary_ray(cam, rx, ry, &o, &d);
    clvis_vec3 dir = unit3(d);
    clvis_vec3 n = cross3(sub3(p1, p0), sub3(p2, p0));
    float area2 = sqrt(dot3(n, n));
    n = area2 > 0.0f ? scale3(n, 1.0f / area2) : scale3(dir, -1.0f);
    if (has_normals && area2 > 0.0f) {
        /* barycentrics of the hit point in the triangle's plane */
        clvis_vec3 p = add3(o, scale3(d, depth));
        float b0 = dot3(cross3(sub3(p2, p1), sub3(p, p1)), n) / area2;
        float b1 = dot3(cross3(sub3(p0, p2), sub3(p, p2)), n) / area2;
        float b2 = 1.0f - b0 - b1;
        clvis_vec3 s = add3(add3(scale3(load3(normals, i0), b0), scale3(load3(normals, i1), b1)),
                            scale3(load3(normals, i2), b2));
        if (dot3(s, s) > 0.0f) n = unit3(s);
    }
    if (dot3(n, dir) > 0.0f) n = scale3(n, -1.0f); /* two-sided: face the viewer */
    float lambert = fmax(-dot3(n, light), 0.0f);
    float facing = fmax(-dot3(n, dir), 0.0f);
    float k = 0.10f + 0.65f * lambert + 0.25f * facing;
    return v3(clamp(0.85f * k, 0.0f, 1.0f), clamp(0.80f * k, 0.0f, 1.0f), clamp(0.72f * k, 0.0f, 1.0f));
}

/* One pixel: the mean of its samples' colours (cam.sample_log2, shared/samples.h), so several
   samples per pixel give an anti-aliased image; one sample is shaded as it always was. */
__kernel void shade(__global const ulong* keys, __global uchar4* out, clvis_camera_gpu cam,
                    __global const float* positions, __global const uint* indices,
                    __global const float* normals, int has_normals, uint triangle_count,
                    int mode, float light_x, float light_y, float light_z)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= cam.width || y >= cam.height) return;
    size_t pixel = (size_t)y * cam.width + x;
    clvis_vec3 light = unit3(v3(light_x, light_y, light_z));
    if (cam.sample_log2 == 0) { /* one sample: straight-line code, as it always was */
        clvis_vec3 c = shade_sample(keys[pixel], (float)x + 0.5f, (float)y + 0.5f, cam, positions, indices, normals,
                                    has_normals, triangle_count, mode, light);
        out[pixel] = rgba(c.x, c.y, c.z);
        return;
    }
    int n = 1 << cam.sample_log2;
    clvis_vec3 sum = v3(0.0f, 0.0f, 0.0f);
    for (int k = 0; k < n; ++k) {
        float rx = (float)x + clvis_sample_fraction(cam.sample_log2, k, 0);
        float ry = (float)y + clvis_sample_fraction(cam.sample_log2, k, 1);
        sum = add3(sum, shade_sample(keys[(pixel << cam.sample_log2) + (size_t)k], rx, ry, cam, positions, indices,
                                     normals, has_normals, triangle_count, mode, light));
    }
    out[pixel] = rgba(sum.x / (float)n, sum.y / (float)n, sum.z / (float)n);
}
