// The raster path: the shared raster math on the host (top-left rule, symmetric clip cuts), then
// the device against hand-made cases with known answers (shared edges and vertices on pixel
// centres, near, far, behind, huge, degenerate, coincident, orthographic, culling, crowded
// tiles), a plain double-precision ray-cast reference on small random scenes, closed meshes
// from outside and inside, and determinism across runs and tile sizes. Every frame drawn through
// render() is drawn twice, with the atomic depth test and with tile ownership, and the two must
// give the same keys bit for bit.
#include "catch.hpp"
#include "test_meshes.hpp"

#include "shared/raster.h"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <string>
#include <vector>

using namespace clvis;

namespace {

using test::look;

Device& device()
{
    static Device d = Device::open();
    return d;
}

/// Relative depth tolerance of CONVENTIONS.md: the reference's in/out band at near and far.
constexpr double depth_rel = 1e-6;
/// Relative depth error allowed of the answer: the kernels' camera frame is float32, whose rounded
/// rotation moves the depth at a fixed sample by about 2^-24 tan(angle) on a plane seen at a
/// grazing angle; the steep near-cut test triangles reach a few 1e-6.
constexpr double depth_check_rel = 1e-5;
/// The referee's edge band in pixels: samples closer than this to an edge are ambiguous.
constexpr double edge_eps = 1e-3;

Scene scene_of(const MeshData& mesh)
{
    Scene s;
    s.add_mesh(mesh);
    return s;
}

MeshData mesh_of(const std::vector<float>& positions, const std::vector<std::uint32_t>& indices)
{
    MeshData m;
    m.positions = positions;
    m.indices = indices;
    return m;
}

/// The raster path's keys with `options`; where the device has 64-bit atomics, also checks that
/// the atomic depth test and tile ownership (RasterAtomics::On and Off) give them bit for bit.
std::vector<std::uint64_t> render_keys(const Scene& scene, const Camera& camera, int w, int h,
                                       RenderOptions options = {})
{
    Renderer r(device(), scene, options);
    std::vector<std::uint64_t> keys = r.render(camera, w, h, Path::Raster).read_keys();
    if (device().info().int64_atomics) {
        options.raster_atomics = options.raster_atomics == RasterAtomics::Off ? RasterAtomics::On : RasterAtomics::Off;
        Renderer other(device(), scene, options);
        INFO("raster atomics " << to_string(options.raster_atomics) << " against the default, " << w << "x" << h);
        CHECK(other.render(camera, w, h, Path::Raster).read_keys() == keys);
    }
    return keys;
}

HostVisibility render(const Scene& scene, const Camera& camera, int w, int h, RenderOptions options = {})
{
    std::vector<std::uint64_t> keys = render_keys(scene, camera, w, h, options);
    return split_keys(keys.data(), w, h);
}

/// Orthographic camera looking down -z whose world x, y map to raster x - w/2, h/2 - y: with
/// power-of-two sizes every step of the projection is exact, so vertices land where asked.
Camera pixel_camera(int w, int h, double near = 0.5, double far = 100)
{
    Camera c = Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, double(h), near, far);
    (void)w;
    return c;
}

/// World position of raster point (x, y) under pixel_camera(w, h), at depth d.
std::vector<float> at_raster(double x, double y, int w, int h, double d)
{
    return {float(x - w / 2.0), float(h / 2.0 - y), float(-d)};
}

// ---------------------------------------------------------------------------------------------
// A plain double-precision reference: one primary ray per pixel centre (Camera::primary_ray,
// whose t is the view depth) against every triangle, Moller-Trumbore in double. A triangle is
// *in* at a sample when the centre and 8 probes edge_eps away all hit it and its depth lies
// inside [near, far] by more than depth_rel; *maybe* when some but not all do.

struct Probe {
    bool hit = false;
    double t = 0;
};

Probe intersect(const Ray& ray, const Vec3 v[3])
{
    Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0];
    Vec3 p = cross(ray.direction, e2);
    double det = dot(e1, p);
    Probe r;
    if (det == 0) return r;
    double inv = 1 / det;
    Vec3 s = ray.origin - v[0];
    double u = dot(s, p) * inv;
    Vec3 q = cross(s, e1);
    double v2 = dot(ray.direction, q) * inv;
    r.t = dot(e2, q) * inv;
    r.hit = u >= 0 && v2 >= 0 && u + v2 <= 1;
    return r;
}

struct Reference {
    int w = 0, h = 0;
    std::vector<std::uint32_t> id;                 ///< nearest *in* triangle, or background
    std::vector<double> depth;                     ///< its depth
    std::vector<std::vector<std::uint32_t>> ok;    ///< acceptable triangle answers
    std::vector<std::vector<double>> ok_depth;     ///< their depths

