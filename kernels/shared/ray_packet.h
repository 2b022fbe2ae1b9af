/* The 16-ray packets of ray_trace.cl (OpenCL C only: vector types): the packet's rays, made with
   the same operations as the scalar clvis_primary_ray, clvis_make_shear and clvis_make_box_ray, and
   the box tests on all 16 rays at once (the scalar clvis_ray_hits_box's operations per lane, and
   a conservative interval test of a node's children against the whole packet). */
#ifndef CLVIS_SHARED_RAY_PACKET_H
#define CLVIS_SHARED_RAY_PACKET_H

#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/instance.h"
#include "shared/ray.h"

/* 4x4 pixels as the 16 lanes: make_packet's column and row vectors and trace_packet's one ulong4
   store per row of keys are written for that shape. */
#if CLVIS_PACKET_W != 4 || CLVIS_PACKET_H != 4
#error "ray packets are 4x4 pixels, the 16 lanes of float16"
#endif

typedef float16 lanes_f;
typedef int16 lanes_i;
typedef uint16 lanes_u;

/* The packet's rays, lane l = pixel (l % 4, l / 4) of the packet. */
typedef struct packet {
    lanes_f ox, oy, oz;          /* origin, world axes */
    lanes_f ix, iy, iz;          /* 1 / direction */
    lanes_i nx, ny, nz;          /* 1 / direction < 0: the slab is entered through hi */
    lanes_f px, py, pz;          /* origin permuted to the shear's axes (kx, ky, kz) */
    lanes_f sx, sy, sz;          /* shear (clvis_ray_shear) */
    lanes_i kx0, kx1, ky0, ky1, kz0, kz1; /* kx == 0, kx == 1, ...: per-lane permutation */
    float cx, cy, cz;            /* direction of a central ray: orders children near to far */
    int same_signs;              /* every lane enters boxes through the same planes, (neg_x, ...) */
    int neg_x, neg_y, neg_z;
    int perspective;             /* every lane starts at the eye */
    float eye_x, eye_y, eye_z;
    int uniform;                 /* every lane has the same permutation, (ukx, uky, ukz) */
    int common_origin;           /* and the same origin (perspective), (uox, uoy, uoz) permuted */
    float uox, uoy, uoz;
    int ukx, uky, ukz;
    int span;                    /* perspective, same signs, every 1 / direction finite and not 0: */
    float ix_lo, ix_hi, iy_lo, iy_hi, iz_lo, iz_hi; /* the lanes' range of each, for packet_span_hits */
} packet;

static float pick(float x, float y, float z, int k) { return k == 0 ? x : (k == 1 ? y : z); }

/* The OR of a mask's lanes (a bit set in any lane), by halves through private memory (which
   compilers turn into shuffles): Oclgrind 21.10 tracked .lo/.hi swizzles of 16-wide vectors as
   uninitialised and crashed on int2 ones. */
static int or_lanes(lanes_i m)
{
    int r[CLVIS_PACKET];
    vstore16(m, 0, r);
    vstore8(vload8(0, r) | vload8(1, r), 0, r);
    vstore4(vload4(0, r) | vload4(1, r), 0, r);
    return r[0] | r[1] | r[2] | r[3];
}

/* Whether some lane of a mask is set: by the compiler's vector OR reduction where the host asks
   for it (CLVIS_REDUCE_OR, PoCL's CPU device: Device::Impl::cpu_hints) and the compiler has it
   (Clang 15, PoCL 3.1: one kortestw with AVX-512, where or_lanes' halves take a chain of
   shuffles; 3% of a bunny frame at 640x480), else or_lanes. Oclgrind 21.10's Clang has the
   builtin, but its interpreter cannot run the intrinsic it becomes (llvm.vector.reduce.or).
   (__has_builtin in its own #if: a preprocessor without it could not parse the call.) */
#if defined(CLVIS_REDUCE_OR) && defined(__has_builtin)
#if __has_builtin(__builtin_reduce_or)
#define CLVIS_ANY_LANE_REDUCE 1
#endif
#endif
static int any_lane(lanes_i m)
{
#ifdef CLVIS_ANY_LANE_REDUCE
    return __builtin_reduce_or(m) != 0;
#else
    return or_lanes(m) != 0;
#endif
}

/* clvis_raise / clvis_lower on lanes: a NaN v leaves acc. */
static lanes_f raise(lanes_f acc, lanes_f v) { return select(acc, v, v > acc); }
static lanes_f lower(lanes_f acc, lanes_f v) { return select(acc, v, v < acc); }

