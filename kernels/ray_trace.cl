/* Casts one primary ray per pixel centre through the BVH (shared/bvh.h) and writes the visibility
   key of every pixel; launched by host/ray/ray_pipeline.cpp. Each work-item traces a packet of 4x4
   pixels as the 16 lanes of OpenCL vectors (Wald et al., "Interactive rendering with coherent ray
   tracing", 2001): one walk of the 4-wide tree per packet, nearest child first, with a short
   stack; every box and triangle test runs on all 16 rays at once, the same operations as the
   scalar tests of shared/ray.h, so each ray gets the bits that ray_brute.cl computes for it. A
   child is skipped when no ray of the packet can meet it before its nearest hit so far.
   Work-groups are screen tiles of packets. Built with CLVIS_RASTER_RULE (RenderOptions::coverage),
   each candidate triangle is judged by the raster path's predicate instead (packet_rule_leaf). */
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/instance.h"
#include "shared/ray.h"
#include "shared/region.h"
#include "shared/visibility.h"
#ifdef CLVIS_RASTER_RULE
#include "shared/raster_rule.h"
#endif

#define CLVIS_RAY_NONE 0xFFFFFFFFu

/* CLVIS_RAY_STACK (entries, at least 3 x the 4-wide tree's depth) is set by the host at build
   time. */
#ifndef CLVIS_RAY_STACK
#error "CLVIS_RAY_STACK must be defined"
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

/* clvis_raise / clvis_lower on lanes: a NaN v leaves acc. */
static lanes_f raise(lanes_f acc, lanes_f v) { return select(acc, v, v > acc); }
static lanes_f lower(lanes_f acc, lanes_f v) { return select(acc, v, v < acc); }

#ifndef CLVIS_RASTER_RULE /* the watertight test on packets (the raster rule's is below) */
/* clvis_ray_hits_box on every lane for child k of node n; `cull` is each ray's far distance (far,
   or its nearest hit) already scaled by CLVIS_IZE_SCALE. Where every lane enters through the same
   planes the planes are picked once, and with a common origin (perspective) plane - origin is
   one scalar subtraction: the same operations on the same values as the per-lane form. */
