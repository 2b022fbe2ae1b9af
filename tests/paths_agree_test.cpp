// Both paths against the referee: every pixel of every buffer judged, ids and depths (zero errors
// anywhere, with the renderer's own options), raster against ray compared (explained mismatches
// counted, within CONVENTIONS.md's budget on real meshes under general cameras), on the bundled meshes under framing and seeded random cameras, and on
// procedural stress scenes built to put samples on shared edges, ties, slivers, huge triangles and
// extreme depth ranges. Every case also renders the ray and brute paths with the raster-rule
// coverage, whose ids and depths must equal the raster path's bit for bit on every pixel. Each
// case prints one line, so a regression shows in the test log.
#include "catch.hpp"
#include "test_meshes.hpp"
#include "runtime/cl_runtime.hpp"
#include "shared/samples.h"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

using namespace clvis;

namespace {

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

const char* const bundled[] = {"stanford-bunny", "teapot", "spot", "suzanne"};

/// Deterministic on every standard library: mt19937_64's bits, turned into doubles by hand.
struct Random {
    std::mt19937_64 bits;
    explicit Random(std::uint64_t seed) : bits(seed) {}
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(bits() >> 11) * 0x1p-53; }
    Vec3 unit()
    {
        for (;;) {
            Vec3 v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
            double l = length(v);
            if (l > 0.1 && l <= 1) return v * (1 / l);
        }
    }
};

double norm(Vec3 v) { return std::fmax(std::fmax(std::fabs(v.x), std::fabs(v.y)), std::fabs(v.z)); }

/// The nearest `near` at which float32 keeps its promise for every vertex of the scene seen from
/// `eye` (see uncertainty() below): within a share of EPS in pixels and of the depth tolerance.
double rounding(const Scene& s, Vec3 eye)
{
    double m = 0;
    for (float v : s.world_positions()) m = std::fmax(m, std::fabs(double(v)));
    return (m + norm(eye)) * float_ulp;
}

double precise_near(const Scene& s, Vec3 eye, bool perspective, double fov_y, int height)
{
    double err = rounding(s, eye);
    double n = err / (depth_share * referee_depth_rel);
    if (perspective)
        n = std::fmax(n, err * height / (2 * std::tan(fov_y / 2 * pi / 180)) / (precision_share * referee_edge_eps));
    return n * 1.01; // clear of the bound whatever the rounding
}

/// The smallest orthographic view height that keeps the same promise (pixels grow with 1 / height).
double precise_ortho_height(const Scene& s, Vec3 eye, int height)
{
    return 1.01 * rounding(s, eye) * height / (precision_share * referee_edge_eps);
}

/// How far float32 rounding may move what a path sees, as CONVENTIONS.md estimates it: a vertex of
/// magnitude M (and the eye) is uncertain by M 2^-24 world units, which near a triangle's nearest
/// visible depth d is M 2^-24 / d relative and, under perspective, M 2^-24 H / (2 d tan(fov / 2))
/// pixels (the largest over the scene's triangles); and raster_rounding() px from the image size.
struct Uncertainty {
    double px = 0, depth = 0; ///< from world magnitudes
    double raster = 0;        ///< from raster-space magnitudes, px
};

double raster_rounding(int w, int h) { return raster_ops * (std::max(w, h) + 2 * guard_margin) * float_ulp; }

Uncertainty uncertainty(const Scene& s, const Camera& c, int width, int height)
{
    double eye = norm(c.eye);
    bool persp = c.projection == Projection::Perspective;
    double px_scale = persp ? height / (2 * std::tan(c.fov_y / 2 * pi / 180)) : height / c.ortho_height;
    if (c.intrinsics) px_scale = std::fmax(c.intrinsics->fx, c.intrinsics->fy);
    Uncertainty u;
    u.raster = raster_rounding(width, height);
    for (std::uint32_t id = 0; id < s.triangle_count(); ++id) {
        float v[9];
        s.triangle(id, v);
        double m = 0, d = 1e300;
        for (int k = 0; k < 3; ++k) {
            Vec3 p{v[3 * k], v[3 * k + 1], v[3 * k + 2]};
            m = std::fmax(m, norm(p));
            d = std::fmin(d, c.to_camera(p).z * -1);
        }
        d = std::fmax(d, c.near); // nothing nearer is seen
        double err = (m + eye) * float_ulp;
        u.depth = std::fmax(u.depth, err / d);
        u.px = std::fmax(u.px, persp ? err * px_scale / d : err * px_scale);
    }
    return u;
}

/// The referee's tolerance where float32 cannot honour CONVENTIONS.md's (its last precision
/// paragraph): the uncertainty above over its shares, never below EPS and 1e-6. Each case that
/// uses it says why in `reason`; the loosened values are printed with the case.
RefereeTolerance float32_tolerance(const Scene& s, const Camera& c, int w, int h, const char* reason)
{
    Uncertainty u = uncertainty(s, c, w, h);
    RefereeTolerance t;
    t.edge_eps = std::fmax(referee_edge_eps, std::fmax(u.px / precision_share, u.raster / raster_share) * 1.01);
    t.depth_rel = std::fmax(referee_depth_rel, u.depth / depth_share * 1.01);
    std::printf("agree tolerance %.2e px, %.2e relative (float32 cannot honour EPS: %s)\n", t.edge_eps, t.depth_rel,
                reason);
    return t;
}

struct Tally {
    std::size_t pixels = 0, explained = 0, cases = 0;
    double seconds = 0;
};

struct Frames {
    std::vector<HostVisibility> vis; ///< raster, ray, then brute when asked
};

std::string first_errors(const CompareReport& r)
{
    std::string s;
    for (const PixelVerdict& v : r.first_errors) s += "\n    " + v.describe();
    return s;
}

/// Keys of the raster path that differ between the atomic depth test and tile ownership
/// (RasterAtomics::On and Off), which must agree bit for bit; 0 where the device has no 64-bit
/// atomics (tile ownership is then the only raster path, and the frame above used it).
std::size_t raster_modes_differ(Renderer& renderer, const Scene& scene, const Camera& cam, int w, int h)
{
    if (!renderer.device().info().int64_atomics) return 0;
    RenderOptions other = renderer.options(); // Auto is On on such a device: draw the other mode
    other.raster_atomics = other.raster_atomics == RasterAtomics::Off ? RasterAtomics::On : RasterAtomics::Off;
    std::vector<std::uint64_t> a = renderer.render(cam, w, h, Path::Raster).read_keys();
    std::vector<std::uint64_t> b = Renderer(renderer.device(), scene, other).render(cam, w, h, Path::Raster).read_keys();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
    return differ;
}

