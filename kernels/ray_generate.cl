/* Makes rays on the device from a visibility buffer, the first users of the ray queries
   (ray_query.cl): ambient occlusion rays (cosine-weighted about the face normal, seeded by a
   hash of seed, pixel and sample, so the same call gives the same rays) and shadow rays toward a
   point light. Each starts at the pixel's visible point, moved off the surface along the normal
   on the camera's side. A background pixel gets a ray of zero direction, which the queries answer
   as a miss. Launched by host/ray_generate.cpp; writes AoS rays (shared/ray_query.h). */
#include "shared/camera.h"
#include "shared/ray_query.h"
#include "shared/visibility.h"

/* A 32-bit integer hash with good avalanche (Chris Wellons' lowbias32). */
static uint hash32(uint x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* A float in [0, 1) from the top 24 bits of a hash. */
static float unit_float(uint h) { return (float)(h >> 8) * (1.0f / 16777216.0f); }

static clvis_vec3 vertex(__global const float* positions, uint v)
{
    clvis_vec3 p = {positions[3 * (size_t)v], positions[3 * (size_t)v + 1], positions[3 * (size_t)v + 2]};
    return p;
}

/* The visible point of `pixel` lifted by `offset` world units along its unit face normal, turned
   toward the camera; 0 for a background pixel. */
static int surface_point(__global const ulong* keys, clvis_camera_gpu cam, __global const float* positions,
                         __global const uint* indices, uint pixel, float offset, float3* point, float3* normal)
{
    ulong key = keys[pixel];
    uint id = clvis_key_id(key);
    if (id == CLVIS_BACKGROUND_ID) return 0;
    clvis_vec3 o, d;
    clvis_primary_ray(cam, (float)(pixel % (uint)cam.width) + 0.5f, (float)(pixel / (uint)cam.width) + 0.5f, &o, &d);
    float t = clvis_key_depth(key);
    float3 dir = (float3)(d.x, d.y, d.z);
    float3 p = (float3)(o.x, o.y, o.z) + t * dir;
    clvis_vec3 a = vertex(positions, indices[3 * (size_t)id]), b = vertex(positions, indices[3 * (size_t)id + 1]);
    clvis_vec3 c = vertex(positions, indices[3 * (size_t)id + 2]);
    float3 n = cross((float3)(b.x - a.x, b.y - a.y, b.z - a.z), (float3)(c.x - a.x, c.y - a.y, c.z - a.z));
    float len = length(n);
    n = len > 0.0f ? n / len : -normalize(dir);
    if (dot(n, dir) > 0.0f) n = -n;
    *point = p + offset * n;
    *normal = n;
    return 1;
}

static void store_ray(__global float* rays, size_t i, float3 o, float tmin, float3 d, float tmax)
{
    float r[CLVIS_RAY_FIELDS] = {o.x, o.y, o.z, tmin, d.x, d.y, d.z, tmax};
    for (int k = 0; k < CLVIS_RAY_FIELDS; ++k) rays[i * CLVIS_RAY_FIELDS + (size_t)k] = r[k];
}

/* Ray k of pixel first_pixel + g / per_pixel: a cosine-weighted direction (Malley's method) in
   the frame of the normal (Duff et al. 2017's branchless orthonormal basis), length `distance`. */
__kernel void ray_generate_ao(__global const ulong* keys, clvis_camera_gpu cam, __global const float* positions,
                              __global const uint* indices, uint first_pixel, uint pixels, uint per_pixel,
                              float offset, __global float* rays, float distance, uint seed_lo, uint seed_hi)
{
    uint g = (uint)get_global_id(0);
    if (g >= pixels * per_pixel) return;
    uint pixel = first_pixel + g / per_pixel, k = g % per_pixel;
    float3 p, n;
    if (!surface_point(keys, cam, positions, indices, pixel, offset, &p, &n)) {
        store_ray(rays, g, (float3)(0.0f), 0.0f, (float3)(0.0f), 0.0f);
        return;
    }
    uint h = hash32(hash32(hash32(seed_lo) ^ seed_hi) ^ pixel);
    uint h1 = hash32(h ^ (2u * k + 1u)), h2 = hash32(h1 ^ 0x9e3779b9u);
    float r = sqrt(unit_float(h1)), phi = 6.28318530718f * unit_float(h2);
    float lx = r * cos(phi), ly = r * sin(phi), lz = sqrt(fmax(0.0f, 1.0f - r * r));
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
    float3 tx = (float3)(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    float3 ty = (float3)(b, sign + n.y * n.y * a, -n.y);
    float3 dir = lx * tx + ly * ty + lz * n;
    store_ray(rays, g, p, 0.0f, dir * distance, 1.0f);
}

/* The shadow ray of pixel first_pixel + g: from the visible point to the light, t in [0, 1]. */
__kernel void ray_generate_shadow(__global const ulong* keys, clvis_camera_gpu cam, __global const float* positions,
                                  __global const uint* indices, uint first_pixel, uint pixels, uint per_pixel,
                                  float offset, __global float* rays, float light_x, float light_y, float light_z)
{
    uint g = (uint)get_global_id(0);
    if (g >= pixels * per_pixel) return;
    float3 p, n;
    if (!surface_point(keys, cam, positions, indices, first_pixel + g, offset, &p, &n)) {
        store_ray(rays, g, (float3)(0.0f), 0.0f, (float3)(0.0f), 0.0f);
        return;
    }
    store_ray(rays, g, p, 0.0f, (float3)(light_x, light_y, light_z) - p, 1.0f);
}
