// The ray path on the device: the BVH traversal gives the same keys as the brute force over every
// triangle, closed meshes show no holes from any camera, rays through shared edges and vertices
// hit, near/far/behind/orthographic/ties/degenerate cases, axis-parallel rays against flat
// boxes, determinism, and refits that draw what rebuilds draw.
#include "catch.hpp"
#include "test_files.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>

#include <CL/cl.h>

#include "shared/ray.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <utility>
#include <vector>

using namespace clvis;

namespace {

using test::triangle;
using test::covered;
using test::look;

Device device() { return Device::open(); }

/// An n x n grid of quads over [x0, x0 + n*step] x [y0, y0 + n*step], at z = slope_x * x + slope_y * y,
/// split along alternating diagonals.
MeshData plane_grid(int n, float x0, float y0, float step, float slope_x = 0, float slope_y = 0)
{
    MeshData m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            float x = x0 + float(i) * step, y = y0 + float(j) * step;
            m.positions.insert(m.positions.end(), {x, y, slope_x * x + slope_y * y});
        }
    test::add_grid_triangles(m, n);
    return m;
}

/// Keys of the BVH path and of the brute path for the same frame.
void check_paths_agree(Renderer& r, const Camera& cam, int w, int h, const std::string& what)
{
    auto bvh = r.render(cam, w, h, Path::Ray).read_keys();
    auto brute = r.render(cam, w, h, Path::Brute).read_keys();
    std::size_t differ = 0, hit = 0;
    for (std::size_t i = 0; i < bvh.size(); ++i) {
        differ += bvh[i] != brute[i];
        hit += (brute[i] & 0xFFFFFFFFu) != background_id;
    }
    INFO(what << ": " << differ << " of " << bvh.size() << " pixels differ, " << hit << " hit");
    CHECK(differ == 0);
}

Vec3 random_direction(std::mt19937& rng)
{
    std::normal_distribution<double> g;
    Vec3 v{g(rng), g(rng), g(rng)};
    return normalize(v);
}

/// Whether the double-precision ray robustly passes through a triangle of the scene (every
/// barycentric above `margin`) inside [near, far]: such a pixel may not be background.
bool robust_hit(const Scene& s, const Ray& ray, double near, double far, double margin)
{
    for (std::uint32_t id = 0; id < s.triangle_count(); ++id) {
        float v[9];
        s.triangle(id, v);
        Vec3 a{v[0], v[1], v[2]}, b{v[3], v[4], v[5]}, c{v[6], v[7], v[8]};
        Vec3 e1 = b - a, e2 = c - a, p = cross(ray.direction, e2);
        double det = dot(e1, p);
        if (std::fabs(det) < 1e-300) continue;
        Vec3 q = ray.origin - a;
        double u = dot(q, p) / det;
        Vec3 qq = cross(q, e1);
        double w = dot(ray.direction, qq) / det;
        double t = dot(e2, qq) / det;
        if (u > margin && w > margin && 1 - u - w > margin && t > near * (1 + 1e-6) && t < far * (1 - 1e-6)) return true;
    }
    return false;
}

/// Background pixels next to a covered one where the scene robustly covers the pixel centre.
std::size_t holes(const Scene& s, const Camera& cam, const HostVisibility& v)
{
    std::size_t n = 0;
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x) {
            if (v.id(x, y) != background_id) continue;
            bool next_to_cover = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < v.width && yy < v.height) next_to_cover |= v.id(xx, yy) != background_id;
                }
            if (next_to_cover && robust_hit(s, cam.primary_ray(x + 0.5, y + 0.5, v.width, v.height), cam.near, cam.far, 1e-4))
                ++n;
        }
    return n;
}

} // namespace