/// The ray path (and the brute path) with Coverage::RasterRule on a twin of `renderer` (the same
/// scene and options): their ids and depths must equal the raster path's bit for bit, every
/// pixel. Returns the pixels that differ (summed over the paths).
std::size_t raster_rule_differ(const Renderer& renderer, const Scene& scene, const Camera& cam, int w, int h,
                               bool brute, const HostVisibility& raster)
{
    RenderOptions o = renderer.options();
    o.coverage = Coverage::RasterRule;
    Renderer twin(renderer.device(), scene, o);
    std::size_t differ = 0;
    // The brute path walks every triangle in one loop per work-item, with the raster rule's
    // clipper inside: on a driver that ends a work-item's loops after a fixed count (llvmpipe's
    // 65535, kernels/device_probe.cl) it is cut short, a known limit of the brute path (the BVH
    // path stays far below it). Checked on every device without such a cap.
    Device device = renderer.device();
    bool capped = device.impl()->loop_limit() != Device::Impl::loop_unlimited;
    for (Path p : {Path::Ray, Path::Brute}) {
        if (p == Path::Brute && (!brute || capped)) continue;
        std::size_t d = test::differing_bits(raster, twin.render(cam, w, h, p).read());
        INFO(to_string(p) << " path, raster-rule coverage: " << d << " pixels differ from the raster path's");
        CHECK(d == 0);
        differ += d;
    }
    return differ;
}

/// Renders one frame with both paths (and the brute path), judges every pixel of each with the
/// referee, checks ids and, optionally, agreement with reference(); compares raster with ray, the
/// raster path's two depth tests (raster_modes_differ) and the ray paths' raster rule with the
/// raster path (raster_rule_differ).
Frames agree(Renderer& renderer, const Scene& scene, const std::string& name, const Camera& cam, int w, int h,
             bool brute, bool with_reference, Tally& tally, RefereeTolerance tol = {})
{
    auto t0 = std::chrono::steady_clock::now();
    INFO("case " << name << " " << w << "x" << h << ": " << cam.to_flags());
    Uncertainty unc = uncertainty(scene, cam, w, h);
    REQUIRE(unc.px <= precision_share * tol.edge_eps);
    REQUIRE(unc.raster <= raster_share * tol.edge_eps);
    REQUIRE(unc.depth <= depth_share * tol.depth_rel);

    Referee ref(scene, cam, w, h, renderer.options(), tol);
    std::vector<Path> paths = {Path::Raster, Path::Ray};
    if (brute) paths.push_back(Path::Brute);
    Frames f;
    char line[512];
    int len = std::snprintf(line, sizeof line, "agree %-34s %5dx%-5d", name.c_str(), w, h);
    CompareOptions options;
    options.max_reported = 5;
    // Depths: the gradient's share of the tolerance over CONVENTIONS.md's 1/65536 px, or over
    // what float32 leaves of the positions when that is more (the vertices' uncertainty above,
    // and about max(w, h) 2^-24 px per operation in raster space), printed as "zpx".
    options.depth_px = std::fmax(referee_depth_judge_px, 2 * std::fmax(unc.px, std::max(w, h) * float_ulp));
    for (Path p : paths) {
        f.vis.push_back(renderer.render(cam, w, h, p).read());
        const HostVisibility& v = f.vis.back();
        REQUIRE(v.samples == renderer.options().samples);
        REQUIRE(v.ids.size() == std::size_t(w) * std::size_t(h) * std::size_t(v.samples));
        std::size_t invalid = 0, covered = 0;
        for (std::uint32_t id : v.ids) {
            invalid += id != background_id && id >= scene.triangle_count();
            covered += id != background_id;
        }
        CompareReport r = ref.check(v, options);
        INFO(to_string(p) << " path: " << r.errors << " errors, " << r.depth_errors << " depth errors, " << invalid
                          << " invalid ids" << first_errors(r));
        CHECK(invalid == 0);
        CHECK(r.errors == 0);
        CHECK(r.depths_judged);
        CHECK(r.depth_errors == 0);
        if (with_reference && v.samples == 1) { // reference() answers at pixel centres
            std::size_t differ = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    bool ambiguous = false;
                    std::uint32_t id = ref.reference(x, y, &ambiguous);
                    differ += !ambiguous && v.id(x, y) != id;
                }
            CHECK(differ == 0);
        }
        len += std::snprintf(line + len, sizeof line - len, " | %s %zu err %zu zerr %zu cov", to_string(p), r.errors,
                             r.depth_errors, covered);
    }
    std::size_t modes_differ = raster_modes_differ(renderer, scene, cam, w, h);
    CHECK(modes_differ == 0);
    len += std::snprintf(line + len, sizeof line - len, " | atomics/tiles %zu differ", modes_differ);
    std::size_t rule_differ = raster_rule_differ(renderer, scene, cam, w, h, brute, f.vis[0]);
    len += std::snprintf(line + len, sizeof line - len, " | rule %zu differ", rule_differ);
    CompareReport rr = ref.compare(f.vis[0], f.vis[1], options);
    INFO("raster vs ray" << first_errors(rr));
    CHECK(rr.errors == 0);
    CHECK(rr.depth_errors == 0);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s | raster/ray %zu explained | unc %.1e px %.1e raster px %.1e rel | zpx %.1e | %.2f s\n", line,
                rr.explained, unc.px, unc.raster, unc.depth, options.depth_px, seconds);
    std::fflush(stdout);
    tally.pixels += rr.pixels; // samples
    tally.explained += rr.explained;
    tally.cases += 1;
    tally.seconds += seconds;
    return f;
}

void check_budget(const Tally& t, const char* what)
{
    double share = t.pixels ? double(t.explained) / double(t.pixels) : 0;
    std::printf("agree %s: %zu cases, %zu pixels, %zu explained (%.5f %%), %.1f s\n", what, t.cases, t.pixels,
                t.explained, 100 * share, t.seconds);
    CHECK(t.cases > 0);
    CHECK(share <= explained_budget);
}

enum class View { Outside, OrthoOutside, Grazing, Inside, Close };

const char* to_string(View v)
{
    switch (v) {
    case View::Outside: return "outside";
    case View::OrthoOutside: return "ortho";
    case View::Grazing: return "grazing";
    case View::Inside: return "inside";
    case View::Close: return "close";
    }
    return "?";
}

/// A point on the surface of a random (non-degenerate) triangle, and its unit normal.
void surface_point(const Scene& s, Random& rng, Vec3* p, Vec3* n)
{
    for (;;) {
        float v[9];
        s.triangle(std::uint32_t(rng.uniform(0, double(s.triangle_count()))) % s.triangle_count(), v);
        Vec3 a{v[0], v[1], v[2]}, b{v[3], v[4], v[5]}, c{v[6], v[7], v[8]};
        Vec3 nn = cross(b - a, c - a);
        if (length(nn) > 0) {
            *p = (a + b + c) * (1.0 / 3);
            *n = normalize(nn);
            return;
        }
    }
}

Vec3 up_for(Vec3 eye, Vec3 target)
{
    Vec3 f = normalize(target - eye);
    return std::fabs(f.y) > 0.95 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
}

