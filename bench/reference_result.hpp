// What a reference renderer hands back to `clvis bench`: the id buffer of CONVENTIONS.md (row 0 on
// top, background 0xFFFFFFFF), view depth, and the timings of its warm frames, so that clvis's
// paths and the references are judged and timed on the same scene and camera.
#pragma once

#include "bench_stats.hpp"

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

} // namespace clvis::bench
