// A double-precision oracle for the ray queries: each triangle judged *in* (the ray meets it
// clearly inside its edges and its interval), *out*, or *ambiguous* (within a margin of an edge,
// of tmin or tmax, or within rounding of its plane), as the referee judges pixels. Answers of the device are
// acceptable when they agree with every clear verdict.
#pragma once

#include <clvis/rays.hpp>
#include <clvis/scene.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace clvis::test {

enum class Verdict { Out, In, Ambiguous };

struct Judged {
    Verdict verdict = Verdict::Out;
    double t = std::numeric_limits<double>::infinity();
    double t_tol = 0; ///< how far a float32 t may lie from t: relative to t and to the triangle's size
    bool any_t = false; ///< the ray lies within rounding of the triangle's plane and touches it: any t
};

/// Relative margin of the oracle: edge functions within this fraction of the triangle's scale,
/// and t within this fraction of the interval's end, are ambiguous.
constexpr double oracle_eps = 1e-5;

inline Judged judge_triangle(const RayRecord& r, const float v[9])
{
    double o[3] = {r.ox, r.oy, r.oz}, d[3] = {r.dx, r.dy, r.dz};
    double p[3][3];
    for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) p[k][c] = double(v[3 * k + c]) - o[c];
    auto triple = [&](const double* a, const double* b) {
        double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2], cz = a[0] * b[1] - a[1] * b[0];
        return d[0] * cx + d[1] * cy + d[2] * cz;
    };
    double e[3] = {triple(p[1], p[2]), triple(p[2], p[0]), triple(p[0], p[1])};
    double scale = 0;
    for (int k = 0; k < 3; ++k)
        scale = std::fmax(scale, std::sqrt(p[k][0] * p[k][0] + p[k][1] * p[k][1] + p[k][2] * p[k][2]));
    double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double tol = oracle_eps * scale * scale * dl;
    Judged j;
    bool pos = e[0] > tol && e[1] > tol && e[2] > tol, neg = e[0] < -tol && e[1] < -tol && e[2] < -tol;
    bool out = (e[0] < -tol || e[1] < -tol || e[2] < -tol) && (e[0] > tol || e[1] > tol || e[2] > tol);
    double det = e[0] + e[1] + e[2];
    if (out) return j;
    if (std::fabs(det) <= tol) {
        // Within rounding of the triangle's plane (a float32 shear cannot tell): ambiguous anywhere.
        j.verdict = Verdict::Ambiguous;
        j.any_t = true;
        j.t_tol = oracle_eps * scale / dl;
        return j;
    }
    // t of the plane: the hit point is sum(e_k p_k) / det relative to the origin, t = its along d / |d|^2
    double hit[3];
    for (int c = 0; c < 3; ++c) hit[c] = (e[0] * p[0][c] + e[1] * p[1][c] + e[2] * p[2][c]) / det;
    j.t = (hit[0] * d[0] + hit[1] * d[1] + hit[2] * d[2]) / (dl * dl);
    j.t_tol = oracle_eps * (std::fabs(j.t) + scale / dl);
    bool clear_in_range = j.t > double(r.tmin) + j.t_tol && j.t < double(r.tmax) - j.t_tol;
    bool clear_out_range = j.t < double(r.tmin) - j.t_tol || j.t > double(r.tmax) + j.t_tol;
    if (clear_out_range) return j;
    j.verdict = (pos || neg) && clear_in_range ? Verdict::In : Verdict::Ambiguous;
    return j;
}

/// The oracle's view of one ray against a scene.
struct RayVerdict {
    double nearest_in = std::numeric_limits<double>::infinity(); ///< nearest *in* t
    std::uint32_t in = 0, ambiguous = 0;                          ///< triangles of each verdict
};

inline RayVerdict judge_ray(const RayRecord& r, const Scene& scene)
{
    RayVerdict rv;
    float v[9];
    for (std::uint32_t id = 0; id < scene.triangle_count(); ++id) {
        scene.triangle(id, v);
        Judged j = judge_triangle(r, v);
        if (j.verdict == Verdict::In) {
            ++rv.in;
            rv.nearest_in = std::fmin(rv.nearest_in, j.t);
        } else if (j.verdict == Verdict::Ambiguous) {
            ++rv.ambiguous;
        }
    }
    return rv;
}

/// Whether `hit` is an acceptable closest hit: the background only when no triangle is clearly
/// in, else a triangle not clearly out, no farther than the nearest clear one.
inline bool closest_acceptable(const RayRecord& r, const Scene& scene, const RayVerdict& rv, const HitRecord& hit)
{
    if (hit.id == background_id) return rv.in == 0;
    if (hit.id >= scene.triangle_count()) return false;
    float v[9];
    scene.triangle(hit.id, v);
    Judged j = judge_triangle(r, v);
    if (j.verdict == Verdict::Out) return false;
    if (j.any_t)
        return double(hit.t) >= double(r.tmin) && double(hit.t) <= double(r.tmax) &&
               double(hit.t) <= rv.nearest_in + j.t_tol + oracle_eps * rv.nearest_in;
    return std::fabs(double(hit.t) - j.t) <= j.t_tol && double(hit.t) <= rv.nearest_in + j.t_tol;
}

} // namespace clvis::test