/// A seeded random camera of the given kind, with near no closer than float32 allows at `height`.
Camera random_camera(const Scene& s, View kind, Random& rng, int height)
{
    Bounds b = s.bounds();
    Vec3 c = b.center();
    double r = length(b.extent()) / 2;
    double fov = rng.uniform(25, 90);
    Vec3 eye, target;
    double near_wish = 0;
    switch (kind) {
    case View::Outside:
    case View::OrthoOutside: {
        double dist = r * rng.uniform(1.3, 4);
        eye = c + rng.unit() * dist;
        target = c + rng.unit() * (0.3 * r);
        near_wish = 0.8 * (dist - r);
        break;
    }
    case View::Grazing: {
        Vec3 p, n;
        surface_point(s, rng, &p, &n);
        Vec3 t = normalize(cross(n, rng.unit()));
        eye = p + n * (r * rng.uniform(0.01, 0.08)) - t * (r * rng.uniform(0.3, 1.2));
        target = p + t * (0.5 * r);
        break;
    }
    case View::Inside:
        eye = c + rng.unit() * (0.2 * r);
        target = eye + rng.unit();
        break;
    case View::Close: {
        // The eye nearer to the surface than near: the triangles around it cross the near plane.
        Vec3 p, n;
        surface_point(s, rng, &p, &n);
        double n0 = precise_near(s, p, true, fov, height);
        eye = p + n * (n0 * rng.uniform(0.2, 0.8));
        target = p - n * r + normalize(cross(n, rng.unit())) * (r * rng.uniform(0, 0.7));
        break;
    }
    }
    bool persp = kind != View::OrthoOutside;
    double n0 = precise_near(s, eye, persp, fov, height);
    double near = std::fmax(n0, near_wish);
    double far = std::fmax(length(eye - c) + 2 * r, 2 * near);
    Vec3 up = up_for(eye, target);
    if (!persp) {
        double oh = std::fmax(r * rng.uniform(0.4, 3), precise_ortho_height(s, eye, height));
        return Camera::orthographic(eye, target, up, oh, near, far);
    }
    return Camera::perspective(eye, target, up, fov, near, far);
}

Scene load_bundled(const std::string& name)
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + name + ".obj"));
    return s;
}

/// An n x n grid of quads of size `step` from (x0, y0) at z, split along alternating diagonals
/// (vertices shared by four and by eight triangles).
MeshData grid(int n, double x0, double y0, double step, double z)
{
    MeshData m;
    m.name = "grid";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            m.positions.insert(m.positions.end(), {float(x0 + i * step), float(y0 + j * step), float(z)});
    test::add_grid_triangles(m, n);
    return m;
}

MeshData triangles(std::vector<float> positions, const char* name)
{
    MeshData m;
    m.name = name;
    m.positions = std::move(positions);
    for (std::uint32_t i = 0; i < m.positions.size() / 3; ++i) m.indices.push_back(i);
    return m;
}

Mat4 scale(double s)
{
    Mat4 m;
    m(0, 0) = m(1, 1) = m(2, 2) = s;
    return m;
}

Mat4 rotate_y(double radians, Vec3 offset = {})
{
    Mat4 m;
    m(0, 0) = std::cos(radians);
    m(0, 2) = std::sin(radians);
    m(2, 0) = -std::sin(radians);
    m(2, 2) = std::cos(radians);
    m(0, 3) = offset.x;
    m(1, 3) = offset.y;
    m(2, 3) = offset.z;
    return m;
}

/// Pixels whose centre lies strictly inside [x0, x1] x [y0, y1] in raster space and shows the
/// background.
std::size_t holes(const HostVisibility& v, double x0, double x1, double y0, double y1)
{
    std::size_t n = 0;
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x)
            if (x + 0.5 > x0 && x + 0.5 < x1 && y + 0.5 > y0 && y + 0.5 < y1) n += v.id(x, y) == background_id;
    return n;
}

} // namespace

TEST_CASE("both paths give acceptable answers on every pixel of the bundled meshes", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    Random rng(20261124);
    for (const char* mesh : bundled) {
        Scene s = load_bundled(mesh);
        Renderer renderer(device, s);
        bool small = s.triangle_count() < 10000;
        std::string m = mesh;
        Camera framing = Camera::framing(s.bounds());
        Frames f = agree(renderer, s, m + " framing", framing, 160, 120, false, false, tally);
        // The same judge rejects a corrupted copy: the checks above can fail.
        Referee ref(s, framing, 160, 120);
        HostVisibility bad = f.vis[0];
        std::size_t centre = 60 * 160 + 80;
        REQUIRE(bad.ids[centre] != background_id);
        bad.ids[centre] = background_id;
        bad.ids[centre + 1] = bad.ids[centre + 1] == 0 ? 1 : 0;
        bad.ids[centre + 2] = std::uint32_t(s.triangle_count());
        CompareReport r = ref.check(bad);
        CHECK(r.errors == 3);
        REQUIRE(r.first_errors.size() == 3);
        CHECK(r.first_errors[0].error == AnswerError::Missed);
        CHECK(r.first_errors[1].error != AnswerError::None);
        CHECK(r.first_errors[2].error == AnswerError::InvalidId);
        // ... and a copy with a depth 1e-4 off and a finite background depth.
        HostVisibility bad_depth = f.vis[0];
        REQUIRE(bad_depth.ids[0] == background_id);
        bad_depth.depth[0] = 5;
        bad_depth.depth[centre] *= 1.0001f;
        CompareReport rz = ref.check(bad_depth);
        CHECK(rz.errors == 0);
        CHECK(rz.depth_errors == 2);
        agree(renderer, s, m + " framing ortho", Camera::framing(s.bounds(), Projection::Orthographic), 160, 120,
              false, false, tally);
        agree(renderer, s, m + " framing", framing, 1, 1, true, true, tally);
        agree(renderer, s, m + " framing", framing, 3, 7, true, true, tally);
        agree(renderer, s, m + " framing wide", framing, 400, 30, false, false, tally);
        agree(renderer, s, m + " framing", framing, 48, 36, small, true, tally);
        for (View kind : {View::Outside, View::OrthoOutside, View::Grazing, View::Inside, View::Close}) {
            Camera cam = random_camera(s, kind, rng, 96);
            agree(renderer, s, m + " " + to_string(kind), cam, 128, 96, false, false, tally);
            agree(renderer, s, m + " " + to_string(kind), cam, 3, 7, true, true, tally);
        }
    }
    check_budget(tally, "bundled meshes");
}

