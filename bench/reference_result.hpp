// What a reference renderer hands back to `clvis bench`: the id buffer of CONVENTIONS.md (row 0 on
// top, background 0xFFFFFFFF), view depth, and the timings of its warm frames, so that clvis's
// paths and the references are judged and timed on the same scene and camera.
#pragma once

#include "bench_stats.hpp"

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace clvis::bench {

struct ReferenceResult {
    std::string name;                ///< "embree-intersect1", "embree-intersect16", "llvmpipe"
    int width = 0, height = 0;
    std::vector<std::uint32_t> ids;  ///< width * height, row 0 on top; 0xFFFFFFFF where empty
    std::vector<float> depth;        ///< view depth, +inf where empty; empty if not produced
    std::vector<double> frame_ms;    ///< one per timed frame, taken after an untimed warm-up
    double build_ms = 0;             ///< acceleration structure build (median of builds), 0 if none
    std::vector<double> build_samples_ms; ///< every timed build
    std::string error;               ///< set when the reference failed: nothing else is valid

    bool ok() const { return error.empty(); }
};

/// One camera and image size of a reference renderer, framed one at a time so that `clvis bench`
/// can interleave it with other renderers (A B A B ...). Made with one untimed warm-up frame.
class ReferenceView {
public:
    virtual ~ReferenceView() = default;
    /// One timed frame (before_frame() untimed, then render_frame()); returns its wall time (ms),
    /// also kept in result().frame_ms.
    double frame()
    {
        before_frame();
        auto t0 = std::chrono::steady_clock::now();
        render_frame();
        double ms = ms_since(t0);
        result_.frame_ms.push_back(ms);
        return ms;
    }
    /// The last frame's ids and depth (read back, not timed) and every timed frame. Throws
    /// std::runtime_error on a failure of the reference.
    virtual const ReferenceResult& result() = 0;

protected:
    /// What the next frame needs that is not part of it (a context made current).
    virtual void before_frame() {}
    virtual void render_frame() = 0;
    ReferenceResult result_;
};

} // namespace clvis::bench
