/* Flow between two views (CONVENTIONS.md "Motion between views (flow)"): for each sample of view A,
   the point P its primary ray meets on its triangle's plane (A's barycentrics, shared/resolve.h),
   carried to P_B, the same barycentrics on the triangle's corners as placed at view B, and
   projected by B's camera. Writes per pixel flow.x, flow.y (raster px, y down), valid and
   occluded; flow NaN and both masks 0 for the background and invalid samples. P_B, its depth and
   its projection are computed in double where the device has it. Launched by
   host/render/flow.cpp. */
#include "shared/camera.h"
#include "shared/resolve.h"
#include "shared/visibility.h"

static clvis_vec3 flow_corner(__global const float* p, __global const uint* indices, uint id, int k)
{
    uint v = indices[3 * (size_t)id + k];
    clvis_vec3 r;
    r.x = p[3 * (size_t)v];
    r.y = p[3 * (size_t)v + 1];
    r.z = p[3 * (size_t)v + 2];
    return r;
}

__kernel void flow(__global const ulong* keys_a, clvis_camera_gpu cam_a, __global const ulong* keys_b,
                   clvis_camera_gpu cam_b, __global const float* positions_a, __global const float* positions_b,
                   __global const uint* indices, uint triangle_count, __global float* out)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= cam_a.width || y >= cam_a.height) return;
    size_t pixel = (size_t)y * cam_a.width + x;
    uint id = clvis_key_id(keys_a[pixel]);
    float4 result = (float4)(NAN, NAN, 0.0f, 0.0f);
    if (id != CLVIS_BACKGROUND_ID && id < triangle_count) {
        clvis_vec3 a0 = flow_corner(positions_a, indices, id, 0), a1 = flow_corner(positions_a, indices, id, 1);
        clvis_vec3 a2 = flow_corner(positions_a, indices, id, 2);
        clvis_vec3 o, d;
        float sx = x + 0.5f, sy = y + 0.5f;
        clvis_primary_ray(cam_a, sx, sy, &o, &d);
        float u, v, t;
        if (clvis_plane_barycentrics(o, d, a0, a1, a2, &u, &v, &t)) {
            clvis_vec3 b0 = flow_corner(positions_b, indices, id, 0), b1 = flow_corner(positions_b, indices, id, 1);
            clvis_vec3 b2 = flow_corner(positions_b, indices, id, 2);
            clvis_real w = (clvis_real)1 - (clvis_real)u - (clvis_real)v;
            /* P_B relative to B's eye, then in B's camera axes. */
            clvis_real px = w * b0.x + (clvis_real)u * b1.x + (clvis_real)v * b2.x - cam_b.eye_x;
            clvis_real py = w * b0.y + (clvis_real)u * b1.y + (clvis_real)v * b2.y - cam_b.eye_y;
            clvis_real pz = w * b0.z + (clvis_real)u * b1.z + (clvis_real)v * b2.z - cam_b.eye_z;
            clvis_real qx = px * cam_b.r_x + py * cam_b.r_y + pz * cam_b.r_z;
            clvis_real qy = px * cam_b.u_x + py * cam_b.u_y + pz * cam_b.u_z;
            clvis_real depth = px * cam_b.f_x + py * cam_b.f_y + pz * cam_b.f_z;
            if (depth >= (clvis_real)cam_b.near_d && depth <= (clvis_real)cam_b.far_d) {
                clvis_real scx = cam_b.ortho ? qx : qx / depth, scy = cam_b.ortho ? qy : qy / depth;
                clvis_real rx = (clvis_real)cam_b.cx + (clvis_real)cam_b.fx * scx;
                clvis_real ry = (clvis_real)cam_b.cy - (clvis_real)cam_b.fy * scy;
                if (rx >= 0 && rx < (clvis_real)cam_b.width && ry >= 0 && ry < (clvis_real)cam_b.height) {
                    int ix = min((int)floor(rx), cam_b.width - 1), iy = min((int)floor(ry), cam_b.height - 1);
                    clvis_real seen = clvis_key_depth(keys_b[(size_t)iy * cam_b.width + ix]);
                    result.x = (float)(rx - (clvis_real)sx);
                    result.y = (float)(ry - (clvis_real)sy);
                    result.z = 1.0f;
                    result.w = seen < depth - (clvis_real)1e-4 * depth ? 1.0f : 0.0f;
                }
            }
        }
    }
    vstore4(result, pixel, out);
}
