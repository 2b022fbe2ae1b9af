// The referee's internals, shared by its set-up (referee_setup.cpp: triangles in double
// precision, binned into tiles; referee_items.cpp: the scene's items copied, and the triangles
// that can be a candidate at some sample set up, any other set up again on demand), its
// classification (referee.cpp: per triangle and sample) and its judgement (referee_judge.cpp: ids
// and depths, per sample, per pixel, per buffer).
#pragma once

#include <clvis/referee.hpp>

#include "shared/samples.h"

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace clvis::detail {

constexpr double inf = std::numeric_limits<double>::infinity();
/// Binning tiles, in pixels per side.
constexpr int tile_log2 = 3;
constexpr int tile_size = 1 << tile_log2;
/// A plane through the eye (perspective) or parallel to the view direction (orthographic), to
/// within this fraction of its size, is edge-on: its projection has no inside.
constexpr double edge_on_rel = 1e-12;
/// Most vertices of a triangle clipped by two parallel planes.
constexpr int max_poly = 5;
/// A triangle touching more than this share of the tiles is tested at every pixel instead of
/// binned: a few hundred screen-filling triangles would otherwise fill gigabytes of tile lists.
constexpr double everywhere_share = 0.25;

/// The raster position of sample k of 2^log2n of pixel i along an axis (kernels/shared/samples.h,
/// the kernels' own table): i + 0.5 for one sample. Exact in double.
inline double sample_position(int i, int log2n, int k, int axis)
{
    return i + 0.5 + clvis_sample_offset(log2n, k, axis) / 16.0;
}

/// a x + b y + c over raster positions.
struct Linear {
    double a = 0, b = 0, c = 0;
    double at(double x, double y) const { return a * x + b * y + c; }
};

/// A triangle set up for one camera and image size.
struct Triangle {
    Linear edge[3];     ///< signed distance in px, positive inside (orientation folded in)
    Linear det, num;    ///< view depth of the plane along the primary ray = num / det
    bool flat = false;  ///< zero area or edge-on: no inside
    bool culled = false; ///< faces the way RenderOptions::cull drops (never when flat)
    int n = 0;          ///< vertices of the visible part (0: nothing in the depth range)
    double px[max_poly], py[max_poly], pd[max_poly]; ///< its raster position and view depth
    double lo_x = inf, lo_y = inf, hi_x = -inf, hi_y = -inf; ///< EPS-expanded raster bounds
};

/// Geometry the scene holds once: a prototype, or a plain mesh (copied: the referee keeps no
/// reference to the scene).
struct RefereeSource {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::string name;
};

/// One item of the scene: where its geometry is and how it is placed (instance_transform.hpp).
struct RefereeItem {
    std::uint32_t first = 0;     ///< id of its first triangle
    std::uint32_t triangles = 0; ///< its triangle count
    std::uint32_t source = 0;    ///< index into Impl::sources
    bool identity = true;        ///< an identity transform keeps the positions' bits
    std::array<float, 12> m{};   ///< else instance_matrix of its transform
};

} // namespace clvis::detail

namespace clvis {

struct Referee::Impl {
    Camera camera;
    int width = 0, height = 0;
    double eps = referee_edge_eps, rel = referee_depth_rel; ///< RefereeTolerance
    Cull cull = Cull::None;
    bool perspective = true;
    double near_lo = 0, near_in = 0, far_in = 0, far_hi = 0; ///< depth range with tolerances
    CameraFrame frame;
    /// `camera` with its raster map fixed as intrinsics: the same numbers, without the canvas'
    /// tangent computed again at every projection.
    Camera raster_camera;
    std::size_t triangle_count = 0; ///< the scene's
    std::vector<detail::RefereeSource> sources;
    std::vector<detail::RefereeItem> items;
    /// Set up once: the triangles whose visible part's bounds hold a sample position of the image
    /// (any sample count), the only ones for_candidates can meet; the rest are set up on demand.
    std::vector<detail::Triangle> kept;
    std::vector<std::uint32_t> kept_ids; ///< their ids, ascending
    int tiles_x = 0, tiles_y = 0;
    std::vector<std::uint32_t> tile_start; ///< tiles_x * tiles_y + 1 offsets into tile_tris
    std::vector<std::uint32_t> tile_tris;  ///< indices into kept per tile, ascending
    std::vector<std::uint32_t> everywhere; ///< indices into kept of triangles too large to bin, ascending

    /// What the nearest robustly covering triangle is at a sample.
    struct Nearest {
        std::uint32_t id = background_id;
        double depth = detail::inf;
    };

