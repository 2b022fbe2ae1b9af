// The benchmark's reference renderers (bench/): Embree, by single rays and 16-ray packets, and
// Mesa's OpenGL through EGL must give the exact ids of a hand-made scene whose pixel centres all
// lie at least a third of a pixel from every edge. Both references are required: the set-up
// installs Embree and Mesa, so a reference that was not built fails here.
#include "catch.hpp"

#include "reference.hpp"

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>

#include <cmath>
#include <string>

using namespace clvis;

namespace {

/// View depth read back from GL's float depth buffer (window z in [0, 1], near 0.5, far 10)
/// carries about 1e-6 relative error; Embree's t is exact to float rounding.
constexpr double depth_rel_tolerance = 1e-4;

const Camera camera = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 0.5, 10);

/// The world point at raster (x, y) and view depth d for `camera` in a width x height image.
Vec3 at_raster(double x, double y, double d, int width, int height)
{
    double top = std::tan(45.0 * 3.14159265358979323846 / 180), right = double(width) / height * top;
    double sx = (2 * x / width - 1) * right, sy = (1 - 2 * y / height) * top;
    return {sx * d, sy * d, -d}; // camera space is world space for this camera
}

/// Triangles given in raster space (x, y) at a view depth each:
///   0: depth 4, covers x > 8 (every other edge is outside the image);
///   1: depth 2, the half-square x > 4, y > 4, x + y < 16.5, in front of 0;
///   2: depth 3, inside 1 and behind it: never visible, drawn after 1;
///   3: depth 20, covers the whole image beyond far = 10: clipped.
/// Pixel centres (i + .5, j + .5) keep >= 0.35 px from every edge in images up to 18 x 14.
Scene hand_made_scene(int width, int height)
{
    struct RasterTriangle {
        double x[3], y[3], depth;
    };
    const RasterTriangle triangles[] = {
        {{8, 40, 8}, {-20, 8, 36}, 4},
        {{4, 12.5, 4}, {4, 4, 12.5}, 2},
        {{5, 10.5, 5}, {5, 5, 10.5}, 3},
        {{-20, 60, -20}, {-20, -20, 60}, 20},
    };
    MeshData mesh;
    mesh.name = "hand-made";
    std::uint32_t next = 0;
    for (const auto& t : triangles)
        for (int k = 0; k < 3; ++k) {
            Vec3 p = at_raster(t.x[k], t.y[k], t.depth, width, height);
            mesh.positions.insert(mesh.positions.end(), {float(p.x), float(p.y), float(p.z)});
            mesh.indices.push_back(next++);
        }
    Scene scene;
    scene.add_mesh(std::move(mesh));
    return scene;
}

std::uint32_t expected_id(int i, int j)
{
    if (i >= 4 && j >= 4 && i + j <= 15) return 1;
    if (i >= 8) return 0;
    return background_id;
}

float expected_depth(std::uint32_t id)
{
    return id == 1 ? 2.0f : id == 0 ? 4.0f : INFINITY;
}

void check_exact(const bench::ReferenceResult& r, int width, int height)
{
    INFO(r.name << " " << width << "x" << height << ": " << r.error);
    REQUIRE(r.ok());
    REQUIRE(r.width == width);
    REQUIRE(r.height == height);
    REQUIRE(r.ids.size() == std::size_t(width) * height);
    REQUIRE(r.depth.size() == r.ids.size());
    REQUIRE(r.frame_ms.size() == 3);
    std::size_t wrong_ids = 0, wrong_depths = 0;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            std::size_t p = std::size_t(j) * width + i;
            std::uint32_t want = expected_id(i, j);
            if (r.ids[p] != want) {
                ++wrong_ids;
                UNSCOPED_INFO("pixel (" << i << ", " << j << "): id " << r.ids[p] << ", expected " << want);
            }
            float d = r.depth[p], want_d = expected_depth(want);
            bool depth_ok = std::isinf(want_d) ? std::isinf(d) : std::fabs(d - want_d) <= depth_rel_tolerance * want_d;
            if (!depth_ok) ++wrong_depths;
        }
    CHECK(wrong_ids == 0);
    CHECK(wrong_depths == 0);
}

} // namespace

TEST_CASE("Embree single rays give the exact ids and depths of a hand-made scene", "[bench_refs]")
{
    REQUIRE(bench::embree_available());
    for (auto [w, h] : {std::pair{16, 16}, std::pair{18, 14}}) {
        Scene scene = hand_made_scene(w, h);
        bench::EmbreeReference embree(scene, 2, 2);
        CHECK(embree.build_samples_ms().size() == 2);
        check_exact(embree.render(camera, w, h, bench::EmbreeMode::Single, 3), w, h);
    }
}

TEST_CASE("Embree 16-ray packets give the exact ids of a hand-made scene, partial tiles",
          "[bench_refs]")
{
    REQUIRE(bench::embree_available());
    for (auto [w, h] : {std::pair{16, 16}, std::pair{18, 14}})
        check_exact(bench::render_embree(hand_made_scene(w, h), camera, w, h, bench::EmbreeMode::Packet16, 3), w, h);
}

TEST_CASE("llvmpipe through EGL gives the exact ids of a hand-made scene, top row first",
          "[bench_refs]")
{
    REQUIRE(bench::gl_available());
    for (auto [w, h] : {std::pair{16, 16}, std::pair{18, 14}})
        check_exact(bench::render_gl(hand_made_scene(w, h), camera, w, h, 3), w, h);
}

TEST_CASE("a reference reports a failure in its result instead of throwing", "[bench_refs]")
{
    Scene empty;
    auto embree = bench::render_embree(empty, camera, 16, 16, bench::EmbreeMode::Single, 1);
    CHECK_FALSE(embree.ok());
    CHECK(embree.error.find("no triangles") != std::string::npos);
    auto gl = bench::render_gl(empty, camera, 16, 16, 1);
    CHECK_FALSE(gl.ok());
    CHECK(gl.error.find("no triangles") != std::string::npos);
}
