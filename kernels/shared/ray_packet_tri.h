/* The watertight triangle test on the 16 rays of a packet (OpenCL C only: vector types): the
   operations of the scalar clvis_intersect_triangle (shared/ray.h) on every lane, so each lane
   gets the bits the scalar test gives its ray, and a leaf's triangles tested in turn. */
#ifndef CLVIS_SHARED_RAY_PACKET_TRI_H
#define CLVIS_SHARED_RAY_PACKET_TRI_H

#include "shared/ray_packet.h"

static lanes_f permuted(float x, float y, float z, lanes_i k0, lanes_i k1)
{
    return select(select((lanes_f)(z), (lanes_f)(y), k1), (lanes_f)(x), k0);
}

typedef struct { lanes_f u, v, w, det, tz; } packet_edges;

/* The scalar code's exact fallback (clvis_exact_edges), lane by lane, on the lanes where an edge
   function rounded to zero. It is rare and kept out of line, so that packet_edges_of, free of its
   arrays, is inlined into every triangle's test. */
static CLVIS_NOINLINE packet_edges packet_exact_edges(packet_edges r, lanes_i zero, lanes_f ax, lanes_f ay,
                                                      lanes_f bx, lanes_f by, lanes_f cx, lanes_f cy)
{
    float l_ax[CLVIS_PACKET], l_ay[CLVIS_PACKET], l_bx[CLVIS_PACKET], l_by[CLVIS_PACKET], l_cx[CLVIS_PACKET];
    float l_cy[CLVIS_PACKET], l_u[CLVIS_PACKET], l_v[CLVIS_PACKET], l_w[CLVIS_PACKET];
    int l_zero[CLVIS_PACKET];
    vstore16(ax, 0, l_ax); vstore16(ay, 0, l_ay); vstore16(bx, 0, l_bx);
    vstore16(by, 0, l_by); vstore16(cx, 0, l_cx); vstore16(cy, 0, l_cy);
    vstore16(r.u, 0, l_u); vstore16(r.v, 0, l_v); vstore16(r.w, 0, l_w);
    vstore16(zero, 0, l_zero);
    for (int l = 0; l < CLVIS_PACKET; ++l)
        if (l_zero[l]) clvis_exact_edges(&l_u[l], &l_v[l], &l_w[l], l_ax[l], l_ay[l], l_bx[l], l_by[l], l_cx[l], l_cy[l]);
    r.u = vload16(0, l_u);
    r.v = vload16(0, l_v);
    r.w = vload16(0, l_w);
    return r;
}

/* clvis_ray_edges_of on every lane: the shear, the edge functions (with the exact recompute on
   the lanes where one rounded to zero: one OR of the lanes decides), det and tz. The results go
   out by pointers to the caller's vectors, one each: inlined at its one call, they stay in
   registers, where a struct written through a pointer (or returned: sret, an intrinsic that
   Oclgrind 21.10 cannot run, clvis_project_triangle in shared/ray.h) was copied by a call to
   memcpy per triangle on PoCL. Only the rare fallback fills a struct. */
static void packet_edges_of(const packet* p, lanes_f akx, lanes_f aky, lanes_f akz, lanes_f bkx, lanes_f bky,
                            lanes_f bkz, lanes_f ckx, lanes_f cky, lanes_f ckz, lanes_f* u_out, lanes_f* v_out,
                            lanes_f* w_out, lanes_f* det_out, lanes_f* tz_out)
{
    lanes_f ax = akx - p->sx * akz;
    lanes_f ay = aky - p->sy * akz;
    lanes_f bx = bkx - p->sx * bkz;
    lanes_f by = bky - p->sy * bkz;
    lanes_f cx = ckx - p->sx * ckz;
    lanes_f cy = cky - p->sy * ckz;
    lanes_f u = cx * by - cy * bx;
    lanes_f v = ax * cy - ay * cx;
    lanes_f w = bx * ay - by * ax;
    lanes_i zero = (u == 0.0f) | (v == 0.0f) | (w == 0.0f);
    if (any_lane(zero)) {
        packet_edges r;
        r.u = u;
        r.v = v;
        r.w = w;
        r = packet_exact_edges(r, zero, ax, ay, bx, by, cx, cy);
        u = r.u;
        v = r.v;
        w = r.w;
    }
    *u_out = u;
    *v_out = v;
    *w_out = w;
    *det_out = u + v + w;
    *tz_out = u * (p->sz * akz) + v * (p->sz * bkz) + w * (p->sz * ckz);
}