#ifdef CLVIS_HAVE_TINYGLTF
TEST_CASE("the Khronos glTF sample models Debian ships, no error on either path", "[device][agree][gltf]")
{
    // assimp-testmodels' copies of Khronos samples (glTF-Sample-Models, the glTF Asset Generator's
    // triangle modes, the tutorial's skin and camera scenes): .glb, embedded and external buffers.
    const std::string root = "/usr/share/assimp/models/glTF2/";
    const char* const models[] = {
        "2CylinderEngine-glTF-Binary/2CylinderEngine.glb", "BoxTextured-glTF-Binary/BoxTextured.glb",
        "BoxTextured-glTF-Embedded/BoxTextured.gltf", "BoxTextured-glTF/BoxTextured.gltf",
        "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", "ClearCoat-glTF/ClearCoatTest.gltf",
        "textureTransform/TextureTransformTest.gltf", "cameras/Cameras.gltf", "simple_skin/simple_skin.gltf",
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf",
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf",
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf",
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf"};
    Device device = Device::open();
    Tally tally;
    Random rng(20);
    for (const char* model : models) {
        Scene s = load_scene({root + model});
        Renderer renderer(device, s);
        std::string m = std::string(model).substr(std::string(model).rfind('/') + 1);
        agree(renderer, s, m + " framing", Camera::framing(s.bounds()), 160, 120, false, false, tally);
        agree(renderer, s, m + " framing ortho", Camera::framing(s.bounds(), Projection::Orthographic), 96, 72,
              false, false, tally);
        Camera cam = random_camera(s, View::Outside, rng, 96);
        agree(renderer, s, m + " outside", cam, 128, 96, false, false, tally);
        agree(renderer, s, m + " outside", cam, 5, 4, true, true, tally);
    }
    check_budget(tally, "Khronos glTF samples");
}
#endif

TEST_CASE("both paths are right on the bundled meshes from many cameras at larger sizes",
          "[device][agree][slow]")
{
    Device device = Device::open();
    Tally tally;
    Random rng(7);
    for (const char* mesh : bundled) {
        Scene s = load_bundled(mesh);
        Renderer renderer(device, s);
        std::string m = mesh;
        agree(renderer, s, m + " framing", Camera::framing(s.bounds()), 1280, 720, false, false, tally);
        agree(renderer, s, m + " framing ortho", Camera::framing(s.bounds(), Projection::Orthographic), 640, 480,
              false, false, tally);
        for (int k = 0; k < 12; ++k)
            for (View kind : {View::Outside, View::OrthoOutside, View::Grazing, View::Inside, View::Close}) {
                Camera cam = random_camera(s, kind, rng, 360);
                agree(renderer, s, m + " " + to_string(kind) + " " + std::to_string(k), cam, 480, 360, false, false,
                      tally);
            }
    }
    Scene bunny = load_bundled("stanford-bunny");
    Renderer renderer(device, bunny);
    agree(renderer, bunny, "stanford-bunny framing", Camera::framing(bunny.bounds()), 1920, 1080, false, false, tally);
    check_budget(tally, "bundled meshes, larger");
}

TEST_CASE("a plane face-on, samples on shared edges and vertices, no error, no hole", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    // One world unit per pixel with vertices on pixel centres: world (x, y) is raster (x, 64 - y).
    Scene s;
    s.add_mesh(grid(40, 12.5, 12.5, 1, 0));
    Renderer renderer(device, s);
    Camera ortho = Camera::orthographic({32, 32, 20}, {32, 32, 0}, {0, 1, 0}, 64, 15, 100);
    for (const auto& f : {agree(renderer, s, "plane face-on ortho", ortho, 64, 64, true, true, tally),
                          // fov 90 at distance 32: the same mapping, up to tan's rounding
                          agree(renderer, s, "plane face-on persp", Camera::perspective({32, 32, 32}, {32, 32, 0},
                                                                                        {0, 1, 0}, 90, 16, 100),
                                64, 64, true, true, tally)})
        for (std::size_t p = 0; p < f.vis.size(); ++p) {
            INFO("path " << p);
            CHECK(holes(f.vis[p], 12.5, 52.5, 64 - 52.5, 64 - 12.5) == 0);
        }
    // Half-pixel steps, rotated by an irrational angle: edges at every slope.
    Scene tilted;
    tilted.add_mesh(grid(60, -15, -15, 0.5, 0), rotate_y(0.3, {32, 32, -5}));
    Renderer r2(device, tilted);
    agree(r2, tilted, "plane tilted persp", Camera::perspective({30, 40, 30}, {32, 32, -5}, {0, 1, 0}, 60, 12, 100),
          96, 80, true, true, tally);
    agree(r2, tilted, "plane tilted ortho", Camera::orthographic({30, 40, 30}, {32, 32, -5}, {0, 1, 0}, 40, 12, 100),
          96, 80, true, true, tally);
    std::printf("agree plane face-on: %zu explained (on edges by construction: judged on errors alone)\n",
                tally.explained);
}

TEST_CASE("2 to 16 samples per pixel: both paths judged at every sample", "[device][agree][samples]")
{
    Device device = Device::open();
    Tally tally, on_edges;
    Random rng(20261202);
    // Vertices on pixel centres, one world unit per pixel (raster (x, 24 - y)): the samples' 1/16 px
    // offsets put many of them exactly on shared edges and vertices (the top-left rule at every
    // sample; judged on errors alone, like the face-on plane above).
    Scene plane;
    plane.add_mesh(grid(14, 4.5, 4.5, 1, 0));
    Scene bunny = load_bundled("stanford-bunny");
    Camera ortho = Camera::orthographic({12, 12, 20}, {12, 12, 0}, {0, 1, 0}, 24, 15, 100);
    for (int n : {2, 4, 8, 16}) {
        RenderOptions o;
        o.samples = n;
        std::string tag = std::to_string(n) + " samples ";
        Renderer rp(device, plane, o);
        Frames f = agree(rp, plane, tag + "plane face-on ortho", ortho, 24, 24, true, false, on_edges);
        for (const HostVisibility& v : f.vis) {
            std::size_t holes_inside = 0; // every sample of the pixels inside the grid is covered
            for (int y = 6; y <= 18; ++y)
                for (int x = 5; x <= 17; ++x)
                    for (int k = 0; k < n; ++k) holes_inside += v.id(x, y, k) == background_id;
            CHECK(holes_inside == 0);
        }
        Renderer rb(device, bunny, o);
        agree(rb, bunny, tag + "bunny framing", Camera::framing(bunny.bounds()), 32, 24, false, false, tally);
        agree(rb, bunny, tag + "bunny close", random_camera(bunny, View::Close, rng, 16), 16, 16, false, false,
              tally);
    }
    check_budget(tally, "samples per pixel");
    std::printf("agree samples on a plane face-on: %zu explained (on edges by construction)\n", on_edges.explained);
}

TEST_CASE("several samples: sample k is where samples.h puts it; shading averages", "[device][samples]")
{
    // A half-plane x < 16.5 + 1/32 px (ortho, one world unit per pixel): sample k of a pixel in
    // column 16, at x = 16.5 + dx_k / 16, is covered exactly when dx_k / 16 < 1/32: dx_k <= 0.
    Device device = Device::open();
    Scene s;
    s.add_mesh(triangles({-100, -100, 0, 16.53125f, -100, 0, 16.53125f, 100, 0, -100, -100, 0, 16.53125f, 100, 0,
                          -100, 100, 0},
                         "half-plane"));
    Camera cam = Camera::orthographic({16, 16, 20}, {16, 16, 0}, {0, 1, 0}, 32, 15, 100);
    for (int n : {1, 2, 4, 8, 16}) {
        RenderOptions o;
        o.samples = n;
        Renderer r(device, s, o);
        for (Path p : {Path::Raster, Path::Ray, Path::Brute}) {
            INFO(n << " samples, " << to_string(p) << " path");
            HostVisibility v = r.render(cam, 32, 32, p).read();
            REQUIRE(v.samples == n);
            int log2n = samples_log2(n);
            for (int k = 0; k < n; ++k) {
                int dx = clvis_sample_offset(log2n, k, 0);
                CHECK((v.id(16, 9, k) != background_id) == (dx * 2 < 1));
                CHECK(v.id(15, 9, k) != background_id);
                CHECK(v.id(17, 9, k) == background_id);
            }
        }
        Image img = shade(r, r.render(cam, 32, 32, Path::Raster), cam, {});
        int covered = 0;
        for (int k = 0; k < n; ++k) covered += clvis_sample_offset(samples_log2(n), k, 0) * 2 < 1;
        std::uint8_t lit = img.rgba[(9 * 32 + 15) * 4], bg = img.rgba[(9 * 32 + 17) * 4];
        std::uint8_t edge = img.rgba[(9 * 32 + 16) * 4];
        INFO(n << " samples: lit " << int(lit) << ", edge " << int(edge) << ", background " << int(bg));
        // The edge pixel is the mean of its samples' colours (within the 8-bit rounding).
        double expected = (covered * double(lit) + (n - covered) * double(bg)) / n;
        CHECK(std::fabs(double(edge) - expected) <= 1.0);
    }
}

TEST_CASE("a tessellated plane edge-on and at grazing angles, no errors", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    Scene s;
    MeshData g = grid(50, -50, -50, 2, 0);
    for (std::size_t v = 0; v < g.positions.size(); v += 3) std::swap(g.positions[v + 1], g.positions[v + 2]);
    s.add_mesh(g); // the plane y = 0, x and z in [-50, 50]
    Renderer renderer(device, s);
    // The eye in the plane: it is seen exactly edge-on; an odd height puts a row on its horizon.
    Camera edge_on = Camera::perspective({0, 0, 30}, {0, 0, -50}, {0, 1, 0}, 60, 15, 200);
    Frames f = agree(renderer, s, "plane edge-on", edge_on, 121, 81, true, true, tally);
    for (const HostVisibility& v : f.vis) CHECK(std::count(v.ids.begin(), v.ids.end(), background_id) == 121 * 81);
    for (double h : {1e-3, 1e-2, 0.3}) {
        Camera grazing = Camera::perspective({0.3, h, 45}, {10, 0, -50}, {0, 1, 0}, 50, 15, 200);
        agree(renderer, s, "plane grazing h=" + std::to_string(h), grazing, 161, 121, false, false, tally);
    }
    agree(renderer, s, "plane grazing ortho",
          Camera::orthographic({0, 0.5, 60}, {0, 0, -50}, {0, 1, 0}, 4, 15, 200), 160, 120, false, false, tally);
}

TEST_CASE("coincident triangles go to the lower id; intersecting ones give no error", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    Scene s;
    MeshData sphere = make_uv_sphere(1500);
    std::size_t n = sphere.triangle_count();
    s.add_mesh(sphere);                                   // ids [0, n)
    s.add_mesh(sphere);                                   // the same triangles again: [n, 2n)
    s.add_mesh(sphere, rotate_y(0.7, {0.35, 0.1, 0.2}));  // through the first
    // Two large triangles crossing at a shallow angle, in front of the spheres.
    s.add_mesh(triangles({-3, -3, 1.6f, 3, -3, 1.6f, 0, 3, 1.6f, -3, -3, 1.4f, 3, -3, 1.4f, 0, 3, 1.9f}, "crossing"));
    Renderer renderer(device, s);
    Random rng(99);
    std::vector<Camera> cams = {Camera::framing(s.bounds()), Camera::framing(s.bounds(), Projection::Orthographic)};
    for (int k = 0; k < 3; ++k) cams.push_back(random_camera(s, View::Outside, rng, 96));
    cams.push_back(random_camera(s, View::Inside, rng, 96));
    for (std::size_t k = 0; k < cams.size(); ++k) {
        Frames f = agree(renderer, s, "coincident+intersecting " + std::to_string(k), cams[k], 128, 96, k < 2,
                         k < 2, tally);
        for (std::size_t p = 0; p < f.vis.size(); ++p) {
            std::size_t copy_wins = 0;
            for (std::uint32_t id : f.vis[p].ids) copy_wins += id >= n && id < 2 * n;
            INFO("path " << p << ": the copy's higher id won " << copy_wins << " exact ties");
            CHECK(copy_wins == 0);
        }
    }
}

TEST_CASE("slivers, needles and zero-area triangles, no errors", "[device][agree][rusticl]")
{
    Device device = Device::open();
    Tally tally;
    std::vector<float> fan;
    // 2000 triangles of 0.18 degrees around (32, 32): samples near the centre lie within EPS of many.
    const int k = 2000;
    for (int i = 0; i < k; ++i) {
        double a0 = 2 * pi * i / k, a1 = 2 * pi * (i + 1) / k;
        fan.insert(fan.end(), {32, 32, 0, float(32 + 30 * std::cos(a0)), float(32 + 30 * std::sin(a0)), 0,
                               float(32 + 30 * std::cos(a1)), float(32 + 30 * std::sin(a1)), 0});
    }
    std::vector<float> needles;
    Random rng(5);
    for (int i = 0; i < 300; ++i) {
        double x = rng.uniform(4, 60), y = rng.uniform(4, 60), a = rng.uniform(0, pi), l = rng.uniform(5, 40);
        double w = std::pow(10.0, rng.uniform(-4, -1)), z = rng.uniform(0.5, 2);
        double dx = std::cos(a) * l / 2, dy = std::sin(a) * l / 2, nx = -std::sin(a) * w, ny = std::cos(a) * w;
        needles.insert(needles.end(), {float(x - dx), float(y - dy), float(z), float(x + dx), float(y + dy), float(z),
                                       float(x - dx + nx), float(y - dy + ny), float(z)});
        // and a zero-area one: a repeated vertex
        needles.insert(needles.end(), {float(x - dx), float(y - dy), float(z), float(x + dx), float(y + dy), float(z),
                                       float(x + dx), float(y + dy), float(z)});
    }
    Scene s;
    s.add_mesh(triangles(fan, "fan"));
    s.add_mesh(triangles(needles, "needles"));
    Renderer renderer(device, s);
    agree(renderer, s, "slivers ortho", Camera::orthographic({32, 32, 40}, {32, 32, 0}, {0, 1, 0}, 64, 15, 100), 64, 64,
          true, true, tally);
    agree(renderer, s, "slivers persp", Camera::perspective({25, 20, 40}, {32, 32, 0}, {0, 1, 0}, 70, 18, 100), 96,
          96, true, true, tally);
    agree(renderer, s, "slivers persp 3x7", Camera::perspective({25, 20, 40}, {32, 32, 0}, {0, 1, 0}, 70, 18, 100),
          3, 7, true, true, tally);
}

TEST_CASE("triangles far larger than the frustum, behind the eye, across near, no error", "[device][agree][rusticl]")
{
    Device device = Device::open();
    Tally tally;
    Scene s;
    // Under a 2 degree field of view the frustum is 0.1 wide at depth 3: these are 40 times larger.
    // The second meets the first along y = 0.03, in the middle of the view.
    s.add_mesh(triangles({-2, -2, -3, 2, -2, -3, 0, 2, -3,                  // facing
                          -2, -2, -2.9f, 2, -2, -2.9f, 0, 2, -3.097f,       // crossing it in view
                          -2, -2, 3, 2, -2, 3, 0, 2, 3},                    // behind the eye
                         "huge"));
    Renderer renderer(device, s);
    Camera narrow = Camera::perspective({0, 0, 0}, {0, 0.01, -1}, {0, 1, 0}, 2, 2.5, 10);
    agree(renderer, s, "huge narrow", narrow, 96, 72, true, true, tally);
    agree(renderer, s, "huge narrow wide", narrow, 300, 20, true, true, tally);

    // A ground from behind the eye to far ahead, a wall and a tilted sheet, under 60 degrees.
    Scene g;
    g.add_mesh(triangles({-30, -1, 10, 30, -1, 10, 0, -1, -40,           // ground, crossing near
                          -60, -60, -35, 60, -60, -35, 0, 60, -35,       // wall
                          -40, 30, -20, 40, 30, -20, 0, -30, -38},       // sheet through ground and wall
                         "ground"));
    Renderer rg(device, g);
    Camera wide = Camera::perspective({0, 0, 0}, {0, -0.05, -1}, {0, 1, 0}, 60, 1, 100);
    wide.near = precise_near(g, wide.eye, true, 60, 96);
    agree(rg, g, "huge ground across near", wide, 128, 96, true, true, tally);
    Camera wide_ortho = Camera::orthographic({0, 0, 0}, {0, -0.05, -1}, {0, 1, 0}, 8, 1, 100);
    wide_ortho.near = precise_near(g, wide.eye, false, 0, 96);
    agree(rg, g, "huge ground ortho", wide_ortho, 128, 96, true, true, tally);
}

TEST_CASE("soups of intersecting triangles, and triangles all around the eye, no error", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    Random rng(11);
    Scene soup;
    soup.add_mesh(make_soup(3000, 17));
    Renderer rs(device, soup);
    agree(rs, soup, "soup framing", Camera::framing(soup.bounds()), 128, 96, true, true, tally);
    agree(rs, soup, "soup framing ortho", Camera::framing(soup.bounds(), Projection::Orthographic), 128, 96, false,
          false, tally);
    agree(rs, soup, "soup inside", random_camera(soup, View::Inside, rng, 96), 128, 96, false, false, tally);

    // Triangles with vertices in a ball of radius 1 around the eye at the origin: most cross the
    // near plane or the eye's plane, some have vertices behind the eye.
    std::vector<float> v;
    for (int i = 0; i < 400; ++i) {
        Vec3 c = rng.unit() * rng.uniform(0.2, 1);
        for (int k = 0; k < 3; ++k) {
            Vec3 p = c + rng.unit() * rng.uniform(0.05, 0.6);
            v.insert(v.end(), {float(p.x), float(p.y), float(p.z)});
        }
    }
    Scene around;
    around.add_mesh(triangles(v, "around the eye"));
    Renderer ra(device, around);
    for (int k = 0; k < 4; ++k) {
        Vec3 eye{0, 0, 0};
        double fov = rng.uniform(40, 120);
        Camera cam = Camera::perspective(eye, rng.unit(), {0, 1, 0}, fov, precise_near(around, eye, true, fov, 96),
                                         3);
        agree(ra, around, "around the eye " + std::to_string(k), cam, 128, 96, k < 2, k < 2, tally);
    }
}

TEST_CASE("triangles seen edge-on, in planes through pixel-centre rays, no error", "[device][agree]")
{
    // Each triangle lies in a plane through the eye that contains the primary ray of a pixel
    // centre, near that ray but off it: the ray meets the plane everywhere and the triangle
    // nowhere. Float rounding makes edge functions of such rays cancel to exactly zero.
    Device device = Device::open();
    Tally tally;
    Random rng(41);
    const int w = 64, h = 48;
    for (int k = 0; k < 60; ++k) {
        Vec3 eye{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        Camera cam = Camera::perspective(eye, eye + Vec3{rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), -1},
                                         {0, 1, 0}, 60, 1, 50);
        std::vector<float> v;
        for (int i = 0; i < 300; ++i) {
            Ray ray = cam.primary_ray(std::floor(rng.uniform(0, w)) + 0.5, std::floor(rng.uniform(0, h)) + 0.5, w, h);
            Vec3 d1 = normalize(ray.direction), d2 = normalize(cross(d1, rng.unit()));
            double size = rng.uniform(0.01, 0.5);
            Vec3 base = eye + d1 * rng.uniform(3, 8);
            for (int j = 0; j < 3; ++j) {
                Vec3 p = base + d2 * (size * (j < 2 ? rng.uniform(0.05, 1) : rng.uniform(-1, 1))) + d1 * rng.uniform(-1, 1);
                v.insert(v.end(), {float(p.x), float(p.y), float(p.z)});
            }
        }
        Scene s;
        s.add_mesh(triangles(v, "edge-on"));
        cam.near = precise_near(s, eye, true, 60, h);
        Renderer renderer(device, s);
        agree(renderer, s, "edge-on triangles " + std::to_string(k), cam, w, h, true, true, tally);
    }
}

TEST_CASE("surfaces 4e-6 inside or outside near and far, and layers 3e-6 apart", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    // The camera at the origin looks down -z: a rectangle of screen positions at view depth d.
    auto rect = [](std::vector<float>& out, double sx0, double sx1, double sy0, double sy1, double d0, double d1) {
        auto p = [&](double sx, double sy, double d) {
            out.insert(out.end(), {float(sx * d), float(sy * d), float(-d)});
        };
        p(sx0, sy0, d0), p(sx1, sy0, d1), p(sx1, sy1, d1);
        p(sx0, sy0, d0), p(sx1, sy1, d1), p(sx0, sy1, d0);
    };
    const double near = 1, far = 100, in = 1 + 4e-6, out = 1 - 4e-6;
    std::vector<float> v;
    rect(v, -0.85, -0.45, -0.5, 0.5, near * out, near * out); // ids 0-1: before near, clipped
    rect(v, -0.85, -0.45, -0.5, 0.5, near * in, near * in);   // ids 2-3: just behind near, seen
    rect(v, -0.85, -0.45, -0.5, 0.5, 50, 50);                 // ids 4-5: a backdrop
    rect(v, -0.4, 0, -0.5, 0.5, far / out, far / out);        // ids 6-7: beyond far, clipped
    rect(v, 0.05, 0.4, -0.5, 0.5, far * out, far * out);      // ids 8-9: just before far, seen
    // Two tilted layers, the far one (lower ids) 3e-6 deeper along every ray.
    std::vector<float> front;
    rect(front, 0.45, 0.85, -0.5, 0.5, 5, 20);
    for (float f : front) v.push_back(float(f * (1 + 3e-6))); // ids 10-11
    v.insert(v.end(), front.begin(), front.end());            // ids 12-13
    Scene s;
    s.add_mesh(triangles(v, "tolerances"));
    Renderer renderer(device, s);
    Camera cam = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, near, far);
    for (auto [w, h] : {std::pair{96, 64}, {301, 201}}) {
        Frames f = agree(renderer, s, "near/far/layers " + std::to_string(w), cam, w, h, true, true, tally);
        for (std::size_t p = 0; p < f.vis.size(); ++p) {
            std::size_t seen[14] = {};
            for (std::uint32_t id : f.vis[p].ids)
                if (id < 14) ++seen[id];
            INFO("path " << p);
            CHECK(seen[0] + seen[1] + seen[6] + seen[7] + seen[10] + seen[11] == 0);
            CHECK(seen[2] + seen[3] > 0);
            CHECK(seen[8] + seen[9] > 0);
            CHECK(seen[12] + seen[13] > 0);
        }
    }
    Camera ortho = Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 4, near, far);
    agree(renderer, s, "near/far/layers ortho", ortho, 96, 64, true, true, tally);
}

