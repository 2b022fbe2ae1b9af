// The referee of CONVENTIONS.md: judges, in double precision from the scene's float32 vertices,
// whether a triangle id is an acceptable answer at a pixel centre, and compares two visibility
// buffers pixel by pixel. It is the project's definition of "right", independent of both paths.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>
#include <clvis/visibility.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace clvis {

/// Distances in pixels within which a sample is neither in nor out of a triangle, and the
/// relative depth tolerance, as CONVENTIONS.md sets them.
constexpr double referee_edge_eps = 1e-3;
constexpr double referee_depth_rel = 1e-6;

/// What is wrong with an unacceptable answer.
enum class AnswerError {
    None,          ///< acceptable
    Coverage,      ///< the answered triangle does not cover the sample (outside by > EPS)
    HiddenSurface, ///< it covers the sample but a nearer triangle robustly does too
    Missed,        ///< background answered where a triangle robustly covers the sample
    Clipped,       ///< its depth at the sample is outside [near, far]
    InvalidId,     ///< an id that is neither a triangle of the scene nor the background
};

const char* to_string(AnswerError error) noexcept;

struct PixelVerdict {
    int x = 0, y = 0;
    std::uint32_t id = background_id;      ///< the answer judged
    AnswerError error = AnswerError::None;
    double edge_distance = 0;   ///< px: how far outside its nearest edge the sample is (Coverage)
    double depth = 0;           ///< view depth of the answer at the sample (if a triangle)
    double depth_excess = 0;    ///< relative: depth / d* - 1 (HiddenSurface)
    std::uint32_t nearest_id = background_id; ///< the nearest robustly covering triangle
    double nearest_depth = 0;   ///< d*, its depth

    bool acceptable() const { return error == AnswerError::None; }
    /// One line for people: "pixel (12, 40): id 7 ... (coverage: 0.013 px outside an edge)".
    std::string describe() const;
};

struct CompareReport {
    std::size_t pixels = 0;     ///< pixels looked at
    std::size_t equal = 0;      ///< same id in both
    std::size_t explained = 0;  ///< different ids, both acceptable
    std::size_t errors = 0;     ///< pixels where at least one answer is unacceptable
    std::size_t errors_a = 0, errors_b = 0; ///< unacceptable answers of each buffer
    std::vector<PixelVerdict> first_errors; ///< up to max_reported, in raster order
};

struct CompareOptions {
    bool all = false;            ///< judge every pixel of both, not only where they differ
    std::size_t max_reported = 20;
};

class Referee {
public:
    /// Projects the scene with `camera` for a width x height image (double precision) and
    /// indexes triangles by the pixels they may touch.
    Referee(const Scene& scene, const Camera& camera, int width, int height);
    ~Referee();
    Referee(Referee&&) noexcept;
    Referee& operator=(Referee&&) noexcept;

    /// Judges `id` as the answer at pixel (x, y).
    PixelVerdict judge(int x, int y, std::uint32_t id) const;
    /// The plain reference answer: the nearest triangle robustly covering the sample (ties to
    /// the lower id), or background_id; `ambiguous` is set when an ambiguous triangle is no
    /// farther than it (several answers are then acceptable).
    std::uint32_t reference(int x, int y, bool* ambiguous = nullptr, double* depth = nullptr) const;
    /// Compares two buffers of this referee's size (Error(InvalidArgument) otherwise).
    CompareReport compare(const HostVisibility& a, const HostVisibility& b,
                          const CompareOptions& options = {}) const;
    /// Judges every pixel of one buffer.
    CompareReport check(const HostVisibility& a, const CompareOptions& options = {}) const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

} // namespace clvis
