// The agreement suite's harness (paths_agree_test.cpp, paths_agree_edges_test.cpp): agree()
// renders one case with every path, judges every pixel with the referee and compares the paths;
// the precision model that keeps each case within what float32 can honour; seeded cameras and
// the small scene builders the cases share.
#pragma once

#include <clvis/clvis.hpp>

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace clvis::agreement {

constexpr double pi = 3.14159265358979323846;
/// float32's relative rounding, 2^-24.
constexpr double float_ulp = 1.0 / 16777216.0;
/// Explained raster-vs-ray mismatches allowed on real meshes under general cameras, as a fraction
/// of the pixels (CONVENTIONS.md: 0.005 %).
constexpr double explained_budget = 5e-5;
/// Test scenes keep float32's vertex uncertainty (CONVENTIONS.md's last precision paragraph)
/// within this share of EPS in pixels, and within depth_share of the relative depth tolerance
/// (a vertex M 2^-24 off moves a surface at view depth d by M 2^-24 / d relative).
constexpr double precision_share = 0.25;
constexpr double depth_share = 0.5;
/// Float32 rounding in raster space, which grows with the image (a ulp of 2^-24 of coordinates up
/// to its size): each path maps between screen and raster space in a few float32 operations
/// (shared/camera.h: a division by right or top, an addition of 1, a product by the size; the
/// ray path the inverse and the direction), each off by up to 2^-24 of coordinates reaching the
/// image's size and, where the raster path clips, CLVIS_GUARD_MARGIN px past each edge (shared/
/// raster.h). So a sample's position relative to an edge is off by about raster_ops x
/// (max(W, H) + 2 margin) x 2^-24 px; test cases keep that within raster_share of EPS.
constexpr double raster_ops = 3;
constexpr double raster_share = 0.5;
constexpr double guard_margin = 64; // CLVIS_GUARD_MARGIN, kernels/shared/raster.h

inline const char* const bundled[] = {"stanford-bunny", "teapot", "spot", "suzanne"};

/// Deterministic on every standard library: mt19937_64's bits, turned into doubles by hand.
struct Random {
    std::mt19937_64 bits;
    explicit Random(std::uint64_t seed) : bits(seed) {}
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(bits() >> 11) * 0x1p-53; }
    Vec3 unit();
};

/// The nearest `near` at which float32 keeps its promise for every vertex of the scene seen from
/// `eye` (see uncertainty() below): within a share of EPS in pixels and of the depth tolerance.
double precise_near(const Scene& s, Vec3 eye, bool perspective, double fov_y, int height);

/// The smallest orthographic view height that keeps the same promise (pixels grow with 1 / height).
double precise_ortho_height(const Scene& s, Vec3 eye, int height);

/// How far float32 rounding may move what a path sees, as CONVENTIONS.md estimates it: a vertex of
/// magnitude M (and the eye) is uncertain by M 2^-24 world units, which near a triangle's nearest
/// visible depth d is M 2^-24 / d relative and, under perspective, M 2^-24 H / (2 d tan(fov / 2))
/// pixels (the largest over the scene's triangles); and raster_rounding() px from the image size.
struct Uncertainty {
    double px = 0, depth = 0; ///< from world magnitudes
    double raster = 0;        ///< from raster-space magnitudes, px
};

Uncertainty uncertainty(const Scene& s, const Camera& c, int width, int height);

/// The referee's tolerance where float32 cannot honour CONVENTIONS.md's (its last precision
/// paragraph): the uncertainty above over its shares, never below EPS and 1e-6. Each case that
/// uses it says why in `reason`; the loosened values are printed with the case.
RefereeTolerance float32_tolerance(const Scene& s, const Camera& c, int w, int h, const char* reason);

struct Tally {
    std::size_t pixels = 0, explained = 0, cases = 0;
    double seconds = 0;
};

struct Frames {
    std::vector<HostVisibility> vis; ///< raster, ray, then brute when asked
};

/// Renders one frame with both paths (and the brute path), judges every pixel of each with the
/// referee, checks ids and, optionally, agreement with reference(); compares raster with ray, the
/// raster path's two depth tests (atomic and tile ownership, which must agree bit for bit) and the
/// ray paths' raster-rule coverage with the raster path (bit for bit, every pixel).
Frames agree(Renderer& renderer, const Scene& scene, const std::string& name, const Camera& cam, int w, int h,
             bool brute, bool with_reference, Tally& tally, RefereeTolerance tol = {});

/// Prints the tally and checks its explained mismatches against explained_budget.
void check_budget(const Tally& t, const char* what);

enum class View { Outside, OrthoOutside, Grazing, Inside, Close };

const char* to_string(View v);

/// A point on the surface of a random (non-degenerate) triangle, and its unit normal.
void surface_point(const Scene& s, Random& rng, Vec3* p, Vec3* n);

/// An up vector not along the view from `eye` to `target`.
Vec3 up_for(Vec3 eye, Vec3 target);

/// A seeded random camera of the given kind, with near no closer than float32 allows at `height`.
Camera random_camera(const Scene& s, View kind, Random& rng, int height);

/// scenes/<name>.obj as a scene of one mesh.
Scene load_bundled(const std::string& name);

/// An n x n grid of quads of size `step` from (x0, y0) at z, split along alternating diagonals
/// (vertices shared by four and by eight triangles).
MeshData grid(int n, double x0, double y0, double step, double z);

/// A mesh of the triangles in `positions`, 9 floats each, indexed in order.
MeshData triangles(std::vector<float> positions, const char* name);

Mat4 scale(double s);

Mat4 rotate_y(double radians, Vec3 offset = {});

/// Pixels whose centre lies strictly inside [x0, x1] x [y0, y1] in raster space and shows the
/// background.
std::size_t holes(const HostVisibility& v, double x0, double x1, double y0, double y1);

} // namespace clvis::agreement
