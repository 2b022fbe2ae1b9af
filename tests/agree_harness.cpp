// The agreement suite's harness: agree_harness.hpp says what each piece is for.
#include "agree_harness.hpp"
#include "catch.hpp"
#include "test_meshes.hpp"
#include "runtime/cl_runtime.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace clvis::agreement {

Vec3 Random::unit()
{
    for (;;) {
        Vec3 v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
        double l = length(v);
        if (l > 0.1 && l <= 1) return v * (1 / l);
    }
}

namespace {

double norm(Vec3 v) { return std::fmax(std::fmax(std::fabs(v.x), std::fabs(v.y)), std::fabs(v.z)); }

/// The magnitude of float32's rounding of the scene's vertices and the eye, in world units.
double rounding(const Scene& s, Vec3 eye)
{
    double m = 0;
    for (float v : s.world_positions()) m = std::fmax(m, std::fabs(double(v)));
    return (m + norm(eye)) * float_ulp;
}

double raster_rounding(int w, int h) { return raster_ops * (std::max(w, h) + 2 * guard_margin) * float_ulp; }

std::string first_errors(const CompareReport& r)
{
    std::string s;
    for (const PixelVerdict& v : r.first_errors) s += "\n    " + v.describe();
    return s;
}

/// Keys of the raster path that differ between the atomic depth test and tile ownership
/// (RasterAtomics::On and Off), which must agree bit for bit; 0 where the device has no 64-bit
/// atomics (tile ownership is then the only raster path, and agree()'s frame used it).
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
    bool capped = detail::DeviceAccess::of(device, "test").loop_limit() != Device::Impl::loop_unlimited;
    for (Path p : {Path::Ray, Path::Brute}) {
        if (p == Path::Brute && (!brute || capped)) continue;
        std::size_t d = test::differing_bits(raster, twin.render(cam, w, h, p).read());
        INFO(to_string(p) << " path, raster-rule coverage: " << d << " pixels differ from the raster path's");
        CHECK(d == 0);
        differ += d;
    }
    return differ;
}

} // namespace

double precise_near(const Scene& s, Vec3 eye, bool perspective, double fov_y, int height)
{
    double err = rounding(s, eye);
    double n = err / (depth_share * referee_depth_rel);
    if (perspective)
        n = std::fmax(n, err * height / (2 * std::tan(fov_y / 2 * pi / 180)) / (precision_share * referee_edge_eps));
    return n * 1.01; // clear of the bound whatever the rounding
}

double precise_ortho_height(const Scene& s, Vec3 eye, int height)
{
    return 1.01 * rounding(s, eye) * height / (precision_share * referee_edge_eps);
}

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

Frames agree(Renderer& renderer, const Scene& scene, const std::string& name, const Camera& cam, int w, int h,
             bool brute, bool with_reference, Tally& tally, RefereeTolerance tol)
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
    // what float32 leaves of the positions when that is more (the vertices' uncertainty(),
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

Mat4 rotate_y(double radians, Vec3 offset)
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

} // namespace clvis::agreement