/* The smallest and the largest lane, by halves as or_lanes, for lanes without NaN and without
   both signs of zero (then every comparison picks the one value fmin and fmax would). */
static float min_lanes(lanes_f v)
{
    float r[CLVIS_PACKET];
    vstore16(v, 0, r);
    float8 a = vload8(0, r), b = vload8(1, r);
    vstore8(select(a, b, b < a), 0, r);
    float4 c = vload4(0, r), d = vload4(1, r);
    vstore4(select(c, d, d < c), 0, r);
    float e = r[1] < r[0] ? r[1] : r[0], f = r[3] < r[2] ? r[3] : r[2];
    return f < e ? f : e;
}

static float max_lanes(lanes_f v)
{
    float r[CLVIS_PACKET];
    vstore16(v, 0, r);
    float8 a = vload8(0, r), b = vload8(1, r);
    vstore8(select(a, b, b > a), 0, r);
    float4 c = vload4(0, r), d = vload4(1, r);
    vstore4(select(c, d, d > c), 0, r);
    float e = r[1] > r[0] ? r[1] : r[0], f = r[3] > r[2] ? r[3] : r[2];
    return f > e ? f : e;
}

/* Lanes where a value is not finite (clvis_finite's bits). */
static lanes_i not_finite(lanes_f v) { return (as_uint16(v) & 0x7F800000u) == 0x7F800000u; }

static lanes_f component(lanes_f x, lanes_f y, lanes_f z, lanes_i k)
{
    return select(select(z, y, k == 1), x, k == 0);
}

/* The packet's rays: clvis_primary_ray, clvis_make_shear and clvis_make_box_ray on 16 lanes, the
   same operations in the same order, so each lane holds the bits the scalar code gives its pixel.
   Lanes past the image's edge repeat the edge pixel's ray and are not written. */