static lanes_i packet_hits_box(const packet* p, __global const clvis_bvh4_node* n, int k, __global const clvis_instance* xi,
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

static lanes_f permuted(float x, float y, float z, lanes_i k0, lanes_i k1)
{
    return select(select((lanes_f)(z), (lanes_f)(y), k1), (lanes_f)(x), k0);
}

/* clvis_ray_edges_of on every lane: the shear, the edge functions (with the exact recompute,
   clvis_exact_edges, on the lanes where one rounded to zero: one OR of the lanes decides), det
   and tz. */
typedef struct { lanes_f u, v, w, det, tz; } packet_edges;

static packet_edges packet_edges_of(const packet* p, lanes_f akx, lanes_f aky, lanes_f akz, lanes_f bkx, lanes_f bky,
                                    lanes_f bkz, lanes_f ckx, lanes_f cky, lanes_f ckz)
{
    lanes_f ax = akx - p->sx * akz;
    lanes_f ay = aky - p->sy * akz;
    lanes_f bx = bkx - p->sx * bkz;
    lanes_f by = bky - p->sy * bkz;
    lanes_f cx = ckx - p->sx * ckz;
    lanes_f cy = cky - p->sy * ckz;
    packet_edges r;
    r.u = cx * by - cy * bx;
    r.v = ax * cy - ay * cx;
    r.w = bx * ay - by * ax;
    lanes_i zero = (r.u == 0.0f) | (r.v == 0.0f) | (r.w == 0.0f);
    if (or_lanes(zero)) { /* rare: lane by lane, the scalar code's exact fallback */
        float l_ax[CLVIS_PACKET], l_ay[CLVIS_PACKET], l_bx[CLVIS_PACKET], l_by[CLVIS_PACKET], l_cx[CLVIS_PACKET];
        float l_cy[CLVIS_PACKET], l_u[CLVIS_PACKET], l_v[CLVIS_PACKET], l_w[CLVIS_PACKET];
        int l_zero[CLVIS_PACKET];
        vstore16(ax, 0, l_ax); vstore16(ay, 0, l_ay); vstore16(bx, 0, l_bx);
        vstore16(by, 0, l_by); vstore16(cx, 0, l_cx); vstore16(cy, 0, l_cy);
        vstore16(r.u, 0, l_u); vstore16(r.v, 0, l_v); vstore16(r.w, 0, l_w);
        vstore16(zero, 0, l_zero);
        for (int l = 0; l < CLVIS_PACKET; ++l)
            if (l_zero[l])
                clvis_exact_edges(&l_u[l], &l_v[l], &l_w[l], l_ax[l], l_ay[l], l_bx[l], l_by[l], l_cx[l], l_cy[l]);
        r.u = vload16(0, l_u);
        r.v = vload16(0, l_v);
        r.w = vload16(0, l_w);
    }
    r.det = r.u + r.v + r.w;
    r.tz = r.u * (p->sz * akz) + r.v * (p->sz * bkz) + r.w * (p->sz * ckz);
    return r;
}

/* Lanes where a value is not finite (clvis_finite's bits). */
static lanes_i not_finite(lanes_f v) { return (as_uint16(v) & 0x7F800000u) == 0x7F800000u; }

/* clvis_intersect_triangle on every lane (culling by `faces`, CLVIS_CULL_*), keeping each lane's
   nearest key (t bits, then id). The vertices are permuted to each lane's shear axes and the lane's permuted origin subtracted: the
   same single subtraction as the scalar test, whichever comes first. */
static void packet_test_triangle(const packet* p, const float* vert, uint tri_id, float near_t, float far_t,
                                 int faces, lanes_u* best_t, lanes_u* best_id)
{
    lanes_f akx, aky, akz, bkx, bky, bkz, ckx, cky, ckz;
    if (p->common_origin) {
        /* vertex minus origin once for all lanes: the same subtraction, done in scalar */
        akx = (lanes_f)(pick(vert[0], vert[1], vert[2], p->ukx) - p->uox);
        aky = (lanes_f)(pick(vert[0], vert[1], vert[2], p->uky) - p->uoy);
        akz = (lanes_f)(pick(vert[0], vert[1], vert[2], p->ukz) - p->uoz);
        bkx = (lanes_f)(pick(vert[3], vert[4], vert[5], p->ukx) - p->uox);
        bky = (lanes_f)(pick(vert[3], vert[4], vert[5], p->uky) - p->uoy);
        bkz = (lanes_f)(pick(vert[3], vert[4], vert[5], p->ukz) - p->uoz);
        ckx = (lanes_f)(pick(vert[6], vert[7], vert[8], p->ukx) - p->uox);
        cky = (lanes_f)(pick(vert[6], vert[7], vert[8], p->uky) - p->uoy);
        ckz = (lanes_f)(pick(vert[6], vert[7], vert[8], p->ukz) - p->uoz);
    } else if (p->uniform) {
        akx = (lanes_f)(pick(vert[0], vert[1], vert[2], p->ukx)) - p->px;
        aky = (lanes_f)(pick(vert[0], vert[1], vert[2], p->uky)) - p->py;
        akz = (lanes_f)(pick(vert[0], vert[1], vert[2], p->ukz)) - p->pz;
        bkx = (lanes_f)(pick(vert[3], vert[4], vert[5], p->ukx)) - p->px;
        bky = (lanes_f)(pick(vert[3], vert[4], vert[5], p->uky)) - p->py;
        bkz = (lanes_f)(pick(vert[3], vert[4], vert[5], p->ukz)) - p->pz;
        ckx = (lanes_f)(pick(vert[6], vert[7], vert[8], p->ukx)) - p->px;
        cky = (lanes_f)(pick(vert[6], vert[7], vert[8], p->uky)) - p->py;
        ckz = (lanes_f)(pick(vert[6], vert[7], vert[8], p->ukz)) - p->pz;
    } else {
        akx = permuted(vert[0], vert[1], vert[2], p->kx0, p->kx1) - p->px;
        aky = permuted(vert[0], vert[1], vert[2], p->ky0, p->ky1) - p->py;
        akz = permuted(vert[0], vert[1], vert[2], p->kz0, p->kz1) - p->pz;
        bkx = permuted(vert[3], vert[4], vert[5], p->kx0, p->kx1) - p->px;
        bky = permuted(vert[3], vert[4], vert[5], p->ky0, p->ky1) - p->py;
        bkz = permuted(vert[3], vert[4], vert[5], p->kz0, p->kz1) - p->pz;
        ckx = permuted(vert[6], vert[7], vert[8], p->kx0, p->kx1) - p->px;
        cky = permuted(vert[6], vert[7], vert[8], p->ky0, p->ky1) - p->py;
        ckz = permuted(vert[6], vert[7], vert[8], p->kz0, p->kz1) - p->pz;
    }
    packet_edges r = packet_edges_of(p, akx, aky, akz, bkx, bky, bkz, ckx, cky, ckz);
    lanes_f unscale = (lanes_f)(1.0f);
    lanes_i huge = not_finite(r.det) | not_finite(r.tz);
    if (or_lanes(huge)) {
        /* clvis_intersect_triangle's scaled retest: every coordinate times clvis_ray_scale of the
           largest magnitude among the vertices and the lane's origin. */
        float m = 0.0f;
        for (int i = 0; i < 9; ++i) m = fabs(vert[i]) > m ? fabs(vert[i]) : m;
        lanes_f mo = select(fabs(p->px), fabs(p->py), fabs(p->py) > fabs(p->px));
        mo = select(mo, fabs(p->pz), fabs(p->pz) > mo);
        mo = select(mo, (lanes_f)(m), (lanes_f)(m) > mo);
        lanes_i e = convert_int16((as_uint16(mo) >> 23) & 0xFFu) - 127;
        lanes_f k = select((lanes_f)(1.0f), as_float16(convert_uint16(157 - e) << 23), e > 30);
        packet_edges q = packet_edges_of(
            p, permuted(vert[0], vert[1], vert[2], p->kx0, p->kx1) * k - p->px * k,
            permuted(vert[0], vert[1], vert[2], p->ky0, p->ky1) * k - p->py * k,
            permuted(vert[0], vert[1], vert[2], p->kz0, p->kz1) * k - p->pz * k,
            permuted(vert[3], vert[4], vert[5], p->kx0, p->kx1) * k - p->px * k,
            permuted(vert[3], vert[4], vert[5], p->ky0, p->ky1) * k - p->py * k,
            permuted(vert[3], vert[4], vert[5], p->kz0, p->kz1) * k - p->pz * k,
            permuted(vert[6], vert[7], vert[8], p->kx0, p->kx1) * k - p->px * k,
            permuted(vert[6], vert[7], vert[8], p->ky0, p->ky1) * k - p->py * k,
            permuted(vert[6], vert[7], vert[8], p->kz0, p->kz1) * k - p->pz * k);
        r.u = select(r.u, q.u, huge);
        r.v = select(r.v, q.v, huge);
        r.w = select(r.w, q.w, huge);
        r.det = select(r.det, q.det, huge);
        r.tz = select(r.tz, q.tz, huge);
        unscale = select(unscale, 1.0f / k, huge);
    }
    /* Not outside: the edge functions do not take both signs. (Masks come only from comparisons,
       never from ~, so every lane is 0 or -1 on every implementation.) */
    lanes_i inside = ((r.u >= 0.0f) & (r.v >= 0.0f) & (r.w >= 0.0f)) | ((r.u <= 0.0f) & (r.v <= 0.0f) & (r.w <= 0.0f));
    lanes_f t = r.tz / r.det * unscale;
    lanes_i hit = inside & (r.det != 0.0f) & (t >= near_t) & (t <= far_t);
    if (faces == CLVIS_CULL_BACK) hit &= r.det > 0.0f; /* clvis_cull_keeps on every lane */
    else if (faces == CLVIS_CULL_FRONT) hit &= r.det < 0.0f;
    lanes_u bits = as_uint16(t), id = (lanes_u)(tri_id);
    lanes_i nearer = hit & ((bits < *best_t) | ((bits == *best_t) & (id < *best_id)));
    *best_t = select(*best_t, bits, nearer);
    *best_id = select(*best_id, id, nearer);
}
#endif

/* Lane l's pixel offset within the packet: (l % 4, l / 4). */
#define CLVIS_LANE_X ((lanes_i)(0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3))
#define CLVIS_LANE_Y ((lanes_i)(0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3))

static lanes_f component(lanes_f x, lanes_f y, lanes_f z, lanes_i k)
{
    return select(select(z, y, k == 1), x, k == 0);
}

/* The packet's rays: clvis_primary_ray, clvis_make_shear and clvis_make_box_ray on 16 lanes, the
   same operations in the same order, so each lane holds the bits the scalar code gives its pixel.
   Lanes past the image's edge repeat the edge pixel's ray and are not written. */
static void make_packet(clvis_camera_gpu cam, int x0, int y0, packet* out)
{
    lanes_f rx = convert_float16(min((lanes_i)(x0) + CLVIS_LANE_X, (lanes_i)(cam.width - 1))) + clvis_camera_sample(cam).x;
    lanes_f ry = convert_float16(min((lanes_i)(y0) + CLVIS_LANE_Y, (lanes_i)(cam.height - 1))) + clvis_camera_sample(cam).y;
    /* clvis_screen_from_raster */
    lanes_f sx = (rx - cam.cx) / cam.fx;
    lanes_f sy = (cam.cy - ry) / cam.fy;
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
    packet p;
    p.sx = component(dx, dy, dz, kx) / d_kz;
    p.sy = component(dx, dy, dz, ky) / d_kz;
    p.sz = 1.0f / d_kz;
    p.px = component(ox, oy, oz, kx);
    p.py = component(ox, oy, oz, ky);
    p.pz = component(ox, oy, oz, kz);
    p.kx0 = kx == 0; p.kx1 = kx == 1;
    p.ky0 = ky == 0; p.ky1 = ky == 1;
    p.kz0 = kz == 0; p.kz1 = kz == 1;
    p.ukx = kx.s0; p.uky = ky.s0; p.ukz = kz.s0;
    p.uniform = !any((kx != p.ukx) | (ky != p.uky));
    p.common_origin = p.uniform && !cam.ortho;
    p.uox = pick(cam.eye_x, cam.eye_y, cam.eye_z, p.ukx);
    p.uoy = pick(cam.eye_x, cam.eye_y, cam.eye_z, p.uky);
    p.uoz = pick(cam.eye_x, cam.eye_y, cam.eye_z, p.ukz);
    /* clvis_make_box_ray */
    p.ox = ox; p.oy = oy; p.oz = oz;
    p.cx = dx.s5; p.cy = dy.s5; p.cz = dz.s5;
    p.ix = 1.0f / dx; p.iy = 1.0f / dy; p.iz = 1.0f / dz;
    p.nx = p.ix < 0.0f; p.ny = p.iy < 0.0f; p.nz = p.iz < 0.0f;
    p.neg_x = p.nx.s0; p.neg_y = p.ny.s0; p.neg_z = p.nz.s0;
    p.same_signs = !any((p.nx != p.neg_x) | (p.ny != p.neg_y) | (p.nz != p.neg_z));
    p.perspective = !cam.ortho;
    p.eye_x = cam.eye_x; p.eye_y = cam.eye_y; p.eye_z = cam.eye_z;
    *out = p;
}

#ifdef CLVIS_RASTER_RULE
/* Coverage by the raster path's rule (RenderOptions::coverage, CLVIS_RASTER_RULE): the packet
   keeps its 16 keys in private memory, every candidate triangle leaves at each pixel the key the
   raster path leaves there (shared/raster_rule.h: set up once per triangle for the whole packet),
   and a box is skipped only where no ray can find such a key in it: the ray misses the box
   widened by clvis_rule_box_of's margin, or every key in it would lie beyond the ray's nearest
   (its depth range starts past it) or before near. */
static lanes_i packet_hits_box_rule(const packet* p, clvis_camera_gpu cam, __global const clvis_bvh4_node* n, int k,
                                    __global const clvis_instance* xi, lanes_f cull)
{
    float lo[3], hi[3];
    clvis_instance_child_box(n, k, xi, lo, hi);
    float lx = lo[0], ly = lo[1], lz = lo[2], hx = hi[0], hy = hi[1], hz = hi[2];
    if (!(lx <= hx && ly <= hy && lz <= hz)) return (lanes_i)(0); /* an unused slot */
    clvis_rule_box b = clvis_rule_box_of(cam, lx, ly, lz, hx, hy, hz);
    if (b.hi_d < cam.near_d) return (lanes_i)(0);
    float lo_d = b.lo_d == b.lo_d ? b.lo_d : -CLVIS_INFINITY; /* a NaN (overflow) skips nothing */
    lanes_f lox = (lanes_f)(lx - b.margin), loy = (lanes_f)(ly - b.margin), loz = (lanes_f)(lz - b.margin);
    lanes_f hix = (lanes_f)(hx + b.margin), hiy = (lanes_f)(hy + b.margin), hiz = (lanes_f)(hz + b.margin);
    /* from -inf and +inf, so that a NaN slab (an origin in a slab plane of an axis the ray runs
       parallel to: 0 * inf) is ignored on every axis, the first included */
    lanes_f t0 = raise(raise(raise((lanes_f)(-CLVIS_INFINITY), (select(lox, hix, p->nx) - p->ox) * p->ix),
                             (select(loy, hiy, p->ny) - p->oy) * p->iy),
                       (select(loz, hiz, p->nz) - p->oz) * p->iz);
    lanes_f t1 = lower(lower(lower((lanes_f)(CLVIS_INFINITY), (select(hix, lox, p->nx) - p->ox) * p->ix),
                             (select(hiy, loy, p->ny) - p->oy) * p->iy),
                       (select(hiz, loz, p->nz) - p->oz) * p->iz);
    /* the whole line, either side of its origin; the margin dwarfs the slab test's rounding */
    t0 = t0 - fabs(t0) * 9.5367431640625e-7f;
    t1 = t1 + fabs(t1) * 9.5367431640625e-7f;
    return (t0 <= t1) & ((lanes_f)(lo_d) <= cull);
}

/* The raster rule on every pixel of the packet for the triangles of a leaf; `cull` becomes each
   ray's nearest key depth (or far). */
static void packet_rule_leaf(__global const clvis_bvh_tri* tris, uint first, uint count, __global const clvis_instance* xi,
                             clvis_camera_gpu cam, int faces, int x0, int y0, ulong* best, lanes_f* cull)
{
    clvis_pixel_block blk = {x0, y0, min(CLVIS_PACKET_W, cam.width - x0), min(CLVIS_PACKET_H, cam.height - y0),
                             CLVIS_PACKET_W};
    for (uint k = first; k < first + count; ++k) {
        float v[9];
        uint id = clvis_instance_triangle(tris + k, xi, v);
        clvis_vec3 a = {v[0], v[1], v[2]}, b = {v[3], v[4], v[5]}, c = {v[6], v[7], v[8]};
        clvis_raster_rule_keys(cam, faces, a, b, c, id, blk, best);
    }
    uint depth[CLVIS_PACKET];
    for (int l = 0; l < CLVIS_PACKET; ++l) depth[l] = (uint)(best[l] >> 32);
    *cull = fmin((lanes_f)(cam.far_d), as_float16(vload16(0, depth)));
}
#endif

#ifndef CLVIS_RASTER_RULE
/* Tests the triangles of a leaf on every lane. */
static void packet_test_leaf(const packet* p, __global const clvis_bvh_tri* tris, uint first, uint count,
                             __global const clvis_instance* xi, clvis_camera_gpu cam, int faces, lanes_u* best_t,
                             lanes_u* best_id, lanes_f* cull)
{
    for (uint k = first; k < first + count; ++k) {
        float v[9];
        uint id = clvis_instance_triangle(tris + k, xi, v);
        packet_test_triangle(p, v, id, cam.near_d, cam.far_d, faces, best_t, best_id);
    }
    *cull = fmin((lanes_f)(cam.far_d), as_float16(*best_t)) * CLVIS_IZE_SCALE;
}
#endif

/* Traces the packet of pixels from (x0, y0) (in the image) and writes the keys of those inside
   `region` into its buffer (shared/region.h); `faces` is the cull mode (CLVIS_CULL_*). Stack
   entries name a child slot, (4-wide node << 2) | slot, so that a popped child is tested again
   against the hits found since it was pushed, with the instance it lies in (shared/instance.h:
   boxes and triangles tested in world space); `two_level` starts in the top level of `instances`. */
static void trace_packet(clvis_camera_gpu cam, clvis_region region, int x0, int y0, __global const clvis_bvh4_node* nodes,
                         uint node_count, __global const clvis_bvh_tri* tris, __global const clvis_instance* instances,
                         int two_level, int faces, __global ulong* keys)
{
    int x_end = region.x + region.width, y_end = region.y + region.height;
    packet p;
    make_packet(cam, x0, y0, &p);
#ifdef CLVIS_RASTER_RULE
    ulong best[CLVIS_PACKET];
    for (int l = 0; l < CLVIS_PACKET; ++l) best[l] = CLVIS_BACKGROUND_KEY;
    lanes_f cull = (lanes_f)(cam.far_d); /* each ray's nearest key depth, or far */
#define CLVIS_HITS_BOX(nd, k) packet_hits_box_rule(&p, cam, nd, k, xi, cull)
#define CLVIS_TEST_LEAF(nd, k) packet_rule_leaf(tris, nd->child[k], nd->count[k], xi, cam, faces, x0, y0, best, &cull)
#else
    lanes_u best_t = (lanes_u)(clvis_float_bits(CLVIS_INFINITY)), best_id = (lanes_u)(CLVIS_BACKGROUND_ID);
    /* each ray's far distance (far, or its nearest hit), scaled for the conservative slab test */
    lanes_f cull = (lanes_f)(cam.far_d * CLVIS_IZE_SCALE);
#define CLVIS_HITS_BOX(nd, k) packet_hits_box(&p, nd, k, xi, cam.near_d, cull)
#define CLVIS_TEST_LEAF(nd, k) \
    packet_test_leaf(&p, tris, nd->child[k], nd->count[k], xi, cam, faces, &best_t, &best_id, &cull)
#endif
#define CLVIS_OPEN_LEAF(nd, k)                                                                            \
    if (inst == CLVIS_INST_TOP) node = clvis_enter_instances(nd, k, instances, stack, stack_inst, &sp, &inst, &xi); \
    else CLVIS_TEST_LEAF(nd, k)

    uint stack[CLVIS_RAY_STACK], stack_inst[CLVIS_RAY_STACK];
    uint sp = 0, node = node_count > 0 ? 0u : CLVIS_RAY_NONE;
    uint inst = two_level ? CLVIS_INST_TOP : CLVIS_INST_FLAT;
    __global const clvis_instance* xi = 0; /* instance `inst`, or none at the top level and in the flat tree */
    for (;;) {
        if (node != CLVIS_RAY_NONE) {
            __global const clvis_bvh4_node* nd = nodes + node;
            /* The children some ray meets, nearest first by their box centres along a central ray. */
            uint order[4];
            float along[4];
            uint hits = 0;
            /* the four children's masks as bits 0-3 of each lane, then one reduction for all */
            int child_bits = or_lanes((CLVIS_HITS_BOX(nd, 0) & 1) | (CLVIS_HITS_BOX(nd, 1) & 2) |
                                      (CLVIS_HITS_BOX(nd, 2) & 4) | (CLVIS_HITS_BOX(nd, 3) & 8));
            for (int k = 0; k < 4; ++k) {
                if (!(child_bits & (1 << k))) continue;
                float d = (nd->lo_x[k] + nd->hi_x[k]) * p.cx + (nd->lo_y[k] + nd->hi_y[k]) * p.cy +
                          (nd->lo_z[k] + nd->hi_z[k]) * p.cz;
                clvis_insert_child(order, along, &hits, (uint)k, d);
            }
            node = CLVIS_RAY_NONE;
            if (hits > 0) {
                for (uint i = hits - 1; i > 0; --i, ++sp)
                    stack_inst[sp] = inst, stack[sp] = (uint)(nd - nodes) << 2 | order[i];
                uint k = order[0];
                if (nd->count[k] > 0) { CLVIS_OPEN_LEAF(nd, k); }
                else node = nd->child[k];
            }
        }
        /* Pop the next child that some ray may still reach before its nearest hit. */
        while (node == CLVIS_RAY_NONE && sp > 0) {
            uint e = stack[--sp];
            inst = stack_inst[sp];
            xi = inst < CLVIS_INST_TOP ? instances + inst : 0;
            if (e == CLVIS_ENTER_INSTANCE) { node = clvis_enter_instance(instances, inst, &inst, &xi); break; }
            __global const clvis_bvh4_node* nd = nodes + (e >> 2);
            uint k = e & 3;
            if (or_lanes(CLVIS_HITS_BOX(nd, (int)k)) >= 0) continue; /* no lane's sign bit */
            if (nd->count[k] > 0) { CLVIS_OPEN_LEAF(nd, k); }
            else node = nd->child[k];
        }
        if (node == CLVIS_RAY_NONE) break;
    }

#undef CLVIS_HITS_BOX
#undef CLVIS_TEST_LEAF
#undef CLVIS_OPEN_LEAF
#ifndef CLVIS_RASTER_RULE
    uint t_bits[CLVIS_PACKET], ids[CLVIS_PACKET];
    vstore16(best_t, 0, t_bits);
    vstore16(best_id, 0, ids);
    ulong best[CLVIS_PACKET];
    for (int l = 0; l < CLVIS_PACKET; ++l) best[l] = ((ulong)t_bits[l] << 32) | ids[l];
#endif
    for (int l = 0; l < CLVIS_PACKET; ++l) {
        int x = x0 + l % CLVIS_PACKET_W, y = y0 + l / CLVIS_PACKET_W;
        if (x < x_end && y < y_end)
            keys[(((size_t)(y - region.y) * region.width + (x - region.x)) << cam.sample_log2) + cam.sample] = best[l];
    }
}

__kernel void ray_trace(clvis_camera_gpu cam, __global const clvis_bvh4_node* nodes, uint node_count,
                        __global const clvis_bvh_tri* tris, int faces, __global ulong* keys, clvis_region region,
                        __global const clvis_instance* instances, int two_level)
{
    /* Packets start at the region's corner; each lane's ray is its own pixel's. */
    int x0 = region.x + (int)get_global_id(0) * CLVIS_PACKET_W, y0 = region.y + (int)get_global_id(1) * CLVIS_PACKET_H;
    if (x0 >= region.x + region.width || y0 >= region.y + region.height) return; /* the launch is rounded up */
    trace_packet(cam, region, x0, y0, nodes, node_count, tris, instances, two_level, faces, keys);
}

/* Many views in one launch: the third dimension is the view, whose keys start `stride` keys after
   the previous view's. Each view gets the bits ray_trace gives it alone (the same function). */
__kernel void ray_trace_views(__global const clvis_camera_gpu* cams, __global const clvis_bvh4_node* nodes,
                              uint node_count, __global const clvis_bvh_tri* tris, int faces, __global ulong* keys,
                              ulong stride, __global const clvis_instance* instances, int two_level)
{
    size_t view = get_global_id(2);
    clvis_camera_gpu cam = cams[view];
    int x0 = (int)get_global_id(0) * CLVIS_PACKET_W, y0 = (int)get_global_id(1) * CLVIS_PACKET_H;
    if (x0 >= cam.width || y0 >= cam.height) return;
    clvis_region whole = {0, 0, cam.width, cam.height};
    trace_packet(cam, whole, x0, y0, nodes, node_count, tris, instances, two_level, faces, keys + view * stride);
}
