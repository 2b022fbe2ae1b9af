// Procedural meshes for tests, examples and benchmarks: a closed UV sphere, a height-field grid
// and a triangle soup. Everything is computed with + - * / sqrt floor in double (IEEE, no FMA:
// the host builds with -ffp-contract=off) and rounded to float once, so the bits are the same on
// every machine: no libm sin/cos, no std::*_distribution.
#include <clvis/error.hpp>
#include <clvis/procedural.hpp>

#include <cmath>
#include <cstdint>
#include <string>

namespace clvis {

namespace {

constexpr double CLVIS_HALF_PI = 1.57079632679489661923;

/// sin and cos of (turns * 2 pi): the quadrant from floor, then Taylor series to x^23 on
/// [0, pi/2) (error below 1e-16), so the result does not depend on the C library.
void sin_cos_turns(double turns, double& s, double& c)
{
    double t = (turns - std::floor(turns)) * 4; // quarter turns in [0, 4)
    double q = std::floor(t);
    double x = (t - q) * CLVIS_HALF_PI;
    double x2 = x * x;
    double sx = 1, cx = 1;
    for (int n = 22; n >= 2; n -= 2) {
        sx = 1 - sx * x2 / double((n + 1) * n); // sin x / x = 1 - x^2/3! (1 - x^2/(4*5) (...))
        cx = 1 - cx * x2 / double(n * (n - 1));
    }
    sx *= x;
    switch (int(q) & 3) {
    case 0: s = sx; c = cx; break;
    case 1: s = cx; c = -sx; break;
    case 2: s = -sx; c = -cx; break;
    default: s = -cx; c = sx; break;
    }
}

double sin_turns(double turns)
{
    double s, c;
    sin_cos_turns(turns, s, c);
    return s;
}

/// splitmix64 (Steele, Lea, Flood): the same stream on every machine.
struct SplitMix64 {
    std::uint64_t state;
    std::uint64_t next()
    {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1), 53 bits.
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
};

void check_count(const char* function, std::size_t triangles)
{
    // A generous cap on requests: far past any device, well inside size_t arithmetic below.
    if (triangles > (std::size_t(1) << 31))
        throw Error(Error::Kind::InvalidArgument, std::string(function) + ": " + std::to_string(triangles) +
                                                      " triangles requested, at most 2^31 allowed");
}

void push(MeshData& m, double x, double y, double z)
{
    m.positions.push_back(float(x));
    m.positions.push_back(float(y));
    m.positions.push_back(float(z));
}

void push(MeshData& m, std::size_t a, std::size_t b, std::size_t c)
{
    m.indices.push_back(std::uint32_t(a));
    m.indices.push_back(std::uint32_t(b));
    m.indices.push_back(std::uint32_t(c));
}

} // namespace

MeshData make_uv_sphere(std::size_t triangles)
{
    check_count("make_uv_sphere", triangles);
    if (triangles < 8) triangles = 8;
    // stacks bands of latitude, segments around: 2 * segments * (stacks - 1) triangles; segments
    // about twice stacks keeps the quads square near the equator.
    double t = double(triangles);
    std::size_t stacks = std::size_t(std::floor((1 + std::sqrt(1 + t)) / 2 + 0.5));
    if (stacks < 2) stacks = 2;
    std::size_t segments = std::size_t(std::floor(t / double(2 * (stacks - 1)) + 0.5));
    if (segments < 4) segments = 4;

    MeshData m;
    m.name = "sphere";
    m.positions.reserve((2 + (stacks - 1) * segments) * 3);
    m.indices.reserve(2 * segments * (stacks - 1) * 3);
    push(m, 0.0, 1.0, 0.0); // north pole: vertex 0
    for (std::size_t i = 1; i < stacks; ++i) {
        double sin_theta, cos_theta;
        sin_cos_turns(double(i) / double(2 * stacks), sin_theta, cos_theta);
        for (std::size_t j = 0; j < segments; ++j) {
            double sin_phi, cos_phi;
            sin_cos_turns(double(j) / double(segments), sin_phi, cos_phi);
            push(m, sin_theta * cos_phi, cos_theta, sin_theta * sin_phi);
        }
    }
    std::size_t south = 1 + (stacks - 1) * segments;
    push(m, 0.0, -1.0, 0.0);

    // Ring i (1-based) vertex j; the seam wraps by index, so every edge is shared exactly.
    auto ring = [segments](std::size_t i, std::size_t j) { return 1 + (i - 1) * segments + j % segments; };
    // Winding: counter-clockwise seen from outside (outward normals).
    for (std::size_t j = 0; j < segments; ++j) push(m, 0, ring(1, j + 1), ring(1, j));
    for (std::size_t i = 1; i + 1 < stacks; ++i)
        for (std::size_t j = 0; j < segments; ++j) {
            std::size_t a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
            push(m, a, d, c);
            push(m, a, b, d);
        }
    for (std::size_t j = 0; j < segments; ++j) push(m, south, ring(stacks - 1, j), ring(stacks - 1, j + 1));
    return m;
}

MeshData make_grid(std::size_t triangles, std::uint64_t seed)
{
    check_count("make_grid", triangles);
    std::size_t n = std::size_t(std::floor(std::sqrt(double(triangles) / 2) + 0.5)); // cells per side
    if (n < 1) n = 1;

    // The terrain: four plane waves of halving amplitude, seeded direction, frequency and phase,
    // plus a little per-vertex noise.
    constexpr int waves = 4;
    double dir_x[waves], dir_z[waves], freq[waves], phase[waves], amp[waves];
    SplitMix64 rng{seed};
    for (int k = 0; k < waves; ++k) {
        double s, c;
        sin_cos_turns(rng.uniform(), s, c);
        dir_x[k] = c;
        dir_z[k] = s;
        freq[k] = 0.5 * double(1 << k) * (1 + rng.uniform()); // cycles across the grid's width
        phase[k] = rng.uniform();
        amp[k] = 0.15 / double(1 << k);
    }
    const double noise = 0.005; // world units

    MeshData m;
    m.name = "grid";
    m.positions.reserve((n + 1) * (n + 1) * 3);
    m.indices.reserve(2 * n * n * 3);
    for (std::size_t row = 0; row <= n; ++row) {
        double z = -1 + 2 * double(row) / double(n);
        for (std::size_t col = 0; col <= n; ++col) {
            double x = -1 + 2 * double(col) / double(n);
            double y = 0;
            for (int k = 0; k < waves; ++k) y += amp[k] * sin_turns(freq[k] * (x * dir_x[k] + z * dir_z[k]) / 2 + phase[k]);
            y += noise * (2 * rng.uniform() - 1);
            push(m, x, y, z);
        }
    }
    // Row by row, two triangles per cell, counter-clockwise seen from above (+y).
    for (std::size_t row = 0; row < n; ++row)
        for (std::size_t col = 0; col < n; ++col) {
            std::size_t v00 = row * (n + 1) + col, v01 = v00 + 1, v10 = v00 + n + 1, v11 = v10 + 1;
            push(m, v00, v10, v01);
            push(m, v01, v10, v11);
        }
    return m;
}

MeshData make_soup(std::size_t triangles, std::uint64_t seed)
{
    check_count("make_soup", triangles);
    // Edge about 2 / sqrt(n): the total area stays near one square unit whatever the count
    // (a moderate share of the screen when the cube is framed), capped for tiny counts.
    double size = triangles ? 2 / std::sqrt(double(triangles)) : 0;
    if (size > 0.25) size = 0.25;

    MeshData m;
    m.name = "soup";
    m.positions.reserve(triangles * 9);
    m.indices.reserve(triangles * 3);
    SplitMix64 rng{seed};
    for (std::size_t t = 0; t < triangles; ++t) {
        double centre[3];
        for (double& c : centre) c = size / 2 + (1 - size) * rng.uniform();
        for (int v = 0; v < 3; ++v) {
            double p[3];
            for (int k = 0; k < 3; ++k) p[k] = centre[k] + size * (rng.uniform() - 0.5);
            push(m, p[0], p[1], p[2]);
        }
        push(m, 3 * t, 3 * t + 1, 3 * t + 2);
    }
    return m;
}

} // namespace clvis