TEST_CASE("extreme aspects and fields of view, any up, far cuts, tile and leaf sizes", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    Random rng(23);
    Scene s = load_bundled("spot");
    Bounds b = s.bounds();
    Vec3 c = b.center();
    double r = length(b.extent()) / 2;
    Renderer renderer(device, s);
    Camera framing = Camera::framing(b);
    agree(renderer, s, "spot tall", framing, 1, 200, true, true, tally);
    Camera near_view = framing; // 1.6 r away, looking at a point of the surface
    Vec3 p, n;
    surface_point(s, rng, &p, &n);
    near_view.eye = p + n * (1.6 * r);
    near_view.target = p;
    near_view.near = precise_near(s, near_view.eye, true, 45, 1);
    agree(renderer, s, "spot long", near_view, 500, 1, true, true, tally);
    agree(renderer, s, "spot long", near_view, 997, 3, true, true, tally);
    // Far through the middle of the mesh: samples on the far plane's cut.
    Camera cut = framing;
    cut.far = length(cut.eye - c);
    agree(renderer, s, "spot far cut", cut, 128, 96, false, true, tally);
    {
        Vec3 eye = c + rng.unit() * (1.5 * r);
        Vec3 up = rng.unit(); // any up vector not along the view
        Camera cam = Camera::perspective(eye, c, up, 170, precise_near(s, eye, true, 170, 96), length(eye - c) + 2 * r);
        agree(renderer, s, "spot fov 170", cam, 128, 96, false, true, tally);
    }
    {
        // A 5 degree view from far away: float32 keeps EPS only with the eye near the origin, so
        // the mesh moves out there (the scene moves, not the camera).
        Vec3 at = rng.unit() * (r / std::tan(2.5 * pi / 180));
        Mat4 move;
        move(0, 3) = at.x - c.x;
        move(1, 3) = at.y - c.y;
        move(2, 3) = at.z - c.z;
        Scene far_spot;
        far_spot.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"), move);
        Renderer rf(device, far_spot);
        Vec3 eye{0, 0, 0};
        Camera cam = Camera::perspective(eye, at, rng.unit(), 5, precise_near(far_spot, eye, true, 5, 96),
                                         length(at) + 2 * r);
        agree(rf, far_spot, "spot fov 5", cam, 128, 96, false, true, tally);
    }
    for (int tile : {4, 64, 256})
        for (int leaf : {1, 16}) {
            RenderOptions o;
            o.tile_size = tile;
            o.bvh.max_leaf_size = leaf;
            o.bvh.sah_bins = leaf == 1 ? 2 : 64;
            Renderer tuned(device, s, o);
            Camera cam = random_camera(s, View::Close, rng, 96);
            agree(tuned, s, "spot tile " + std::to_string(tile) + " leaf " + std::to_string(leaf), cam, 128, 96, false,
                  false, tally);
        }
}

