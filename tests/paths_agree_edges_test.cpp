// The agreement suite on procedural stress scenes built to put samples on shared edges and
// vertices, ties, slivers, huge triangles, edge-on planes, near and far and extreme depth ranges:
// every pixel of both paths judged by the referee, raster against ray compared, and the raster-rule
// coverage's ray and brute paths equal to the raster path bit for bit (agree_harness.hpp). The
// bundled meshes and cameras are in paths_agree_test.cpp.
#include "agree_harness.hpp"
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

using namespace clvis;
using namespace clvis::agreement;

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

TEST_CASE("slivers, needles and zero-area triangles, no errors", "[device][agree][rusticl][rusticl_long]")
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