TEST_CASE("the BVH path gives the brute path's keys", "[device][ray]")
{
    Device d = device();
    std::vector<std::pair<std::string, Scene>> scenes;
    {
        Scene s;
        s.add_mesh(make_uv_sphere(3000));
        scenes.emplace_back("sphere", s);
    }
    {
        Scene s;
        s.add_mesh(make_grid(2000, 4));
        Mat4 m;
        m(0, 3) = 0.5;
        s.add_mesh(make_soup(500, 9), m);
        s.add_mesh(make_uv_sphere(400));
        scenes.emplace_back("terrain, soup and sphere", s);
    }
    {
        Scene s;
        s.add_mesh(load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj"));
        scenes.emplace_back("spot", s);
    }
    for (auto& [name, scene] : scenes) {
        Camera framing = Camera::framing(scene.bounds());
        Camera ortho = Camera::framing(scene.bounds(), Projection::Orthographic);
        Bounds b = scene.bounds();
        Camera close = look(b.center() + Vec3{0.2, 0.3, 0.6} * length(b.extent()), b.center(), 60, 1e-3, 100);
        // Looking along a diagonal with a wide view: packets whose rays change their largest
        // axis (the shear's permutation) and the signs of their components.
        Camera wide = look(b.center() + Vec3{0.7, 0.7, 0.05} * length(b.extent()), b.center(), 120, 1e-3, 100);
        for (int leaf : {1, 4, 16}) {
            RenderOptions o;
            o.bvh.max_leaf_size = leaf;
            Renderer r(d, scene, o);
            check_paths_agree(r, framing, 67, 45, name + ", framing, leaf " + std::to_string(leaf));
            check_paths_agree(r, ortho, 40, 33, name + ", orthographic, leaf " + std::to_string(leaf));
            check_paths_agree(r, close, 48, 37, name + ", close-up, leaf " + std::to_string(leaf));
            check_paths_agree(r, wide, 53, 41, name + ", wide diagonal, leaf " + std::to_string(leaf));
        }
    }
}

TEST_CASE("a closed sphere shows no hole from random cameras outside and inside", "[device][ray]")
{
    Device d = device();
    Scene s;
    s.add_mesh(make_uv_sphere(6000));
    Renderer r(d, s);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(0, 1);
    const int w = 48, h = 36;
    for (int i = 0; i < 24; ++i) {
        // Outside: every pixel whose ray passes well inside the sphere's inscribed ball hits it.
        Vec3 eye = random_direction(rng) * (1.5 + 6 * u(rng));
        Vec3 target = random_direction(rng) * (0.3 * u(rng));
        Camera cam = look(eye, target, 20 + 50 * u(rng), 0.01, 100);
        if (i % 4 == 3) cam = Camera::orthographic(eye, target, cam.up, 1.0 + 2 * u(rng), 0.01, 100);
        HostVisibility v = r.render(cam, w, h, Path::Ray).read();
        std::size_t holes = 0, wrong = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                Ray ray = cam.primary_ray(x + 0.5, y + 0.5, w, h);
                Vec3 dir = normalize(ray.direction);
                Vec3 to_centre = ray.origin * -1.0;
                double along = dot(to_centre, dir);
                double miss = length(to_centre - dir * along);
                holes += miss < 0.97 && v.id(x, y) == background_id;
                wrong += miss > 1.001 && v.id(x, y) != background_id;
            }
        INFO("outside camera " << i << ": " << cam.to_flags());
        CHECK(holes == 0);
        CHECK(wrong == 0);
        CHECK(covered(v) > 0);
    }
    for (int i = 0; i < 12; ++i) {
        // Inside: every pixel hits.
        Vec3 eye = random_direction(rng) * (0.8 * u(rng));
        Camera cam = look(eye, eye + random_direction(rng), 30 + 120 * u(rng), 1e-4, 10);
        HostVisibility v = r.render(cam, w, h, Path::Ray).read();
        INFO("inside camera " << i << ": " << cam.to_flags());
        CHECK(covered(v) == std::size_t(w) * h);
    }
}

TEST_CASE("spot shows no hole from random cameras", "[device][ray][slow]")
{
    Device d = device();
    Scene s;
    s.add_mesh(load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj"));
    Renderer r(d, s);
    Bounds b = s.bounds();
    double radius = length(b.extent()) * 0.5;
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 12; ++i) {
        Vec3 eye = b.center() + random_direction(rng) * (radius * (1.2 + 3 * u(rng)));
        Camera cam = look(eye, b.center() + random_direction(rng) * (0.3 * radius * u(rng)), 25 + 40 * u(rng), 1e-3, 100);
        HostVisibility v = r.render(cam, 40, 30, Path::Ray).read();
        INFO("camera " << i << ": " << cam.to_flags());
        CHECK(covered(v) > 0);
        CHECK(holes(s, cam, v) == 0);
    }
}

