/* a b - c d for floats, exactly rounded: the float nearest the exact value (ties to even), so its
   sign is exact and it is zero only when the exact value is. The ray path's edge functions fall
   back to it where their float form rounds to zero (shared/ray.h). Two forms give the same bits:
   - clvis_exact_dp_double: the products in double (exact: 24-bit significands), their difference
     rounded to odd (TwoSum's error decides the last bit), then to float: rounding to odd at
     53 >= 24 + 2 bits and then to nearest is the single rounding to nearest.
   - clvis_exact_dp_int: float-only devices (no cl_khr_fp64), or any device built with
     CLVIS_EXACT_FLOAT: the significands' 48-bit integer products, aligned in 64-bit integers (a
     product more than 14 binades below the other only sets a sticky bit, which cannot move a
     rounding at least 36 bits above it), rounded to nearest even at 24 bits or at the
     subnormal quantum, scaled by powers of two (exact).
   Non-finite inputs give a b - c d in float: not finite, as in double. A value of magnitude at
   most 2^-150 rounds to zero (underflow), in both forms. */
#ifndef CLVIS_SHARED_EXACT_H
#define CLVIS_SHARED_EXACT_H

#include "shared/types.h"

/* 2^k as a float, k in [-126, 127]. */
static inline float clvis_pow2f(int k) { return clvis_bits_float((clvis_u32)(k + 127) << 23); }

/* Leading zeros of a 32- and a 64-bit word (the width for 0). No loops here: Mesa's llvmpipe ends
   every loop of a work-item after 65535 passes in all, and this runs inside the ray loops. */
#ifdef __OPENCL_C_VERSION__
static inline int clvis_clz32(clvis_u32 m) { return (int)clz(m); }
static inline int clvis_clz64(clvis_u64 m) { return (int)clz(m); }
#else
static inline int clvis_clz32(clvis_u32 m) { return m ? __builtin_clz(m) : 32; }
static inline int clvis_clz64(clvis_u64 m) { return m ? __builtin_clzll(m) : 64; }
#endif

/* x 2^k for an x >= 1 below 2^25 whose result is representable, or overflows or underflows to 0:
   exact, in steps that never round (going up, every step is below the result; going down, above
   it). Two steps each way reach every representable result (k in [-173, 127]); beyond, the result
   is 0 or infinite whatever the last factor. */
static inline float clvis_scale2f(float x, int k)
{
    if (k > 127) {
        x = x * clvis_pow2f(127);
        k -= 127;
    }
    if (k > 127) {
        x = x * clvis_pow2f(127);
        k -= 127;
    }
    if (k < -126) {
        x = x * clvis_pow2f(-126);
        k += 126;
    }
    if (k < -126) {
        x = x * clvis_pow2f(-126);
        k += 126;
    }
    k = k > 127 ? 127 : (k < -126 ? -126 : k);
    return x * clvis_pow2f(k);
}

/* A finite float as sign, integer significand and exponent, v = (-1)^s m 2^e, the significand
   normalised to [2^23, 2^24) (subnormals too) or 0. */
typedef struct { clvis_u32 s, m; int e; } clvis_float_parts;

static inline clvis_float_parts clvis_parts(float v)
{
    clvis_u32 b = clvis_float_bits(v), ex = (b >> 23) & 0xFFu;
    clvis_float_parts p;
    p.s = b >> 31;
    p.m = ex == 0u ? (b & 0x7FFFFFu) : ((b & 0x7FFFFFu) | 0x800000u);
    p.e = ex == 0u ? -149 : (int)ex - 150;
    if (p.m != 0u && p.m < 0x800000u) { /* a subnormal: bit 23 is the ninth from the top */
        int shift = clvis_clz32(p.m) - 8;
        p.m <<= shift;
        p.e -= shift;
    }
    return p;
}

/* Bits of m (m > 0): 64 - count of leading zeros. */
static inline int clvis_bit_length(clvis_u64 m) { return 64 - clvis_clz64(m); }

static inline int clvis_finite_bits(float v) { return (clvis_float_bits(v) & 0x7F800000u) != 0x7F800000u; }

