// Flow between views (include/clvis/flow.hpp, CONVENTIONS.md "Motion between views (flow)"): on
// both paths, judged in double by judge_flow (host/referee/referee_flow.cpp) for a camera move over
// the bunny (perspective, orthographic, intrinsics), an instance that moves, and an object that
// moves in front in the second view; views files whose cameras move items, rendered as batches;
// what is refused.
#include "catch.hpp"
#include "test_files.hpp"

#include <clvis/clvis.hpp>
#include <clvis/flow.hpp>
#include <clvis/referee_flow.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace clvis;

namespace {

Mat4 translation(double x, double y, double z)
{
    Mat4 m;
    m(0, 3) = x;
    m(1, 3) = y;
    m(2, 3) = z;
    return m;
}

/// `c` turned about the vertical axis through `centre` by `angle` radians.
Camera orbit(Camera c, Vec3 centre, double angle)
{
    Vec3 d = c.eye - centre;
    c.eye = centre + Vec3{d.x * std::cos(angle) - d.z * std::sin(angle), d.y, d.x * std::sin(angle) + d.z * std::cos(angle)};
    return c;
}

struct Judged {
    FlowReport report;
    std::vector<float> flow;
    HostVisibility a, b;
};

/// Renders A (the scene with items_a), then B (with items_b), computes the flow A -> B and judges it.
Judged flow_judged(Device& device, Scene scene, const Camera& ca, const Camera& cb, int w, int h, Path path,
                   const ItemTransforms& items_a = {}, const ItemTransforms& items_b = {})
{
    Renderer renderer(device, scene);
    Scene moved = scene;
    for (const auto& [item, t] : items_a) moved.set_transform(item, t);
    renderer.update(moved);
    VisibilityBuffer a = renderer.render(ca, w, h, path);
    moved = scene;
    for (const auto& [item, t] : items_b) moved.set_transform(item, t);
    renderer.update(moved);
    VisibilityBuffer b = renderer.render(cb, w, h, path);
    renderer.update(scene); // the corners at each view are the renderer's scene with the items replaced
    Judged j;
    j.flow = flow(renderer, a, ca, b, cb, items_a, items_b).read();
    a.read(j.a);
    b.read(j.b);
    j.report = judge_flow(scene, j.a, ca, j.b, cb, j.flow, items_a, items_b);
    INFO(to_string(path) << ": " << j.report.first_error);
    CHECK(j.report.ok());
    CHECK(j.report.flow_errors == 0);
    CHECK(j.report.valid_errors == 0);
    CHECK(j.report.occluded_errors == 0);
    CHECK(j.report.max_flow_error <= 1e-3);
    return j;
}

Scene bunny()
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/stanford-bunny.obj"));
    return s;
}

} // namespace

