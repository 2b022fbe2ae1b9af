// Instances that never expand (issue 34): every entry point works from a scene's items (a prototype
// stored once, a transform per item) and never builds Scene::world_positions() of the expansion,
// on the host (bounds, framing, triangles, both referees) nor on the device (shading in every
// mode, resolve, AO and shadow rays, ray queries), while answering with the expansion's bits.
#include "catch.hpp"
#include "render/renderer_probe.hpp"
#include "scene/scene_probe.hpp"
#include "test_files.hpp"
#include "test_meshes.hpp"

#include <clvis/attributes.hpp>
#include <clvis/clvis.hpp>
#include <clvis/referee_attributes.hpp>

#include <cmath>
#include <cstring>
#include <vector>

using namespace clvis;

namespace {

using test::placed;

/// The spot with vertex normals (its positions, normalised: any non-zero field will do), a plain
/// quad and 40 instances of the spot: instanced, or written out as meshes.
Scene many_spots(bool instanced)
{
    MeshData spot = load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj");
    spot.normals = spot.positions;
    for (std::size_t i = 0; i < spot.normals.size(); i += 3) {
        float* n = &spot.normals[i];
        float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) n[k] = len > 0 ? n[k] / len : 1.0f;
    }
    MeshData quad;
    quad.name = "quad";
    quad.positions = {-9, -9, -3, 9, -9, -3, 9, 9, -3, -9, 9, -3};
    quad.indices = {0, 1, 2, 0, 2, 3};
    Scene s;
    s.add_mesh(quad);
    std::size_t p = instanced ? s.add_prototype(spot) : 0;
    for (int i = 0; i < 40; ++i) {
        Mat4 t = placed(0.37 * i, {double(i % 8) - 3.5, double(i / 8) - 2.0, 0.05 * i}, 0.6);
        instanced ? s.add_instance(p, t) : s.add_mesh(spot, t);
    }
    return s;
}

bool same_floats(const std::vector<float>& a, const std::vector<float>& b)
{
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::uint64_t expansions() { return detail::expansion_vertices_built.load(); }

} // namespace

TEST_CASE("bounds, framing, triangles and the referees never expand an instanced scene", "[instances][referee]")
{
    Scene a = many_spots(true), b = many_spots(false);
    Bounds expected = b.bounds();
    std::vector<float> expansion = b.world_positions(); // the reference: a plain scene's own arrays
    std::uint64_t before = expansions();
    Bounds got = a.bounds();
    CHECK(got.lo.x == expected.lo.x);
    CHECK(got.lo.y == expected.lo.y);
    CHECK(got.lo.z == expected.lo.z);
    CHECK(got.hi.x == expected.hi.x);
    CHECK(got.hi.y == expected.hi.y);
    CHECK(got.hi.z == expected.hi.z);
    Camera framed = Camera::framing(a.bounds());
    CHECK(framed.eye.x == Camera::framing(expected).eye.x);
    for (std::uint32_t id : {0u, 1u, 2u, 777u, std::uint32_t(a.triangle_count() - 1)}) {
        float ta[9], tb[9];
        a.triangle(id, ta);
        b.triangle(id, tb);
        CHECK(std::memcmp(ta, tb, sizeof ta) == 0);
    }
    // The referees set up from the items judge as from the expansion.
    HostVisibility none;
    none.width = 32;
    none.height = 24;
    none.ids.assign(32 * 24, background_id);
    none.depth.assign(32 * 24, INFINITY);
    Referee ra(a, framed, 32, 24), rb(b, framed, 32, 24);
    CompareReport ca = ra.check(none), cb = rb.check(none);
    CHECK(ca.errors == cb.errors);
    CHECK(ca.errors > 0); // the spots cover the image: background is wrong there
    BarycentricReferee bary(a, framed, 32, 24);
    Vec3 p[3];
    bary.vertices(5, p);
    float tb[9];
    b.triangle(5, tb);
    CHECK(p[2].z == double(tb[8]));
    CHECK(expansions() == before); // nothing above built the expansion
    // An instance whose float32 vertices overflow is named by bounds(), as by world_positions().
    Scene big;
    big.add_instance(big.add_prototype(many_spots(false).data_of(1)), placed(0, {3e38, 0, 0}, 1e38));
    CHECK_THROWS_WITH(big.bounds(), Catch::Contains("overflows float32"));
}