    bool ambiguous(std::size_t p) const
    {
        return id[p] == background_id ? !ok[p].empty() : ok[p].size() > 1;
    }
};

Reference reference(const Scene& scene, const Camera& cam, int w, int h)
{
    Reference ref;
    ref.w = w;
    ref.h = h;
    std::size_t n = std::size_t(w) * h;
    ref.id.assign(n, background_id);
    ref.depth.assign(n, 0);
    ref.ok.assign(n, {});
    ref.ok_depth.assign(n, {});
    const double ox[9] = {0, 1, -1, 0, 0, 0.7071, 0.7071, -0.7071, -0.7071};
    const double oy[9] = {0, 0, 0, 1, -1, 0.7071, -0.7071, 0.7071, -0.7071};
    struct State {
        bool in, maybe;
        double t;
    };
    std::vector<std::vector<std::pair<std::uint32_t, double>>> maybe(n);
    for (std::uint32_t t = 0; t < scene.triangle_count(); ++t) {
        float f[9];
        scene.triangle(t, f);
        Vec3 v[3] = {{f[0], f[1], f[2]}, {f[3], f[4], f[5]}, {f[6], f[7], f[8]}};
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                int hits = 0;
                double t0 = 0;
                for (int k = 0; k < 9; ++k) {
                    Ray ray = cam.primary_ray(x + 0.5 + ox[k] * edge_eps, y + 0.5 + oy[k] * edge_eps, w, h);
                    Probe pr = intersect(ray, v);
                    hits += pr.hit;
                    if (k == 0) t0 = pr.t;
                }
                if (hits == 0) continue;
                bool depth_in = t0 >= cam.near * (1 + depth_rel) && t0 <= cam.far * (1 - depth_rel);
                bool depth_maybe = t0 >= cam.near * (1 - depth_rel) && t0 <= cam.far * (1 + depth_rel);
                std::size_t p = std::size_t(y) * w + x;
                if (hits == 9 && depth_in) {
                    if (ref.id[p] == background_id || t0 < ref.depth[p] || (t0 == ref.depth[p] && t < ref.id[p])) {
                        ref.id[p] = t;
                        ref.depth[p] = t0;
                    }
                    maybe[p].push_back({t, t0});
                } else if (depth_maybe) {
                    maybe[p].push_back({t, t0});
                }
            }
    }
    for (std::size_t p = 0; p < n; ++p)
        for (auto [t, d] : maybe[p])
            if (ref.id[p] == background_id || d <= ref.depth[p] * (1 + depth_rel)) {
                ref.ok[p].push_back(t);
                ref.ok_depth[p].push_back(d);
            }
    return ref;
}

struct Verdict {
    std::size_t errors = 0, ambiguous = 0, covered = 0, depth_errors = 0;
    std::string first;
};

/// Judges every pixel of `got` against the reference.
Verdict judge(const Reference& ref, const HostVisibility& got, bool check_depth = true)
{
    Verdict v;
    for (int y = 0; y < ref.h; ++y)
        for (int x = 0; x < ref.w; ++x) {
            std::size_t p = std::size_t(y) * ref.w + x;
            std::uint32_t a = got.ids[p];
            v.ambiguous += ref.ambiguous(p);
            v.covered += ref.id[p] != background_id;
            bool good;
            if (a == background_id) {
                good = ref.id[p] == background_id;
            } else {
                auto it = std::find(ref.ok[p].begin(), ref.ok[p].end(), a);
                good = it != ref.ok[p].end();
                if (good) {
                    double d = ref.ok_depth[p][std::size_t(it - ref.ok[p].begin())];
                    if (check_depth && std::fabs(double(got.depth[p]) - d) > depth_check_rel * d) {
                        ++v.depth_errors;
                        if (v.first.empty())
                            v.first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): depth " +
                                      std::to_string(got.depth[p]) + ", reference " + std::to_string(d);
                    }
                }
            }
            if (!good) {
                ++v.errors;
                if (v.first.empty())
                    v.first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): got id " +
                              std::to_string(a) + ", reference " + std::to_string(ref.id[p]) + " (" +
                              std::to_string(ref.ok[p].size()) + " acceptable)";
            }
        }
    return v;
}

void check_against_reference(const Scene& scene, const Camera& cam, int w, int h, const std::string& what,
                             std::size_t max_ambiguous, bool check_depth = true)
{
    HostVisibility got = render(scene, cam, w, h);
    Verdict v = judge(reference(scene, cam, w, h), got, check_depth);
    INFO(what << ": " << v.errors << " errors, " << v.depth_errors << " depth errors, " << v.ambiguous
              << " ambiguous, " << v.covered << " covered; " << v.first);
    CHECK(v.errors == 0);
    CHECK(v.depth_errors == 0);
    CHECK(v.ambiguous <= max_ambiguous);
}