TEST_CASE("flow of a camera move over the bunny is judged right on both paths", "[device][flow]")
{
    Device device = Device::open();
    Scene s = bunny();
    Vec3 centre = s.bounds().center();
    const int w = 200, h = 150;
    struct Pair {
        const char* what;
        Camera a, b;
    };
    Camera persp = Camera::framing(s.bounds());
    Camera ortho = Camera::framing(s.bounds(), Projection::Orthographic);
    Camera intr = persp;
    intr.intrinsics = Intrinsics{230, 210, 90.5, 80.25};
    std::vector<Pair> pairs = {{"perspective", persp, orbit(persp, centre, 0.15)},
                               {"orthographic", ortho, orbit(ortho, centre, -0.2)},
                               {"intrinsics", intr, orbit(intr, centre, 0.1)},
                               {"perspective to orthographic", persp, ortho}};
    for (const Pair& p : pairs)
        for (Path path : {Path::Raster, Path::Ray}) {
            INFO(p.what << ", " << to_string(path));
            Judged j = flow_judged(device, s, p.a, p.b, w, h, path);
            CHECK(j.report.foreground > 3000);
            CHECK(j.report.valid > j.report.foreground * 9 / 10);
            // CONVENTIONS.md compares P_B's depth with B's depth at the centre of the pixel it lands
            // in: on the bunny's slopes that alone flags about half of the samples (docs: noted).
            CHECK(j.report.occluded > 0);
        }
    // Corners placed on the host for A's visible triangles (as when an item moves, here to where it
    // is) give the resident expansion's flow bit for bit.
    {
        Renderer renderer(device, s);
        VisibilityBuffer a = renderer.render(persp, w, h, Path::Ray), b = renderer.render(pairs[0].b, w, h, Path::Ray);
        std::vector<float> resident = flow(renderer, a, persp, b, pairs[0].b).read();
        std::vector<float> placed = flow(renderer, a, persp, b, pairs[0].b, {{0, Mat4::identity()}}, {}).read();
        CHECK(std::memcmp(resident.data(), placed.data(), resident.size() * 4) == 0);
    }
    // The same camera twice: zero flow, nothing occluded.
    Judged same = flow_judged(device, s, persp, persp, w, h, Path::Ray);
    std::size_t moved = 0, occluded = 0;
    for (std::size_t p = 0; p < std::size_t(w) * h; ++p)
        if (same.flow[p * 4 + 2] == 1.0f) {
            moved += std::fabs(same.flow[p * 4]) > 1e-3 || std::fabs(same.flow[p * 4 + 1]) > 1e-3;
            occluded += same.flow[p * 4 + 3] == 1.0f;
        }
    CHECK(moved == 0);
    CHECK(occluded == 0);
    // The referee sees a flow off by 2e-3 px, a mask flipped, a valid sample without flow.
    Judged turn = flow_judged(device, s, persp, pairs[0].b, w, h, Path::Raster);
    std::size_t p = 0;
    while (turn.flow[p * 4 + 2] != 1.0f || turn.flow[p * 4 + 3] != 0.0f) ++p;
    auto judged = [&](std::size_t channel, float value) {
        std::vector<float> broken = turn.flow;
        broken[p * 4 + channel] = value;
        return judge_flow(s, turn.a, persp, turn.b, pairs[0].b, broken);
    };
    CHECK(judged(0, turn.flow[p * 4] + 2e-3f).flow_errors == 1);
    CHECK(judged(1, NAN).flow_errors == 1);
    CHECK(judged(2, 0.0f).valid_errors + judged(2, 0.0f).flow_errors == 1);
    CHECK(judged(3, 1.0f).occluded_errors == 1);
    CHECK(judged(2, 0.5f).valid_errors == 1);
    INFO("valid " << turn.report.valid << ", occluded " << turn.report.occluded << ", ambiguous " << turn.report.ambiguous);
    CHECK(turn.report.ambiguous < turn.report.valid / 100);
}

TEST_CASE("flow follows an instance that moves between views", "[device][flow]")
{
    Device device = Device::open();
    Scene s;
    std::size_t proto = s.add_prototype(make_uv_sphere(2000));
    s.add_instance(proto, translation(-1.5, 0, 0));
    s.add_instance(proto, translation(1.5, 0, 0));
    Camera cam = Camera::perspective({0, 0, 8}, {0, 0, 0}, {0, 1, 0}, 45, 0.1, 100);
    const int w = 160, h = 96;
    ItemTransforms at_b = {{1, translation(1.5, 0.4, 0)}}; // item 1 moves up by 0.4 world units
    for (Path path : {Path::Raster, Path::Ray}) {
        INFO(to_string(path));
        Judged j = flow_judged(device, s, cam, cam, w, h, path, {}, at_b);
        // The still sphere does not move; the moved one moves up (y down in raster space) by about
        // 0.4 * fy / depth px.
        double fy = h / (2 * std::tan(M_PI / 8));
        std::size_t still = 0, up = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float* f = &j.flow[(std::size_t(y) * w + x) * 4];
                if (j.a.id(x, y) == background_id || f[2] != 1.0f) continue;
                if (x < w / 2) still += std::fabs(f[0]) < 1e-3 && std::fabs(f[1]) < 1e-3;
                else up += f[1] < -0.3 * fy * 0.4 / 8 && f[1] > -2 * fy * 0.4 / 8 && std::fabs(f[0]) < 1.5;
            }
        CHECK(still > 500);
        CHECK(up > 500);
        CHECK(j.report.valid > 1000);
    }
}

