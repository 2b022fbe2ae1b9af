// Camera descriptions (include/clvis/camera_spec.hpp): the one table of fields that the tool's
// flags and scene files share, strict values named by where they came from, a file's description
// overridden by flags, and the resolution into the cameras of CONVENTIONS.md.
#include "catch.hpp"

#include <clvis/camera_spec.hpp>
#include <clvis/error.hpp>

#include <cmath>
#include <string>

using namespace clvis;

namespace {

Bounds unit_box()
{
    Bounds b;
    b.lo = {-1, -1, -1};
    b.hi = {1, 1, 1};
    return b;
}

std::string refusal(const std::string& name, const std::string& text)
{
    CameraSpec s;
    try {
        set_camera_field(s, name, text, "--" + name);
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::InvalidArgument);
        return e.what();
    }
    return "accepted";
}

std::string flag(const std::string& field) { return "--" + field; }

} // namespace

TEST_CASE("camera text values are strict and name where they came from", "[camera]")
{
    CameraSpec s;
    set_camera_field(s, "eye", "1,-2.5,3e-2", "--eye");
    REQUIRE(s.eye);
    CHECK(s.eye->y == -2.5);
    CHECK(s.eye->z == 3e-2);
    set_camera_field(s, "ortho", "", "--ortho");
    CHECK(s.ortho);
    CHECK_FALSE(s.ortho_height);
    set_camera_field(s, "fit", "overscan", "--fit");
    CHECK(s.fit == FilmFit::Overscan);
    CHECK(refusal("eye", "1,2") == "--eye: expected 3 numbers (X,Y,Z)");
    CHECK(refusal("eye", "1,,2").find("--eye: '' is not a number") == 0);
    CHECK(refusal("eye", "1, 2,3").find("is not a number") != std::string::npos);
    CHECK(refusal("fov", "nan").find("--fov: nan is not finite") == 0);
    CHECK(refusal("ortho", "0") == "--ortho: the view height must be > 0, got 0");
    CHECK(refusal("ortho", "-2").find("--ortho: the view height must be > 0") == 0);
    CHECK(refusal("fov", "").find("--fov: needs a value") == 0);
    CHECK(refusal("film_gate", "36,-1").find("--film_gate: the gate's height must be > 0") == 0);
    CHECK(refusal("fit", "wide") == "--fit: expected fill or overscan, got 'wide'");
    CHECK(refusal("zoom", "2") == "--zoom: not a camera field");
}

TEST_CASE("flags override a scene file's camera field by field, projections whole", "[camera]")
{
    CameraSpec file;
    set_camera_field(file, "eye", "0,0,5", "eye");
    set_camera_field(file, "target", "0,0,0", "target");
    set_camera_field(file, "focal_length", "50", "focal_length");
    set_camera_field(file, "film_gate", "36,24", "film_gate");
    set_camera_field(file, "near", "1", "near");

    CameraSpec fit;
    set_camera_field(fit, "fit", "overscan", "--fit");
    CameraSpec merged = file.overridden_by(fit);
    CHECK(merged.focal_length == 50.0);
    CHECK(merged.fit == FilmFit::Overscan);

    CameraSpec ortho;
    set_camera_field(ortho, "ortho", "3", "--ortho");
    set_camera_field(ortho, "eye", "0,1,5", "--eye");
    merged = file.overridden_by(ortho);
    CHECK_FALSE(merged.focal_length);
    CHECK_FALSE(merged.film_gate);
    CHECK(merged.ortho_height == 3.0);
    CHECK(merged.eye->y == 1);
    CHECK(merged.target->z == 0);
    CHECK(merged.near == 1.0);
    Camera c = merged.resolve(unit_box(), 64, 32);
    CHECK(c.projection == Projection::Orthographic);
    CHECK(c.ortho_height == 3);
    CHECK(c.near == 1);

    CameraSpec fov;
    set_camera_field(fov, "fov", "30", "--fov");
    CHECK(merged.overridden_by(fov).resolve(unit_box(), 64, 32).projection == Projection::Perspective);
    CHECK_FALSE(merged.overridden_by(fov).ortho);
    CHECK(file.overridden_by(CameraSpec{}).focal_length == 50.0);
}

TEST_CASE("a description resolves to the cameras of the command line's conventions", "[camera]")
{
    Bounds b = unit_box();
    CHECK(CameraSpec{}.resolve(b, 64, 32).eye.z == Camera::framing(b).eye.z);

    CameraSpec look;
    set_camera_field(look, "eye", "0,0,10", "eye");
    set_camera_field(look, "target", "0,0,0", "target");
    Camera c = look.resolve(b, 64, 32);
    CHECK(c.fov_y == 45);
    CHECK(c.near == Approx(0.9 * (10 - std::sqrt(3.0))));
    CHECK(c.far == Approx(1.1 * (10 + std::sqrt(3.0))));

    CameraSpec physical = look;
    set_camera_field(physical, "focal_length", "50", "focal_length");
    set_camera_field(physical, "film_gate", "36,24", "film_gate");
    Camera wide = physical.resolve(b, 300, 100);
    CHECK(wide.fov_y == Approx(Camera::physical(c.eye, c.target, c.up, 50, 36, 24, FilmFit::Fill, 3.0, c.near, c.far).fov_y));

    auto refused = [&](CameraSpec s, const std::string& says) {
        INFO(says);
        CHECK_THROWS_WITH(s.resolve(b, 64, 32, flag), Catch::StartsWith(says));
    };
    CameraSpec s;
    set_camera_field(s, "fit", "fill", "fit");
    refused(s, "--fit: applies to the physical camera only");
    s = {};
    set_camera_field(s, "focal_length", "35", "focal_length");
    refused(s, "--film_gate: is needed with --focal_length");
    s = {};
    set_camera_field(s, "eye", "0,0,3", "eye");
    refused(s, "--target: is needed with --eye");
    s = look;
    set_camera_field(s, "near", "20", "near");
    refused(s, "--far: far must be finite and greater than near");
    s = look;
    set_camera_field(s, "up", "0,0,1", "up");
    refused(s, "--up: up (0,0,1) is parallel");
    s = look;
    set_camera_field(s, "fov", "30", "fov");
    set_camera_field(s, "ortho", "2", "ortho");
    refused(s, "--fov: give one projection");
}