static void make_packet(clvis_camera_gpu cam, int x0, int y0, packet* p)
{
    /* clvis_screen_from_raster at each lane's pixel (lane l: column l % 4, row l / 4), the same
       operations on the same values as for one pixel; no trip through private memory, whose
       vector stores and wider loads stall store forwarding on CPUs */
    const lanes_i column = (lanes_i)(0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3);
    const lanes_i row = (lanes_i)(0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3);
    clvis_vec2 frac = clvis_camera_sample(cam);
    lanes_f rx = convert_float16(min((lanes_i)(x0) + column, (lanes_i)(cam.width - 1))) + frac.x;
    lanes_f ry = convert_float16(min((lanes_i)(y0) + row, (lanes_i)(cam.height - 1))) + frac.y;
    lanes_f sx = (rx - cam.cx) / cam.fx, sy = (cam.cy - ry) / cam.fy;
    /* clvis_primary_ray */
    lanes_f ox, oy, oz, dx, dy, dz;
    if (cam.ortho) {
        ox = cam.eye_x + sx * cam.r_x + sy * cam.u_x;
        oy = cam.eye_y + sx * cam.r_y + sy * cam.u_y;
        oz = cam.eye_z + sx * cam.r_z + sy * cam.u_z;
        dx = (lanes_f)(cam.f_x);
        dy = (lanes_f)(cam.f_y);
        dz = (lanes_f)(cam.f_z);
    } else {
        ox = (lanes_f)(cam.eye_x);
        oy = (lanes_f)(cam.eye_y);
        oz = (lanes_f)(cam.eye_z);
        dx = sx * cam.r_x + sy * cam.u_x + cam.f_x;
        dy = sx * cam.r_y + sy * cam.u_y + cam.f_y;
        dz = sx * cam.r_z + sy * cam.u_z + cam.f_z;
    }
    /* clvis_make_box_ray's reciprocals, which clvis_make_shear's 1 / d_kz is one of */
    p->ox = ox; p->oy = oy; p->oz = oz;
    p->cx = dx.s5; p->cy = dy.s5; p->cz = dz.s5;
    p->ix = 1.0f / dx; p->iy = 1.0f / dy; p->iz = 1.0f / dz;
    p->nx = p->ix < 0.0f; p->ny = p->iy < 0.0f; p->nz = p->iz < 0.0f;
    p->neg_x = p->nx.s0; p->neg_y = p->ny.s0; p->neg_z = p->nz.s0;
    /* clvis_make_shear */
    lanes_f ax = fabs(dx), ay = fabs(dy), az = fabs(dz);
    lanes_i kz = select(select((lanes_i)(2), (lanes_i)(1), ay >= az), (lanes_i)(0), (ax >= ay) & (ax >= az));
    lanes_i kx = select(kz + 1, (lanes_i)(0), kz == 2);
    lanes_i ky = select(kx + 1, (lanes_i)(0), kx == 2);
    lanes_f d_kz = component(dx, dy, dz, kz);
    lanes_i swap = d_kz < 0.0f;
    lanes_i kx_s = select(kx, ky, swap);
    ky = select(ky, kx, swap);
    kx = kx_s;
    p->sx = component(dx, dy, dz, kx) / d_kz;
    p->sy = component(dx, dy, dz, ky) / d_kz;
    p->sz = component(p->ix, p->iy, p->iz, kz);
    p->px = component(ox, oy, oz, kx);
    p->py = component(ox, oy, oz, ky);
    p->pz = component(ox, oy, oz, kz);
    p->kx0 = kx == 0; p->kx1 = kx == 1;
    p->ky0 = ky == 0; p->ky1 = ky == 1;
    p->kz0 = kz == 0; p->kz1 = kz == 1;
    p->ukx = kx.s0; p->uky = ky.s0; p->ukz = kz.s0;
    /* The lanes that differ from lane 0, one reduction for three flags: bit 0 in its permutation,
       bit 1 in its entry planes; bit 2 marks a 1 / direction that is infinite, NaN or 0. */
    int mixed = or_lanes((((kx != p->ukx) | (ky != p->uky)) & 1) |
                         (((p->nx != p->neg_x) | (p->ny != p->neg_y) | (p->nz != p->neg_z)) & 2) |
                         ((not_finite(p->ix) | (p->ix == 0.0f) | not_finite(p->iy) | (p->iy == 0.0f) |
                           not_finite(p->iz) | (p->iz == 0.0f)) & 4));
    p->uniform = !(mixed & 1);
    p->common_origin = p->uniform && !cam.ortho;
    p->uox = pick(cam.eye_x, cam.eye_y, cam.eye_z, p->ukx);
    p->uoy = pick(cam.eye_x, cam.eye_y, cam.eye_z, p->uky);
    p->uoz = pick(cam.eye_x, cam.eye_y, cam.eye_z, p->ukz);
    p->same_signs = !(mixed & 2);
    p->perspective = !cam.ortho;
    p->eye_x = cam.eye_x; p->eye_y = cam.eye_y; p->eye_z = cam.eye_z;
    p->span = p->perspective && p->same_signs && !(mixed & 4);
    /* the ranges only the interval test reads, which has neither NaN nor zeros */
    p->ix_lo = p->ix_hi = p->iy_lo = p->iy_hi = p->iz_lo = p->iz_hi = 0.0f;
    if (p->span) {
        p->ix_lo = min_lanes(p->ix); p->ix_hi = max_lanes(p->ix);
        p->iy_lo = min_lanes(p->iy); p->iy_hi = max_lanes(p->iy);
        p->iz_lo = min_lanes(p->iz); p->iz_hi = max_lanes(p->iz);
    }
}

#ifndef CLVIS_RASTER_RULE /* the watertight test (ray_trace.cl has the raster rule's) */
/* clvis_ray_hits_box on every lane for child k of node n; `cull` is each ray's far distance (far,
   or its nearest hit) already scaled by CLVIS_IZE_SCALE. Where every lane enters through the same
   planes the planes are picked once, and with a common origin (perspective) plane - origin is
   one scalar subtraction: the same operations on the same values as the per-lane form. */