std::vector<bool> coverage(const HostVisibility& v)
{
    std::vector<bool> c(v.ids.size());
    for (std::size_t i = 0; i < c.size(); ++i) c[i] = v.ids[i] != background_id;
    return c;
}

/// Renders each triangle of `mesh` alone and checks that every pixel is covered by at most one,
/// and that the union is what the whole mesh covers. Returns the union's size.
std::size_t check_additive_coverage(const MeshData& mesh, const Camera& cam, int w, int h)
{
    std::vector<int> count(std::size_t(w) * h, 0);
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        MeshData one;
        one.positions = mesh.positions;
        one.indices.assign(mesh.indices.begin() + 3 * t, mesh.indices.begin() + 3 * t + 3);
        auto c = coverage(render(scene_of(one), cam, w, h));
        for (std::size_t i = 0; i < c.size(); ++i) count[i] += c[i];
    }
    auto all = coverage(render(scene_of(mesh), cam, w, h));
    std::size_t doubled = 0, mismatched = 0, total = 0;
    for (std::size_t i = 0; i < count.size(); ++i) {
        doubled += count[i] > 1;
        mismatched += (count[i] > 0) != all[i];
        total += all[i];
    }
    INFO(doubled << " pixels covered twice, " << mismatched << " differ from the whole mesh");
    CHECK(doubled == 0);
    CHECK(mismatched == 0);
    return total;
}

MeshData random_triangles(std::mt19937& rng, int count, double spread, double max_size)
{
    std::uniform_real_distribution<double> u(-1, 1), s(0.02, 1);
    MeshData m;
    for (int t = 0; t < count; ++t) {
        double size = max_size * s(rng) * s(rng);
        double c[3] = {u(rng) * spread, u(rng) * spread, u(rng) * spread};
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) m.positions.push_back(float(c[k] + u(rng) * size));
        for (int v = 0; v < 3; ++v) m.indices.push_back(std::uint32_t(3 * t + v));
    }
    return m;
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Host: the shared header the kernels compile.

TEST_CASE("the top-left rule gives every sample of a split quad to exactly one half", "[raster]")
{
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> coord(0, 12);
    const clvis_i64 one = CLVIS_SUBPIXEL_ONE, half = CLVIS_SUBPIXEL_HALF;
    std::size_t on_shared_edge = 0;
    for (int round = 0; round < 1000; ++round) {
        // Vertices on pixel centres or corners, so that many samples lie exactly on edges.
        clvis_raster_vertex q[4];
        for (auto& v : q) {
            v.x = coord(rng) * half + half;
            v.y = coord(rng) * half + half;
            v.v = 1;
        }
        clvis_raster_tri a{}, b{};
        int ha = clvis_raster_setup(q[0], q[1], q[2], 0, 16, 16, CLVIS_CULL_NONE, &a);
        int hb = clvis_raster_setup(q[0], q[2], q[3], 1, 16, 16, CLVIS_CULL_NONE, &b);
        // The two halves lie on opposite sides of the diagonal q0-q2 only when q1 and q3 do.
        auto side = [&](clvis_raster_vertex p) {
            return (q[2].x - q[0].x) * (p.y - q[0].y) - (q[2].y - q[0].y) * (p.x - q[0].x);
        };
        if (!ha || !hb || !((side(q[1]) > 0 && side(q[3]) < 0) || (side(q[1]) < 0 && side(q[3]) > 0))) continue;
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                bool in_a = clvis_raster_sample(&a, i, j, 1, 0.0f, 10.0f) != CLVIS_BACKGROUND_KEY;
                bool in_b = clvis_raster_sample(&b, i, j, 1, 0.0f, 10.0f) != CLVIS_BACKGROUND_KEY;
                CHECK(!(in_a && in_b));
                // A sample strictly inside the quad's diagonal, strictly between q0 and q2, belongs
                // to one of them.
                clvis_raster_vertex s{i * one + half, j * one + half, 0};
                clvis_i64 dot = (s.x - q[0].x) * (q[2].x - q[0].x) + (s.y - q[0].y) * (q[2].y - q[0].y);
                clvis_i64 len2 = (q[2].x - q[0].x) * (q[2].x - q[0].x) + (q[2].y - q[0].y) * (q[2].y - q[0].y);
                if (side(s) == 0 && dot > 0 && dot < len2) {
                    ++on_shared_edge;
                    CHECK((in_a || in_b));
                }
            }
    }
    CHECK(on_shared_edge > 100);
}

