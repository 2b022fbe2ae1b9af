// Renderer(Device, Scene&&, RenderOptions) (issue 37's memory): a Renderer that takes its scene
// over renders, follows updates and answers as one given a copy, and leaves the caller's Scene
// empty; a temporary Scene binds to it.
#include "catch.hpp"

#include <clvis/clvis.hpp>
#include <clvis/procedural.hpp>

#include <utility>
#include <vector>

using namespace clvis;

namespace {

Scene two_meshes()
{
    Scene s;
    s.add_mesh(make_uv_sphere(3000));
    Mat4 moved; // a transformed item: the Renderer's world expansion, not the mesh's own arrays
    moved(0, 3) = 0.2;
    moved(1, 3) = -0.5;
    moved(2, 3) = 0.1;
    s.add_mesh(make_grid(1000, 2), moved);
    return s;
}

} // namespace

TEST_CASE("a Renderer given its scene to keep renders what one given a copy renders", "[device][renderer]")
{
    Device d = Device::open();
    const Scene kept = two_meshes();
    Scene handed = kept;
    Renderer copied(d, kept);
    Renderer moved(d, std::move(handed));
    CHECK(handed.empty());
    CHECK(handed.meshes().empty());
    Renderer temporary(d, two_meshes()); // a temporary binds to Scene&&
    Camera cam = Camera::perspective({0.5, 2, 4}, {0, 0, 0}, {0, 1, 0}, 50, 0.1, 50);
    for (Path path : {Path::Raster, Path::Ray, Path::Brute}) {
        INFO(to_string(path));
        std::vector<std::uint64_t> want = copied.render(cam, 64, 48, path).read_keys();
        CHECK(moved.render(cam, 64, 48, path).read_keys() == want);
        CHECK(temporary.render(cam, 64, 48, path).read_keys() == want);
    }
    CHECK(moved.bvh_stats().nodes == copied.bvh_stats().nodes);

    // An update against the caller's own copy of the scene, moved since.
    Scene now = kept;
    std::vector<float> p = now.meshes()[0].data.positions;
    for (float& x : p) x *= 1.1f;
    now.set_positions(0, p.data(), p.size() / 3);
    copied.update(now);
    moved.update(now);
    for (Path path : {Path::Raster, Path::Ray}) {
        INFO(to_string(path) << " after the update");
        CHECK(moved.render(cam, 64, 48, path).read_keys() == copied.render(cam, 64, 48, path).read_keys());
    }
    CHECK(moved.bvh_stats().refitted);
}
