// Both paths against the referee: every pixel of every buffer judged, ids and depths (zero errors
// anywhere, with the renderer's own options), raster against ray compared (explained mismatches
// counted, within CONVENTIONS.md's budget on real meshes under general cameras), on the bundled
// meshes and the Khronos glTF samples under framing and seeded random cameras, with several samples
// per pixel, intrinsics and poses, and up to the raster limit. Every case also renders the ray and
// brute paths with the raster-rule coverage, whose ids and depths must equal the raster path's bit
// for bit on every pixel (agree_harness.hpp). Each case prints one line, so a regression shows in
// the test log. The procedural stress scenes are in paths_agree_edges_test.cpp.
#include "agree_harness.hpp"
#include "catch.hpp"
#include "shared/samples.h"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace clvis;
using namespace clvis::agreement;

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

TEST_CASE("2 to 16 samples per pixel: both paths judged at every sample", "[device][agree][samples]")
{
    Device device = Device::open();
    Tally tally, on_edges;
    Random rng(20261202);
    // Vertices on pixel centres, one world unit per pixel (raster (x, 24 - y)): the samples' 1/16 px
    // offsets put many of them exactly on shared edges and vertices (the top-left rule at every
    // sample; judged on errors alone, like the face-on plane of paths_agree_edges_test.cpp).
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
    // Where float32 cannot keep uncertainty() (agree_harness.hpp) within its share of EPS, the
    // referee judges with float32_tolerance(), which prints the tolerance and its reason;
    // everything else about the judgement (every pixel of both paths, raster against ray) is
    // unchanged.
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