TEST_CASE("snapping rounds to the nearest fixed-point step, ties to even", "[raster]")
{
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-9000.0f, 17000.0f);
    std::vector<float> values = {0.0f, -0.0f, 0.5f / 65536, 1.5f / 65536, -2.5f / 65536, 127.99999f, -8000.0f};
    for (int i = 0; i < 100000; ++i) values.push_back(u(rng));
    for (int i = 0; i < 1000; ++i) values.push_back(float(int(u(rng) * 2)) / 131072.0f); // exact half steps
    for (float v : values) {
        INFO("v = " << v);
        CHECK(clvis_snap(v) == clvis_i64(std::nearbyint(double(v) * 65536.0)));
    }
}

TEST_CASE("a clip cut does not depend on the direction the edge is walked", "[raster]")
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-50, 50);
    const clvis_guard g = clvis_guard_make(-0.6f, 0.7f, -0.4f, 0.3f); // off-centre, as with a shifted principal point
    for (int i = 0; i < 1000; ++i) {
        clvis_clip_vertex a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
        for (int plane = 0; plane < CLVIS_CLIP_PLANES; ++plane) {
            float da = clvis_clip_distance(a, plane, 1.0f, g, 0);
            float db = clvis_clip_distance(b, plane, 1.0f, g, 0);
            if ((da >= 0) == (db >= 0)) continue;
            clvis_clip_vertex p = clvis_clip_cut(a, da, b, db, plane, 1.0f, g, 0);
            clvis_clip_vertex q = clvis_clip_cut(b, db, a, da, plane, 1.0f, g, 0);
            CHECK(std::memcmp(&p, &q, sizeof p) == 0);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Device: hand-made cases.

TEST_CASE("one triangle covers the pixel centres inside it at their exact depth", "[device][raster][rusticl]")
{
    const int w = 64, h = 64;
    std::vector<float> p;
    for (auto v : {at_raster(10.3, 5.2, w, h, 3), at_raster(50.7, 20.1, w, h, 3), at_raster(20.2, 58.9, w, h, 3)})
        p.insert(p.end(), v.begin(), v.end());
    Scene s = scene_of(mesh_of(p, {0, 1, 2}));
    check_against_reference(s, pixel_camera(w, h), w, h, "orthographic", 0);
    Camera persp = look({0.3, -0.2, 60}, {0, 0, -3}, 50, 0.5, 100);
    check_against_reference(s, persp, w, h, "perspective", 4);
}

TEST_CASE("a pixel centre on an edge shared by two triangles belongs to exactly one", "[device][raster][rusticl]")
{
    const int w = 64, h = 64;
    Camera cam = pixel_camera(w, h);
    // A quad with corners on pixel centres whose diagonal (slope 1/2) crosses a centre every 2 px.
    auto corner = [&](double x, double y) { return at_raster(x, y, w, h, 4); };
    std::vector<float> p;
    for (auto v : {corner(8.5, 8.5), corner(40.5, 8.5), corner(40.5, 24.5), corner(8.5, 24.5)})
        p.insert(p.end(), v.begin(), v.end());
    for (auto indices : std::vector<std::vector<std::uint32_t>>{
             {0, 1, 2, 0, 2, 3}, {0, 2, 1, 0, 3, 2}, {2, 1, 0, 0, 2, 3}, {0, 1, 3, 1, 2, 3}, {3, 1, 0, 1, 3, 2}}) {
        MeshData quad = mesh_of(p, indices);
        std::size_t total = check_additive_coverage(quad, cam, w, h);
        // Top-left rule: the quad's top and left edges are in, its right and bottom edges out.
        CHECK(total == 32 * 16);
        auto v = render(scene_of(quad), cam, w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) CHECK((v.id(x, y) != background_id) == (x >= 8 && x < 40 && y >= 8 && y < 24));
    }
}

TEST_CASE("a fan around a vertex on a pixel centre covers each centre exactly once", "[device][raster][rusticl]")
{
    const int w = 64, h = 64;
    Camera cam = pixel_camera(w, h);
    const double ring[8][2] = {{16.5, 16.5}, {32.5, 16.5}, {48.5, 16.5}, {48.5, 32.5},
                               {48.5, 48.5}, {32.5, 48.5}, {16.5, 48.5}, {16.5, 32.5}};
    std::vector<float> p = at_raster(32.5, 32.5, w, h, 2);
    for (auto& r : ring) {
        auto v = at_raster(r[0], r[1], w, h, 2);
        p.insert(p.end(), v.begin(), v.end());
    }
    std::mt19937 rng(5);
    for (int round = 0; round < 3; ++round) {
        std::vector<std::uint32_t> idx;
        for (std::uint32_t k = 0; k < 8; ++k) {
            std::uint32_t a = 1 + k, b = 1 + (k + 1) % 8;
            if (rng() % 2) idx.insert(idx.end(), {0, a, b});
            else idx.insert(idx.end(), {b, a, 0});
        }
        MeshData fan = mesh_of(p, idx);
        CHECK(check_additive_coverage(fan, cam, w, h) == 32 * 32);
    }
}

TEST_CASE("a tilted grid under perspective covers each pixel once and leaves no crack", "[device][raster][rusticl]")
{
    const int w = 64, h = 48;
    MeshData grid;
    const int n = 5;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> jitter(-0.08f, 0.08f);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            float x = -1 + 2.0f * i / n + (i % n ? jitter(rng) : 0), y = -1 + 2.0f * j / n + (j % n ? jitter(rng) : 0);
            grid.positions.insert(grid.positions.end(), {x, y, 0.3f * x - 0.2f * y});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + n + 1, d = c + 1;
            if ((i + j) % 2) grid.indices.insert(grid.indices.end(), {a, b, d, a, d, c});
            else grid.indices.insert(grid.indices.end(), {a, b, c, c, b, d});
        }
    Camera cam = look({0.4, 0.3, 2.2}, {0, 0, 0}, 60, 0.1, 10);
    CHECK(check_additive_coverage(grid, cam, w, h) > 500);
    check_against_reference(scene_of(grid), cam, w, h, "grid", 20);
}

TEST_CASE("a triangle behind the camera draws nothing", "[device][raster][rusticl]")
{
    Scene s = scene_of(mesh_of({-1, -1, 2, 1, -1, 2, 0, 1, 2}, {0, 1, 2}));
    auto v = render(s, look({0, 0, 0}, {0, 0, -1}, 60, 0.1, 100), 32, 32);
    for (auto id : v.ids) CHECK(id == background_id);
}

TEST_CASE("a triangle crossing the near plane is cut, never dropped or wrapped", "[device][raster][rusticl]")
{
    const int w = 64, h = 48;
    // One vertex behind the eye, one between the eye and near, one in front.
    Scene s = scene_of(mesh_of({-0.3f, -0.2f, 1.0f, 0.4f, -0.1f, -0.05f, 0.0f, 0.3f, -2.0f}, {0, 1, 2}));
    Camera cam = look({0, 0, 0}, {0, 0, -1}, 70, 0.2, 100);
    check_against_reference(s, cam, w, h, "one vertex in front", 6);
    // Two vertices in front: the cut leaves a quad (two triangles).
    Scene s2 = scene_of(mesh_of({-0.5f, -0.3f, -1.5f, 0.6f, -0.2f, -0.8f, 0.1f, 0.4f, 0.5f}, {0, 1, 2}));
    HostVisibility v = render(s2, cam, w, h);
    CHECK(std::count(v.ids.begin(), v.ids.end(), 0u) > 100);
    check_against_reference(s2, cam, w, h, "two vertices in front", 6);
    // Orthographic: near cuts as well.
    Camera ortho = Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 2, 0.5, 10);
    check_against_reference(s2, ortho, w, h, "orthographic", 6);
}