    void setup(const Scene& scene);
    /// referee_items.cpp: copies the scene's items and sources, and throws as world_positions()
    /// would for the first item with a transformed vertex that overflows float32.
    void copy_items(const Scene& scene);
    /// referee_items.cpp: sets up every triangle (in parallel), keeping those that may_be_candidate.
    void set_up_candidates();
    /// The float32 world vertices of triangle `local` of item `it` (in double) and their camera
    /// coordinates (Camera::to_camera), as the set-up takes them.
    void vertices(const detail::RefereeItem& it, std::size_t local, Vec3 world[3], Vec3 cam[3]) const;
    /// Triangle `id` (< triangle_count) set up: the kept one, or `scratch` set up now, the same bits.
    const detail::Triangle& triangle(std::uint32_t id, detail::Triangle& scratch) const;
    void setup_triangle(detail::Triangle& t, const Vec3 world[3], const Vec3 cam[3]) const;
    /// The part of setup_triangle that depends on the plane: edges, depth, flat and culled.
    void setup_plane(detail::Triangle& t, const Vec3 world[3], const Vec3 cam[3]) const;
    /// The part of setup_triangle that clips and projects: n, px, py, pd and the bounds.
    void setup_visible_part(detail::Triangle& t, const Vec3 cam[3]) const;
    /// t's EPS-expanded bounds from its n projected vertices (t's bounds as default-constructed).
    void set_bounds(detail::Triangle& t) const;
    /// Whether -cam.z passes the clip of setup_visible_part against near and far.
    bool within_near(const Vec3& cam) const { return -cam.z - near_lo >= 0; }
    bool within_far(const Vec3& cam) const { return far_hi + cam.z >= 0; }
    /// Whether t's bounds (setup_visible_part) hold a sample position of the image, of any sample
    /// count: false means no sample of any buffer ever meets it in for_candidates.
    bool may_be_candidate(const detail::Triangle& t) const;
    void bin();
    TriangleAtSample classify(const detail::Triangle& t, double x, double y) const;
    // Every judgement below is at sample k of 2^log2n of pixel (x, y) (detail::sample_position):
    // its centre by default.
    TriangleAtSample classify_id(std::uint32_t id, int x, int y, int log2n = 0, int k = 0) const
    {
        detail::Triangle scratch;
        return classify(triangle(id, scratch), detail::sample_position(x, log2n, k, 0),
                        detail::sample_position(y, log2n, k, 1));
    }
    template <class Fn> void for_candidates(int x, int y, Fn fn, int log2n = 0, int k = 0) const;
    Nearest nearest(int x, int y, int log2n = 0, int k = 0) const;
    /// nearest() among the triangles other than the `count` ids of `excluded` (depth layers).
    Nearest nearest_excluding(int x, int y, const std::uint32_t* excluded, int count, int log2n = 0, int k = 0) const;
    /// Judges one answer (its id, and its depth when it has one) at pixel (x, y).
    /// `depth_px`: CompareOptions::depth_px.
    PixelVerdict judge(int x, int y, const SampleAnswer& answer, const Nearest& n, double depth_px, int log2n = 0,
                       int k = 0) const;
    /// Judges the depth of v.answer_depth for triangle t at raster (x, y) into v.
    void judge_depth(const detail::Triangle& t, double x, double y, double depth_px, PixelVerdict& v) const;
    /// The view depths of t's visible part within EPS (a square) of raster (x, y); false if none.
    bool window_depths(const detail::Triangle& t, double x, double y, double* lo, double* hi) const;
    template <class RowFn> CompareReport by_rows(std::size_t max_reported, RowFn row) const;
    /// A screen-space linear function k.x sx + k.y sy + k.z as a function of raster (x, y).
    detail::Linear to_raster(double kx, double ky, double k0) const;
    void project(Vec3 cam, double* x, double* y) const;
};

/// Counts one sample's verdicts of two buffers' answers into r (pb null: one buffer, checked);
/// same_id and same_depth say whether the two answers (check(): answer and reference) are equal.
void referee_tally(CompareReport& r, const PixelVerdict& va, const PixelVerdict* pb, bool same_id, bool same_depth,
                   std::size_t max_reported);
/// Error(InvalidArgument) unless o is valid (CompareOptions::depth_px).
void referee_check_options(const CompareOptions& o);

/// Error(InvalidArgument) unless (x, y) is a pixel of the referee's image.
void referee_check_pixel(const Referee::Impl& impl, int x, int y);

} // namespace clvis
