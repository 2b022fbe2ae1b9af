/* The projection of CONVENTIONS.md, in float32, shared by the raster kernels, the ray kernels and
   the host (which tests it against the double-precision clvis::Camera). Camera space is
   (r, u, -f): the camera looks down -z; raster space has its origin at the top-left corner, y
   down, and pixel (i, j) is sampled at (i + 0.5, j + 0.5), or at the positions of
   shared/samples.h when the camera asks for several samples per pixel. Screen space maps to raster space
   through intrinsics (x = cx + fx s.x, y = cy - fy s.y): a field of view or an orthographic
   height is the case cx = width / 2, cy = height / 2 (CONVENTIONS.md "Cameras from
   intrinsics"). */
#ifndef CLVIS_SHARED_CAMERA_H
#define CLVIS_SHARED_CAMERA_H

#include "shared/samples.h"
#include "shared/types.h"

typedef struct clvis_camera_gpu {
    float eye_x, eye_y, eye_z; /* world units */
    float near_d;              /* view depth, > 0 */
    float r_x, r_y, r_z;       /* right, unit */
    float far_d;               /* view depth, > near_d */
    float u_x, u_y, u_z;       /* up, unit */
    float fx;                  /* px per screen unit in x: per unit at unit distance (perspective),
                                  per world unit (ortho) */
    float f_x, f_y, f_z;       /* forward (camera space -z), unit */
    float fy;                  /* px per screen unit in y, same unit as fx */
    float cx, cy;              /* raster position of the optical axis, px */
    clvis_i32 width, height;   /* pixels */
    clvis_i32 ortho;           /* 1: orthographic, 0: perspective */
    clvis_i32 sample_log2;     /* log2 of the samples per pixel (shared/samples.h); 0: one */
    clvis_i32 sample;          /* the sample a launch draws, 0 .. 2^sample_log2 - 1 */
    clvis_i32 pad;
} clvis_camera_gpu;

/* World -> camera space: x right, y up, z backwards (visible points have z < 0). */
static inline clvis_vec3 clvis_camera_from_world(clvis_camera_gpu cam, float x, float y, float z)
{
    float dx = x - cam.eye_x, dy = y - cam.eye_y, dz = z - cam.eye_z;
    clvis_vec3 p;
    p.x = dx * cam.r_x + dy * cam.r_y + dz * cam.r_z;
    p.y = dx * cam.u_x + dy * cam.u_y + dz * cam.u_z;
    p.z = -(dx * cam.f_x + dy * cam.f_y + dz * cam.f_z);
    return p;
}

/* Camera space -> screen space: the perspective divide, or the identity (orthographic). */
static inline clvis_vec2 clvis_screen_from_camera(clvis_camera_gpu cam, clvis_vec3 p)
{
    clvis_vec2 s;
    if (cam.ortho) {
        s.x = p.x;
        s.y = p.y;
    } else {
        s.x = p.x / -p.z;
        s.y = p.y / -p.z;
    }
    return s;
}

/* Screen -> raster: x = cx + fx s.x, y = cy - fy s.y (y down). */
static inline clvis_vec2 clvis_raster_from_screen(clvis_camera_gpu cam, clvis_vec2 s)
{
    clvis_vec2 r;
    r.x = cam.cx + cam.fx * s.x;
    r.y = cam.cy - cam.fy * s.y;
    return r;
}

/* Raster -> screen: the inverse of clvis_raster_from_screen. */
static inline clvis_vec2 clvis_screen_from_raster(clvis_camera_gpu cam, float rx, float ry)
{
    clvis_vec2 s;
    s.x = (rx - cam.cx) / cam.fx;
    s.y = (cam.cy - ry) / cam.fy;
    return s;
}

/* The image's edges in screen units: left, right, bottom and top (the view window, not
   necessarily centred on the optical axis). */
static inline float clvis_window_left(clvis_camera_gpu cam) { return -cam.cx / cam.fx; }
static inline float clvis_window_right(clvis_camera_gpu cam) { return ((float)cam.width - cam.cx) / cam.fx; }
static inline float clvis_window_bottom(clvis_camera_gpu cam) { return (cam.cy - (float)cam.height) / cam.fy; }
static inline float clvis_window_top(clvis_camera_gpu cam) { return cam.cy / cam.fy; }

/* Where the camera's sample (sample of 2^sample_log2, shared/samples.h) lies inside every pixel,
   px from its top-left corner: (0.5, 0.5) for one sample. */
static inline clvis_vec2 clvis_camera_sample(clvis_camera_gpu cam)
{
    clvis_vec2 f;
    f.x = clvis_sample_fraction(cam.sample_log2, cam.sample, 0);
    f.y = clvis_sample_fraction(cam.sample_log2, cam.sample, 1);
    return f;
}

/* The primary ray through raster position (rx, ry). Its direction is not normalised: the ray
   parameter t of a hit equals its view depth (CONVENTIONS.md "Primary rays"). */
static inline void clvis_primary_ray(clvis_camera_gpu cam, float rx, float ry,
                                     clvis_vec3* origin, clvis_vec3* dir)
{
    clvis_vec2 s = clvis_screen_from_raster(cam, rx, ry);
    if (cam.ortho) {
        origin->x = cam.eye_x + s.x * cam.r_x + s.y * cam.u_x;
        origin->y = cam.eye_y + s.x * cam.r_y + s.y * cam.u_y;
        origin->z = cam.eye_z + s.x * cam.r_z + s.y * cam.u_z;
        dir->x = cam.f_x;
        dir->y = cam.f_y;
        dir->z = cam.f_z;
    } else {
        origin->x = cam.eye_x;
        origin->y = cam.eye_y;
        origin->z = cam.eye_z;
        dir->x = s.x * cam.r_x + s.y * cam.u_x + cam.f_x;
        dir->y = s.x * cam.r_y + s.y * cam.u_y + cam.f_y;
        dir->z = s.x * cam.r_z + s.y * cam.u_z + cam.f_z;
    }
}

#endif
