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
// within EPS of its projected segment, out elsewhere. With RenderOptions::cull, a triangle facing
// the culled way (render_options.hpp) is out wherever it would be in (the sample robustly inside
// its projection fixes its orientation); near its edges it stays ambiguous.
//
// Depths are judged too: the depth a buffer holds for its answer at a sample must lie within the
// depth tolerance of CONVENTIONS.md ("Barycentrics") of the answered triangle's exact view depth
// there, the depth of its plane along the sample's primary ray: `referee_depth_judge_rel` d plus
// the change of depth over `referee_depth_judge_px` px along the triangle's screen-space depth
// gradient. Where the ray misses the triangle (within EPS outside it), or the triangle has no
// inside (zero area, seen edge-on), the depths of its visible part within EPS of the sample are
// accepted too, widened by the relative tolerance: along a ray that misses a plane seen almost
// edge-on, the plane's depth means nothing. The background's depth must be +inf.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/render_options.hpp>
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

/// A looser tolerance, for cases where float32 cannot honour CONVENTIONS.md's (its last
/// precision paragraph: huge images, far meshes); never tighter than referee_edge_eps and
/// referee_depth_rel. Whoever loosens it states why.
struct RefereeTolerance {
    double edge_eps = referee_edge_eps;   ///< px
    double depth_rel = referee_depth_rel; ///< relative; judged depths are never held tighter than it
};
/// The depth tolerance of a buffer's depths: relative, plus the gradient over this many pixels
/// (the raster path's 1/65536 px snapping: 1 / CLVIS_SUBPIXEL_ONE of kernels/shared/raster.h,
/// which referee_setup.cpp checks).
constexpr double referee_depth_judge_rel = 1e-5;
constexpr double referee_depth_judge_px = 1.0 / 65536;

/// What is wrong with an unacceptable answer.
enum class AnswerError {
    None,          ///< acceptable
    Coverage,      ///< the answered triangle does not cover the sample (outside by > EPS)
    HiddenSurface, ///< it covers the sample but a nearer triangle robustly does too
    Missed,        ///< background answered where a triangle robustly covers the sample
    Clipped,       ///< its depth at the sample is outside [near, far]
    InvalidId,     ///< an id that is neither a triangle of the scene nor the background
    Culled,        ///< it robustly covers the sample but faces the way RenderOptions::cull drops
    Repeated,      ///< depth layers: a triangle an earlier layer of the sample already holds
};

const char* to_string(AnswerError error) noexcept;

/// What is wrong with the depth a buffer holds for its answer.
enum class DepthError {
    None,       ///< within the tolerance of the answered triangle's exact depth (or not judged)
    Wrong,      ///< outside [depth_lo, depth_hi]: a triangle's depth off, or a finite background
    NoTriangle, ///< the answer is an invalid id: there is no depth to judge it against
};

const char* to_string(DepthError error) noexcept;

/// One answer at one sample, as a buffer holds it. More per-sample outputs (barycentrics) are
/// judged by adding fields here and checks in the referee's per-sample judge.
struct SampleAnswer {
    std::uint32_t id = background_id;
    bool has_depth = false; ///< whether `depth` is judged
    float depth = 0;        ///< the buffer's view depth (+inf for the background)
};

/// One triangle at one sample, as the conventions classify it.
enum class SampleClass { In, Ambiguous, Out };

struct TriangleAtSample {
    SampleClass cls = SampleClass::Out;
    bool out_by_depth = false; ///< Out because of the depth range (else because of the edges)
    bool culled = false;       ///< Out because RenderOptions::cull drops it (it would be In)
    double outside = 0;        ///< px outside the triangle's visible projection (Out by edges)
    double depth = 0;          ///< view depth of the triangle at the sample (NaN when undefined)
};

struct PixelVerdict {
    int x = 0, y = 0;
    int sample = 0, samples = 1; ///< the sample judged, of the buffer's samples per pixel
    std::uint32_t id = background_id;      ///< the answer judged
    AnswerError error = AnswerError::None;
    int source = -1;            ///< compare(): 0 the first buffer, 1 the second, 2 both; else -1
    double edge_distance = 0;   ///< px: how far outside its nearest edge the sample is (Coverage)
    double depth = 0;           ///< view depth of the answer at the sample (NaN if undefined)
    double depth_excess = 0;    ///< relative: depth / d* - 1 (HiddenSurface)
    std::uint32_t nearest_id = background_id; ///< the nearest robustly covering triangle
    double nearest_depth = 0;   ///< d*, its depth
    // The depth answered (judged only when the SampleAnswer has one).
    bool depth_judged = false;
    DepthError depth_error = DepthError::None;
    float answer_depth = 0;     ///< the buffer's depth
    double depth_expected = 0;  ///< the plane's exact depth along the ray (NaN when it has none)
    double depth_lo = 0, depth_hi = 0; ///< the accepted range

    /// The id is acceptable (its depth may not be: depth_acceptable()).
    bool acceptable() const { return error == AnswerError::None; }
    bool depth_acceptable() const { return depth_error == DepthError::None; }
    /// One line for people: "pixel (12, 40): id 7 ... (coverage: 0.013 px outside an edge)".
    std::string describe() const;
};

