/* Makes rays on the device from a visibility buffer, the first users of the ray queries
   (ray_query.cl): ambient occlusion rays (cosine-weighted about the face normal, seeded by a
   hash of seed, pixel and sample, so the same call gives the same rays) and shadow rays toward a
   point light. Each starts at the pixel's visible point, moved off the surface along the normal
   on the camera's side. A background pixel gets a ray of zero direction, which the queries answer
   as a miss. With a list of covered pixels (`covered`, not null) the rays are made for the pixels
   it lists, entries first_pixel .. first_pixel + pixels - 1, so no ray is made for the background;
   without one for pixels first_pixel .. first_pixel + pixels - 1 of the buffer. A ray depends on
   its pixel and its number only, so both give the same rays. Launched by
   host/query/ray_generate.cpp; writes AoS rays (shared/ray_query.h). */
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

/* Three-float vectors as plain structs: Oclgrind 21.10's uninitialised-value checker crashes on
   the 3-element vector types (12 bytes in registers, 16 in memory) this file used. */
static clvis_vec3 v3(float x, float y, float z)
{
    clvis_vec3 r = {x, y, z};
    return r;
}
static clvis_vec3 v3_sub(clvis_vec3 a, clvis_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static clvis_vec3 v3_mad(clvis_vec3 a, float k, clvis_vec3 b) { return v3(a.x + k * b.x, a.y + k * b.y, a.z + k * b.z); }
static clvis_vec3 v3_scale(clvis_vec3 a, float k) { return v3(k * a.x, k * a.y, k * a.z); }
static float v3_dot(clvis_vec3 a, clvis_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static clvis_vec3 v3_cross(clvis_vec3 a, clvis_vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/* The visible point of `pixel` lifted by `offset` world units along its unit face normal, turned
   toward the camera; 0 for a background pixel. */
static int surface_point(__global const ulong* keys, clvis_camera_gpu cam, __global const float* positions,
                         __global const uint* indices, uint pixel, float offset, clvis_vec3* point, clvis_vec3* normal)
{
    ulong key = keys[pixel];
    uint id = clvis_key_id(key);
    if (id == CLVIS_BACKGROUND_ID) return 0;
    clvis_vec3 o, d;
    /* Row and column without `%`: LLVM pairs a division with its remainder through a `freeze`
       instruction, which Oclgrind 21.10's uninitialised-value checker cannot interpret. */
    uint width = (uint)cam.width, row = pixel / width, column = pixel - row * width;
    clvis_primary_ray(cam, (float)column + 0.5f, (float)row + 0.5f, &o, &d);
    clvis_vec3 p = v3_mad(o, clvis_key_depth(key), d);
    clvis_vec3 a = vertex(positions, indices[3 * (size_t)id]), b = vertex(positions, indices[3 * (size_t)id + 1]);
    clvis_vec3 c = vertex(positions, indices[3 * (size_t)id + 2]);
    clvis_vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    float len = sqrt(v3_dot(n, n));
    n = len > 0.0f ? v3_scale(n, 1.0f / len) : v3_scale(d, -1.0f / sqrt(v3_dot(d, d)));
    if (v3_dot(n, d) > 0.0f) n = v3_scale(n, -1.0f);
    *point = v3_mad(p, offset, n);
    *normal = n;
    return 1;
}

static void store_ray(__global float* rays, size_t i, clvis_vec3 o, float tmin, clvis_vec3 d, float tmax)
{
    float r[CLVIS_RAY_FIELDS] = {o.x, o.y, o.z, tmin, d.x, d.y, d.z, tmax};
    for (int k = 0; k < CLVIS_RAY_FIELDS; ++k) rays[i * CLVIS_RAY_FIELDS + (size_t)k] = r[k];
}

/* The pixel of entry q of the launch: covered[first + q], or first + q without a list. */
static uint pixel_of(__global const uint* covered, uint first, uint q) { return covered ? covered[first + q] : first + q; }

/* Ray k of pixel entry g / per_pixel: a cosine-weighted direction (Malley's method) in
   the frame of the normal (Duff et al. 2017's branchless orthonormal basis), length `distance`. */
__kernel void ray_generate_ao(__global const ulong* keys, clvis_camera_gpu cam, __global const float* positions,
                              __global const uint* indices, uint first_pixel, uint pixels, uint per_pixel,
                              float offset, __global float* rays, float distance, uint seed_lo, uint seed_hi,
                              __global const uint* covered)
{
    uint g = (uint)get_global_id(0);
    if (g >= pixels * per_pixel) return;
    uint q = g / per_pixel, pixel = pixel_of(covered, first_pixel, q), k = g - q * per_pixel; /* no `%`: see surface_point */
    clvis_vec3 p, n, zero = v3(0.0f, 0.0f, 0.0f);
    if (!surface_point(keys, cam, positions, indices, pixel, offset, &p, &n)) {
        store_ray(rays, g, zero, 0.0f, zero, 0.0f);
        return;
    }
    uint h = hash32(hash32(hash32(seed_lo) ^ seed_hi) ^ pixel);
    uint h1 = hash32(h ^ (2u * k + 1u)), h2 = hash32(h1 ^ 0x9e3779b9u);
    float r = sqrt(unit_float(h1)), phi = 6.28318530718f * unit_float(h2);
    float lx = r * cos(phi), ly = r * sin(phi), lz = sqrt(fmax(0.0f, 1.0f - r * r));
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
    clvis_vec3 tx = v3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    clvis_vec3 ty = v3(b, sign + n.y * n.y * a, -n.y);
    clvis_vec3 dir = v3_mad(v3_mad(v3_scale(tx, lx), ly, ty), lz, n);
    store_ray(rays, g, p, 0.0f, v3_scale(dir, distance), 1.0f);
}

/* The shadow ray of pixel entry g: from the visible point to the light, t in [0, 1]. */
__kernel void ray_generate_shadow(__global const ulong* keys, clvis_camera_gpu cam, __global const float* positions,
                                  __global const uint* indices, uint first_pixel, uint pixels, uint per_pixel,
                                  float offset, __global float* rays, float light_x, float light_y, float light_z,
                                  __global const uint* covered)
{
    uint g = (uint)get_global_id(0);
    if (g >= pixels * per_pixel) return;
    clvis_vec3 p, n, zero = v3(0.0f, 0.0f, 0.0f);
    if (!surface_point(keys, cam, positions, indices, pixel_of(covered, first_pixel, g), offset, &p, &n)) {
        store_ray(rays, g, zero, 0.0f, zero, 0.0f);
        return;
    }
    store_ray(rays, g, p, 0.0f, v3_sub(v3(light_x, light_y, light_z), p), 1.0f);
}

/* The primary rays of every sample of the camera's image (CONVENTIONS.md "Primary rays as
   arrays"): clvis_primary_ray at the sample's raster position, tmin = near, tmax = far, record
   (pixel << sample_log2) + sample, AoS or SoA planes `stride` elements apart. The third dimension
   is the sample. Launched by RayQuery::primary_rays (host/query/ray_generate.cpp); the host's
   clvis::primary_rays computes the same operations. */
__kernel void ray_generate_primary(clvis_camera_gpu cam, __global float* rays, int layout, ulong stride)
{
    int x = (int)get_global_id(0), y = (int)get_global_id(1);
    if (x >= cam.width || y >= cam.height) return;
    cam.sample = (int)get_global_id(2);
    clvis_vec2 f = clvis_camera_sample(cam);
    clvis_vec3 o, d;
    clvis_primary_ray(cam, (float)x + f.x, (float)y + f.y, &o, &d);
    ulong i = ((((ulong)y * (ulong)cam.width + (ulong)x)) << cam.sample_log2) + (ulong)cam.sample;
    float r[CLVIS_RAY_FIELDS] = {o.x, o.y, o.z, cam.near_d, d.x, d.y, d.z, cam.far_d};
    for (int k = 0; k < CLVIS_RAY_FIELDS; ++k) {
        if (layout == CLVIS_LAYOUT_AOS) rays[i * CLVIS_RAY_FIELDS + (ulong)k] = r[k];
        else rays[(ulong)k * stride + i] = r[k];
    }
}
