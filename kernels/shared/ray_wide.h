/* The wide retest of the watertight triangle test, part of shared/ray.h (which includes this
   file where its projection is defined, and is what the kernels and tests include). */
#ifndef CLVIS_SHARED_RAY_WIDE_H
#define CLVIS_SHARED_RAY_WIDE_H

/* Triangle (a, b, c) against the ray in wider arithmetic, for the triangles the float test cannot
   be trusted with (clvis_ray_trusted): every coordinate scaled by clvis_ray_scale of the largest
   magnitude (a power of two: exact, and nothing overflows in float), the vertices translated per
   axis (no axis mixed into another before the products: a small coordinate beside huge ones
   keeps its bits), the edge functions as triple products with the sheared direction
   (sx, sy, 1), exactly the float form's u = cx by - cy bx expanded, and the plane's ray parameter
   from its normal, N.A / N.D, which does not cancel the way the float form's sum of u akz, v bkz
   and w ckz does when the vertices lie far beyond the hit. In double where the device has it
   (rounding 2^-53 relative to each product), else in float. Each edge function is antisymmetric
   bit for bit in its two vertices, so two such triangles sharing an edge stay watertight. The
   edge functions come back divided by the largest of them (their signs and ratios, the
   barycentrics, kept; float cannot hold their magnitudes). Out of line, by value: it is rare. */
#if defined(CLVIS_HAVE_DOUBLE)
typedef double clvis_wide;
#else
typedef float clvis_wide;
#endif

static inline clvis_wide clvis_wide_edge(clvis_wide sx, clvis_wide sy, const clvis_wide* B, const clvis_wide* C)
{
    return sx * (C[1] * B[2] - C[2] * B[1]) + sy * (C[2] * B[0] - C[0] * B[2]) + (C[0] * B[1] - C[1] * B[0]);
}

static inline clvis_wide clvis_wide_abs(clvis_wide x) { return x < 0 ? -x : x; }

/* The scale of clvis_project_triangle_wide: clvis_ray_scale of the largest magnitude among the
   vertices' and the origin's coordinates. */
static inline float clvis_wide_scale(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b, clvis_vec3 c)
{
    float m = clvis_max_abs3(a), mb = clvis_max_abs3(b), mc = clvis_max_abs3(c), mo = clvis_max_abs3(s.origin);
    m = m > mb ? m : mb;
    m = m > mc ? m : mc;
    m = m > mo ? m : mo;
    return clvis_ray_scale(m);
}

/* The wide arithmetic of clvis_project_triangle_wide on p, the triangle projected with the scale k
   (clvis_project_triangle_scaled): the edge functions and the plane's parameter replaced. */
static inline CLVIS_ALWAYS_INLINE void clvis_wide_retest(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b,
                                                         clvis_vec3 c, float k, clvis_tri_2d* out)
{
    clvis_tri_2d p = *out;
    clvis_vec3 v[3] = {a, b, c};
    clvis_wide P[3][3], Q[3][3], o[3];
    clvis_i32 axis[3] = {s.kx, s.ky, s.kz};
    for (int j = 0; j < 3; ++j) o[j] = (clvis_wide)(clvis_component(s.origin, axis[j]) * k);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            Q[i][j] = (clvis_wide)(clvis_component(v[i], axis[j]) * k); /* the scaled vertex */
            P[i][j] = Q[i][j] - o[j];                                   /* minus the origin */
        }
    clvis_wide sx = (clvis_wide)s.sx, sy = (clvis_wide)s.sy;
    clvis_wide u = clvis_wide_edge(sx, sy, P[1], P[2]), vv = clvis_wide_edge(sx, sy, P[2], P[0]);
    clvis_wide w = clvis_wide_edge(sx, sy, P[0], P[1]);
    /* the plane: N = (q1 - q0) x (q2 - q0), the hit at N.P0 / N.D along D = (sx, sy, 1), from the
       vertex q0 nearest the origin (the others may lie far beyond the hit: N.P0 cancels least) */
    int i0 = 0;
    clvis_wide near0 = -1;
    for (int i = 0; i < 3; ++i) {
        clvis_wide mi = clvis_wide_abs(P[i][0]);
        mi = clvis_wide_abs(P[i][1]) > mi ? clvis_wide_abs(P[i][1]) : mi;
        mi = clvis_wide_abs(P[i][2]) > mi ? clvis_wide_abs(P[i][2]) : mi;
        if (near0 < 0 || mi < near0) {
            near0 = mi;
            i0 = i;
        }
    }
    int i1 = i0 == 2 ? 0 : i0 + 1, i2 = i1 == 2 ? 0 : i1 + 1;
    clvis_wide e1[3], e2[3];
    for (int j = 0; j < 3; ++j) {
        e1[j] = Q[i1][j] - Q[i0][j];
        e2[j] = Q[i2][j] - Q[i0][j];
    }
    clvis_wide nx = e1[1] * e2[2] - e1[2] * e2[1], ny = e1[2] * e2[0] - e1[0] * e2[2];
    clvis_wide nz = e1[0] * e2[1] - e1[1] * e2[0];
    clvis_wide na = nx * P[i0][0] + ny * P[i0][1] + nz * P[i0][2], nd = nx * sx + ny * sy + nz;
    p.t = (float)(na / nd * (clvis_wide)s.sz / (clvis_wide)k);
    clvis_wide big = clvis_wide_abs(u);
    big = clvis_wide_abs(vv) > big ? clvis_wide_abs(vv) : big;
    big = clvis_wide_abs(w) > big ? clvis_wide_abs(w) : big;
    if (big > 0) {
        u /= big;
        vv /= big;
        w /= big;
    }
    p.u = (float)u;
    p.v = (float)vv;
    p.w = (float)w;
    p.wide = 1;
    *out = p;
}

static inline CLVIS_NOINLINE clvis_tri_2d clvis_project_triangle_wide(clvis_ray_shear s, clvis_vec3 a, clvis_vec3 b,
                                                               clvis_vec3 c)
{
    float k = clvis_wide_scale(s, a, b, c);
    clvis_tri_2d p;
    clvis_project_triangle_scaled(s, a, b, c, k, &p); /* the 2D positions, for clvis_edge_side */
    clvis_wide_retest(s, a, b, c, k, &p);
    return p;
}

/* clvis_project_triangle_wide given f, the triangle projected with scale 1: where the wide scale is
   1 too, f's 2D positions are the ones it would compute again (the same operations). */
static inline CLVIS_NOINLINE clvis_tri_2d clvis_project_triangle_wide_from(clvis_ray_shear s, clvis_vec3 a,
                                                                           clvis_vec3 b, clvis_vec3 c, clvis_tri_2d f)
{
    float k = clvis_wide_scale(s, a, b, c);
    clvis_tri_2d p = f;
    if (k != 1.0f) clvis_project_triangle_scaled(s, a, b, c, k, &p);
    clvis_wide_retest(s, a, b, c, k, &p);
    return p;
}

#endif