/// Counts that add up: equal + explained + errors == pixels, and depth_equal + depth_explained +
/// depth_errors == pixels when depths_judged.
struct CompareReport {
    std::size_t pixels = 0;     ///< pixels of the buffers; samples, when they hold several per pixel
    std::size_t judged = 0;     ///< pixels the referee judged (all unless differing_only)
    std::size_t equal = 0;      ///< same id in both, acceptable or not judged (check(): the answer
                                ///< is acceptable and equals reference())
    std::size_t explained = 0;  ///< different ids, both acceptable (check(): acceptable, differs
                                ///< from reference())
    std::size_t errors = 0;     ///< pixels where at least one id is unacceptable
    std::size_t errors_a = 0, errors_b = 0; ///< unacceptable ids of each buffer
    bool depths_judged = false; ///< both buffers (check(): the buffer) hold depths
    std::size_t depth_equal = 0;     ///< same depth bits in both, acceptable or not judged (check():
                                     ///< acceptable and equal to the exact depth as a float)
    std::size_t depth_explained = 0; ///< different depths (check(): not that float), both acceptable
    std::size_t depth_errors = 0;    ///< pixels where at least one depth is unacceptable
    std::size_t depth_errors_a = 0, depth_errors_b = 0;
    /// Up to max_reported verdicts with an unacceptable id or depth, in raster order.
    std::vector<PixelVerdict> first_errors;
};

struct CompareOptions {
    /// Judge only the pixels where the buffers differ (in id, or in depth when both hold depths);
    /// the others count as equal without being judged, so two buffers with the same wrong answer
    /// pass. Off by default: every pixel of both is judged.
    bool differing_only = false;
    std::size_t max_reported = 20;
    /// The distance in px over which the depth gradient is allowed in the depth tolerance:
    /// CONVENTIONS.md's 1/65536 px (the raster path's snapping). Float32 positions are uncertain
    /// by more far from the origin and on large images (about M 2^-24 world units, and width
    /// 2^-24 px per operation in raster space); a caller that knows its inputs are less precise
    /// may widen this (to at most 1 px, never below the default), and should say so.
    double depth_px = referee_depth_judge_px;
};

class Referee {
public:
    /// Projects the scene with `camera` for a width x height image (double precision) and
    /// indexes triangles by the pixel tiles their EPS-expanded projected bounds touch. Judges with
    /// `options` as the paths render with them (only `cull` changes an answer). Throws
    /// Error(InvalidArgument) for an invalid camera or a size <= 0. The scene is copied from.
    /// `tolerance` loosens CONVENTIONS.md's EPS and depth tolerance where float32 cannot honour
    /// them; tighter or non-finite values throw Error(InvalidArgument). A moved-from Referee throws
    /// Error(InvalidArgument) naming the call from every member.
    Referee(const Scene& scene, const Camera& camera, int width, int height, const RenderOptions& options = {},
            RefereeTolerance tolerance = {});
    ~Referee();
    Referee(Referee&&) noexcept;
    Referee& operator=(Referee&&) noexcept;

    int width() const;
    int height() const;

    /// Classifies triangle `id` (< the scene's triangle count) at pixel (x, y)'s centre.
    TriangleAtSample classify(std::uint32_t id, int x, int y) const;
    /// Judges `id` as the answer at pixel (x, y).
    PixelVerdict judge(int x, int y, std::uint32_t id) const;
    /// Judges an answer with its depth (when it has one) at pixel (x, y).
    PixelVerdict judge(int x, int y, const SampleAnswer& answer) const;
    /// The plain reference answer: the nearest triangle robustly covering the sample (ties to
    /// the lower id), or background_id. `ambiguous` is set when another answer is acceptable
    /// too (an ambiguous or in triangle no farther than it); `depth` receives d* (+inf if none).
    std::uint32_t reference(int x, int y, bool* ambiguous = nullptr, double* depth = nullptr) const;
    /// Compares two buffers of this referee's size (Error(InvalidArgument) otherwise); depths are
    /// judged when both hold them (a depth vector that is neither empty nor of the buffer's size
    /// is an Error(InvalidArgument)).
    CompareReport compare(const HostVisibility& a, const HostVisibility& b,
                          const CompareOptions& options = {}) const;
    /// Judges every pixel of one buffer, its depths too when it holds them (errors_a counts its
    /// errors; equal and explained compare it with reference()).
    CompareReport check(const HostVisibility& a, const CompareOptions& options = {}) const;
    /// Depth layers (HostVisibility::layers, CONVENTIONS.md "Depth layers"), one report per layer.
    /// Layer k is judged as the (k+1)-th nearest covering triangle: as layer 0 is judged, with
    /// the triangles the buffer holds at the sample's earlier layers taken out (d* is the nearest
    /// *in* triangle not among them), and a triangle an earlier layer holds is an error
    /// (AnswerError::Repeated). With one layer, check() and compare() give reports[0].
    std::vector<CompareReport> check_layers(const HostVisibility& a, const CompareOptions& options = {}) const;
    /// Compares two buffers with the same number of layers, layer by layer, each judged as above
    /// against its own earlier layers.
    std::vector<CompareReport> compare_layers(const HostVisibility& a, const HostVisibility& b,
                                              const CompareOptions& options = {}) const;

    struct Impl;

private:
    const Impl& checked(const char* call) const;
    std::unique_ptr<Impl> impl_;
};

} // namespace clvis