TEST_CASE("rays aimed exactly at shared edges and vertices of a tessellated plane all hit", "[device][ray]")
{
    Device d = device();
    const int w = 64, h = 48;
    // Orthographic, one world unit per pixel: pixel centres fall on x, y = k + 0.5 exactly.
    Camera ortho = Camera::orthographic({0, 0, 40}, {0, 0, 0}, {0, 1, 0}, h, 0.5, 100);
    struct Layout {
        const char* what;
        float x0, y0, step, slope_x, slope_y;
    };
    for (Layout l : {Layout{"vertices", -40.5f, -30.5f, 1.0f, 0, 0}, Layout{"diagonals", -40.0f, -30.0f, 1.0f, 0, 0},
                     Layout{"horizontal edges", -40.0f, -30.5f, 1.0f, 0, 0},
                     Layout{"vertical edges", -40.5f, -30.0f, 1.0f, 0, 0},
                     Layout{"vertices, tilted", -40.5f, -30.5f, 1.0f, 0.25f, -0.125f},
                     Layout{"diagonals, tilted", -40.0f, -30.0f, 1.0f, -0.25f, 0.5f},
                     Layout{"vertices, fine", -40.5f, -30.5f, 0.5f, 0.0f, 0.0f}}) {
        Scene s;
        int n = int(std::ceil(82 / l.step));
        s.add_mesh(plane_grid(n, l.x0, l.y0, l.step, l.slope_x, l.slope_y));
        Renderer r(d, s);
        HostVisibility v = r.render(ortho, w, h, Path::Ray).read();
        INFO(l.what);
        CHECK(covered(v) == std::size_t(w) * h);
        HostVisibility brute = r.render(ortho, w, h, Path::Brute).read();
        CHECK(covered(brute) == std::size_t(w) * h);
    }
    // Perspective: a finely tessellated plane filling the view from random cameras.
    Scene s;
    s.add_mesh(plane_grid(200, -10.0f, -10.0f, 0.1f, 0.1f, 0.05f));
    Renderer r(d, s);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 16; ++i) {
        Vec3 eye{u(rng), u(rng), 2 + 0.5 * u(rng)};
        Vec3 target{u(rng) * 0.5, u(rng) * 0.5, 0};
        Camera cam = Camera::perspective(eye, target, {0, 1, 0}, 40, 0.01, 100);
        HostVisibility v = r.render(cam, 61, 47, Path::Ray).read();
        INFO(cam.to_flags());
        CHECK(covered(v) == std::size_t(61) * 47);
    }
}

namespace {

/// Sets CLVIS_EXACT_FLOAT for its lifetime (kernels built meanwhile take the float-only exact
/// fallback, shared/exact.h), then restores what was there.
struct ExactFloat : test::ScopedEnv {
    explicit ExactFloat(const char* value) : ScopedEnv("CLVIS_EXACT_FLOAT", value) {}
};

/// Pairs of a ray and a triangle whose float edge functions round one to zero (the exact fallback
/// runs) for rays (x, y, 40) -> -z at pixel centres x, y = k + 0.5 of a w x h grid around 0.
std::size_t fallbacks(const Scene& s, int w, int h)
{
    std::size_t n = 0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            clvis_vec3 origin = {float(i - w / 2) + 0.5f, float(h / 2 - j) - 0.5f, 40.0f};
            clvis_ray_shear ray = clvis_make_shear(origin, {0, 0, -1});
            for (std::uint32_t id = 0; id < s.triangle_count(); ++id) {
                float v[9];
                s.triangle(id, v);
                clvis_tri_2d p;
                clvis_project_triangle_scaled(ray, {v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, 1.0f,
                                              &p);
                float u = p.cx * p.by - p.cy * p.bx, vv = p.ax * p.cy - p.ay * p.cx, ww = p.bx * p.ay - p.by * p.ax;
                n += u == 0.0f || vv == 0.0f || ww == 0.0f;
            }
        }
    return n;
}

} // namespace