TEST_CASE("a triangle larger than the screen covers every pixel at its exact depth", "[device][raster][rusticl]")
{
    const int w = 80, h = 60;
    Camera cam = look({0, 0, 0}, {0, 0, -1}, 60, 0.1, 100);
    Scene s = scene_of(mesh_of({-1e5f, -1e5f, -5, 1e5f, -1e5f, -5, 0, 1e5f, -5}, {0, 1, 2}));
    HostVisibility v = render(s, cam, w, h);
    for (std::size_t i = 0; i < v.ids.size(); ++i) {
        CHECK(v.ids[i] == 0u);
        CHECK(std::fabs(v.depth[i] - 5.0) <= 5.0 * depth_rel);
    }
    // A ground plane from behind the eye to the horizon: near cut and guard band at once. Its
    // world coordinates of 1e4 carry 1e-3 units of float32 uncertainty (CONVENTIONS.md), which
    // at the horizon is far more than depth_check_rel: ids are judged, not depths.
    Scene ground = scene_of(mesh_of({-1e4f, -1, 1e4f, 1e4f, -1, 1e4f, 0, -1, -1e4f}, {0, 1, 2}));
    check_against_reference(ground, look({0, 0, 0}, {0, -0.3, -1}, 60, 0.1, 1e5), w, h, "ground", 8, false);
    // Very close to the eye and huge on screen.
    Scene close = scene_of(mesh_of({-0.5f, -0.4f, -0.11f, 0.6f, -0.3f, -0.12f, 0.05f, 0.5f, -0.13f}, {0, 1, 2}));
    check_against_reference(close, cam, w, h, "close", 8);
}