/* Lanes where the edge functions do not take both signs. (Masks come only from comparisons, never
   from ~, so every lane is 0 or -1 on every implementation.) */
static lanes_i not_outside(lanes_f u, lanes_f v, lanes_f w)
{
    return ((u >= 0.0f) & (v >= 0.0f) & (w >= 0.0f)) | ((u <= 0.0f) & (v <= 0.0f) & (w <= 0.0f));
}

/* clvis_ray_trusted on every lane, from the vertices minus each lane's origin. */
static lanes_i packet_trusted(lanes_f akx, lanes_f aky, lanes_f akz, lanes_f bkx, lanes_f bky, lanes_f bkz,
                              lanes_f ckx, lanes_f cky, lanes_f ckz)
{
    lanes_f lx = select(akx, bkx, bkx < akx), hx = select(akx, bkx, bkx > akx);
    lanes_f ly = select(aky, bky, bky < aky), hy = select(aky, bky, bky > aky);
    lanes_f lz = select(akz, bkz, bkz < akz), hz = select(akz, bkz, bkz > akz);
    lx = select(lx, ckx, ckx < lx); hx = select(hx, ckx, ckx > hx);
    ly = select(ly, cky, cky < ly); hy = select(hy, cky, cky > hy);
    lz = select(lz, ckz, ckz < lz); hz = select(hz, ckz, ckz > hz);
    lanes_f gx = select(-hx, lx, lx > -hx), gy = select(-hy, ly, ly > -hy), gz = select(-hz, lz, lz > -hz);
    lanes_f gap = select(gx, gy, gy > gx);
    gap = select(gap, gz, gz > gap);
    lanes_f mx = select(hx, -lx, -lx > hx), my = select(hy, -ly, -ly > hy), mz = select(hz, -lz, -lz > hz);
    lanes_f m = select(mx, my, my > mx);
    m = select(m, mz, mz > m);
    return m <= CLVIS_RAY_RANGE * gap;
}

/* The lanes in `wide` tested as the scalar test does there (clvis_project_triangle_wide on each
   lane's ray): their edge functions and plane parameter replace r's. Rare: out of line. */
static CLVIS_NOINLINE packet_edges packet_wide(const packet* p, const float* vert, lanes_i wide, packet_edges r,
                                               lanes_f* t)
{
    float l_ox[CLVIS_PACKET], l_oy[CLVIS_PACKET], l_oz[CLVIS_PACKET], l_sx[CLVIS_PACKET], l_sy[CLVIS_PACKET];
    float l_sz[CLVIS_PACKET], l_u[CLVIS_PACKET], l_v[CLVIS_PACKET], l_w[CLVIS_PACKET], l_t[CLVIS_PACKET];
    int l_wide[CLVIS_PACKET], l_kx0[CLVIS_PACKET], l_kx1[CLVIS_PACKET], l_ky0[CLVIS_PACKET], l_ky1[CLVIS_PACKET];
    int l_kz0[CLVIS_PACKET], l_kz1[CLVIS_PACKET];
    vstore16(p->ox, 0, l_ox); vstore16(p->oy, 0, l_oy); vstore16(p->oz, 0, l_oz);
    vstore16(p->sx, 0, l_sx); vstore16(p->sy, 0, l_sy); vstore16(p->sz, 0, l_sz);
    vstore16(r.u, 0, l_u); vstore16(r.v, 0, l_v); vstore16(r.w, 0, l_w); vstore16(*t, 0, l_t);
    vstore16(wide, 0, l_wide);
    vstore16(p->kx0, 0, l_kx0); vstore16(p->kx1, 0, l_kx1); vstore16(p->ky0, 0, l_ky0);
    vstore16(p->ky1, 0, l_ky1); vstore16(p->kz0, 0, l_kz0); vstore16(p->kz1, 0, l_kz1);
    clvis_vec3 a = {vert[0], vert[1], vert[2]}, b = {vert[3], vert[4], vert[5]}, c = {vert[6], vert[7], vert[8]};
    for (int l = 0; l < CLVIS_PACKET; ++l) {
        if (!l_wide[l]) continue;
        clvis_ray_shear s;
        s.origin.x = l_ox[l];
        s.origin.y = l_oy[l];
        s.origin.z = l_oz[l];
        s.sx = l_sx[l];
        s.sy = l_sy[l];
        s.sz = l_sz[l];
        s.kx = l_kx0[l] ? 0 : (l_kx1[l] ? 1 : 2);
        s.ky = l_ky0[l] ? 0 : (l_ky1[l] ? 1 : 2);
        s.kz = l_kz0[l] ? 0 : (l_kz1[l] ? 1 : 2);
        clvis_tri_2d q = clvis_project_triangle_wide(s, a, b, c);
        l_u[l] = q.u;
        l_v[l] = q.v;
        l_w[l] = q.w;
        l_t[l] = q.t;
    }
    r.u = vload16(0, l_u);
    r.v = vload16(0, l_v);
    r.w = vload16(0, l_w);
    r.det = r.u + r.v + r.w;
    *t = vload16(0, l_t);
    return r;
}

