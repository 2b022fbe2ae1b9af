// The untimed host logic of `clvis bench --views` (bench/bench_views.hpp): the orbit of cameras
// and the frames-per-second figure.
#include "catch.hpp"

#include "bench_views.hpp"

#include <clvis/error.hpp>
#include <clvis/math.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace clvis;
using namespace clvis::bench;

namespace {

const Bounds box{{-1, 0, 2}, {3, 2, 5}};

double angle_between(Vec3 a, Vec3 b) { return std::acos(std::clamp(dot(a, b) / (length(a) * length(b)), -1.0, 1.0)); }

} // namespace

TEST_CASE("The orbit starts at the framing camera and keeps its distance")
{
    Camera framing = Camera::framing(box);
    std::vector<Camera> cams = orbit_cameras(box, 8);
    REQUIRE(cams.size() == 8);
    CHECK(length(cams[0].eye - framing.eye) == 0);
    double d = length(framing.eye - box.center());
    for (const Camera& c : cams) {
        CHECK(std::abs(length(c.eye - box.center()) - d) < 1e-9 * d);
        CHECK(length(c.target - framing.target) == 0);
        CHECK(c.near == framing.near);
        CHECK(c.far == framing.far);
        // On the circle about the up axis: the eye's height along up does not change.
        CHECK(std::abs(dot(c.eye - framing.eye, normalize(framing.up))) < 1e-9 * d);
    }
}

TEST_CASE("Consecutive orbit views are 360 / N degrees apart")
{
    const double pi = 3.14159265358979323846;
    for (int n : {3, 7, 64}) {
        std::vector<Camera> cams = orbit_cameras(box, n);
        Vec3 up = normalize(cams[0].up);
        for (int i = 0; i < n; ++i) {
            Vec3 a = cams[i].eye - box.center(), b = cams[(i + 1) % n].eye - box.center();
            a = a - up * dot(a, up);
            b = b - up * dot(b, up);
            CHECK(std::abs(angle_between(a, b) - 2 * pi / n) < 1e-9);
        }
    }
}

TEST_CASE("One orbit view is the framing camera alone")
{
    std::vector<Camera> cams = orbit_cameras(box, 1);
    REQUIRE(cams.size() == 1);
    CHECK(length(cams[0].eye - Camera::framing(box).eye) == 0);
}

TEST_CASE("An orbit of fewer than one view is refused naming --views")
{
    for (int n : {0, -3}) {
        try {
            orbit_cameras(box, n);
            FAIL("no error for " << n << " views");
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::InvalidArgument);
            CHECK(std::string(e.what()).find("--views") != std::string::npos);
        }
    }
}

TEST_CASE("Views per second divide the view count by the set's time")
{
    CHECK(views_per_second(500, 64) == Approx(128));
    CHECK(views_per_second(1000, 1) == Approx(1));
    CHECK(views_per_second(0, 64) == 0);
    CHECK(views_per_second(-1, 64) == 0);
}