TEST_CASE("depth ranges from 1e-3 to 1e6, the scene scaled, not the camera", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    Random rng(3);
    for (double sc : {1e-3, 1.0, 1e6}) {
        Scene s;
        s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"), scale(sc));
        s.add_mesh(make_uv_sphere(800), scale(0.6 * sc));
        Renderer renderer(device, s);
        char name[64];
        std::snprintf(name, sizeof name, "spot+sphere x%g", sc);
        agree(renderer, s, std::string(name) + " framing", Camera::framing(s.bounds()), 128, 96, false, false, tally);
        for (View kind : {View::Outside, View::OrthoOutside, View::Close})
            agree(renderer, s, std::string(name) + " " + to_string(kind), random_camera(s, kind, rng, 96), 128, 96,
                  false, false, tally);
    }
    check_budget(tally, "scaled scenes");
}

TEST_CASE("intrinsics with an off-centre principal point and pose matrices agree", "[device][agree]")
{
    Device device = Device::open();
    Tally tally;
    Random rng(31);
    for (const char* name : {"stanford-bunny", "spot"}) {
        Scene s = load_bundled(name);
        Renderer renderer(device, s);
        for (int i = 0; i < 3; ++i) {
            const int w = 96 + 16 * i, h = 72;
            Camera base = random_camera(s, i == 2 ? View::Close : View::Outside, rng, h);
            // Focal lengths of the base's field of view, unequal, and an optical axis off the centre.
            double f = h / (2 * std::tan(base.fov_y / 2 * pi / 180));
            Intrinsics k{f * rng.uniform(0.8, 1.2), f * rng.uniform(0.8, 1.2), w * rng.uniform(0.2, 0.8),
                         h * rng.uniform(0.2, 0.8)};
            Camera cam = Camera::from_pose(base.pose(), base);
            cam.intrinsics = k;
            cam.near = precise_near(s, cam.eye, true, 2 * std::atan(h / (2 * std::fmax(k.fx, k.fy))) * 180 / pi, h);
            cam.near = std::fmax(cam.near, base.near);
            agree(renderer, s, std::string(name) + " intrinsics+pose " + std::to_string(i), cam, w, h, false, true,
                  tally);
        }
    }
    check_budget(tally, "intrinsics and poses");
}

