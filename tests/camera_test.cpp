// The camera of CONVENTIONS.md: hand-computed projections, the matrices against the direct
// path, the physical camera, the orthographic limit, round trips, and the float32 header that
// the kernels compile (kernels/shared/camera.h) against the double-precision reference.
#include "catch.hpp"

#include "frame/frame.hpp"

#include <clvis/camera.hpp>
#include <clvis/error.hpp>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

using namespace clvis;

namespace {

constexpr double pi = 3.14159265358979323846;

// A camera at the origin looking down -z with y up: camera space equals world space.
Camera axis_camera(double fov = 90)
{
    return Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, fov, 0.1, 100);
}

Vec3 apply(const Mat4& m, Vec3 p, double* w)
{
    double x = m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2) * p.z + m(0, 3);
    double y = m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2) * p.z + m(1, 3);
    double z = m(2, 0) * p.x + m(2, 1) * p.y + m(2, 2) * p.z + m(2, 3);
    *w = m(3, 0) * p.x + m(3, 1) * p.y + m(3, 2) * p.z + m(3, 3);
    return {x, y, z};
}

} // namespace

TEST_CASE("a point at z = -2 lands on the canvas at half its x and y", "[camera]")
{
    Camera cam = axis_camera(90); // top = tan(45 deg) = 1: screen space equals NDC vertically
    Vec3 c = cam.to_camera({0.6, -0.4, -2});
    CHECK(c.x == Approx(0.6));
    CHECK(c.y == Approx(-0.4));
    CHECK(c.z == Approx(-2));
    // s = (0.3, -0.2); aspect 1 so NDC = s; raster = ((0.3 + 1) / 2 * 100, (1 + 0.2) / 2 * 100).
    Vec3 r = cam.to_raster({0.6, -0.4, -2}, 100, 100);
    CHECK(r.x == Approx(65.0));
    CHECK(r.y == Approx(60.0));
    CHECK(r.z == Approx(2.0));
}

TEST_CASE("raster space has its origin at the top-left corner and y down", "[camera]")
{
    Camera cam = axis_camera(90);
    Vec3 top_left = cam.to_raster({-1, 1, -1}, 200, 100); // aspect 2: right = 2
    CHECK(top_left.x == Approx(50.0));
    CHECK(top_left.y == Approx(0.0).margin(1e-12));
    Vec3 centre = cam.to_raster({0, 0, -5}, 200, 100);
    CHECK(centre.x == Approx(100.0));
    CHECK(centre.y == Approx(50.0));
}

TEST_CASE("the look-at frame is right-handed and looks down -z", "[camera]")
{
    Camera cam = Camera::perspective({1, 2, 3}, {4, 2, 3}, {0, 1, 0}, 60, 0.1, 10);
    CameraFrame fr = cam.frame();
    CHECK(fr.f.x == Approx(1.0));
    CHECK(fr.r.z == Approx(1.0)); // cross((1,0,0), (0,1,0)) = (0,0,1)
    CHECK(fr.u.y == Approx(1.0));
    Vec3 c = cam.to_camera({6, 2, 3});
    CHECK(c.z == Approx(-5.0));
    CHECK(c.x == Approx(0.0).margin(1e-12));
}

TEST_CASE("the OpenGL matrices agree with the direct projection", "[camera]")
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-3, 3);
    for (int kind = 0; kind < 3; ++kind) {
        Camera cam = Camera::perspective({1, 2, 5}, {0.2, -0.1, 0}, {0, 1, 0}, 50, 0.5, 40);
        Projection proj = kind == 1 ? Projection::Orthographic : Projection::Perspective;
        cam.projection = proj;
        cam.ortho_height = 3;
        if (kind == 2) cam.intrinsics = Intrinsics{500, 420, 250.5, 290}; // off-centre
        const int w = 640, h = 360;
        Mat4 pv = cam.projection_matrix(w, h) * cam.view_matrix();
        for (int i = 0; i < 50; ++i) {
            Vec3 p{u(rng), u(rng), u(rng)};
            Vec3 direct = cam.to_raster(p, w, h);
            double wc = 0;
            Vec3 clip = apply(pv, p, &wc);
            double nx = clip.x / wc, ny = clip.y / wc, nz = clip.z / wc;
            CHECK((nx + 1) / 2 * w == Approx(direct.x).margin(1e-9));
            CHECK((1 - ny) / 2 * h == Approx(direct.y).margin(1e-9));
            // NDC z maps near to -1 and far to +1.
            double d = direct.z;
            double expected_z = proj == Projection::Perspective
                                    ? (cam.far + cam.near) / (cam.far - cam.near) - 2 * cam.far * cam.near / ((cam.far - cam.near) * d)
                                    : 2 * (d - cam.near) / (cam.far - cam.near) - 1;
            CHECK(nz == Approx(expected_z).margin(1e-9));
        }
    }
}