TEST_CASE("the float-only exact edge fallback gives the double form's bits, watertight", "[device][ray]")
{
    // Pixel centres on the vertices and edges of plane grids (orthographic, 1 px per unit: the
    // fallback runs on every shared edge); tilted grids under perspective behind triangles in
    // planes x = k / 4, one of them through the eye and the middle column of pixels (edge-on).
    Device d = device();
    const int w = 64, h = 48;
    Camera ortho = Camera::orthographic({0, 0, 40}, {0, 0, 0}, {0, 1, 0}, h, 0.5, 100);
    struct Case {
        Scene scene;
        Camera cam;
        int w;
    };
    std::vector<Case> cases;
    for (float x0 : {-40.5f, -40.0f}) {
        Scene s;
        s.add_mesh(plane_grid(82, x0, -30.5f, 1.0f, x0 < -40.25f ? 0.0f : 0.25f, -0.125f));
        cases.push_back({s, ortho, w});
    }
    std::size_t taken = fallbacks(cases[0].scene, w, h);
    std::printf("exact fallback: %zu ray/triangle pairs of the vertex grid take it\n", taken);
    CHECK(taken > std::size_t(w) * h);
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 4; ++i) {
        Scene s;
        s.add_mesh(plane_grid(100, -10.0f, -10.0f, 0.2f, 0.1f * float(i), 0.05f));
        for (int k = -10; k <= 10; ++k) {
            float x = 0.25f * float(k);
            s.add_mesh(triangle(x, -3, 1, x, 3, 1, x, 0, 2.5f));
        }
        cases.push_back({s, Camera::perspective({0, u(rng), 4 + u(rng)}, {0, 0, 0}, {0, 1, 0}, 50, 0.01, 100), w + 1});
    }
    for (const Case& c : cases) {
        std::vector<HostVisibility> forms;
        for (const char* exact_float : {"0", "1"}) {
            ExactFloat env(exact_float);
            Renderer r(d, c.scene);
            forms.push_back(r.render(c.cam, c.w, h, Path::Ray).read());
            forms.push_back(r.render(c.cam, c.w, h, Path::Brute).read());
        }
        INFO(c.cam.to_flags());
        CHECK(covered(forms[2]) == std::size_t(c.w) * h); // no hole with the float-only form
        CHECK(test::differing_bits(forms[0], forms[2]) == 0);
        CHECK(test::differing_bits(forms[1], forms[3]) == 0);
        CHECK(test::differing_bits(forms[2], forms[3]) == 0);
    }
    ExactFloat bad("yes");
    CHECK_THROWS_WITH(Renderer(d, cases[0].scene).render(ortho, 8, 8, Path::Ray),
                      Catch::Contains("CLVIS_EXACT_FLOAT must be 0 or 1, got 'yes'"));
}