TEST_CASE("flow marks what an object moving in front hides in the second view", "[device][flow]")
{
    Device device = Device::open();
    Scene s = bunny();
    Bounds bb = s.bounds();
    Vec3 c = bb.center();
    double r = length(bb.extent()) / 2;
    Camera cam = Camera::framing(bb);
    // A square card between the camera and the bunny, out of the view at A, in front at B.
    MeshData card;
    card.name = "card";
    double half = r * 0.3;
    card.positions = {float(-half), float(-half), 0, float(half), float(-half), 0,
                      float(half), float(half), 0, float(-half), float(half), 0};
    card.indices = {0, 1, 2, 0, 2, 3};
    Vec3 mid = c + (cam.eye - c) * 0.4;
    Mat4 away = translation(mid.x + 20 * r, mid.y, mid.z);
    // The card faces the camera: its plane is turned to be perpendicular to eye - c.
    CameraFrame fr = cam.frame();
    Mat4 in_front;
    for (int i = 0; i < 3; ++i) {
        in_front(i, 0) = i == 0 ? fr.r.x : i == 1 ? fr.r.y : fr.r.z;
        in_front(i, 1) = i == 0 ? fr.u.x : i == 1 ? fr.u.y : fr.u.z;
        in_front(i, 2) = i == 0 ? -fr.f.x : i == 1 ? -fr.f.y : -fr.f.z;
    }
    in_front(0, 3) = mid.x;
    in_front(1, 3) = mid.y;
    in_front(2, 3) = mid.z;
    s.add_mesh(card, away);
    const int w = 160, h = 120;
    Camera cb = orbit(cam, c, 0.05);
    for (Path path : {Path::Raster, Path::Ray}) {
        INFO(to_string(path));
        Judged j = flow_judged(device, s, cam, cb, w, h, path, {}, {{1, in_front}});
        CHECK(j.report.occluded > 500);
        // Every valid bunny sample of A that lands where B sees the card (far nearer) is occluded.
        std::size_t on_card = 0, hidden = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float* f = &j.flow[(std::size_t(y) * w + x) * 4];
                if (f[2] != 1.0f) continue;
                int bx = int(std::floor(x + 0.5 + f[0])), by = int(std::floor(y + 0.5 + f[1]));
                std::uint32_t seen = j.b.id(bx, by);
                if (seen == background_id || seen < s.meshes()[1].first_triangle) continue;
                ++on_card;
                hidden += f[3] == 1.0f;
            }
        CHECK(on_card > 500);
        CHECK(hidden == on_card);
    }
}

TEST_CASE("a views file's items move items per view; batches render them as views alone", "[device][flow]")
{
    std::string path = test::write_temp_file("clvis_flow_test", "views.json", R"({"width": 64, "height": 48, "views": [
        {"eye": [0, 0, 8], "target": [0, 0, 0], "fov": 45},
        {"eye": [0, 0, 8], "target": [0, 0, 0], "fov": 45, "items": {"1": [1,0,0,1.5, 0,1,0,0.5, 0,0,1,0, 0,0,0,1]}},
        {"eye": [0, 0, 8], "target": [0, 0, 0], "fov": 45, "items": {"1": [1,0,0,1.5, 0,1,0,0.5, 0,0,1,0, 0,0,0,1]}},
        {"eye": [0.3, 0, 8], "target": [0, 0, 0], "fov": 45}
    ]})");
    ViewsFile vf = load_views_file(path);
    REQUIRE(vf.items.size() == 4);
    CHECK(vf.moves());
    CHECK(vf.items[0].empty());
    CHECK(vf.items[1].at(1)(1, 3) == 0.5);
    Scene s;
    std::size_t proto = s.add_prototype(make_uv_sphere(500));
    s.add_instance(proto, translation(-1.5, 0, 0));
    s.add_instance(proto, translation(1.5, 0, 0));
    check_view_items(vf, s);
    Device device = Device::open();
    Renderer renderer(device, s);
    for (Path p : {Path::Raster, Path::Ray, Path::Brute}) {
        INFO(to_string(p));
        VisibilityBatch batch(device, 4, vf.width, vf.height);
        render_views(renderer, s, vf.views, vf.items, p, batch);
        CHECK(s.meshes()[1].transform.m == translation(1.5, 0, 0).m); // left as it was given
        for (int v = 0; v < 4; ++v) {
            Scene alone = s;
            for (const auto& [item, t] : vf.items[std::size_t(v)]) alone.set_transform(item, t);
            Renderer single(device, alone);
            CHECK(batch.view(v).read_keys() == single.render(vf.views[std::size_t(v)], vf.width, vf.height, p).read_keys());
        }
        CHECK(batch.view(0).read_keys() != batch.view(1).read_keys());
    }
    // Item 7 is not in a scene of 3 items: named with the file and the view.
    ViewsFile far = vf;
    far.items[2][7] = Mat4::identity();
    CHECK_THROWS_WITH(check_view_items(far, s), Catch::Contains("views[2].items.7") && Catch::Contains("no such item"));
    VisibilityBatch batch(device, 4, vf.width, vf.height);
    CHECK_THROWS_AS(render_views(renderer, s, vf.views, far.items, Path::Ray, batch), Error);
}