TEST_CASE("triangles beyond far draw nothing and those crossing far stop at it", "[device][raster][rusticl]")
{
    const int w = 64, h = 48;
    Camera cam = look({0, 0, 0}, {0, 0, -1}, 60, 0.1, 10);
    Scene beyond = scene_of(mesh_of({-1, -1, -20, 1, -1, -20, 0, 1, -20}, {0, 1, 2}));
    for (auto id : render(beyond, cam, w, h).ids) CHECK(id == background_id);
    Scene crossing = scene_of(mesh_of({-3, -1, -5, 3, -1, -5, 0, 2, -30}, {0, 1, 2}));
    HostVisibility v = render(crossing, cam, w, h);
    CHECK(std::count(v.ids.begin(), v.ids.end(), 0u) > 50);
    check_against_reference(crossing, cam, w, h, "crossing far", 16);
    Camera ortho = Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 6, 0.1, 10);
    check_against_reference(crossing, ortho, w, h, "crossing far, orthographic", 16);
}

TEST_CASE("degenerate triangles cover nothing and keep the ids of the others", "[device][raster][rusticl]")
{
    const int w = 32, h = 32;
    std::vector<float> p = {-5, -5, -3, 5, 5, -3, 15, 15, -3, /* collinear */
                            -4, 6, -3, /* fourth */ 8, -9, -3, 0, 12, -3};
    Scene s = scene_of(mesh_of(p, {0, 1, 2, 0, 0, 3, 4, 4, 4, 3, 4, 5}));
    HostVisibility v = render(s, pixel_camera(w, h), w, h);
    std::set<std::uint32_t> ids(v.ids.begin(), v.ids.end());
    CHECK(ids == std::set<std::uint32_t>{3u, background_id});
}

TEST_CASE("coincident triangles, the lower id wins whatever the winding", "[device][raster][rusticl]")
{
    const int w = 48, h = 48;
    std::vector<float> p = {-20.3f, -15.1f, -4, 18.2f, -9.7f, -4, 2.6f, 19.9f, -4};
    Scene s = scene_of(mesh_of(p, {1, 0, 2, 0, 1, 2, 2, 0, 1, 0, 2, 1}));
    for (Camera cam : {pixel_camera(w, h), look({0.5, 0.2, 10}, {0, 0, -4}, 60, 0.1, 100)}) {
        HostVisibility v = render(s, cam, w, h);
        std::set<std::uint32_t> ids(v.ids.begin(), v.ids.end());
        CHECK(ids == std::set<std::uint32_t>{0u, background_id});
    }
}

TEST_CASE("culling drops back or front faces; front faces are counter-clockwise on screen", "[device][raster][rusticl]")
{
    const int w = 64, h = 32;
    // Seen from +z, triangle 0 runs counter-clockwise on screen, triangle 1 clockwise.
    std::vector<float> p = {-30, -10, -2, -5, -10, -2, -18, 12, -2, 5, -10, -2, 18, 12, -2, 30, -10, -2};
    Scene s = scene_of(mesh_of(p, {0, 1, 2, 3, 4, 5}));
    for (Camera cam : {pixel_camera(w, h), look({0, 0, 30}, {0, 0, -2}, 60, 0.1, 100)}) {
        auto ids_with = [&](Cull cull) {
            RenderOptions o;
            o.cull = cull;
            HostVisibility v = render(s, cam, w, h, o);
            return std::set<std::uint32_t>(v.ids.begin(), v.ids.end());
        };
        CHECK(ids_with(Cull::None) == std::set<std::uint32_t>{0u, 1u, background_id});
        CHECK(ids_with(Cull::Back) == std::set<std::uint32_t>{0u, background_id});
        CHECK(ids_with(Cull::Front) == std::set<std::uint32_t>{1u, background_id});
    }
}

