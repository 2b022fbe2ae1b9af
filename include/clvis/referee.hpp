// The referee of CONVENTIONS.md: judges, in double precision from the scene's float32 vertices,
// whether a triangle id is an acceptable answer at a pixel centre, and compares two visibility
// buffers pixel by pixel. It is the project's definition of "right", independent of both paths.
//
// At a sample a triangle is *in* when the sample lies more than referee_edge_eps px inside all
// three projected edges and the view depth of its plane along the sample's primary ray lies in
// [near, far] by more than referee_depth_rel relative. It is *out* when the sample lies more than
// EPS from the projection of the triangle's visible part (the triangle clipped to the depth
// range with the tolerance: a triangle partly behind the eye is judged by what the eye sees), or
// lies more than EPS inside its edges while its depth along the ray is outside [near, far] by more
// than the tolerance. Otherwise it is *ambiguous*: at the depth of its plane along the ray where
// the ray meets it, else at the depth of the nearest point of its visible part (along a ray that
// misses a triangle seen almost edge-on, its plane's depth is meaningless). A triangle of zero
// area (exactly, from its float32 vertices) or seen exactly edge-on has no inside: ambiguous
// within EPS of its projected segment, out elsewhere.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>
#include <clvis/host_visibility.hpp>

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

/// One triangle at one sample, as the conventions classify it.
enum class SampleClass { In, Ambiguous, Out };

struct TriangleAtSample {
    SampleClass cls = SampleClass::Out;
    bool out_by_depth = false; ///< Out because of the depth range (else because of the edges)
    double outside = 0;        ///< px outside the triangle's visible projection (Out by edges)
    double depth = 0;          ///< view depth of the triangle at the sample (NaN when undefined)
};

struct PixelVerdict {
    int x = 0, y = 0;
    std::uint32_t id = background_id;      ///< the answer judged
    AnswerError error = AnswerError::None;
    int source = -1;            ///< compare(): 0 the first buffer, 1 the second, 2 both; else -1
    double edge_distance = 0;   ///< px: how far outside its nearest edge the sample is (Coverage)
    double depth = 0;           ///< view depth of the answer at the sample (NaN if undefined)
    double depth_excess = 0;    ///< relative: depth / d* - 1 (HiddenSurface)
    std::uint32_t nearest_id = background_id; ///< the nearest robustly covering triangle
    double nearest_depth = 0;   ///< d*, its depth

    bool acceptable() const { return error == AnswerError::None; }
    /// One line for people: "pixel (12, 40): id 7 ... (coverage: 0.013 px outside an edge)".
    std::string describe() const;
};

struct CompareReport {
    std::size_t pixels = 0;     ///< pixels looked at
    std::size_t equal = 0;      ///< same id in both (check(): the answer equals reference())
    std::size_t explained = 0;  ///< different ids, both acceptable (check(): acceptable, differs
                                ///< from reference())
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
    /// indexes triangles by the pixel tiles their EPS-expanded projected bounds touch. Throws
    /// Error(InvalidArgument) for an invalid camera or a size <= 0. The scene is copied from.
    Referee(const Scene& scene, const Camera& camera, int width, int height);
    ~Referee();
    Referee(Referee&&) noexcept;
    Referee& operator=(Referee&&) noexcept;

    int width() const;
    int height() const;

    /// Classifies triangle `id` (< the scene's triangle count) at pixel (x, y)'s centre.
    TriangleAtSample classify(std::uint32_t id, int x, int y) const;
    /// Judges `id` as the answer at pixel (x, y).
    PixelVerdict judge(int x, int y, std::uint32_t id) const;
    /// The plain reference answer: the nearest triangle robustly covering the sample (ties to
    /// the lower id), or background_id. `ambiguous` is set when another answer is acceptable
    /// too (an ambiguous or in triangle no farther than it); `depth` receives d* (+inf if none).
    std::uint32_t reference(int x, int y, bool* ambiguous = nullptr, double* depth = nullptr) const;
    /// Compares two buffers of this referee's size (Error(InvalidArgument) otherwise).
    CompareReport compare(const HostVisibility& a, const HostVisibility& b,
                          const CompareOptions& options = {}) const;
    /// Judges every pixel of one buffer (errors_a counts its errors; equal and explained
    /// compare it with reference()).
    CompareReport check(const HostVisibility& a, const CompareOptions& options = {}) const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

} // namespace clvis