TEST_CASE("a shifted principal point equals a crop of a larger image", "[device][agree]")
{
    Device device = Device::open();
    Scene s = load_bundled("stanford-bunny");
    Renderer renderer(device, s);
    const int big_w = 160, big_h = 120, w = 64, h = 48, ox = 71, oy = 37;
    Camera big = Camera::framing(s.bounds());
    Intrinsics k = big.raster_map(big_w, big_h);
    Camera crop = big;
    crop.intrinsics = Intrinsics{k.fx, k.fy, k.cx - ox, k.cy - oy};
    Referee ref_big(s, big, big_w, big_h), ref(s, crop, w, h);
    for (Path p : {Path::Raster, Path::Ray}) {
        HostVisibility whole = renderer.render(big, big_w, big_h, p).read();
        HostVisibility part = renderer.render(crop, w, h, p).read();
        REQUIRE(ref.check(part).errors == 0);
        std::size_t same = 0, judged = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::uint32_t a = part.id(x, y), b = whole.id(x + ox, y + oy);
                same += a == b;
                // The crop's answer is right in the large image, and the large one's in the crop.
                INFO(to_string(p) << " pixel " << x << "," << y);
                CHECK(ref_big.judge(x + ox, y + oy, a).acceptable());
                CHECK(ref.judge(x, y, b).acceptable());
                bool ambiguous = true;
                std::uint32_t id = ref.reference(x, y, &ambiguous);
                bool ambiguous_big = true;
                std::uint32_t id_big = ref_big.reference(x + ox, y + oy, &ambiguous_big);
                if (!ambiguous && !ambiguous_big) {
                    ++judged;
                    CHECK(id == id_big);
                }
            }
        std::printf("crop %s: %zu of %d pixels equal, %zu unambiguous references equal\n", to_string(p), same, w * h,
                    judged);
        CHECK(same >= std::size_t(w * h * 99 / 100));
        CHECK(judged > std::size_t(w * h / 4));
    }
}