TEST_CASE("hand-made cases near, far, behind, ortho, ties, degenerate, every pixel written", "[device][ray]")
{
    Device d = device();
    Camera front = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.5, 20);
    auto ids_and_depth = [&](const Scene& s, const Camera& cam, int w, int h) {
        Renderer r(d, s);
        return r.render(cam, w, h, Path::Ray).read();
    };

    SECTION("a hit exactly at near or far is kept, one ulp outside is clipped")
    {
        Scene s;
        s.add_mesh(triangle(-10, -10, -2, 10, -10, -2, 0, 10, -2));
        Camera cam = front;
        cam.near = 2;
        HostVisibility v = ids_and_depth(s, cam, 16, 16);
        CHECK(covered(v) == 256);
        CHECK(v.depth_at(3, 5) == 2.0f);
        cam.near = 0.5;
        cam.far = 2;
        CHECK(covered(ids_and_depth(s, cam, 16, 16)) == 256);
        cam.far = std::nextafter(2.0f, 1.0f);
        CHECK(covered(ids_and_depth(s, cam, 16, 16)) == 0);
        cam.far = 20;
        cam.near = std::nextafter(float(2.0), 3.0f);
        CHECK(covered(ids_and_depth(s, cam, 16, 16)) == 0);
    }
    SECTION("a triangle behind the camera is not seen")
    {
        Scene s;
        s.add_mesh(triangle(-10, -10, 2, 10, -10, 2, 0, 10, 2));
        CHECK(covered(ids_and_depth(s, front, 16, 16)) == 0);
    }
    SECTION("orthographic rays keep the view depth")
    {
        Scene s;
        s.add_mesh(triangle(-10, -10, -3, 10, -10, -3, 0, 10, -3));
        Camera cam = Camera::orthographic({0.25, 0.5, 1}, {0.25, 0.5, 0}, {0, 1, 0}, 4, 0.5, 20);
        HostVisibility v = ids_and_depth(s, cam, 20, 20);
        CHECK(covered(v) == 400);
        CHECK(v.depth_at(7, 11) == 4.0f);
    }
    SECTION("coincident triangles go to the lower id, whatever their vertex order or mesh")
    {
        Scene s;
        s.add_mesh(triangle(0, 0, -30, 0, 0, -30, 0, 0, -30));                // id 0: degenerate, never hit
        MeshData m;
        m.positions = {-1, -1, -4, 1, -1, -4, 0, 1, -4};
        m.indices = {2, 0, 1, 0, 1, 2, 1, 2, 0}; // ids 1, 2, 3: one triangle three times
        s.add_mesh(m);
        s.add_mesh(triangle(-1, -1, -4, 1, -1, -4, 0, 1, -4)); // id 4
        HostVisibility v = ids_and_depth(s, front, 32, 32);
        REQUIRE(covered(v) > 50);
        for (auto id : v.ids) CHECK((id == 1 || id == background_id));
    }
    SECTION("degenerate triangles are never hit")
    {
        Scene s;
        s.add_mesh(triangle(-1, -1, -4, -1, -1, -4, 1, 1, -4));  // repeated vertex
        s.add_mesh(triangle(-1, -1, -4, 0, 0, -4, 1, 1, -4));    // collinear through the view
        s.add_mesh(triangle(0, 0, -4, 0, 0, -4, 0, 0, -4));      // a point
        s.add_mesh(triangle(0, -1, -1, 0, 1, -1, 0, 0, -9));     // seen edge-on
        CHECK(covered(ids_and_depth(s, front, 33, 33)) == 0);
    }
    SECTION("every pixel is written, whatever the buffer held")
    {
        Scene s;
        s.add_mesh(make_uv_sphere(500));
        Camera cam = Camera::framing(s.bounds());
        Renderer r(d, s);
        VisibilityBuffer target(d, 37, 23);
        cl_ulong junk = 0x123456789ABCDEFull;
        cl_command_queue q = d.queue();
        REQUIRE(clEnqueueFillBuffer(q, target.keys(), &junk, sizeof junk, 0, 37 * 23 * 8, 0, nullptr, nullptr) == CL_SUCCESS);
        REQUIRE(clFinish(q) == CL_SUCCESS);
        for (Path p : {Path::Ray, Path::Brute}) {
            r.render(cam, p, target);
            auto keys = target.read_keys();
            std::size_t bad = 0;
            for (auto k : keys) bad += k != background_key && (k & 0xFFFFFFFFu) >= s.triangle_count();
            CHECK(bad == 0);
            REQUIRE(clEnqueueFillBuffer(q, target.keys(), &junk, sizeof junk, 0, 37 * 23 * 8, 0, nullptr, nullptr) == CL_SUCCESS);
            REQUIRE(clFinish(q) == CL_SUCCESS);
        }
    }
    SECTION("an empty scene is background everywhere")
    {
        Scene s;
        Renderer r(d, s);
        CHECK(covered(r.render(front, 19, 7, Path::Ray).read()) == 0);
        CHECK(covered(r.render(front, 19, 7, Path::Brute).read()) == 0);
        CHECK(r.bvh_stats().nodes == 0);
    }
}

TEST_CASE("axis-parallel rays find flat boxes on every axis", "[device][ray]")
{
    Device d = device();
    // A flat grid seen face-on along each axis, orthographic: every ray has two zero components
    // and every box of the tree is flat along the view.
    for (int axis = 0; axis < 3; ++axis) {
        MeshData g = plane_grid(30, -3.05f, -2.95f, 0.2f);
        for (std::size_t i = 0; i < g.positions.size(); i += 3) {
            float p[3] = {g.positions[i], g.positions[i + 1], g.positions[i + 2]};
            // rotate (x, y, z) so that the grid's normal lies along `axis`
            for (int k = 0; k < 3; ++k) g.positions[i + std::size_t(k)] = p[(k + 2 - axis + 3) % 3];
        }
        Scene s;
        s.add_mesh(g);
        Vec3 eye{0, 0, 0}, up{0, 1, 0};
        (axis == 0 ? eye.x : axis == 1 ? eye.y : eye.z) = 4;
        if (axis == 1) up = {0, 0, 1};
        for (Projection proj : {Projection::Orthographic, Projection::Perspective}) {
            Camera cam = proj == Projection::Orthographic ? Camera::orthographic(eye, {0, 0, 0}, up, 4, 0.5, 10)
                                                          : Camera::perspective(eye, {0, 0, 0}, up, 50, 0.5, 10);
            Renderer r(d, s);
            HostVisibility v = r.render(cam, 32, 24, Path::Ray).read();
            INFO("axis " << axis << (proj == Projection::Orthographic ? ", orthographic" : ", perspective"));
            CHECK(covered(v) == 32 * 24);
            check_paths_agree(r, cam, 32, 24, "axis-parallel");
        }
    }
    // Looking along the plane itself: the rays lie in the plane of flat boxes and hit nothing.
    Scene s;
    s.add_mesh(plane_grid(10, -1, -1, 0.2f));
    Renderer r(d, s);
    Camera grazing = Camera::orthographic({0, -5, 0}, {0, 0, 0}, {0, 0, 1}, 0.5, 0.1, 20);
    // 15 rows: the middle row's rays lie exactly in the plane, the others parallel to it
    CHECK(covered(r.render(grazing, 15, 15, Path::Ray).read()) == 0);
    CHECK(covered(r.render(grazing, 15, 15, Path::Brute).read()) == 0);
}

