// The ray-casting reference: Intel Embree 3 with a robust, high-quality BVH over the scene's
// world-space triangles (geometry 0, primitive id = clvis triangle id), traced with the primary
// rays of CONVENTIONS.md (t = view depth) by single rays or 16-ray packets on a few threads.
#pragma once

#include "reference_result.hpp"

#include <clvis/camera.hpp>
#include <clvis/rays.hpp>
#include <clvis/scene.hpp>

#include <cstdint>
#include <memory>
#include <string>

namespace clvis::bench {

enum class EmbreeMode {
    Single,   ///< rtcIntersect1, one ray at a time
    Packet16, ///< rtcIntersect16, 4x4 pixel tiles with a valid mask
};

const char* to_string(EmbreeMode mode) noexcept;

/// Embree's answers for a batch of rays and the time of each timed run.
struct EmbreeRays {
    std::vector<double> run_ms;
    std::vector<std::uint32_t> ids;     ///< closest: primitive id or 0xFFFFFFFF
    std::vector<float> t;               ///< closest: tfar of the hit, +inf for a miss
    std::vector<std::uint8_t> occluded; ///< occlusion: 1 or 0
};

/// True when clvis_bench_refs was built with Embree (CLVIS_HAVE_EMBREE).
bool embree_available() noexcept;

class EmbreeReference {
public:
    /// Creates an Embree device with `threads` threads and builds the scene `builds` times (each
    /// a fresh RTCScene; the last one is kept), timing rtcCommitScene only. Throws
    /// std::runtime_error naming the failure, or when Embree was not built in.
    EmbreeReference(const Scene& scene, int threads = 2, int builds = 1);
    ~EmbreeReference();
    EmbreeReference(const EmbreeReference&) = delete;
    EmbreeReference& operator=(const EmbreeReference&) = delete;

    /// Builds the scene once more (a fresh RTCScene, then kept): appends the commit's time to
    /// build_samples_ms and returns it. `clvis bench` alternates these with clvis's builds.
    double rebuild(const Scene& scene);

    /// Median and every sample of the timed builds (ms).
    double build_ms() const;
    const std::vector<double>& build_samples_ms() const;
    /// "Embree 3.13.5 (threads=2)".
    std::string description() const;

    /// One untimed warm-up frame, then `repeats` timed frames (ray generation and tracing of
    /// every pixel centre on `threads` std::threads), fewer past `budget_ms` (enough_frames).
    /// Throws std::runtime_error on failure.
    ReferenceResult render(const Camera& camera, int width, int height, EmbreeMode mode, int repeats,
                           double budget_ms = 0);

    /// Traces `n` rays of clvis's records (tnear = tmin, tfar = tmax) with rtcIntersect1 /
    /// rtcOccluded1, or as packets of 16 consecutive rays with rtcIntersect16 / rtcOccluded16, on
    /// `threads` std::threads: one untimed run, then `repeats` timed runs. Throws
    /// std::runtime_error on failure.
    EmbreeRays trace(const RayRecord* rays, std::size_t n, bool occluded, EmbreeMode mode, int repeats);

    /// One camera and image size for interleaved timing (the reference must outlive it, and a
    /// rebuild ends it): frame() traces every pixel centre once; result() adds the builds so far.
    /// Traces the warm-up frame; throws std::runtime_error on failure.
    std::unique_ptr<ReferenceView> view(const Camera& camera, int width, int height, EmbreeMode mode);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Builds and renders in one call; failures land in ReferenceResult::error, never thrown.
ReferenceResult render_embree(const Scene& scene, const Camera& camera, int width, int height,
                              EmbreeMode mode, int repeats, int threads = 2);

} // namespace clvis::bench