TEST_CASE("thousands of large triangles stacked in the same tiles are all drawn", "[device][raster][rusticl]")
{
    // Each square is nearer than the one before: only the last two triangles may show, which
    // requires every triangle to be listed and binned (the buffers grow past their first size).
    const int w = 64, h = 64, squares = 3000;
    MeshData m;
    for (int k = 0; k < squares; ++k) {
        float d = 50.0f - 0.01f * float(k), x0 = -20.25f + 0.003f * float(k % 7), x1 = 19.75f, y0 = -18.5f, y1 = 21.5f;
        m.positions.insert(m.positions.end(), {x0, y0, -d, x1, y0, -d, x1, y1, -d, x0, y1, -d});
        std::uint32_t b = std::uint32_t(4 * k);
        m.indices.insert(m.indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
    }
    for (int tile : {8, 16, 64}) {
        RenderOptions o;
        o.tile_size = tile;
        HostVisibility v = render(scene_of(m), pixel_camera(w, h, 0.5, 100), w, h, o);
        std::set<std::uint32_t> ids(v.ids.begin(), v.ids.end());
        CHECK(ids == std::set<std::uint32_t>{2u * squares - 2, 2u * squares - 1, background_id});
        CHECK(std::count(v.ids.begin(), v.ids.end(), background_id) == w * h - 40 * 40);
    }
}

// ---------------------------------------------------------------------------------------------
// Device: against the double-precision reference, closed meshes, determinism.

TEST_CASE("random scenes agree with a double-precision reference", "[device][raster][rusticl]")
{
    std::mt19937 rng(2024);
    std::size_t ambiguous = 0, pixels = 0;
    for (int round = 0; round < 6; ++round) {
        const int w = 72, h = 56;
        MeshData m = random_triangles(rng, 60, 1.0, round % 2 ? 1.5 : 0.4);
        Scene s = scene_of(m);
        Camera cam = round == 4 ? Camera::orthographic({0.2, 0.1, 3}, {0, 0, 0}, {0, 1, 0}, 2.5, 1.5, 4.2)
                                : look({0.3 * round - 0.6, 0.2, 2.0 + 0.2 * round}, {0, 0, 0}, 55, 0.8 + 0.1 * round,
                                       3.0 + 0.1 * round);
        HostVisibility got = render(s, cam, w, h);
        Verdict v = judge(reference(s, cam, w, h), got);
        INFO("round " << round << ": " << v.errors << " errors, " << v.depth_errors << " depth errors, "
                      << v.ambiguous << " ambiguous of " << v.covered << " covered; " << v.first);
        CHECK(v.errors == 0);
        CHECK(v.depth_errors == 0);
        ambiguous += v.ambiguous;
        pixels += std::size_t(w) * h;
    }
    INFO(ambiguous << " ambiguous pixels of " << pixels);
    CHECK(ambiguous * 500 < pixels);
}

namespace {

/// Background pixels that the reference says some triangle robustly covers: cracks.
std::size_t cracks(const Scene& scene, const Camera& cam, const HostVisibility& v)
{
    std::vector<std::array<Vec3, 3>> tris(scene.triangle_count());
    for (std::uint32_t t = 0; t < tris.size(); ++t) {
        float f[9];
        scene.triangle(t, f);
        tris[t] = {Vec3{f[0], f[1], f[2]}, Vec3{f[3], f[4], f[5]}, Vec3{f[6], f[7], f[8]}};
    }
    std::size_t n = 0;
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x) {
            if (v.id(x, y) != background_id) continue;
            Ray centre = cam.primary_ray(x + 0.5, y + 0.5, v.width, v.height);
            for (const auto& t : tris) {
                Probe p = intersect(centre, t.data());
                if (!p.hit || !(p.t > cam.near * (1 + depth_rel) && p.t < cam.far * (1 - depth_rel))) continue;
                bool robust = true;
                for (int k = 0; k < 8 && robust; ++k) {
                    double a = k * 0.7853981633974483;
                    Ray r = cam.primary_ray(x + 0.5 + edge_eps * std::cos(a), y + 0.5 + edge_eps * std::sin(a),
                                            v.width, v.height);
                    robust = intersect(r, t.data()).hit;
                }
                if (robust) {
                    ++n;
                    break;
                }
            }
        }
    return n;
}

void check_closed_mesh(const Scene& s, double radius, Vec3 centre, int cameras, std::uint32_t seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0, 1);
    Renderer r(device(), s);
    const int w = 64, h = 48;
    for (int c = 0; c < cameras; ++c) {
        Vec3 dir = normalize(Vec3{g(rng), g(rng), g(rng)});
        // Outside: a distance of 1.3 to 4 radii; the silhouette may leave the screen.
        Vec3 eye = centre + dir * (radius * (1.3 + 2.7 * u(rng)));
        Vec3 target = centre + Vec3{g(rng), g(rng), g(rng)} * (0.3 * radius);
        Camera out = c % 4 == 3 ? Camera::orthographic(eye, target, {0, 1, 0}, radius * (1 + 2 * u(rng)), 0.01, 100 * radius)
                                : look(eye, target, 30 + 60 * u(rng), 0.01 * radius, 100 * radius);
        HostVisibility v = r.render(out, w, h, Path::Raster).read();
        INFO("outside camera " << c << ": " << out.to_flags());
        CHECK(cracks(s, out, v) == 0);
    }
}

} // namespace