/* clvis_intersect_triangle on every lane (culling by `faces`, CLVIS_CULL_*), keeping each lane's
   nearest key (t bits, then id). The vertices are permuted to each lane's shear axes and the lane's permuted origin subtracted: the
   same single subtraction as the scalar test, whichever comes first. */
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
/* Depth layers (shared/layers.h): each lane's K nearest keys, sorted, in `lists` (layer k of lane
   l at lists[k * CLVIS_PACKET + l]); best_t and best_id then hold each lane's K-th key, what the
   walk prunes against (the background until K are found). */
#include "shared/layers.h"
#define CLVIS_PACKET_LISTS_PARAM , ulong* lists
#define CLVIS_PACKET_LISTS_ARG , lists
#else
#define CLVIS_PACKET_LISTS_PARAM
#define CLVIS_PACKET_LISTS_ARG
#endif

static void packet_test_triangle(const packet* p, const float* vert, uint tri_id, float near_t, float far_t,
                                 int faces, lanes_u* best_t, lanes_u* best_id CLVIS_PACKET_LISTS_PARAM)
{
    lanes_f akx, aky, akz, bkx, bky, bkz, ckx, cky, ckz;
    lanes_i trusted;
    if (p->common_origin) {
        /* vertex minus origin once for all lanes: the same subtraction, done in scalar */
        float sa[3] = {vert[p->ukx] - p->uox, vert[p->uky] - p->uoy, vert[p->ukz] - p->uoz};
        float sb[3] = {vert[3 + p->ukx] - p->uox, vert[3 + p->uky] - p->uoy, vert[3 + p->ukz] - p->uoz};
        float sc[3] = {vert[6 + p->ukx] - p->uox, vert[6 + p->uky] - p->uoy, vert[6 + p->ukz] - p->uoz};
        clvis_vec3 A = {sa[0], sa[1], sa[2]}, B = {sb[0], sb[1], sb[2]}, C = {sc[0], sc[1], sc[2]};
        trusted = (lanes_i)(clvis_ray_trusted(A, B, C) ? -1 : 0);
        akx = (lanes_f)(sa[0]);
        aky = (lanes_f)(sa[1]);
        akz = (lanes_f)(sa[2]);
        bkx = (lanes_f)(sb[0]);
        bky = (lanes_f)(sb[1]);
        bkz = (lanes_f)(sb[2]);
        ckx = (lanes_f)(sc[0]);
        cky = (lanes_f)(sc[1]);
        ckz = (lanes_f)(sc[2]);
    } else {
        if (p->uniform) {
            akx = (lanes_f)(vert[p->ukx]) - p->px;
            aky = (lanes_f)(vert[p->uky]) - p->py;
            akz = (lanes_f)(vert[p->ukz]) - p->pz;
            bkx = (lanes_f)(vert[3 + p->ukx]) - p->px;
            bky = (lanes_f)(vert[3 + p->uky]) - p->py;
            bkz = (lanes_f)(vert[3 + p->ukz]) - p->pz;
            ckx = (lanes_f)(vert[6 + p->ukx]) - p->px;
            cky = (lanes_f)(vert[6 + p->uky]) - p->py;
            ckz = (lanes_f)(vert[6 + p->ukz]) - p->pz;
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
        trusted = packet_trusted(akx, aky, akz, bkx, bky, bkz, ckx, cky, ckz);
    }
    lanes_f u, v, w, det, tz;
    packet_edges_of(p, akx, aky, akz, bkx, bky, bkz, ckx, cky, ckz, &u, &v, &w, &det, &tz);
    /* clvis_project_triangle's wide retest: where the float test cannot be trusted, or huge
       finite coordinates overflowed */
    lanes_i wide = (trusted == 0) | not_finite(det) | not_finite(tz);
    lanes_i inside = not_outside(u, v, w);
    /* The division on every lane, without first asking whether some lane is inside: whether one
       is varies from triangle to triangle, and the mispredicted branch cost more than the
       division (bunny 256x256: 8% of the frame). A lane outside keeps its key (hit below). */
    lanes_f t = tz / det;
    if (any_lane(wide)) { /* rare: through a struct and a copy of t, so that u .. t stay in registers */
        packet_edges r;
        r.u = u;
        r.v = v;
        r.w = w;
        r.det = det;
        r.tz = tz;
        lanes_f t_wide = t;
        r = packet_wide(p, vert, wide, r, &t_wide);
        t = t_wide;
        u = r.u;
        v = r.v;
        w = r.w;
        det = r.det;
        inside = not_outside(u, v, w);
    }
    lanes_i hit = inside & (det != 0.0f) & (t >= near_t) & (t <= far_t);
    if (faces == CLVIS_CULL_BACK) hit &= det > 0.0f; /* clvis_cull_keeps on every lane */
    else if (faces == CLVIS_CULL_FRONT) hit &= det < 0.0f;
    lanes_u bits = as_uint16(t), id = (lanes_u)(tri_id);
    lanes_i nearer = hit & ((bits < *best_t) | ((bits == *best_t) & (id < *best_id)));
#if defined(CLVIS_LAYERS) && CLVIS_LAYERS > 1
    if (!or_lanes(nearer)) return; /* no lane's K-th key is beaten: no list changes */
    uint tb[CLVIS_PACKET], kt[CLVIS_PACKET], kid[CLVIS_PACKET];
    int take[CLVIS_PACKET];
    vstore16(bits, 0, tb);
    vstore16(nearer, 0, take);
    vstore16(*best_t, 0, kt);
    vstore16(*best_id, 0, kid);
    for (int l = 0; l < CLVIS_PACKET; ++l) {
        if (!take[l]) continue;
        clvis_layers_insert(lists + l, CLVIS_PACKET, ((ulong)tb[l] << 32) | (ulong)tri_id);
        ulong last = lists[(CLVIS_LAYERS - 1) * CLVIS_PACKET + l];
        kt[l] = (uint)(last >> 32);
        kid[l] = (uint)last;
    }
    *best_t = vload16(0, kt);
    *best_id = vload16(0, kid);
    return;
#endif
    *best_t = select(*best_t, bits, nearer);
    *best_id = select(*best_id, id, nearer);
}

/* Tests the triangles of a leaf on every lane, hits between the view depths near_d and far_d. (Two
   floats, not the camera: out of line, a struct argument is copied at every call.) Kept out of
   line: ray_trace.cl's walk (shared/bvh_walk.h) calls it from both its variants, and the compiler
   would inline it at each, a much larger kernel. */
static CLVIS_NOINLINE void packet_test_leaf(const packet* p, __global const clvis_bvh_tri* tris, uint first, uint count,
                             __global const clvis_instance* xi, float near_d, float far_d, int faces, lanes_u* best_t,
                             lanes_u* best_id, lanes_f* cull CLVIS_PACKET_LISTS_PARAM)
{
    for (uint k = first; k < first + count; ++k) {
        float v[9];
        uint id = clvis_instance_triangle(tris + k, xi, v);
        packet_test_triangle(p, v, id, near_d, far_d, faces, best_t, best_id CLVIS_PACKET_LISTS_ARG);
    }
    *cull = fmin((lanes_f)(far_d), as_float16(*best_t)) * CLVIS_IZE_SCALE;
}

#endif