/* (-1)^neg m 2^e rounded to the nearest float, ties to even (subnormals and overflow included). */
static inline float clvis_round_scaled(int neg, clvis_u64 m, int e)
{
    int g = clvis_bit_length(m) - 24; /* bits to drop: above 24 significant ones ... */
    if (-149 - e > g) g = -149 - e;   /* ... or below the smallest subnormal's */
    if (g > 63) return neg ? -0.0f : 0.0f; /* m 2^e < 2^(e + 63) <= 2^-150: half the smallest */
    if (g > 0) {
        clvis_u64 rem = m & ((((clvis_u64)1) << g) - 1u), mid = ((clvis_u64)1) << (g - 1);
        m >>= g;
        if (rem > mid || (rem == mid && (m & 1u))) m += 1u;
        e += g;
    }
    float r = clvis_scale2f((float)m, e); /* m <= 2^24: exact */
    return neg ? -r : r;
}

static inline float clvis_exact_dp_int(float a, float b, float c, float d)
{
    if (!clvis_finite_bits(a) || !clvis_finite_bits(b) || !clvis_finite_bits(c) || !clvis_finite_bits(d))
        return a * b - c * d;
    clvis_float_parts pa = clvis_parts(a), pb = clvis_parts(b), pc = clvis_parts(c), pd = clvis_parts(d);
    /* D = (-1)^s1 m1 2^e1 + (-1)^s2 m2 2^e2: a b and the negated c d */
    clvis_u64 m1 = (clvis_u64)pa.m * (clvis_u64)pb.m, m2 = (clvis_u64)pc.m * (clvis_u64)pd.m;
    clvis_u32 s1 = pa.s ^ pb.s, s2 = pc.s ^ pd.s ^ 1u;
    int e1 = pa.e + pb.e, e2 = pc.e + pd.e;
    if (m1 == 0u && m2 == 0u) return (s1 && s2) ? -0.0f : 0.0f; /* IEEE: -0 - +0 = -0, else +0 */
    if (m1 == 0u || (m2 != 0u && e2 > e1)) { /* the larger binade first */
        clvis_u64 tm = m1; m1 = m2; m2 = tm;
        clvis_u32 ts = s1; s1 = s2; s2 = ts;
        int te = e1; e1 = e2; e2 = te;
    }
    int shift = e1 - e2, e = e2;
    clvis_u64 t = m2;
    if (m2 == 0u) {
        shift = 0;
        e = e1;
    } else if (shift > 14) { /* m2's bits below 2^(e1 - 14) only as a sticky bit */
        int k = shift - 14;
        t = k >= 64 ? 1u : (m2 >> k) | (clvis_u64)((m2 & ((((clvis_u64)1) << k) - 1u)) != 0u);
        shift = 14;
        e = e1 - 14;
    }
    clvis_i64 n1 = (clvis_i64)(m1 << shift), n2 = (clvis_i64)t;
    clvis_i64 n = (s1 ? -n1 : n1) + (s2 ? -n2 : n2);
    if (n == 0) return 0.0f; /* an exact cancellation: +0, as IEEE rounds it */
    return n < 0 ? clvis_round_scaled(1, (clvis_u64)(-n), e) : clvis_round_scaled(0, (clvis_u64)n, e);
}

#ifdef CLVIS_HAVE_DOUBLE
#ifdef __OPENCL_C_VERSION__
static inline clvis_i64 clvis_double_bits(double v) { return as_long(v); }
static inline double clvis_bits_double(clvis_i64 b) { return as_double(b); }
#else
static inline clvis_i64 clvis_double_bits(double v) { clvis_i64 b; std::memcpy(&b, &v, 8); return b; }
static inline double clvis_bits_double(clvis_i64 b) { double v; std::memcpy(&v, &b, 8); return v; }
#endif

static inline float clvis_exact_dp_double(float a, float b, float c, float d)
{
    double p = (double)a * (double)b, q = -((double)c * (double)d); /* exact */
    double r = p + q;
    double bq = r - p; /* TwoSum: r + err == p + q exactly */
    double err = (p - (r - bq)) + (q - bq);
    /* round to odd: an inexact r with an even last bit moves one ulp towards the exact value */
    if (r - r == 0.0 && err != 0.0 && (clvis_double_bits(r) & 1) == 0)
        r = clvis_bits_double(clvis_double_bits(r) + ((err > 0.0) == (r > 0.0) ? 1 : -1));
    return (float)r;
}
#endif

#endif
