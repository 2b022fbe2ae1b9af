// The exact fallback of the ray path's edge functions (kernels/shared/exact.h): a b - c d rounded
// once to the nearest float, in double (rounded to odd) and float-only (integers), bit for bit the
// same on near-cancelling, subnormal, overflowing and random inputs, with exact signs. The device
// side (CLVIS_EXACT_FLOAT=1 builds every kernel with the float-only form) is in ray_test.cpp.
#include "catch.hpp"

#include "shared/ray.h"

#include <cmath>
#include <cstring>
#include <random>

namespace {

std::uint32_t bits(float v)
{
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    return b;
}

/// The sign of a b - c d from exact integer arithmetic on the significands (long double holds the
/// products; their difference's sign is that of the comparison of the exact products).
int exact_sign(float a, float b, float c, float d)
{
    long double p = (long double)a * b, q = (long double)c * d; // 48-bit significands: exact
    return p > q ? 1 : (p < q ? -1 : 0);
}

/// Checks both forms agree bit for bit and have the exact sign; returns the value.
float check_forms(float a, float b, float c, float d)
{
    float fi = clvis_exact_dp_int(a, b, c, d), fd = clvis_exact_dp_double(a, b, c, d);
    INFO(std::hexfloat << a << " * " << b << " - " << c << " * " << d << ": int " << fi << ", double " << fd);
    REQUIRE(bits(fi) == bits(fd));
    // The sign is exact unless the value underflows: |a b - c d| <= 2^-150 rounds to zero.
    long double exact = (long double)a * b - (long double)c * d;
    if (std::fabs(exact) > 0x1p-150L || exact == 0)
        CHECK((fi > 0.0f ? 1 : (fi < 0.0f ? -1 : 0)) == exact_sign(a, b, c, d));
    return fi;
}

} // namespace

TEST_CASE("a b - c d rounds once: where double rounding would tie, the exact forms do not", "[ray]")
{
    // (1 + 2^-12)^2 = 1 + 2^-11 + 2^-24 is a float midpoint; plus 2^-80 it rounds up, while
    // rounding to double first lands on the midpoint and then ties to even (down).
    float a = 1.0f + 0x1p-12f, c = -0x1p-40f, d = 0x1p-40f;
    float naive = float(double(a) * double(a) - double(c) * double(d));
    CHECK(naive == 1.0f + 0x1p-11f);
    CHECK(check_forms(a, a, c, d) == 1.0f + 0x1p-11f + 0x1p-23f);
    CHECK(check_forms(a, a, -c, d) == 1.0f + 0x1p-11f); // minus 2^-80: down
    CHECK(check_forms(a, a, 0.0f, d) == 1.0f + 0x1p-11f); // the tie itself: to even
}

TEST_CASE("the float-only and double forms of a b - c d agree bit for bit", "[ray]")
{
    std::mt19937_64 rng(20261201);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_int_distribution<int> binade(-140, 120), small(-3, 3), ulps(-4, 4);
    auto any = [&] { return std::ldexp(unit(rng), binade(rng)); };
    // zeros, signed zeros, subnormals, overflow, exact cancellation
    const float specials[] = {0.0f, -0.0f, 0x1p-149f, -0x1p-149f, 0x1.8p-140f, 3e38f, -3e38f, 1.0f, -1.0f, 0x1p-75f};
    for (float a : specials)
        for (float b : specials)
            for (float c : specials)
                for (float d : specials) check_forms(a, b, c, d);
    CHECK(check_forms(3e38f, 3e38f, 1.0f, 1.0f) == INFINITY);
    CHECK(std::isnan(clvis_exact_dp_int(INFINITY, 0.0f, 1.0f, 1.0f)));
    for (int i = 0; i < 300000; ++i) {
        float a = any(), b = any(), c, d;
        switch (i % 4) {
        case 0: c = any(); d = any(); break;
        case 1: // c d within a few ulps of a b: cancellation
            c = std::nextafter(a, ulps(rng) > 0 ? INFINITY : -INFINITY);
            d = b + ulps(rng) * std::ldexp(std::fabs(b), -23);
            break;
        case 2: // the same products in another order, scaled by powers of two: exact zero
            c = std::ldexp(b, small(rng));
            d = std::ldexp(a, -small(rng));
            break;
        default: // products 10 to 60 binades apart: the sticky bit
            c = std::ldexp(a, -(i % 50) - 10);
            d = std::ldexp(b, small(rng));
            break;
        }
        check_forms(a, b, c, d);
    }
}