TEST_CASE("focal length and film gate give the field of view", "[camera]")
{
    // 35 mm full frame (36 x 24 mm) at 50 mm focal length: vertical fov = 2 atan(12 / 50).
    double aspect = 36.0 / 24.0;
    Camera cam = Camera::physical({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 36, 24, FilmFit::Fill, aspect, 0.1, 10);
    CHECK(cam.fov_y == Approx(2 * std::atan(12.0 / 50) * 180 / pi));

    // A square image: fill crops the wide gate's sides (vertical extent kept); overscan shows all
    // of its width, so the vertical extent grows by the aspect ratio of the gate.
    Camera fill = Camera::physical({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 36, 24, FilmFit::Fill, 1.0, 0.1, 10);
    Camera over = Camera::physical({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 36, 24, FilmFit::Overscan, 1.0, 0.1, 10);
    CHECK(fill.canvas(1.0).top == Approx(12.0 / 50));
    CHECK(over.canvas(1.0).top == Approx(18.0 / 50));
    // A tall image (aspect 0.5) fills with the gate's height and crops its width to half of it.
    Camera tall = Camera::physical({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 36, 24, FilmFit::Fill, 0.5, 0.1, 10);
    CHECK(tall.canvas(0.5).top == Approx(12.0 / 50));
    CHECK(tall.canvas(0.5).right == Approx(6.0 / 50));
    // A gate narrower than the image: fill keeps the gate's width, overscan its height.
    Camera wide_fill = Camera::physical({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 36, 24, FilmFit::Fill, 3.0, 0.1, 10);
    Camera wide_over = Camera::physical({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 50, 36, 24, FilmFit::Overscan, 3.0, 0.1, 10);
    CHECK(wide_fill.canvas(3.0).right == Approx(18.0 / 50));
    CHECK(wide_over.canvas(3.0).top == Approx(12.0 / 50));
    CHECK_THROWS_AS(Camera::physical({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0, 36, 24, FilmFit::Fill, 1, 0.1, 10), Error);
}

TEST_CASE("the orthographic camera is the limit of a far, narrow perspective camera", "[camera]")
{
    Vec3 p{0.3, -0.2, 0.1};
    Camera ortho = Camera::orthographic({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 2, 0.1, 100);
    Vec3 ro = ortho.to_raster(p, 100, 100);
    double dist = 1e5;
    double fov = 2 * std::atan(1.0 / dist) * 180 / pi; // canvas half-height 1 at the target
    Camera persp = Camera::perspective({0, 0, dist}, {0, 0, 0}, {0, 1, 0}, fov, 1, 2 * dist);
    Vec3 rp = persp.to_raster(p, 100, 100);
    CHECK(rp.x == Approx(ro.x).margin(1e-3));
    CHECK(rp.y == Approx(ro.y).margin(1e-3));
    CHECK(ro.x == Approx((0.3 + 1) / 2 * 100));
}

TEST_CASE("a primary ray projects back to its raster position, t equal to view depth",
          "[camera]")
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u01(0, 1), t(0.5, 20);
    for (Projection proj : {Projection::Perspective, Projection::Orthographic}) {
        Camera cam = Camera::perspective({2, 1, 4}, {0, 0, 0}, {0, 1, 0}, 40, 0.1, 50);
        cam.projection = proj;
        for (int i = 0; i < 100; ++i) {
            double x = u01(rng) * 320, y = u01(rng) * 200, tt = t(rng);
            Ray ray = cam.primary_ray(x, y, 320, 200);
            Vec3 hit = ray.origin + ray.direction * tt;
            Vec3 back = cam.to_raster(hit, 320, 200);
            CHECK(back.x == Approx(x).margin(1e-9));
            CHECK(back.y == Approx(y).margin(1e-9));
            CHECK(back.z == Approx(tt).epsilon(1e-12));
        }
    }
}

TEST_CASE("the float32 projection of the kernels agrees with the double-precision camera", "[camera]")
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int kind = 0; kind < 3; ++kind) {
        Camera cam = Camera::perspective({0.5, 0.8, 3}, {0, 0, 0}, {0, 1, 0}, 45, 0.1, 20);
        if (kind == 1) cam.projection = Projection::Orthographic;
        if (kind == 2) cam.intrinsics = Intrinsics{1500, 1320, 700.25, 610.5}; // off-centre
        const int w = 1920, h = 1080;
        clvis_camera_gpu g = detail::make_gpu_camera(cam, w, h);
        for (int i = 0; i < 200; ++i) {
            Vec3 p{u(rng), u(rng), u(rng)};
            Vec3 ref = cam.to_raster(p, w, h);
            clvis_vec3 c = clvis_camera_from_world(g, float(p.x), float(p.y), float(p.z));
            clvis_vec2 r = clvis_raster_from_screen(g, clvis_screen_from_camera(g, c));
            // float32 raster positions near 1920 carry ~2^-13 px of rounding per operation.
            CHECK(std::fabs(r.x - ref.x) < 2e-3);
            CHECK(std::fabs(r.y - ref.y) < 2e-3);
            CHECK(std::fabs(-c.z - ref.z) < 1e-5 * ref.z + 1e-6);

            double rx = (i % 97) + 0.5, ry = (i % 53) + 0.5;
            Ray ray = cam.primary_ray(rx, ry, w, h);
            clvis_vec3 o, d;
            clvis_primary_ray(g, float(rx), float(ry), &o, &d);
            CHECK(std::fabs(o.x - ray.origin.x) < 1e-5);
            CHECK(std::fabs(d.x - ray.direction.x) < 1e-5);
            CHECK(std::fabs(d.y - ray.direction.y) < 1e-5);
            CHECK(std::fabs(d.z - ray.direction.z) < 1e-5);
        }
    }
}

TEST_CASE("invalid cameras are refused with the field named", "[camera]")
{
    auto msg = [](Camera c) {
        try {
            c.validate();
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::InvalidArgument);
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    Camera ok = axis_camera();
    CHECK(msg(ok) == "accepted");
    Camera c = ok;
    c.eye.x = std::nan("");
    CHECK(msg(c).find("eye") != std::string::npos);
    c = ok;
    c.target = c.eye;
    CHECK(msg(c).find("eye equals target") != std::string::npos);
    c = ok;
    c.up = {0, 0, 1};
    CHECK(msg(c).find("parallel") != std::string::npos);
    c = ok;
    c.near = 0;
    CHECK(msg(c).find("near") != std::string::npos);
    c = ok;
    c.far = c.near;
    CHECK(msg(c).find("far") != std::string::npos);
    c = ok;
    c.fov_y = 180;
    CHECK(msg(c).find("fov") != std::string::npos);
    c = ok;
    c.far = INFINITY;
    CHECK(msg(c).find("far") != std::string::npos);
    c = ok;
    c.projection = Projection::Orthographic;
    c.ortho_height = -1;
    CHECK(msg(c).find("ortho height") != std::string::npos);
}

TEST_CASE("camera factories refuse NaN and out-of-range values when made", "[camera]")
{
    const double nan = std::nan("");
    const Vec3 o{0, 0, 0}, ahead{0, 0, -1}, y{0, 1, 0};
    auto refused = [](auto make, const char* field) { CHECK_THROWS_WITH(make(), Catch::Contains(field)); };
    try {
        Camera::perspective(o, ahead, y, 45, nan, 10);
        FAIL("made a camera with a NaN near");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::InvalidArgument);
    }
    refused([&] { Camera::perspective({nan, 0, 0}, ahead, y, 45, 0.1, 10); }, "eye");
    refused([&] { Camera::perspective(o, {0, nan, -1}, y, 45, 0.1, 10); }, "target");
    refused([&] { Camera::perspective(o, ahead, {0, nan, 0}, 45, 0.1, 10); }, "up");
    refused([&] { Camera::perspective(o, ahead, y, nan, 0.1, 10); }, "fov");
    refused([&] { Camera::perspective(o, ahead, y, 0, 0.1, 10); }, "fov");
    refused([&] { Camera::perspective(o, ahead, y, 1e-40, 0.1, 10); }, "fov");
    refused([&] { Camera::perspective(o, ahead, y, 45, nan, 10); }, "near");
    refused([&] { Camera::perspective(o, ahead, y, 45, 1e-300, 10); }, "near");
    refused([&] { Camera::perspective(o, ahead, y, 45, 0.1, nan); }, "far");
    refused([&] { Camera::perspective(o, ahead, y, 45, 0.1, 1e39); }, "far");
    refused([&] { Camera::perspective({1e39, 0, 0}, {1e39, 0, -1}, y, 45, 0.1, 10); }, "eye");
    refused([&] { Camera::orthographic(o, ahead, y, nan, 0.1, 10); }, "ortho height");
    refused([&] { Camera::orthographic(o, ahead, y, 1e-300, 0.1, 10); }, "ortho height");
    refused([&] { Camera::orthographic(o, ahead, y, 1e39, 0.1, 10); }, "ortho height");
    refused([&] { Camera::orthographic(o, o, y, 2, 0.1, 10); }, "eye equals target");
    refused([&] { Camera::physical(o, ahead, y, nan, 36, 24, FilmFit::Fill, 1.5, 0.1, 10); }, "focal length");
    refused([&] { Camera::physical(o, ahead, y, 50, 36, nan, FilmFit::Fill, 1.5, 0.1, 10); }, "film gate");
    refused([&] { Camera::physical(o, ahead, y, 50, 36, 24, FilmFit::Fill, nan, 0.1, 10); }, "aspect");
    refused([&] { Camera::physical(o, ahead, y, 50, 36, 24, FilmFit::Fill, 1.5, 0.1, -1); }, "far");
    Bounds huge;
    huge.lo = {-1e38, -1e38, -1e38};
    huge.hi = {1e38, 1e38, 1e38};
    refused([&] { Camera::framing(huge); }, "outside float32's range");
    // The edges of the ranges are still cameras.
    CHECK_NOTHROW(Camera::perspective(o, ahead, y, 179.9, 1.2e-38, 3.4e38));
    CHECK_NOTHROW(Camera::orthographic({3e38, 0, 0}, {3e38, 0, -1}, y, 3e38, 0.1, 10));
}

TEST_CASE("the framing camera sees the whole bounding sphere", "[camera]")
{
    Bounds b;
    b.add({-1, -2, -0.5});
    b.add({3, 1, 0.5});
    Camera cam = Camera::framing(b);
    double radius = length(b.extent()) / 2;
    double dist = length(cam.eye - b.center());
    CHECK(dist == Approx(radius / std::sin(22.5 * pi / 180)));
    CHECK(cam.near == Approx(0.9 * (dist - radius)));
    CHECK(cam.far == Approx(1.1 * (dist + radius)));
    Vec3 dir = normalize(cam.eye - b.center());
    CHECK(dir.x == Approx(0.3 / std::sqrt(1.25)));
    // Every corner of the box projects inside a square image.
    for (int i = 0; i < 8; ++i) {
        Vec3 p{i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z};
        Vec3 r = cam.to_raster(p, 100, 100);
        CHECK(r.x >= 0);
        CHECK(r.x <= 100);
        CHECK(r.y >= 0);
        CHECK(r.y <= 100);
        CHECK(r.z > cam.near);
        CHECK(r.z < cam.far);
    }
    Camera ortho = Camera::framing(b, Projection::Orthographic);
    CHECK(ortho.ortho_height == Approx(2 * radius));
    CHECK(length(ortho.eye - b.center()) == Approx(2 * radius));
    CHECK_THROWS_AS(Camera::framing(Bounds{}), Error);
}

TEST_CASE("camera flags reproduce the camera exactly", "[camera]")
{
    Camera cam = Camera::perspective({0.1, 1.0 / 3, -2e-7}, {1, 2, 3}, {0, 1, 0}, 33.3, 0.01, 1e6);
    std::string flags = cam.to_flags();
    CHECK(flags.find("--eye 0.1,0.3333333333333333,-2e-07") != std::string::npos);
    CHECK(flags.find("--fov 33.3") != std::string::npos);
    CHECK(flags.find("--far 1e+06") != std::string::npos);
}

TEST_CASE("intrinsics of a field of view give the same projection", "[camera]")
{
    Camera fov = Camera::perspective({1, 2, 5}, {0.2, -0.1, 0}, {0, 1, 0}, 50, 0.5, 40);
    const int w = 640, h = 360;
    double f = h / (2 * std::tan(25 * pi / 180));
    Camera k = Camera::from_intrinsics(fov.eye, fov.target, fov.up, {f, f, w / 2.0, h / 2.0}, 0.5, 40);
    Intrinsics m = fov.raster_map(w, h);
    CHECK(m.fx == Approx(f).epsilon(1e-14));
    CHECK(m.fy == Approx(f).epsilon(1e-14));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-3, 3);
    for (int i = 0; i < 50; ++i) {
        Vec3 p{u(rng), u(rng), u(rng)};
        Vec3 a = fov.to_raster(p, w, h), b = k.to_raster(p, w, h);
        CHECK(a.x == Approx(b.x).margin(1e-9));
        CHECK(a.y == Approx(b.y).margin(1e-9));
    }
    // The conventions' formula: x = cx + fx P.x / -P.z, y = cy - fy P.y / -P.z.
    Camera off = Camera::from_intrinsics({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, {100, 80, 30.5, 20.25}, 0.1, 10);
    Vec3 r = off.to_raster({0.5, -0.25, -2}, 64, 48);
    CHECK(r.x == Approx(30.5 + 100 * 0.25));
    CHECK(r.y == Approx(20.25 + 80 * 0.125));
    Ray ray = off.primary_ray(r.x, r.y, 64, 48);
    CHECK(ray.direction.x == Approx(0.25));
    CHECK(ray.direction.y == Approx(-0.125));
    CHECK(ray.direction.z == Approx(-1));
    CHECK(off.to_flags().find("--intrinsics 100,80,30.5,20.25") != std::string::npos);
}

TEST_CASE("OpenCV's intrinsics and extrinsics land on its pixels plus half a pixel", "[camera]")
{
    // OpenCV: x_cv = fx Xc / Zc + cx, y_cv = fy Yc / Zc + cy with Xc = R X + t, z forward, y down.
    const double fx = 700, fy = 650, cx = 310.2, cy = 245.7;
    double a = 0.3, b = -0.2;
    double R[3][3] = {{std::cos(a), 0, std::sin(a)}, {0, 1, 0}, {-std::sin(a), 0, std::cos(a)}};
    double Rx[3][3] = {{1, 0, 0}, {0, std::cos(b), -std::sin(b)}, {0, std::sin(b), std::cos(b)}};
    Mat4 w2c;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += Rx[i][k] * R[k][j];
            w2c(i, j) = s;
        }
    w2c(0, 3) = 0.4;
    w2c(1, 3) = -0.3;
    w2c(2, 3) = 6;
    Camera cam = Camera::from_opencv(fx, fy, cx, cy, w2c, 0.1, 100);
    cam.validate();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int i = 0; i < 50; ++i) {
        Vec3 p{u(rng), u(rng), u(rng)};
        Vec3 c = w2c.transform_point(p);
        Vec3 r = cam.to_raster(p, 640, 480);
        CHECK(r.x == Approx(fx * c.x / c.z + cx + 0.5).margin(1e-9));
        CHECK(r.y == Approx(fy * c.y / c.z + cy + 0.5).margin(1e-9));
        CHECK(r.z == Approx(c.z).epsilon(1e-12)); // view depth is OpenCV's Zc
    }
    Intrinsics k = Intrinsics::from_opencv(fx, fy, cx, cy);
    CHECK(k.cx == cx + 0.5);
    CHECK(k.cy == cy + 0.5);
}

TEST_CASE("a pose matrix round-trips and a bad one is refused", "[camera]")
{
    Camera cam = Camera::perspective({1, 2, 5}, {0.2, -0.1, 0}, {0.1, 1, 0}, 50, 0.5, 40);
    Mat4 pose = cam.pose();
    Camera back = Camera::from_pose(pose, cam);
    CameraFrame a = cam.frame(), b = back.frame();
    CHECK(length(a.r - b.r) < 1e-12);
    CHECK(length(a.u - b.u) < 1e-12);
    CHECK(length(a.f - b.f) < 1e-12);
    CHECK(length(cam.eye - back.eye) == 0);
    CHECK(back.fov_y == cam.fov_y);
    // Its columns are r, u, -f and eye; view_matrix is its inverse.
    Mat4 id = cam.view_matrix() * pose;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) CHECK(id(i, j) == Approx(i == j ? 1 : 0).margin(1e-12));
    auto refused = [](Mat4 m, const char* what) {
        try {
            Camera::from_pose(m);
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::InvalidArgument);
            CHECK(std::string(e.what()).find(what) != std::string::npos);
            return true;
        }
        return false;
    };
    Mat4 m = pose;
    m(0, 0) *= 1 + 1e-5;
    CHECK(refused(m, "orthonormal"));
    m = pose;
    for (int i = 0; i < 3; ++i) m(i, 0) = -m(i, 0);
    CHECK(refused(m, "reflection"));
    m = pose;
    m(3, 0) = 0.5;
    CHECK(refused(m, "last row"));
    m = pose;
    m(1, 3) = NAN;
    CHECK(refused(m, "finite"));
    m = pose;
    m(0, 0) *= 1 + 5e-7; // within the tolerance
    CHECK_FALSE(refused(m, ""));
    auto message = [](const Camera& c) {
        try {
            c.validate();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    Camera bad = cam;
    bad.intrinsics = Intrinsics{0, 10, 1, 1};
    CHECK(message(bad).find("intrinsics") != std::string::npos);
    bad.intrinsics = Intrinsics{10, 10, 1, 1};
    bad.projection = Projection::Orthographic;
    CHECK(message(bad).find("perspective") != std::string::npos);
}

TEST_CASE("the sample positions are the standard ones of CONVENTIONS.md, in order", "[samples]")
{
    // CONVENTIONS.md "Samples per pixel", typed from it: (dx, dy) in 1/16 px.
    const std::vector<std::vector<std::pair<int, int>>> table = {
        {{0, 0}},
        {{4, 4}, {-4, -4}},
        {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}},
        {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}},
        {{1, 1}, {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5}, {5, 3}, {3, -5}, {-2, 6}, {0, -7}, {-4, -6},
         {-6, 4}, {-8, 0}, {7, -4}, {6, 7}, {-7, -8}}};
    for (int log2n = 0; log2n <= CLVIS_MAX_SAMPLES_LOG2; ++log2n)
        for (int k = 0; k < 1 << log2n; ++k) {
            INFO("sample " << k << " of " << (1 << log2n));
            CHECK(clvis_sample_offset(log2n, k, 0) == table[std::size_t(log2n)][std::size_t(k)].first);
            CHECK(clvis_sample_offset(log2n, k, 1) == table[std::size_t(log2n)][std::size_t(k)].second);
            CHECK(double(7.0f + clvis_sample_fraction(log2n, k, 0)) == 7.5 + table[std::size_t(log2n)][std::size_t(k)].first / 16.0);
        }
    CHECK(clvis_sample_fraction(0, 0, 0) == 0.5f);
    for (int n : {1, 2, 4, 8, 16}) CHECK(1 << samples_log2(n) == n);
    CHECK_THROWS_WITH(samples_log2(12), Catch::Contains("12"));
}