TEST_CASE("a closed sphere shows no crack from outside and covers every pixel from inside", "[device][raster][rusticl]")
{
    Scene s = scene_of(make_uv_sphere(2000));
    check_closed_mesh(s, 1.0, {0, 0, 0}, 12, 99);
    std::mt19937 rng(17);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0, 1);
    Renderer r(device(), s);
    for (int c = 0; c < 16; ++c) {
        Vec3 eye = normalize(Vec3{g(rng), g(rng), g(rng)}) * (0.5 * u(rng));
        Vec3 target = eye + normalize(Vec3{g(rng), g(rng), g(rng)});
        Camera in = look(eye, target, 20 + 100 * u(rng), 0.01, 10);
        HostVisibility v = r.render(in, 64, 48, Path::Raster).read();
        INFO("inside camera " << c << ": " << in.to_flags());
        CHECK(std::count(v.ids.begin(), v.ids.end(), background_id) == 0);
    }
}

TEST_CASE("spot shows no crack from random cameras", "[device][raster]")
{
    Scene s = scene_of(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"));
    Bounds b = s.bounds();
    check_closed_mesh(s, length(b.extent()) / 2, b.center(), 8, 5);
}

TEST_CASE("the same frame gives bit-identical keys across runs and tile sizes", "[device][raster][rusticl]")
{
    std::mt19937 rng(8);
    MeshData m = random_triangles(rng, 3000, 1.0, 0.3);
    MeshData sphere = make_uv_sphere(5000);
    for (const MeshData* mesh : {&m, &sphere}) {
        Scene s = scene_of(*mesh);
        Camera cam = look({0.4, 0.9, 2.6}, {0, 0, 0}, 50, 0.5, 10);
        std::vector<std::uint64_t> first = render_keys(s, cam, 160, 120);
        CHECK(first == render_keys(s, cam, 160, 120));
        for (int tile : {4, 8, 32, 128, 256}) {
            RenderOptions o;
            o.tile_size = tile;
            INFO("tile " << tile);
            CHECK(first == render_keys(s, cam, 160, 120, o));
        }
    }
}

TEST_CASE("the referee accepts every pixel of real meshes from framing and random cameras", "[device][raster][rusticl]")
{
    std::mt19937 rng(31);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> u(0, 1);
    for (const char* name : {"spot.obj", "teapot.obj", "suzanne.obj"}) {
        Scene s = scene_of(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + name));
        Bounds b = s.bounds();
        double radius = length(b.extent()) / 2;
        Renderer r(device(), s);
        std::vector<Camera> cams = {Camera::framing(b), Camera::framing(b, Projection::Orthographic)};
        for (int c = 0; c < 3; ++c) {
            Vec3 eye = b.center() + normalize(Vec3{g(rng), g(rng), g(rng)}) * (radius * (0.6 + 2 * u(rng)));
            cams.push_back(look(eye, b.center(), 40 + 40 * u(rng), 0.01 * radius, 10 * radius));
        }
        for (const Camera& cam : cams) {
            const int w = 160, h = 120;
            HostVisibility v = r.render(cam, w, h, Path::Raster).read();
            CompareReport report = Referee(s, cam, w, h).check(v);
            INFO(name << " " << cam.to_flags() << ": " << report.errors << " errors"
                      << (report.first_errors.empty() ? "" : "; " + report.first_errors.front().describe()));
            CHECK(report.errors == 0);
        }
    }
}

TEST_CASE("a million triangles binned into the same tiles are all drawn", "[device][raster][slow]")
{
    // Each triangle covers the same right triangle with 40-pixel legs (too wide for setup's small
    // path, so every one is binned) and is nearer than the one before: only the last may show.
    const int w = 64, h = 64, count = 1000000;
    MeshData m;
    m.positions.reserve(std::size_t(count) * 9);
    for (int k = 0; k < count; ++k) {
        float d = 90.0f - 80.0f * float(k) / float(count);
        m.positions.insert(m.positions.end(), {-10.25f, -10.25f, -d, 30.25f, -10.25f, -d, -10.25f, 30.25f, -d});
        for (int v = 0; v < 3; ++v) m.indices.push_back(std::uint32_t(3 * k + v));
    }
    HostVisibility v = render(scene_of(m), pixel_camera(w, h, 0.5, 100), w, h);
    std::set<std::uint32_t> ids(v.ids.begin(), v.ids.end());
    CHECK(ids == std::set<std::uint32_t>{std::uint32_t(count - 1), background_id});
}
