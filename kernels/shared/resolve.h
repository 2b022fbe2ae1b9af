/* Attributes of a visible triangle at a sample, shared by kernels/resolve.cl and the host tests:
   the barycentrics of the point where the sample's primary ray meets the triangle's plane
   (CONVENTIONS.md "Barycentrics"), from which world position and normals follow. Both paths
   resolve their visibility buffers through it, so they give one meaning to each attribute. */
#ifndef CLVIS_SHARED_RESOLVE_H
#define CLVIS_SHARED_RESOLVE_H

#include "shared/camera.h"
#include "shared/ray.h" /* CLVIS_HAVE_DOUBLE */
#include "shared/types.h"

/* Which attributes resolve.cl writes (bits of its `what` argument). */
#define CLVIS_RESOLVE_BARY 1
#define CLVIS_RESOLVE_POSITION 2
#define CLVIS_RESOLVE_NORMAL 4
#define CLVIS_RESOLVE_SMOOTH_NORMAL 8
/* Normals in camera axes (x = r, y = u, z = -f) instead of world axes. */
#define CLVIS_RESOLVE_CAMERA_SPACE 16

#ifdef CLVIS_HAVE_DOUBLE
typedef double clvis_real;
#else
typedef float clvis_real;
#endif

/* (u, v) with P = (1 - u - v) a + u b + v c the point where the ray o + t d meets the plane of
   triangle (a, b, c), and that t (Moeller and Trumbore's solve, relative to a, in double where the
   device has it: the ray need not hit the triangle, and a triangle seen at a grazing angle leaves
   little of float's precision). Returns 0, with u = v = 0, where the ray is parallel to the plane
   or the triangle has no area. */
static inline int clvis_plane_barycentrics(clvis_vec3 o, clvis_vec3 d, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c,
                                           float* u, float* v, float* t)
{
    clvis_real e1x = (clvis_real)b.x - (clvis_real)a.x, e1y = (clvis_real)b.y - (clvis_real)a.y;
    clvis_real e1z = (clvis_real)b.z - (clvis_real)a.z;
    clvis_real e2x = (clvis_real)c.x - (clvis_real)a.x, e2y = (clvis_real)c.y - (clvis_real)a.y;
    clvis_real e2z = (clvis_real)c.z - (clvis_real)a.z;
    clvis_real sx = (clvis_real)o.x - (clvis_real)a.x, sy = (clvis_real)o.y - (clvis_real)a.y;
    clvis_real sz = (clvis_real)o.z - (clvis_real)a.z;
    clvis_real dx = d.x, dy = d.y, dz = d.z;
    clvis_real px = dy * e2z - dz * e2y, py = dz * e2x - dx * e2z, pz = dx * e2y - dy * e2x;
    clvis_real det = e1x * px + e1y * py + e1z * pz;
    *u = 0.0f;
    *v = 0.0f;
    *t = 0.0f;
    if (det == (clvis_real)0) return 0;
    clvis_real qx = sy * e1z - sz * e1y, qy = sz * e1x - sx * e1z, qz = sx * e1y - sy * e1x;
    *u = (float)((sx * px + sy * py + sz * pz) / det);
    *v = (float)((dx * qx + dy * qy + dz * qz) / det);
    *t = (float)((e2x * qx + e2y * qy + e2z * qz) / det);
    return 1;
}

/* The point (1 - u - v) a + u b + v c. */
static inline clvis_vec3 clvis_barycentric_point(clvis_vec3 a, clvis_vec3 b, clvis_vec3 c, float u, float v)
{
    clvis_real w = (clvis_real)1 - (clvis_real)u - (clvis_real)v;
    clvis_vec3 p;
    p.x = (float)(w * a.x + (clvis_real)u * b.x + (clvis_real)v * c.x);
    p.y = (float)(w * a.y + (clvis_real)u * b.y + (clvis_real)v * c.y);
    p.z = (float)(w * a.z + (clvis_real)u * b.z + (clvis_real)v * c.z);
    return p;
}

#endif
