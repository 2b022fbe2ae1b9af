// Plain types of ray queries (CONVENTIONS.md "Ray queries"): a ray and a hit as the records that
// the kernels, the files of `clvis rays` and the caller's arrays share, their structure-of-arrays
// forms, and what a query reports. No OpenCL here: host-only code can include it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace clvis {

/// A ray: origin, interval start, direction (any length, not zero), interval end; its points are
/// o + t d for t in [tmin, tmax]. 8 float32, 32 bytes. tmax may be +inf.
struct RayRecord {
    float ox, oy, oz, tmin;
    float dx, dy, dz, tmax;
};
static_assert(sizeof(RayRecord) == 32, "a ray record is 8 float32");

/// A closest hit: t, triangle id, barycentrics (u, v) with the hit point (1 - u - v) v0 + u v1 + v v2.
/// A miss is id background_id (0xFFFFFFFF), t = +inf, u = v = 0. 16 bytes.
struct HitRecord {
    float t;
    std::uint32_t id;
    float u, v;
};
static_assert(sizeof(HitRecord) == 16, "a hit record is t, id, u, v");

/// Rays as one array per field (each n long), for callers that keep them that way.
struct RaySoA {
    const float *ox, *oy, *oz, *tmin, *dx, *dy, *dz, *tmax;
};

/// Closest hits as one array per field.
struct HitSoA {
    float* t;
    std::uint32_t* id;
    float *u, *v;
};

enum class RayQueryKind {
    Closest, ///< t, id, u, v per ray
    Any,     ///< one uint8 per ray: 1 when a hit lies in [tmin, tmax] (occlusion)
    Count,   ///< one uint32 per ray: surface crossings in [tmin, tmax], edges and vertices half-open
    All,     ///< max_hits hits per ray (t, id, u, v), nearest first by (t, id), edges inclusive as
             ///< closest hits; optionally the number of all hits per ray (not Count's half-open count)
};

/// The most hits an all-hits query keeps per ray.
constexpr int ray_query_max_hits = 64;

const char* to_string(RayQueryKind kind) noexcept;
/// "closest", "any", "count" or "all" (render_options.cpp's table, as option_names<RayQueryKind>());
/// throws Error(InvalidArgument) otherwise.
RayQueryKind ray_query_kind_from_string(const std::string& name);

/// What one query call did.
struct RayQueryStats {
    std::size_t rays = 0;    ///< rays answered
    std::size_t invalid = 0; ///< of which invalid (NaN or infinite component, zero direction,
                             ///< tmin < 0 or tmin > tmax): answered as misses
    std::size_t batches = 0; ///< kernel launches the rays were split into
    double device_ms = 0;    ///< kernel time summed over batches (profiling events)
    double wall_ms = 0;      ///< host wall time of the call, transfers included
};

/// Why a query validates a ray (the same rule as the kernels, kernels/shared/ray_query.h).
bool ray_is_valid(const RayRecord& ray) noexcept;

} // namespace clvis