static lanes_i packet_hits_box(const packet* p, __global const clvis_wide_node* n, int k, __global const clvis_instance* xi,
                               float near_t, lanes_f cull)
{
    float lo[3], hi[3];
    clvis_instance_child_box(n, k, xi, lo, hi);
    lanes_f tnx, tny, tnz, tfx, tfy, tfz;
    if (p->same_signs) {
        float nx = p->neg_x ? hi[0] : lo[0], fx = p->neg_x ? lo[0] : hi[0];
        float ny = p->neg_y ? hi[1] : lo[1], fy = p->neg_y ? lo[1] : hi[1];
        float nz = p->neg_z ? hi[2] : lo[2], fz = p->neg_z ? lo[2] : hi[2];
        if (p->perspective) {
            tnx = (lanes_f)(nx - p->eye_x) * p->ix;
            tny = (lanes_f)(ny - p->eye_y) * p->iy;
            tnz = (lanes_f)(nz - p->eye_z) * p->iz;
            tfx = (lanes_f)(fx - p->eye_x) * p->ix;
            tfy = (lanes_f)(fy - p->eye_y) * p->iy;
            tfz = (lanes_f)(fz - p->eye_z) * p->iz;
        } else {
            tnx = ((lanes_f)(nx) - p->ox) * p->ix;
            tny = ((lanes_f)(ny) - p->oy) * p->iy;
            tnz = ((lanes_f)(nz) - p->oz) * p->iz;
            tfx = ((lanes_f)(fx) - p->ox) * p->ix;
            tfy = ((lanes_f)(fy) - p->oy) * p->iy;
            tfz = ((lanes_f)(fz) - p->oz) * p->iz;
        }
    } else {
        lanes_f lox = (lanes_f)(lo[0]), loy = (lanes_f)(lo[1]), loz = (lanes_f)(lo[2]);
        lanes_f hix = (lanes_f)(hi[0]), hiy = (lanes_f)(hi[1]), hiz = (lanes_f)(hi[2]);
        tnx = (select(lox, hix, p->nx) - p->ox) * p->ix;
        tny = (select(loy, hiy, p->ny) - p->oy) * p->iy;
        tnz = (select(loz, hiz, p->nz) - p->oz) * p->iz;
        tfx = (select(hix, lox, p->nx) - p->ox) * p->ix;
        tfy = (select(hiy, loy, p->ny) - p->oy) * p->iy;
        tfz = (select(hiz, loz, p->nz) - p->oz) * p->iz;
    }
    lanes_f t0 = raise(raise(raise((lanes_f)(near_t), tnx), tny), tnz);
    lanes_f t1 = lower(lower(lower((lanes_f)(CLVIS_INFINITY), tfx), tfy), tfz) * CLVIS_IZE_SCALE;
    return (t0 <= t1) & (t0 <= cull);
}

/* The extremes over the lanes of a * i, i in [lo, hi] (the lanes' 1 / direction on one axis):
   a product's rounding is monotonic in each factor, so a * lo or a * hi is one lane's own bits. */
static clvis_wfloat span_low(clvis_wfloat a, float lo, float hi) { return select(a * hi, a * lo, a >= 0.0f); }
static clvis_wfloat span_high(clvis_wfloat a, float lo, float hi) { return select(a * lo, a * hi, a >= 0.0f); }
static clvis_wfloat raise_w(clvis_wfloat acc, clvis_wfloat v) { return select(acc, v, v > acc); }
static clvis_wfloat lower_w(clvis_wfloat acc, clvis_wfloat v) { return select(acc, v, v < acc); }

/* The interval test of node n's children against the whole packet (p->span: a common origin,
   one entry plane per axis, no NaN): bit k is set unless no lane can pass packet_hits_box for
   child k. Each lane's entry distance is at least enter[k], the largest of near and the lanes'
   smallest plane distances, and its exit at most the smallest of their largest, scaled as there:
   a child is dropped where enter exceeds that exit or every lane's cull (cull_max, their largest). */
static int packet_span_hits(const packet* p, __global const clvis_wide_node* n, float near_t, float cull_max,
                            clvis_wfloat* enter)
{
    /* rows aligned to their vector in the node, as ray_query.cl's hits_boxes reads them */
    __global const clvis_wfloat* rows = (__global const clvis_wfloat*)n->lo_x;
    clvis_wfloat lx = rows[0], hx = rows[1], ly = rows[2], hy = rows[3], lz = rows[4], hz = rows[5];
    clvis_wfloat ax = (p->neg_x ? hx : lx) - p->eye_x, bx = (p->neg_x ? lx : hx) - p->eye_x;
    clvis_wfloat ay = (p->neg_y ? hy : ly) - p->eye_y, by = (p->neg_y ? ly : hy) - p->eye_y;
    clvis_wfloat az = (p->neg_z ? hz : lz) - p->eye_z, bz = (p->neg_z ? lz : hz) - p->eye_z;
    clvis_wfloat t0 = raise_w(raise_w(raise_w((clvis_wfloat)(near_t), span_low(ax, p->ix_lo, p->ix_hi)),
                                      span_low(ay, p->iy_lo, p->iy_hi)),
                              span_low(az, p->iz_lo, p->iz_hi));
    clvis_wfloat t1 = lower_w(lower_w(lower_w((clvis_wfloat)(CLVIS_INFINITY), span_high(bx, p->ix_lo, p->ix_hi)),
                                      span_high(by, p->iy_lo, p->iy_hi)),
                              span_high(bz, p->iz_lo, p->iz_hi)) * CLVIS_IZE_SCALE;
    clvis_wint hit = (t0 <= t1) & (t0 <= (clvis_wfloat)(cull_max));
    *enter = t0;
    return clvis_wmask_bits(hit);
}

#endif

#endif