TEST_CASE("images up to the raster limit, far meshes and the default near plane, stated tolerances",
          "[device][agree][slow]")
{
    // Where float32 cannot keep the uncertainty above within its share of EPS, the referee judges
    // with float32_tolerance(), which prints the tolerance and its reason; everything else about
    // the judgement (every pixel of both paths, raster against ray) is unchanged.
    Device device = Device::open();
    Tally tally;
    Random rng(2026);
    Scene s = load_bundled("spot");
    Renderer renderer(device, s);
    // The largest accepted sizes both ways, odd ones among them, under cameras whose long side
    // spans half the mesh: it crosses the image's borders (the whole image inside its silhouette,
    // or its silhouette across the image). At that pixel density the world term needs a looser
    // tolerance too (float32_tolerance takes both).
    Bounds b = s.bounds();
    Vec3 c = b.center();
    double r = length(b.extent()) / 2;
    for (auto [w, h] : {std::pair{16384, 64}, {64, 16384}, {16383, 37}, {37, 16383}, {4097, 2049}}) {
        for (double offset : {0.0, 0.6}) {
            Vec3 dir = rng.unit(), eye = c + dir * (3 * r);
            // The offset runs along the image's long side.
            Vec3 up = up_for(eye, c), side = normalize(cross(dir, up));
            if (h > w) side = normalize(cross(side, dir));
            double top = std::atan(0.5 * r / (3 * r) / (w > h ? double(w) / h : 1.0));
            Camera cam = Camera::perspective(eye, c + side * (offset * r), up, 2 * top * 180 / pi, r, 6 * r);
            std::string name = "spot " + std::string(offset > 0 ? "edge" : "fill") + " at the size limit";
            Frames f = agree(renderer, s, name, cam, w, h, false, false, tally,
                             float32_tolerance(s, cam, w, h, "16k px: raster rounding ~1e-3 px, world ~1e-3 px"));
            std::size_t covered = 0, background = 0;
            for (std::uint32_t id : f.vis[0].ids) (id == background_id ? background : covered) += 1;
            CHECK(covered > 0);
            if (offset > 0) CHECK(background > 0);
        }
    }
    // Meshes far from the origin, seen from near by: their coordinates carry M 2^-24 of error.
    for (double offset : {1e3, 3e4}) {
        Mat4 move;
        move(0, 3) = offset;
        move(1, 3) = -0.7 * offset;
        move(2, 3) = 0.3 * offset;
        Scene far_spot;
        far_spot.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"), move);
        Renderer rf(device, far_spot);
        Bounds fb = far_spot.bounds();
        double fr = length(fb.extent()) / 2;
        Vec3 eye = fb.center() + rng.unit() * (2.5 * fr);
        Vec3 up = up_for(eye, fb.center());
        for (bool ortho : {false, true}) {
            // Near at half the way to the mesh: a viewer of a far mesh does not keep the near
            // plane that float32 would need (random_camera's: farther than the mesh).
            Camera cam = ortho ? Camera::orthographic(eye, fb.center(), up, 2.5 * fr, 0.75 * fr, 5 * fr)
                               : Camera::perspective(eye, fb.center(), up, 50, 0.75 * fr, 5 * fr);
            Frames f = agree(rf, far_spot, "spot " + std::to_string(int(offset)) + " from the origin" +
                                               (ortho ? " ortho" : ""), cam, 128, 96, false, false, tally,
                             float32_tolerance(far_spot, cam, 128, 96, "a mesh far from the origin, near the eye"));
            CHECK(std::count(f.vis[0].ids.begin(), f.vis[0].ids.end(), background_id) < 128 * 96);
        }
    }
    // The command line's default depth range for --eye and --target (host/cli/options.cpp): with
    // the eye inside the scene's bounds near is 1e-4 (dist + radius), where a vertex's 2^-24
    // rounding spans a sizeable fraction of a pixel.
    for (int k = 0; k < 2; ++k) {
        double radius = r;
        Vec3 eye = c + rng.unit() * (0.3 * radius);
        Vec3 target = c;
        double dist = length(c - eye);
        double near = std::fmax(0.9 * (dist - radius), 1e-4 * std::fmax(dist + radius, 1e-30));
        double far = std::fmax(1.1 * (dist + radius), 2 * near);
        Camera cam = Camera::perspective(eye, target, up_for(eye, target), 45, near, far);
        Frames f = agree(renderer, s, "spot inside, the CLI's default near", cam, 480, 270, false, false, tally,
                         float32_tolerance(s, cam, 480, 270, "the command line's default near of 1e-4 x the scene"));
        CHECK(std::count(f.vis[0].ids.begin(), f.vis[0].ids.end(), background_id) < 480 * 270);
    }
    // No budget of explained mismatches: a loosened tolerance widens the band where both answers
    // are acceptable, so the count says how far float32 is from EPS, not how well the paths agree.
    std::printf("agree limits, far meshes, default near: %zu cases, %zu pixels, %zu explained, %.1f s\n", tally.cases,
                tally.pixels, tally.explained, tally.seconds);
    CHECK(tally.cases == 16);
}