TEST_CASE("a views file's items are checked when read, naming the view and the item", "[flow]")
{
    auto refused = [](const std::string& items) {
        std::string path = test::write_temp_file("clvis_flow_test", "bad.json",
                                                 R"({"width": 8, "height": 8, "views": [{"eye": [0, 0, 5], "target": [0, 0, 0]},
            {"eye": [0, 0, 5], "target": [0, 0, 0], "items": )" + items + "}]}");
        try {
            load_views_file(path);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    CHECK_THAT(refused(R"({"x": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})"), Catch::Contains("views[1].items.x"));
    CHECK_THAT(refused(R"({"-1": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})"), Catch::Contains("views[1].items.-1"));
    CHECK_THAT(refused(R"({"0": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]})"),
               Catch::Contains("views[1].items.0") && Catch::Contains("0 0 0 1"));
    CHECK_THAT(refused(R"({"0": [1,0,0,0]})"), Catch::Contains("views[1].items.0") && Catch::Contains("16 numbers"));
    CHECK_THAT(refused(R"({"0": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,"a"]})"), Catch::Contains("views[1].items.0[15]"));
    CHECK_THAT(refused("[1]"), Catch::Contains("views[1].items"));
    CHECK(refused(R"({"3": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})") == "accepted");
}

TEST_CASE("flow refuses what it cannot answer, by name", "[device][flow]")
{
    Device device = Device::open();
    Scene s;
    s.add_mesh(make_uv_sphere(200));
    Renderer renderer(device, s);
    Camera cam = Camera::perspective({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45, 0.1, 100);
    VisibilityBuffer a = renderer.render(cam, 32, 24, Path::Ray), b = renderer.render(cam, 24, 32, Path::Ray);
    CHECK_THROWS_WITH(flow(renderer, a, cam, b, cam), Catch::Contains("flow: views of one size"));
    CHECK_THROWS_WITH(flow(renderer, a, cam, a, cam, {{3, Mat4::identity()}}), Catch::Contains("items_a[3]"));
    RenderOptions four;
    four.samples = 4;
    Renderer msaa(device, s, four);
    VisibilityBuffer m = msaa.render(cam, 32, 24, Path::Raster);
    CHECK_THROWS_WITH(flow(msaa, m, cam, m, cam), Catch::Contains("one sample per pixel"));
    CHECK_THROWS_WITH(flow(renderer, VisibilityBuffer(), cam, a, cam), Catch::Contains("empty"));
}

// Not run by default ("[.]"): what the flow costs against the visibility frame, bunny at 1080p,
// warm, best of 5; printed. `clvis_tests "[flow_cost]"`.
TEST_CASE("flow cost against the visibility frame, bunny at 1080p", "[.][flow_cost]")
{
    Device device = Device::open();
    Scene s = bunny();
    Camera a = Camera::framing(s.bounds()), b = orbit(a, s.bounds().center(), 0.05);
    const int w = 1920, h = 1080;
    for (Path path : {Path::Raster, Path::Ray}) {
        Renderer renderer(device, s);
        renderer.prepare(path);
        VisibilityBuffer va(device, w, h), vb(device, w, h);
        FlowBuffer f;
        double render_ms = 1e300, flow_ms = 1e300, moved_ms = 1e300, resolve_ms = 1e300;
        for (int i = 0; i < 6; ++i) {
            auto t0 = std::chrono::steady_clock::now();
            renderer.render(a, path, va);
            auto t1 = std::chrono::steady_clock::now();
            renderer.render(b, path, vb);
            auto t2 = std::chrono::steady_clock::now();
            flow(renderer, va, a, vb, b, f);
            auto t3 = std::chrono::steady_clock::now();
            flow(renderer, va, a, vb, b, f, {{0, Mat4::identity()}}, {});
            auto t4 = std::chrono::steady_clock::now();
            AttributeRequest bary;
            bary.position = true;
            resolve(renderer, va, a, bary);
            auto t5 = std::chrono::steady_clock::now();
            if (i == 0) continue; // first launches compile
            render_ms = std::min(render_ms, std::chrono::duration<double, std::milli>(t1 - t0).count());
            flow_ms = std::min(flow_ms, std::chrono::duration<double, std::milli>(t3 - t2).count());
            moved_ms = std::min(moved_ms, std::chrono::duration<double, std::milli>(t4 - t3).count());
            resolve_ms = std::min(resolve_ms, std::chrono::duration<double, std::milli>(t5 - t4).count());
        }
        std::printf("flow cost, bunny 1920x1080, %s: visibility frame %.2f ms, flow %.2f ms (resident corners), "
                    "%.2f ms (an item moved: visible triangles placed on the host); resolve (position) %.2f ms\n",
                    to_string(path), render_ms, flow_ms, moved_ms, resolve_ms);
        CHECK(flow_ms > 0);
    }
}