TEST_CASE("shading, resolve, AO, shadows and queries of an instanced scene never expand it", "[device][instances]")
{
    Device device = Device::open();
    Scene a = many_spots(true), b = many_spots(false);
    Camera cam = Camera::framing(b.bounds());
    std::uint64_t before = expansions();
    Renderer ra(device, a), rb(device, b);
    for (Path path : {Path::Ray, Path::Raster}) {
        INFO(to_string(path));
        VisibilityBuffer va = ra.render(cam, 80, 60, path), vb = rb.render(cam, 80, 60, path);
        REQUIRE(va.read_keys() == vb.read_keys());
        for (ShadeMode mode : {ShadeMode::Lambert, ShadeMode::Depth, ShadeMode::Ids}) {
            ShadeOptions so;
            so.mode = mode;
            CHECK(shade(ra, va, cam, so).rgba == shade(rb, vb, cam, so).rgba);
        }
        AttributeRequest all;
        all.barycentrics = all.position = all.normal = all.smooth_normal = true;
        AttributeBuffers aa = resolve(ra, va, cam, all), ab = resolve(rb, vb, cam, all);
        for (Attribute at :
             {Attribute::Barycentrics, Attribute::Position, Attribute::Normal, Attribute::SmoothNormal}) {
            INFO(to_string(at));
            std::vector<float> fa = aa.read(at), fb = ab.read(at);
            std::size_t differ = 0, first = fa.size();
            for (std::size_t i = 0; i < fa.size(); ++i)
                if (std::memcmp(&fa[i], &fb[i], 4) != 0) {
                    differ++;
                    if (first == fa.size()) first = i;
                }
            INFO(differ << " differ, first at " << first << ": " << (first < fa.size() ? fa[first] : 0.0f) << " vs "
                        << (first < fa.size() ? fb[first] : 0.0f));
            CHECK(same_floats(fa, fb));
        }
        RayQuery qa(ra), qb(rb);
        AoOptions ao;
        ao.rays = 4;
        CHECK(same_floats(qa.ambient_occlusion(va, cam, ao).value, qb.ambient_occlusion(vb, cam, ao).value));
        std::vector<RayRecord> rays_a = qa.ambient_occlusion_rays(va, cam, ao);
        std::vector<RayRecord> rays_b = qb.ambient_occlusion_rays(vb, cam, ao);
        REQUIRE(rays_a.size() == rays_b.size());
        CHECK(std::memcmp(rays_a.data(), rays_b.data(), rays_a.size() * sizeof(RayRecord)) == 0);
        Vec3 light{2, 6, 9};
        CHECK(same_floats(qa.shadows(va, cam, light).value, qb.shadows(vb, cam, light).value));
    }
    // Several samples per pixel shade each sample's triangle.
    RenderOptions four;
    four.samples = 4;
    Renderer r4(device, a, four), r4b(device, b, four);
    VisibilityBuffer v4 = r4.render(cam, 40, 30, Path::Ray), v4b = r4b.render(cam, 40, 30, Path::Ray);
    REQUIRE(v4.read_keys() == v4b.read_keys());
    std::vector<std::uint8_t> s4 = shade(r4, v4, cam).rgba, s4b = shade(r4b, v4b, cam).rgba;
    std::size_t differ = 0;
    for (std::size_t i = 0; i < s4.size(); ++i) differ += s4[i] != s4b[i];
    INFO(differ << " channels differ");
    CHECK(differ == 0);
    CHECK_FALSE(detail::expansion_uploaded(ra));
    CHECK_FALSE(detail::expansion_uploaded(r4));
    CHECK(expansions() == before);
}

TEST_CASE("a frame's stage times sum to at most its time when stages repeat", "[device][instances][raster]")
{
    Device device = Device::open();
    Scene a = many_spots(true);
    Camera cam = Camera::framing(a.bounds());
    Renderer r(device, a);
    detail::set_raster_chunk(r, 3000); // a dozen chunks: setup, bin and fine run a dozen times each
    for (int frame = 0; frame < 3; ++frame) {
        r.render(cam, 160, 120, Path::Raster);
        const FrameTiming& t = r.last_frame();
        REQUIRE(t.stages_measured);
        double sum = 0;
        for (const StageTiming& s : t.stages) sum += s.ms;
        INFO("frame " << frame << ": stages " << sum << " ms, frame " << t.frame_ms << " ms");
        CHECK(sum > 0);
        CHECK(sum <= t.frame_ms * 1.02 + 0.05); // each stage's span once counted every other stage
    }
}