TEST_CASE("the same scene renders the same bits twice and in two renderers", "[device][ray]")
{
    Device d = device();
    Scene s;
    s.add_mesh(make_soup(4000, 1));
    s.add_mesh(make_uv_sphere(2000));
    Camera cam = Camera::framing(s.bounds());
    Renderer a(d, s), b(d, s);
    auto first = a.render(cam, 80, 60, Path::Ray).read_keys();
    CHECK(a.render(cam, 80, 60, Path::Ray).read_keys() == first);
    CHECK(b.render(cam, 80, 60, Path::Ray).read_keys() == first);
    CHECK(a.bvh_stats().nodes == b.bvh_stats().nodes);
    CHECK(a.bvh_stats().sah_cost == b.bvh_stats().sah_cost);
}

TEST_CASE("a refit after moving a mesh draws what a rebuild draws", "[device][ray]")
{
    Device d = device();
    Scene s;
    s.add_mesh(make_uv_sphere(3000));
    s.add_mesh(make_grid(1000, 2));
    Camera cam = Camera::perspective({0.5, 2, 4}, {0, 0, 0}, {0, 1, 0}, 50, 0.1, 50);
    RenderOptions refit, rebuild;
    refit.bvh.update = BvhUpdate::Refit;
    rebuild.bvh.update = BvhUpdate::Rebuild;
    Renderer a(d, s, refit), b(d, s, rebuild);
    a.render(cam, 8, 8, Path::Ray);
    b.render(cam, 8, 8, Path::Ray);
    std::size_t nodes_before = a.bvh_stats().nodes;
    for (int step = 1; step <= 3; ++step) {
        Scene moved = s;
        Mat4 m; // rotate about y and slide: the tree's boxes all change
        double c = std::cos(0.4 * step), sn = std::sin(0.4 * step);
        m(0, 0) = c;
        m(0, 2) = sn;
        m(2, 0) = -sn;
        m(2, 2) = c;
        m(0, 3) = 0.3 * step;
        m(1, 3) = -0.2 * step;
        moved.set_transform(0, m);
        a.update(moved);
        b.update(moved);
        CHECK(a.bvh_stats().refitted);
        CHECK_FALSE(b.bvh_stats().refitted);
        CHECK(a.bvh_stats().nodes == nodes_before);
        auto keys_refit = a.render(cam, 72, 54, Path::Ray).read_keys();
        auto keys_rebuild = b.render(cam, 72, 54, Path::Ray).read_keys();
        INFO("step " << step);
        CHECK(keys_refit == keys_rebuild);
        CHECK(keys_refit == a.render(cam, 72, 54, Path::Brute).read_keys());
    }
}

TEST_CASE("the ray path reports its BVH", "[device][ray]")
{
    Device d = device();
    Scene s;
    s.add_mesh(make_uv_sphere(10000));
    Renderer r(d, s);
    CHECK(r.bvh_stats().nodes == 0);
    r.prepare(Path::Ray);
    const BvhStats& st = r.bvh_stats();
    CHECK(st.nodes == 2 * st.leaves - 1);
    CHECK(st.leaves >= s.triangle_count() / 4);
    CHECK(st.depth > 5);
    CHECK(st.build_ms > 0);
    CHECK(st.sah_cost > 1);
    CHECK_FALSE(st.refitted);
}
